#!/usr/bin/python3
"""What lens-light subtraction gains: injects lens systems around bright lenses into simulated
fields and searches each field twice with `octarc demo`, without (`--lens-light N`) and with
(`--lens-light LOCAL`) subtraction, over several seeds.

    scripts/lens-light-study.py [--seeds 8] [--lenses 12] [--mode LOCAL]
                                [--octarc build/release/bin/octarc]

The injected lenses are those of the shipped dls population (params/simulation/
population-dls.txt) with the lens window moved to bright galaxies: 17 < R < 20 and
100 < sigma_v < 500 km/s (lens.mag_min, lens.mag_max, lens.sigma_min_km_s, lens.sigma_max_km_s),
and 1" < theta_E < 3" (--min-einstein-radius, --max-einstein-radius). Everything else (field,
grid, search space, SNR_MIN 40) is the demo's.

Prints the README table (Markdown): completeness against theta_E and lens magnitude without and
with subtraction, how many of the found lenses came from the residual (CAND_FLAGS 16), and the
candidates that are no injected arc per deg2 in each run. A field takes about ten seconds
either way on two threads, most of it the simulation."""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import warnings

import numpy as np
from astropy.io import fits

HERE = os.path.dirname(os.path.abspath(__file__))
POPULATION = os.path.join(HERE, "..", "params", "simulation", "population-dls.txt")
BRIGHT_LENSES = {"lens.mag_min": "17.0", "lens.mag_max": "20.0", "lens.sigma_min_km_s": "100.0",
                 "lens.sigma_max_km_s": "500.0"}
THETA_BINS = [(1.0, 1.5), (1.5, 2.0), (2.0, 3.0)]
CANDIDATE_LENS_LIGHT = 16  # CAND_FLAGS bit of a candidate found in the residual


def bright_population(path):
    """The dls population with the bright-lens window, written to path."""
    text = open(POPULATION).read()
    for key, value in BRIGHT_LENSES.items():
        text, count = re.subn(r"^%s\s*=.*$" % re.escape(key), "%s = %s" % (key, value), text,
                              flags=re.M)
        if count != 1:
            sys.exit("%s: key %s not found once" % (POPULATION, key))
    with open(path, "w") as out:
        out.write(text)


def run_field(octarc, seed, lenses, population, mode, out):
    """One demo run. Returns the systems table, the candidates table (number, system, spaces,
    flags) and the searched area in deg2."""
    subprocess.run([octarc, "demo", "--seed", str(seed), "--lenses", str(lenses), "--out", out,
                    "--population", population, "--min-einstein-radius", "1",
                    "--max-einstein-radius", "3", "--lens-light", mode, "--method", "GRID",
                    "--quiet"], check=True,
                   stdout=subprocess.DEVNULL)
    systems = np.loadtxt(os.path.join(out, "injection-systems.txt"), ndmin=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a field without candidates
        cands = np.loadtxt(os.path.join(out, "injection-candidates.txt"), ndmin=2).reshape(-1, 3)
    with fits.open(os.path.join(out, "candidates", "candidates.fits")) as hdus:
        table = hdus["LDAC_OBJECTS"].data
        area = hdus["LDAC_OBJECTS"].header["SRCHAREA"]
        flags_of = dict(zip(table["NUMBER"].astype(int), table["CAND_FLAGS"].astype(int)))
    flags = np.array([flags_of[int(n)] for n in cands[:, 0]], int).reshape(-1, 1)
    return systems, np.hstack([cands, flags]), area


def lens_magnitudes(out):
    """The injected lenses' magnitudes, by system number, from the field's truth list (columns
    ID X Y ALPHA DELTA KIND MAG THETA_E SYSTEM; KIND 1 is a lens galaxy)."""
    truth = np.loadtxt(os.path.join(out, "field.truth.txt"), ndmin=2)
    lenses = truth[truth[:, 5] == 1]
    return {int(system): mag for mag, system in zip(lenses[:, 6], lenses[:, 8])}


def fraction(k, n):
    return "%d/%d (%.0f%%)" % (k, n, 100.0 * k / n) if n else "-"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--lenses", type=int, default=12)
    parser.add_argument("--mode", default="LOCAL", choices=["LOCAL", "IMAGE"])
    parser.add_argument("--octarc", default=os.path.join(HERE, "..", "build", "release", "bin",
                                                         "octarc"))
    args = parser.parse_args()
    runs = {"N": [], args.mode: []}
    lens_mag = []
    with tempfile.TemporaryDirectory() as work:
        population = os.path.join(work, "bright.txt")
        bright_population(population)
        for seed in range(1, args.seeds + 1):
            for mode in runs:
                out = os.path.join(work, "%s-%d" % (mode, seed))
                runs[mode].append(run_field(args.octarc, seed, args.lenses, population, mode, out))
                if mode == "N":
                    mags = lens_magnitudes(out)
                    lens_mag.append([mags[int(s)] for s in runs[mode][-1][0][:, 0]])
            found_without = (runs["N"][-1][0][:, 3] > 0).sum()
            found_with = (runs[args.mode][-1][0][:, 3] > 0).sum()
            print("seed %d: found %d without, %d with subtraction" %
                  (seed, found_without, found_with), file=sys.stderr)
    lens_mag = np.concatenate(lens_mag)
    area = sum(r[2] for r in runs["N"])
    theta = np.vstack([r[0] for r in runs["N"]])[:, 1]
    mag_bins = [(17.0, 18.0), (18.0, 19.0), (19.0, 20.0)]
    print("%d seeds x %d injected lenses (17 < R_lens < 20, 1\" < theta_E < 3\") in simulated "
          "2048^2 fields, %.4f deg2 searched, SNR_MIN 40\n" % (args.seeds, args.lenses, area))
    header = ["LENS_LIGHT"] + ["theta_E %g-%g\"" % b for b in THETA_BINS]
    header += ["R_lens %g-%g" % b for b in mag_bins]
    header += ["all", "found in the residual", "no injected arc / deg2"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for mode, results in runs.items():
        systems = np.vstack([r[0] for r in results])
        cands = np.vstack([r[1] for r in results])
        found = systems[:, 3] > 0
        # The candidate that found each system, to tell those found in the residual.
        via_residual = 0
        for s, c in ((r[0], r[1]) for r in results):
            flag_of = {int(n): int(f) for n, f in zip(c[:, 0], c[:, 3])}
            via_residual += sum(1 for k in s[:, 3] if k > 0 and
                                flag_of[int(k)] & CANDIDATE_LENS_LIGHT)
        row = [mode]
        for lo, hi in THETA_BINS:
            sel = (theta >= lo) & (theta < hi)
            row.append(fraction(found[sel].sum(), sel.sum()))
        for lo, hi in mag_bins:
            sel = (lens_mag >= lo) & (lens_mag < hi)
            row.append(fraction(found[sel].sum(), sel.sum()))
        row.append(fraction(found.sum(), len(found)))
        row.append(str(via_residual))
        no_arc = cands[:, 1] == 0
        spurious = no_arc.sum()
        residual_spurious = (no_arc & ((cands[:, 3].astype(int) & CANDIDATE_LENS_LIGHT) > 0)).sum()
        row.append("%.0f (%d; %d from the residual)" % (spurious / area, spurious,
                                                       residual_spurious))
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
