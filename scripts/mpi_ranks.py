"""The processes of a run under mpirun, found through /proc: for the studies and tests that kill
one MPI rank of a batch (scripts/survey-scale-study.py, tests/integration/test_batch.py)."""
import os


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
