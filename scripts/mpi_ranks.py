"""A batch run under mpirun as the studies and tests that kill one of its ranks see it
(scripts/survey-scale-study.py, tests/integration/test_batch*.py): the environment mpirun needs,
its processes, found through /proc, its journal and the temporaries it leaves."""
import os


def mpi_env():
    """This environment with what Open MPI needs here: it refuses to run as root without the
    first two (CLIENTS.md); a container has no CMA; hwloc's OpenGL plugin looks for GPUs by
    opening X displays :0, :1... over TCP to "localhost", and in a root without /etc/hosts each
    name goes to DNS (mpirun then took 11.3 s instead of 1.3 s: README, "On a cluster")."""
    env = dict(os.environ)
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_btl_vader_single_copy_mechanism="none", HWLOC_COMPONENTS="-gl")
    return env


def journal(out):
    """The lines of the batch's journal in `out` as (run, time, event, tile, detail); none
    before it exists."""
    path = os.path.join(out, "journal.txt")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [line.rstrip("\n").split("\t") for line in f if line.count("\t") == 4]


def temporaries(root):
    """Every temporary file or folder (".tmp." in its name) under `root`."""
    found = []
    for dirpath, dirnames, filenames in os.walk(root):
        found += [os.path.join(dirpath, n) for n in dirnames + filenames if ".tmp." in n]
    return found


def rank_process(octarc, out, rank):
    """The pid of the octarc process (the executable `octarc`) that is MPI rank `rank` of the
    batch writing `out`, or None."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                cmdline = f.read().split(b"\0")
            if os.fsencode(octarc) != cmdline[0] or os.fsencode(out) not in cmdline:
                continue
            with open("/proc/%s/environ" % pid, "rb") as f:
                environ = f.read().split(b"\0")
        except OSError:
            continue
        if b"OMPI_COMM_WORLD_RANK=%d" % rank in environ:
            return int(pid)
    return None
