#!/usr/bin/python3
"""The README's built-in completeness study: `octarc inject` on several simulated survey fields,
its curves added up over the fields.

    scripts/inject-study.py [--seeds 20] [--first-seed 401] [--lenses 12] [--size 2048]
                            [--set KEY=VALUE]... [--lens-mag-offset 0]
                            [--octarc build/release/bin/octarc]

For each seed it simulates a field without lenses (`octarc simulate field`, the demo's setup:
0.257"/px, 0.9" seeing, zero point 30, gain 54) and runs `octarc inject` on it with the shipped
octarc.sex, the field's weight map, the demo grid and the demo model, so that both selection
methods are measured on the same injections. The fields' lists (each run's candidates.txt and
injected.truth.txt) are then pooled: a lens's score is the highest LENS_SCORE among its
candidates in the injected image, the spurious candidates are those of the fields as they are,
and the threshold is lowered until they reach each density per deg2 of all the fields' area.
Prints the Markdown table of the README ("Completeness by injection, built in").

--set KEY=VALUE adds `-KEY VALUE` to the inject command (e.g. LENS_LIGHT=LOCAL, SNR_MIN=20),
after the study's own keys. --lens-mag-offset D injects the same
lenses with their light D magnitudes fainter (a copy of the dls population with
lens.fj.abs_mag_star, lens.mag_min and lens.mag_max moved by D, so that the same systems are
drawn): with D = 10 the lenses are dark, and the completeness over every candidate is what a
perfect removal of the lens light would leave to the selection."""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

from injection_curves import threshold_at, wilson

HERE = os.path.dirname(os.path.abspath(__file__))
PARAMS = os.path.join(HERE, "..", "params")
SCALE = 0.257
DENSITIES = [30, 100, 400, 1000, None]


def read_field(folder):
    """Per method: the spurious scores (the field as it is) and each injected system's best
    score (-inf when no candidate is one of its arcs); and the number of systems."""
    rows = []
    with open(os.path.join(folder, "candidates.txt")) as f:
        for line in f:
            if not line.startswith("#") and line.strip():
                method, image, _, _, score, system = line.split()
                rows.append((method, image, float(score), int(system)))
    truth = np.loadtxt(os.path.join(folder, "injected.truth.txt"), ndmin=2)
    systems = sorted(set(truth[:, 0].astype(int)))
    out = {}
    for method in sorted({r[0] for r in rows} | {"GRID", "TREES"}):
        spurious = [s for m, i, s, _ in rows if m == method and i == "PLAIN"]
        best = {k: -np.inf for k in systems}
        for m, i, s, k in rows:
            if m == method and i == "INJECTED" and k > 0:
                best[k] = max(best[k], s)
        out[method] = (np.array(spurious), np.array([best[k] for k in systems]))
    return out, len(systems)


def completeness_at(spurious, best, area_deg2, per_deg2):
    """Found lenses and spurious candidates at the lowest threshold that keeps the spurious
    candidates at most per_deg2 (None: every candidate)."""
    threshold = threshold_at(spurious, area_deg2, per_deg2)
    # Lenses never found have a best score of -inf: not found at any threshold.
    found = int((np.isfinite(best) & (best >= threshold)).sum())
    return found, int((np.asarray(spurious) >= threshold).sum())


def shifted_population(path, offset_mag):
    """The dls population with every lens `offset_mag` fainter, written to `path`."""
    keys = ("lens.fj.abs_mag_star", "lens.mag_min", "lens.mag_max")
    lines = []
    with open(os.path.join(PARAMS, "simulation", "population-dls.txt")) as f:
        for line in f:
            key = line.split("=")[0].strip()
            if key in keys:
                value = float(line.split("=")[1].split("#")[0]) + offset_mag
                line = "%s = %.6g\n" % (key, value)
            lines.append(line)
    with open(path, "w") as f:
        f.writelines(lines)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=401)
    parser.add_argument("--lenses", type=int, default=12)
    parser.add_argument("--size", type=int, default=2048)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--lens-mag-offset", type=float, default=0.0)
    parser.add_argument("--octarc", default=os.path.join(HERE, "..", "build", "release", "bin",
                                                         "octarc"))
    args = parser.parse_args()
    pooled = {}
    systems = 0
    area_deg2 = 0.0
    with tempfile.TemporaryDirectory() as work:
        extra = []
        for setting in args.set:
            key, _, value = setting.partition("=")
            extra += ["-" + key, value]
        if args.lens_mag_offset != 0:
            extra += ["-INJECT_POPULATION",
                      shifted_population(os.path.join(work, "population.txt"),
                                         args.lens_mag_offset)]
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            field = os.path.join(work, "f%d.fits" % seed)
            subprocess.run([args.octarc, "simulate", "field", "-o", field, "--size",
                            str(args.size), "--seed", str(seed)], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            folder = os.path.join(work, "i%d" % seed)
            subprocess.run([args.octarc, "inject", field, "-c", os.path.join(PARAMS, "octarc.sex"),
                            "-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE",
                            field.replace(".fits", ".weight.fits"),
                            "-GRID_NAME", os.path.join(PARAMS, "demo.grid.fits"),
                            "-MODEL_NAME", os.path.join(PARAMS, "demo.model.fits"),
                            "-INJECT_NUMBER", str(args.lenses), "-INJECT_SEED", str(seed),
                            "-INJECT_DIR", folder, "-SEEING_FWHM", "0.9", "-MAG_ZEROPOINT", "30",
                            "-GAIN", "54", *extra], check=True, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
            field_lists, n = read_field(folder)
            systems += n
            area_deg2 += (args.size * SCALE / 3600.0) ** 2
            for method, (spurious, best) in field_lists.items():
                s, b = pooled.get(method, (np.array([]), np.array([])))
                pooled[method] = (np.concatenate([s, spurious]), np.concatenate([b, best]))
            print("seed %d: %d lenses" % (seed, n), file=sys.stderr)
    print("%d seeds (%d-%d) x %d injected lenses (theta_E >= 1.5\") in %dx%d fields, %.4f deg2, "
          "%s, lens light %+g mag\n"
          % (args.seeds, args.first_seed, args.first_seed + args.seeds - 1, args.lenses,
             args.size, args.size, area_deg2, " ".join(args.set) or "no key set",
             args.lens_mag_offset))
    print("| method | " + " | ".join("<= %d / deg2" % v if v else "every candidate"
                                    for v in DENSITIES) + " |")
    print("|---|" + "---|" * len(DENSITIES))
    for method, (spurious, best) in sorted(pooled.items()):
        row = [method]
        for v in DENSITIES:
            k, n_spurious = completeness_at(spurious, best, area_deg2, v)
            lo, hi = wilson(k, systems)
            row.append("%d/%d (%.0f%%, %.0f-%.0f%%) at %.0f" % (
                k, systems, 100.0 * k / systems, 100 * lo, 100 * hi, n_spurious / area_deg2))
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
