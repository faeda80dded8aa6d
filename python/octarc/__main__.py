"""`python3 -m octarc --version`: the version of the octarc module (as `octarc -v` prints it)."""
import sys

from . import __version__


def main(argv):
    """Prints the version for --version or -v; a usage line otherwise (status 2)."""
    if argv in (["--version"], ["-v"]):
        print("octarc version %s" % __version__)
        return 0
    print("usage: python3 -m octarc --version   (the module: import octarc; see docs/python.md)",
          file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
