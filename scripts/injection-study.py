#!/usr/bin/python3
"""Completeness and purity of `octarc search`, measured by injection: runs `octarc demo` (a
simulated 2048^2 field with injected lenses, searched with the shipped demo grid) for several
seeds and adds up, per search space, which injected lenses came back as candidates.

    scripts/injection-study.py [--seeds 20] [--lenses 12] [--octarc build/release/bin/octarc]

Prints the README table (Markdown): completeness against theta_E and arc magnitude, spurious
candidates per deg2 (candidates that are no injected arc), the fraction of found lenses whose
lens galaxy is named right (within 1"), and, for those, the theta_E estimate against the truth
(median ratio, and the scatter as half the 16-84% range)."""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from astropy.io import fits

# The report spaces of the default SEARCH_SPACE, by bit; "all" is the grid selection alone.
SPACES = [("probability selection alone", None), ("A015: a > 0.15, e > 0.6, S/N > 40", 0),
          ("A010_015: 0.10 < a <= 0.15, e > 0.6, S/N > 40", 1)]
THETA_BINS = [(1.5, 2.0), (2.0, 2.5), (2.5, 99.0)]
MAG_BINS = [(0.0, 22.0), (22.0, 23.0), (23.0, 99.0)]


def run_seed(octarc, seed, lenses, out):
    subprocess.run([octarc, "demo", "--seed", str(seed), "--lenses", str(lenses), "--out", out,
                    "--quiet"], check=True, stdout=subprocess.DEVNULL)
    systems = np.loadtxt(os.path.join(out, "injection-systems.txt"), ndmin=2)
    cands = np.loadtxt(os.path.join(out, "injection-candidates.txt"), ndmin=2)
    area = fits.getheader(os.path.join(out, "candidates", "candidates.fits"),
                          "LDAC_OBJECTS")["SRCHAREA"]
    return systems, cands.reshape(-1, 3), area


def in_space(spaces, bit):
    return np.ones(len(spaces), bool) if bit is None else ((spaces.astype(int) >> bit) & 1) == 1


def fraction(k, n):
    return "%d/%d (%.0f%%)" % (k, n, 100.0 * k / n) if n else "-"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--lenses", type=int, default=12)
    parser.add_argument("--octarc", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                         "release", "bin", "octarc"))
    args = parser.parse_args()
    systems, cands, area = [], [], 0.0
    with tempfile.TemporaryDirectory() as work:
        for seed in range(1, args.seeds + 1):
            s, c, a = run_seed(args.octarc, seed, args.lenses, os.path.join(work, str(seed)))
            systems.append(s)
            cands.append(c)
            area += a
            print("seed %d: %d systems, %d candidates" % (seed, len(s), len(c)), file=sys.stderr)
    systems = np.vstack(systems)
    cands = np.vstack(cands)
    theta, mag, found = systems[:, 1], systems[:, 2], systems[:, 3] > 0
    spaces, lens_right, estimate = systems[:, 4], systems[:, 5] == 1, systems[:, 6]
    print("%d seeds x %d injected lenses (theta_E >= 1.5\"), %.4f deg2 searched\n"
          % (args.seeds, args.lenses, area))
    header = ["search space"] + ["theta_E %g-%g\"" % b if b[1] < 99 else "theta_E > %g\"" % b[0]
                                 for b in THETA_BINS]
    header += ["arc mag < 22", "22-23", "> 23", "all", "spurious / deg2", "lens right",
               "theta_E est./true"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for name, bit in SPACES:
        got = found & in_space(spaces, bit)
        row = [name]
        for lo, hi in THETA_BINS:
            sel = (theta >= lo) & (theta < hi)
            row.append(fraction(got[sel].sum(), sel.sum()))
        for lo, hi in MAG_BINS:
            sel = (mag >= lo) & (mag < hi)
            row.append(fraction(got[sel].sum(), sel.sum()))
        row.append(fraction(got.sum(), len(got)))
        spurious = ((cands[:, 1] == 0) & in_space(cands[:, 2], bit)).sum()
        row.append("%.0f (%d)" % (spurious / area, spurious) if area > 0 else "-")
        row.append(fraction((got & lens_right).sum(), got.sum()))
        right = got & lens_right
        ratio = estimate[right] / theta[right]
        if len(ratio):
            q16, q50, q84 = np.percentile(ratio, [16, 50, 84])
            row.append("%.2f +- %.2f (%d)" % (q50, 0.5 * (q84 - q16), len(ratio)))
        else:
            row.append("-")
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
