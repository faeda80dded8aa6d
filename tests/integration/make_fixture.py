"""Makes the data that the test cases of one module share, once, for ctest (a fixture: see
octarc_add_python_test in CMakeLists.txt).

Usage: /usr/bin/python3 make_fixture.py MODULE DIR

Empties DIR and calls MODULE.make_fixture(DIR); the cases then find DIR in the environment
variable OCTARC_FIXTURE_DIR. Run alone (python3 -m unittest), a case makes its own data.
"""
import importlib
import os
import shutil
import sys


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[3], file=sys.stderr)
        return 2
    module, directory = argv[1], argv[2]
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)
    importlib.import_module(module).make_fixture(directory)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
