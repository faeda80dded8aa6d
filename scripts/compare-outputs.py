#!/usr/bin/python3
"""Runs the same octarc commands with two octarc executables and compares what they write.

For a change that must not change any output (a refactoring): every file both runs write must be
byte for byte the same, except for the cards that record when and how long a run took (SEXDATE,
SEXTIME, SEXELAPS in an LDAC_IMHEAD or a FITS_1.0 primary header), which are blanked in both
before the comparison. The commands: `octarc simulate field` and `octarc detect` on that field (15
levels, every catalog column, weight map, ASSOC with the truth list, SEGMENTATION and BACKGROUND
check-images), `octarc measure` on the README example (new catalog of every level, and appended to
the SExtractor catalogs), `octarc simulate lenses -n 300 --seed 3 --stamps`, and `octarc demo`.

Usage: /usr/bin/python3 scripts/compare-outputs.py OLD_OCTARC NEW_OCTARC [--keep DIR]
Exit status 0 when every output is the same, 1 otherwise (the differing files are listed).
"""
import argparse
import filecmp
import os
import re
import shutil
import subprocess
import sys
import tempfile

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TESTDATA = os.path.join(SOURCE_DIR, "testdata")
RUN_CARDS = re.compile(rb"(SEXDATE |SEXTIME |SEXELAPS)= [^/]{20}")


def all_columns(octarc, path):
    """Every column of `octarc detect -dp`, as a .param file."""
    listing = subprocess.run([octarc, "detect", "-dp"], capture_output=True, text=True,
                             check=True).stdout
    names = [line[1:].split()[0] for line in listing.splitlines() if line.startswith("#")]
    names = ["VECTOR_ASSOC(5)" if n.startswith("VECTOR_ASSOC") else n for n in names]
    with open(path, "w") as f:
        f.write("\n".join(names) + "\n")


def run_all(octarc, out):
    """Runs every command with `octarc`, writing into `out`."""
    os.makedirs(out)
    share = os.path.join(os.path.dirname(os.path.dirname(octarc)), "share", "octarc")
    def run(*args, cwd=out):
        subprocess.run([octarc] + list(args), check=True, cwd=cwd, capture_output=True)
    run("simulate", "field", "-o", "field.fits", "--size", "1024", "--lenses", "4",
        "--seed", "7", "--quiet")
    all_columns(octarc, os.path.join(out, "all.param"))
    run("detect", "field.fits", "-c", os.path.join(share, "octarc.sex"), "-PARAMETERS_NAME",
        "all.param", "-CATALOG_NAME", "field.ldac", "-WEIGHT_TYPE", "MAP_WEIGHT",
        "-WEIGHT_IMAGE", "field.weight.fits", "-ASSOC_NAME", "field.truth.txt",
        "-ASSOC_PARAMS", "2,3", "-ASSOC_DATA", "1,6,7,8,9", "-ASSOC_RADIUS", "5",
        "-ASSOCSELEC_TYPE", "ALL", "-CHECKIMAGE_TYPE", "SEGMENTATION,BACKGROUND",
        "-CHECKIMAGE_NAME", "field.seg.fits,field.bkg.fits", "-VERBOSE_TYPE", "QUIET")
    run("detect", "field.fits", "-c", os.path.join(share, "octarc.sex"), "-PARAMETERS_NAME",
        "all.param", "-CATALOG_NAME", "field.ascii", "-CATALOG_TYPE", "ASCII_HEAD",
        "-ASSOC_NAME", "field.truth.txt", "-ASSOC_PARAMS", "2,3", "-ASSOC_DATA", "1,6,7,8,9",
        "-FILTER", "Y", "-VERBOSE_TYPE", "QUIET")
    run("measure", os.path.join(TESTDATA, "example.fits.gz"), "-c",
        os.path.join(TESTDATA, "example.sex"), "-CATALOG_NAME", os.path.join(out, "example.ldac"),
        "-VERBOSE_TYPE", "QUIET", cwd=SOURCE_DIR)
    cats = [os.path.join(TESTDATA, "example.cat%d.ldac" % k) for k in (1, 2, 3)]
    run("measure", os.path.join(TESTDATA, "example.fits.gz"), "-c",
        os.path.join(TESTDATA, "example.sex"), "-APPEND_COLUMNS", "Y", "-INPUT_CATALOG",
        ",".join(cats), "-CATALOG_NAME",
        ",".join(os.path.join(out, "example.cat%d+oct.ldac" % k) for k in (1, 2, 3)),
        "-VERBOSE_TYPE", "QUIET", cwd=SOURCE_DIR)
    run("simulate", "lenses", "-n", "300", "--seed", "3", "-o", "lenses.fits", "--stamps",
        "stamps.fits", "--quiet")
    run("demo", "--size", "1024", "--lenses", "3", "--out", "demo", "--quiet")


def normalised(path):
    with open(path, "rb") as f:
        data = f.read()
    return RUN_CARDS.sub(lambda m: m.group(1) + b"= " + b" " * 20, data)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--keep", help="keep the outputs in this directory")
    args = parser.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="octarc-compare-")
    try:
        old, new = os.path.join(work, "old"), os.path.join(work, "new")
        run_all(os.path.abspath(args.old), old)
        run_all(os.path.abspath(args.new), new)
        differ, compared = [], 0
        for root, _, files in os.walk(old):
            for name in sorted(files):
                a = os.path.join(root, name)
                rel = os.path.relpath(a, old)
                b = os.path.join(new, rel)
                compared += 1
                if not os.path.exists(b):
                    differ.append(rel + " (missing in the new run)")
                elif not filecmp.cmp(a, b, shallow=False) and normalised(a) != normalised(b):
                    differ.append(rel)
        for root, _, files in os.walk(new):
            for name in files:
                rel = os.path.relpath(os.path.join(root, name), new)
                if not os.path.exists(os.path.join(old, rel)):
                    differ.append(rel + " (only in the new run)")
        for d in differ:
            print("differs: " + d)
        print("%d files compared, %d differ" % (compared, len(differ)))
        return 1 if differ else 0
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
