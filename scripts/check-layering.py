#!/usr/bin/python3
"""Fails when a source file includes a stage it must not depend on.

The stages follow the data flow (STAGES below, earliest first). A file of one stage may include
the headers of its own stage and of an earlier stage whose library its stage's library links:
directly (PUBLIC or PRIVATE in target_link_libraries) or through a chain of PUBLIC links. The
links are read from the CMakeLists.txt files of the source tree. Checked: every file under
include/octarc/, src/, sextractor_compat/ and python/src/ (the Python module's bindings, the
last stage); fuzz/ holds clients that may include any stage, so its files are only counted.

Libraries wrapped once, at the io boundary (include/octarc/io/detail/Cfitsio.h: "Include only
from .cpp files of the io and catalog stages: public headers never expose fitsio.h"):
  - octarc/io/detail/... only from files of the io and catalog stages outside include/ (their
    .cpp files, and private headers in src/io, src/catalog that only those .cpp files can reach);
  - <fitsio.h>, <longnam.h> and <wcslib/...> only from the io and catalog stages, and from no
    public header other than those of include/octarc/io/detail/;
  - a private header in src/<stage>/ only from files of that stage;
  - <mpi.h> only from the .cpp files of the cluster stage;
  - <xgboost/...> only from src/selection/TreeModel.cpp (the learned selection's trees).

Usage: /usr/bin/python3 scripts/check-layering.py [SOURCE_DIR]
Output: one line per violation, "file:line: <stage> includes <stage> (why)", and exit status 1;
or "layering: N files, no violation" and exit status 0.
"""
import os
import re
import sys

# The stages in data-flow order: (name, library target, folders). A stage's headers are included
# as "octarc/<name>/..."; a sub-stage such as "simulation/engine" is a later stage than
# "simulation" and owns the files of its own folders. Folders default to include/octarc/<name>
# and src/<name>.
STAGES = [
    ("core", "octarc_core", None),
    ("cluster", "octarc_cluster", None),
    ("io", "octarc_io", None),
    ("plot", "octarc_plot", None),
    ("background", "octarc_background", None),
    ("detection", "octarc_detection", None),
    ("measure", "octarc_measure", None),
    ("catalog", "octarc_catalog", None),
    ("selection", "octarc_selection", None),
    ("sexcompat", "octarc_sexcompat", ["sextractor_compat"]),
    ("simulation", "octarc_simulation", None),
    ("run", "octarc_run", None),
    ("simulation/engine", "octarc_simulation_engine", None),
    ("lenslight", "octarc_lenslight", None),
    ("calibration", "octarc_calibration", None),
    ("search", "octarc_search", None),
    ("batch", "octarc_batch", None),
    ("app", "octarc_app", None),
    # The Python module: like app, a client on top of the libraries (python/src: one binding
    # file per stage).
    ("python", "octarc_python", ["python/src"]),
]
CHECKED_FOLDERS = ["include/octarc", "src", "sextractor_compat", "python/src"]
CLIENT_FOLDERS = ["fuzz"]  # may include anything
SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".cxx")
WRAPPING_STAGES = {"io", "catalog"}  # may use cfitsio and wcslib
DETAIL_PREFIX = "octarc/io/detail/"

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
WRAPPED_LIBRARY = re.compile(r"^(fitsio2?\.h|longnam\.h|wcslib/.*|wcslib\.h)$")
MPI_HEADER = re.compile(r"^mpi\.h$")  # MPI: only in the .cpp files of the cluster stage
XGBOOST_HEADER = re.compile(r"^xgboost/")  # XGBoost: only in its wrapper
XGBOOST_WRAPPER = "src/selection/TreeModel.cpp"


def stage_folders(name, folders):
    return folders if folders else ["include/octarc/" + name, "src/" + name]


def stage_of_file(relpath):
    """The stage owning a file: the one with the longest folder that holds it, or None."""
    best, best_len = None, -1
    for name, _, folders in STAGES:
        for folder in stage_folders(name, folders):
            if (relpath + "/").startswith(folder + "/") and len(folder) > best_len:
                best, best_len = name, len(folder)
    return best


def stage_of_header(header):
    """The stage of an "octarc/<stage>/..." include (the longest matching stage name)."""
    if not header.startswith("octarc/"):
        return None
    rest = header[len("octarc/"):]
    names = [n for n, _, _ in STAGES if rest.startswith(n + "/")]
    return max(names, key=len) if names else rest.split("/")[0]


def cmake_commands(text, command):
    """Argument lists of every `command(...)` call in a CMake file (comments removed)."""
    text = re.sub(r"#[^\n]*", "", text)
    for match in re.finditer(r"\b%s\s*\(([^)]*)\)" % command, text, re.IGNORECASE):
        yield match.group(1).split()


