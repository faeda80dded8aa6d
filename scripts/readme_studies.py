#!/usr/bin/python3
"""Remakes the figures the README prints for its long studies and compares them with the README,
line for line: today the calibration of 150 000 `dls` systems (README "Simulations": "The
figures below are for the `dls` preset", about 75 CPU seconds). The test suite runs every other
command line of those sections (tests/integration/test_readme_simulations.py) and checks that the
README's study command lines are the ones below; this script is run by hand after a change that
may move the figures, and the README's block is replaced by what it prints on a difference.

Usage: /usr/bin/python3 scripts/readme_studies.py [--octarc build/release/bin/octarc]
                                                 [--workdir DIR]
Exit status 0 when every printed block is the README's, 1 otherwise (with both versions).
"""
import argparse
import os
import re
import shlex
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
README = os.path.join(ROOT, "README.md")

# (the README sentence the study's blocks follow, its command lines as the README prints them
# without their comments, the command whose output the README prints)
STUDIES = [
    ("The figures below are for the `dls` preset",
     ["octarc simulate lenses -n 150000 --seed 31 --preset dls -o dls150k.fits",
      "octarc calibrate dls150k.fits"],
     1),
]
COMMANDS = [line for _, lines, _ in STUDIES for line in lines]


def octarc_lines(sh_block):
    """The `octarc ...` command lines of the text of a ```sh block: continuations joined,
    comments dropped, blanks collapsed."""
    commands = []
    for line in sh_block.replace("\\\n", " ").splitlines():
        line = line.split(" # ")[0].strip()
        if line.startswith("octarc "):
            commands.append(" ".join(line.split()))
    return commands


def blocks_after(text, marker):
    """The command lines of the first ```sh block after `marker` and the lines of the first
    plain ``` block after that one."""
    rest = text[text.index(marker):]
    sh = re.search(r"```sh\n(.*?)```", rest, re.S)
    printed = re.search(r"```\n(.*?)```", rest[sh.end():], re.S)
    return octarc_lines(sh.group(1)), printed.group(1).splitlines()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--octarc", default=os.path.join(ROOT, "build", "release", "bin", "octarc"))
    ap.add_argument("--workdir", default=None)
    args = ap.parse_args()
    octarc = os.path.abspath(args.octarc)
    work = args.workdir or tempfile.mkdtemp(prefix="octarc-studies-")
    os.makedirs(work, exist_ok=True)
    with open(README) as f:
        text = f.read()
    differ = False
    for marker, lines, printed_by in STUDIES:
        commands, expected = blocks_after(text, marker)
        if commands != lines:
            sys.exit("README: the commands after '%s' are not this script's:\n  %s"
                     % (marker, "\n  ".join(commands)))
        for k, line in enumerate(lines):
            print("running:", line, flush=True)
            proc = subprocess.run([octarc] + shlex.split(line)[1:], cwd=work,
                                  capture_output=True, text=True)
            if proc.returncode != 0:
                sys.exit("failed: %s\n%s" % (line, proc.stderr))
            if k == printed_by:
                got = proc.stdout.splitlines()
        if got != expected:
            differ = True
            print("README after '%s' prints:\n%s\nthe run prints:\n%s"
                  % (marker, "\n".join(expected), "\n".join(got)))
        else:
            print("the same %d lines as the README" % len(expected))
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
