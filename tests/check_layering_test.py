"""Tests of scripts/check-layering.py on small fake source trees.

A clean tree (each stage includes only earlier stages that its library links; cfitsio only in
io and catalog .cpp files) must pass; each deliberately wrong include must be reported on its
own line naming the file, the line and the reason.

Usage: /usr/bin/python3 tests/check_layering_test.py [SOURCE_DIR]
"""
import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

SOURCE_DIR = os.path.abspath(sys.argv.pop(1) if len(sys.argv) > 1 else
                             os.path.join(os.path.dirname(__file__), ".."))
CHECKER = os.path.join(SOURCE_DIR, "scripts", "check-layering.py")

# The links of a small tree: simulation sees io and core only; selection links io PRIVATE, so
# run, which links selection, does not see io through it.
CMAKE_FILES = {
    "src/core/CMakeLists.txt": "add_library(octarc_core STATIC A.cpp)\n",
    "src/io/CMakeLists.txt":
        "add_library(octarc_io STATIC A.cpp)\n"
        "target_link_libraries(octarc_io PUBLIC octarc_core PRIVATE PkgConfig::CFITSIO)\n",
    "src/detection/CMakeLists.txt":
        "target_link_libraries(octarc_detection PUBLIC octarc_io)\n",
    "src/catalog/CMakeLists.txt":
        "target_link_libraries(octarc_catalog PUBLIC octarc_io octarc_core\n"
        "  # a comment (with parentheses) inside the call\n"
        "  PRIVATE PkgConfig::CFITSIO)\n",
    "src/selection/CMakeLists.txt":
        "target_link_libraries(octarc_selection PUBLIC octarc_core PRIVATE octarc_io)\n",
    "sextractor_compat/CMakeLists.txt":
        "target_link_libraries(octarc_sexcompat PUBLIC octarc_core)\n",
    "src/simulation/CMakeLists.txt":
        "target_link_libraries(octarc_simulation PUBLIC octarc_io octarc_core)\n",
    "src/run/CMakeLists.txt":
        "target_link_libraries(octarc_run PUBLIC octarc_selection octarc_catalog\n"
        "  octarc_detection octarc_sexcompat octarc_simulation)\n",
    "src/app/CMakeLists.txt": "target_link_libraries(octarc_app PRIVATE octarc_run)\n",
}

CLEAN_FILES = {
    "include/octarc/core/Image.h": "#pragma once\n#include <vector>\n",
    "include/octarc/io/FitsImage.h": '#include "octarc/core/Image.h"\n',
    "include/octarc/io/detail/Cfitsio.h": "#include <fitsio.h>\n",
    "src/io/FitsImage.cpp":
        '#include "octarc/io/FitsImage.h"\n#include "octarc/io/detail/Cfitsio.h"\n',
    "src/io/Wcs.cpp": "#include <wcslib/wcs.h>\n",
    "src/catalog/Columns.h": '#include "octarc/io/detail/Cfitsio.h"\n',
    "src/catalog/Catalog.cpp": '#include "Columns.h"\n#include "octarc/io/FitsImage.h"\n',
    "include/octarc/selection/Grid.h": '#include "octarc/core/Image.h"\n',
    "src/selection/Grid.cpp": '#include "octarc/io/FitsImage.h"\n',  # PRIVATE link
    "sextractor_compat/include/octarc/sexcompat/Config.h": '#include "octarc/core/Image.h"\n',
    "src/simulation/Field.cpp": '#include "octarc/io/FitsImage.h"\n',
    "src/run/Run.cpp":
        '#include "octarc/sexcompat/Config.h"\n#include "octarc/selection/Grid.h"\n'
        '#include "octarc/io/FitsImage.h"\n',  # through catalog's PUBLIC link
    "src/app/main.cpp": '#include "octarc/run/Run.h"\n',
    # A client: may include anything.
    "fuzz/fuzz_x.cpp": '#include "octarc/io/detail/Cfitsio.h"\n#include <fitsio.h>\n',
}


def write_tree(root, files):
    for path, text in files.items():
        full = os.path.join(root, path)
        os.makedirs(os.path.dirname(full), exist_ok=True)
        with open(full, "w") as f:
            f.write(text)


def run_checker(root):
    proc = subprocess.run([sys.executable, CHECKER, root], capture_output=True, text=True)
    return proc.returncode, proc.stdout.splitlines()


class CheckLayeringTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name
        write_tree(self.root, CMAKE_FILES)
        write_tree(self.root, CLEAN_FILES)

    def tearDown(self):
        self.tmp.cleanup()

    def assertReported(self, lines, prefix, *words):
        found = [l for l in lines if l.startswith(prefix)]
        self.assertEqual(len(found), 1, "%s not reported once in %s" % (prefix, lines))
        for w in words:
            self.assertIn(w, found[0])

    def test_clean_tree_passes(self):
        status, lines = run_checker(self.root)
        self.assertEqual(status, 0, lines)
        self.assertEqual(lines, ["layering: %d files, no violation" % len(CLEAN_FILES)])

    def test_later_stage(self):
        write_tree(self.root, {"src/detection/Detector.cpp": textwrap.dedent("""\
            #include <vector>
            #include "octarc/io/FitsImage.h"
            #include "octarc/measure/Registry.h"
            """)})
        status, lines = run_checker(self.root)
        self.assertEqual(status, 1)
        self.assertReported(lines, "src/detection/Detector.cpp:3: detection includes measure",
                            "later")
        self.assertEqual(len(lines), 1, lines)

    def test_unlinked_stage(self):
        write_tree(self.root, {
            "src/simulation/Stamp.cpp": '#include "octarc/detection/Filter.h"\n',
            # selection links io PRIVATE: run does not see io through selection alone.
            "src/run/CMakeLists.txt":
                "target_link_libraries(octarc_run PUBLIC octarc_selection)\n",
        })
        status, lines = run_checker(self.root)
        self.assertEqual(status, 1)
        self.assertReported(lines, "src/simulation/Stamp.cpp:1: simulation includes detection",
                            "octarc_simulation does not link octarc_detection")
        self.assertReported(lines, "src/run/Run.cpp:1: run includes sexcompat",
                            "does not link")
        self.assertReported(lines, "src/run/Run.cpp:3: run includes io",
                            "octarc_run does not link octarc_io")
        self.assertEqual(len(lines), 3, lines)

    def test_mpi_outside_the_cluster_stage(self):
        write_tree(self.root, {
            "src/cluster/CMakeLists.txt":
                "target_link_libraries(octarc_cluster PUBLIC octarc_core PRIVATE MPI::MPI_CXX)\n",
            "src/cluster/ClusterMpi.cpp": "#include <mpi.h>\n",  # the one place: fine
            "include/octarc/cluster/Cluster.h": "#include <mpi.h>\n",
            "src/run/Batch.cpp": "#include <mpi.h>\n",
        })
        status, lines = run_checker(self.root)
        self.assertEqual(status, 1)
        self.assertReported(lines, "include/octarc/cluster/Cluster.h:1: cluster includes mpi.h",
                            "only by the .cpp files of the cluster stage")
        self.assertReported(lines, "src/run/Batch.cpp:1: run includes mpi.h", "cluster stage")
        self.assertEqual(len(lines), 2, lines)

    def test_xgboost_outside_its_wrapper(self):
        write_tree(self.root, {
            "src/selection/TreeModel.cpp": "#include <xgboost/c_api.h>\n",  # the one place
            "src/selection/Other.cpp": "#include <xgboost/c_api.h>\n",
            "include/octarc/selection/TreeModel.h": "#include <xgboost/c_api.h>\n",
        })
        status, lines = run_checker(self.root)
        self.assertEqual(status, 1)
        self.assertReported(lines, "src/selection/Other.cpp:1: selection includes xgboost/c_api.h",
                            "only by src/selection/TreeModel.cpp")
        self.assertReported(lines, "include/octarc/selection/TreeModel.h:1: selection includes "
                            "xgboost/c_api.h", "only by src/selection/TreeModel.cpp")
        self.assertEqual(len(lines), 2, lines)

    def test_cfitsio_outside_io(self):
        write_tree(self.root, {
            "src/simulation/Table.cpp": "#include <fitsio.h>\n",
            "src/simulation/Reader.cpp": '#include "octarc/io/detail/Cfitsio.h"\n',
            "src/measure/Wcs.cpp": "#include <wcslib/wcshdr.h>\n",
            "include/octarc/io/Table.h": '#include "fitsio.h"\n',
            "include/octarc/catalog/Catalog.h": '#include "octarc/io/detail/Cfitsio.h"\n',
        })
        status, lines = run_checker(self.root)
        self.assertEqual(status, 1)
        self.assertReported(lines, "src/simulation/Table.cpp:1: simulation includes fitsio.h",
                            "io and catalog")
        self.assertReported(lines, "src/simulation/Reader.cpp:1: simulation includes io",
                            "io/detail")
        self.assertReported(lines, "src/measure/Wcs.cpp:1: measure includes wcslib/wcshdr.h")
        self.assertReported(lines, "include/octarc/io/Table.h:1: io includes fitsio.h",
                            "public header")
        self.assertReported(lines, "include/octarc/catalog/Catalog.h:1: catalog includes io",
                            "io/detail")
        self.assertEqual(len(lines), 5, lines)

    def test_private_header_of_another_stage(self):
        write_tree(self.root, {"src/run/Write.cpp": '#include "../catalog/Columns.h"\n'})
        status, lines = run_checker(self.root)
        self.assertEqual(status, 1)
        self.assertReported(lines, "src/run/Write.cpp:1: run includes catalog",
                            "private header")

    def test_file_in_no_stage(self):
        write_tree(self.root, {"src/report/Sheet.cpp": '#include "octarc/core/Image.h"\n'})
        status, lines = run_checker(self.root)
        self.assertEqual(status, 1)
        self.assertReported(lines, "src/report/Sheet.cpp:1: (no stage)", "STAGES")


if __name__ == "__main__":
    unittest.main()
