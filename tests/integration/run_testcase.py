"""Runs one unittest TestCase for ctest and reports skips so that ctest can show them.

Usage: /usr/bin/python3 run_testcase.py MODULE.TESTCASE

`python3 -m unittest` exits 0 when tests are skipped, so ctest would show "Passed" for a case
that ran nothing. This runner exits with

  0   every test ran and passed (partial skips are listed at the end, one line per test);
  77  every test of the case was skipped (ctest's SKIP_RETURN_CODE: shown as "Skipped");
  1   a test failed or raised, the case holds no test, or - on the CI machine, where the
      environment variable CI is "true" - a test was skipped because shared data or a program
      was missing (the CI machine has everything, so such a skip means a broken setup).

A skip counts as "missing data or program" when its reason starts with one of the prefixes of
octarc_testlib (MISSING_DATA, MISSING_PROGRAM), which require_shared() and require_program()
use.
"""
import os
import sys
import unittest

import octarc_testlib

SKIP_RETURN_CODE = 77


def test_ids(suite):
    """Ids of every test in a (nested) suite."""
    ids = []
    for item in suite:
        if isinstance(item, unittest.TestSuite):
            ids.extend(test_ids(item))
        else:
            ids.append(item.id())
    return ids


def is_missing_dependency(reason):
    return reason.startswith((octarc_testlib.MISSING_DATA, octarc_testlib.MISSING_PROGRAM))


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    suite = unittest.defaultTestLoader.loadTestsFromName(argv[1])
    ids = test_ids(suite)
    if not ids:
        print("%s: no test to run" % argv[1], file=sys.stderr)
        return 1
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stderr).run(suite)
    # A skip in setUpClass is reported once for the whole class, not per test.
    skipped = [(getattr(test, "id", lambda: str(test))(), reason)
               for test, reason in result.skipped]
    class_skipped = any(name not in ids for name, _ in skipped)
    if skipped:
        print("\nSKIPPED %s of %d tests of %s:" % ("all" if class_skipped else len(skipped),
                                                  len(ids), argv[1]), file=sys.stderr)
        for name, reason in skipped:
            print("  %s: %s" % (name, reason), file=sys.stderr)
    if not result.wasSuccessful():
        return 1
    if os.environ.get("CI") == "true":
        missing = [name for name, reason in skipped if is_missing_dependency(reason)]
        if missing:
            print("CI=true: %d skip(s) for missing data or programs count as failures: %s"
                  % (len(missing), ", ".join(missing)), file=sys.stderr)
            return 1
    if class_skipped or (skipped and len(skipped) == len(ids)):
        return SKIP_RETURN_CODE
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
