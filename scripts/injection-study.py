#!/usr/bin/python3
"""Completeness and purity of `octarc search`, measured by injection: runs `octarc demo` (a
simulated 2048^2 field with injected lenses, searched with the shipped demo grid) for several
seeds and adds up, per search space, which injected lenses came back as candidates.

    scripts/injection-study.py [--seeds 20] [--first-seed 1] [--lenses 12]
                               [--octarc build/release/bin/octarc]
    scripts/injection-study.py --ntt [--seeds 20] [--lenses 6] [--snr-min 10]

--ntt injects into the real NTT/EMMI R frame of ../shared/data/real/ntt-emmi instead (its own
sky, noise, objects and PSF). Its header has no WCS, gain or zero point, so the study assumes
0.35"/px (EMMI red), 1.2" seeing (SExtractor's test configuration), a gain of 1.7 e-/ADU (sky
level over sky variance) and the zero point that gives the frame a 5-sigma limit of 26 mag in
a 2 x FWHM aperture, as the demo's fields have; it first makes a grid for that setup (40 000
simulated lenses of the `dls` population the fields inject, seed 11, about 3 minutes).

Prints the README table (Markdown): completeness against theta_E and arc magnitude, spurious
candidates per deg2 (candidates that are no injected arc), the fraction of found lenses whose
lens galaxy is named right (within 1"), and, for those, the theta_E estimate against the truth
(median ratio, and the scatter as half the 16-84% range)."""
import argparse
import os
import subprocess
import sys
import tempfile
import warnings

import numpy as np
from astropy.io import fits

# The report spaces of the default SEARCH_SPACE, by bit; "all" is the grid selection alone.
SPACES = [("probability selection alone", None), ("A015: a > 0.15, e > 0.6, S/N > 40", 0),
          ("A010_015: 0.10 < a <= 0.15, e > 0.6, S/N > 40", 1)]
THETA_BINS = [(1.5, 2.0), (2.0, 2.5), (2.5, 99.0)]
MAG_BINS = [(0.0, 22.0), (22.0, 23.0), (23.0, 99.0)]


NTT_IMAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data",
                         "real", "ntt-emmi", "galaxies.fits")
NTT_SCALE, NTT_SEEING, NTT_GAIN, LIMIT_MAG = 0.35, 1.2, 1.7, 26.0


def ntt_setup(octarc, work):
    """The NTT frame's sky sigma (octarc's own background estimate), the zero point of a 26 mag
    5-sigma limit, and a grid for that setup. Returns the demo options and the grid path."""
    catalog = os.path.join(work, "ntt.ldac")
    proc = subprocess.run([octarc, "detect", NTT_IMAGE, "-CATALOG_NAME", catalog, "-PIXEL_SCALE",
                           str(NTT_SCALE)], check=True, capture_output=True, text=True)
    import re
    sigma = float(re.search(r"sigma ([\d.eE+-]+) ADU", proc.stderr).group(1))
    aperture = np.pi * (NTT_SEEING / NTT_SCALE) ** 2  # diameter 2 x FWHM
    zero_point = LIMIT_MAG + 2.5 * np.log10(5 * sigma * np.sqrt(aperture))
    sim, grid = os.path.join(work, "ntt-sim.fits"), os.path.join(work, "ntt.grid.fits")
    subprocess.run([octarc, "simulate", "lenses", "-n", "40000", "--seed", "11", "--preset", "dls",
                    "--pixel-scale", str(NTT_SCALE), "--seeing", str(NTT_SEEING), "--gain",
                    str(NTT_GAIN), "--zero-point", "%.4f" % zero_point, "--sky-sigma",
                    "%.4f" % sigma, "-o", sim, "--quiet"], check=True)
    subprocess.run([octarc, "calibrate", sim, "-GRID_AXES", "ARCNESS,E_IMAGE,log10(SNR_ISO)",
                    "-NOISE_STUDY", "N", "-CHECKPLOT_TYPE", "NONE", "-CALIBRATION_NAME",
                    os.path.join(work, "ntt-cal.fits"), "-GRID_NAME", grid], check=True,
                   stdout=subprocess.DEVNULL, cwd=work)
    print("NTT frame: sky sigma %.2f ADU, zero point %.2f" % (sigma, zero_point), file=sys.stderr)
    return ["--into", NTT_IMAGE, "--pixel-scale", str(NTT_SCALE), "--seeing", str(NTT_SEEING),
            "--gain", str(NTT_GAIN), "--mag-zero", "%.4f" % zero_point, "--grid", grid]


def run_seed(octarc, seed, lenses, out, extra):
    subprocess.run([octarc, "demo", "--seed", str(seed), "--lenses", str(lenses), "--out", out,
                    "--quiet", *extra], check=True, stdout=subprocess.DEVNULL)
    systems = np.loadtxt(os.path.join(out, "injection-systems.txt"), ndmin=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a field without candidates
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
    parser.add_argument("--first-seed", type=int, default=1,
                        help="the first seed (the README's figures are from seeds 1-20; tune "
                        "on others)")
    parser.add_argument("--lenses", type=int, default=None)
    parser.add_argument("--ntt", action="store_true", help="inject into the real NTT frame")
    parser.add_argument("--snr-min", type=float, default=40.0, help="the search's S/N floor")
    parser.add_argument("--octarc", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                         "release", "bin", "octarc"))
    args = parser.parse_args()
    if args.lenses is None:
        args.lenses = 6 if args.ntt else 12
    systems, cands, area = [], [], 0.0
    with tempfile.TemporaryDirectory() as work:
        extra = (ntt_setup(args.octarc, work) if args.ntt else []) + ["--snr-min",
                                                                      str(args.snr_min)]
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            s, c, a = run_seed(args.octarc, seed, args.lenses, os.path.join(work, str(seed)),
                               extra)
            systems.append(s)
            cands.append(c)
            area += a
            print("seed %d: %d systems, %d candidates" % (seed, len(s), len(c)), file=sys.stderr)
    systems = np.vstack(systems)
    cands = np.vstack(cands)
    theta, mag, found = systems[:, 1], systems[:, 2], systems[:, 3] > 0
    spaces, lens_right, estimate = systems[:, 4], systems[:, 5] == 1, systems[:, 6]
    where = "the NTT/EMMI frame" if args.ntt else "simulated 2048^2 fields"
    print("%d seeds (%d-%d) x %d injected lenses (theta_E >= 1.5\") in %s, %.4f deg2 searched, "
          "SNR_MIN %g\n" % (args.seeds, args.first_seed, args.first_seed + args.seeds - 1,
                             args.lenses, where, area, args.snr_min))
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
        right = got & lens_right & (estimate > 0)
        ratio = estimate[right] / theta[right]
        if len(ratio):
            q16, q50, q84 = np.percentile(ratio, [16, 50, 84])
            row.append("%.2f +- %.2f (%d)" % (q50, 0.5 * (q84 - q16), len(ratio)))
        else:
            row.append("-")
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