def read_links(source_dir):
    """{target: (public links, private links)} from every CMakeLists.txt outside build trees."""
    links = {}
    for root, dirs, files in os.walk(source_dir):
        dirs[:] = [d for d in dirs if not d.startswith(("build", "."))]
        if "CMakeLists.txt" not in files:
            continue
        with open(os.path.join(root, "CMakeLists.txt")) as f:
            text = f.read()
        for args in cmake_commands(text, "target_link_libraries"):
            if not args:
                continue
            public, private = links.setdefault(args[0], (set(), set()))
            scope = public  # the plain signature propagates like PUBLIC
            for item in args[1:]:
                if item in ("PUBLIC", "INTERFACE"):
                    scope = public
                elif item == "PRIVATE":
                    scope = private
                else:
                    scope.add(item)
    return links


def reachable_targets(target, links):
    """Targets whose headers `target` sees: its direct links, then PUBLIC links transitively."""
    public, private = links.get(target, (set(), set()))
    seen = set()
    todo = list(public | private)
    while todo:
        t = todo.pop()
        if t in seen:
            continue
        seen.add(t)
        todo.extend(links.get(t, (set(), set()))[0])
    return seen


def source_files(source_dir, folders):
    for top in folders:
        for root, dirs, files in os.walk(os.path.join(source_dir, top)):
            dirs.sort()
            for name in sorted(files):
                if name.endswith(SOURCE_SUFFIXES):
                    yield os.path.relpath(os.path.join(root, name), source_dir)


def check_file(source_dir, relpath, order, target_of, visible):
    """Violation lines of one checked file."""
    stage = stage_of_file(relpath)
    problems = []
    with open(os.path.join(source_dir, relpath), errors="replace") as f:
        lines = f.readlines()
    for number, line in enumerate(lines, 1):
        match = INCLUDE.match(line)
        if not match:
            continue
        header = match.group(2).strip()
        where = "%s:%d: %s" % (relpath, number, stage or "(no stage)")
        if stage is None:
            problems.append("%s includes %s (the file is in no stage: add its folder to STAGES "
                            "in scripts/check-layering.py)" % (where, header))
            continue
        if MPI_HEADER.match(header) and (stage != "cluster" or relpath.startswith("include/")):
            problems.append("%s includes %s (MPI is used only by the .cpp files of the cluster "
                            "stage)" % (where, header))
        if XGBOOST_HEADER.match(header) and relpath != XGBOOST_WRAPPER:
            problems.append("%s includes %s (XGBoost is used only by %s)"
                            % (where, header, XGBOOST_WRAPPER))
        if WRAPPED_LIBRARY.match(header):
            if stage not in WRAPPING_STAGES:
                problems.append("%s includes %s (cfitsio and wcslib are used only by the io and "
                                "catalog stages)" % (where, header))
            elif (relpath.startswith("include/")
                  and not relpath.startswith("include/" + DETAIL_PREFIX)):
                problems.append("%s includes %s (a public header never exposes cfitsio or "
                                "wcslib)" % (where, header))
            continue
        other = None
        if match.group(1) == '"' and not header.startswith("octarc/"):
            local = os.path.normpath(os.path.join(os.path.dirname(relpath), header))
            if os.path.isfile(os.path.join(source_dir, local)):
                other = stage_of_file(local)
                if other != stage and local.startswith("src/"):
                    problems.append("%s includes %s (%s, a private header of %s)" %
                                    (where, other, header, other))
                    continue
            # A header found on the include path (octarc/... is the only project form).
        if header.startswith("octarc/"):
            other = stage_of_header(header)
            if header.startswith(DETAIL_PREFIX):
                if stage not in WRAPPING_STAGES or relpath.startswith("include/"):
                    if not relpath.startswith("include/" + DETAIL_PREFIX):
                        problems.append("%s includes io (%s: only .cpp files of the io and "
                                        "catalog stages include io/detail/)" % (where, header))
                        continue
        if other is None or other == stage:
            continue
        if other not in order:
            problems.append("%s includes %s (%s: no such stage in scripts/check-layering.py)" %
                            (where, other, header))
        elif order[other] > order[stage]:
            problems.append("%s includes %s (%s: %s comes later in the data flow)" %
                            (where, other, header, other))
        elif target_of[other] not in visible[stage]:
            problems.append("%s includes %s (%s: %s does not link %s)" %
                            (where, other, header, target_of[stage], target_of[other]))
    return problems


def main():
    source_dir = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                                 os.path.join(os.path.dirname(__file__), ".."))
    order = {name: i for i, (name, _, _) in enumerate(STAGES)}
    target_of = {name: target for name, target, _ in STAGES}
    links = read_links(source_dir)
    # A stage sees the headers of the targets its own library links.
    visible = {name: reachable_targets(target, links) for name, target, _ in STAGES}
    problems = []
    count = 0
    for relpath in source_files(source_dir, CHECKED_FOLDERS):
        count += 1
        problems.extend(check_file(source_dir, relpath, order, target_of, visible))
    count += sum(1 for _ in source_files(source_dir, CLIENT_FOLDERS))
    for p in problems:
        print(p)
    if problems:
        return 1
    print("layering: %d files, no violation" % count)
    return 0


if __name__ == "__main__":
    sys.exit(main())
