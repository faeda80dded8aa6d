#!/usr/bin/python3
"""Completeness and purity of octarc's search, measured by injection, with the Python module
(`import octarc`): for several seeds, a simulated 2048^2 field with injected lenses
(octarc.simulate_field, as `octarc demo` makes it), searched as the demo searches it
(octarc.search with the shipped octarc.sex, the field's weight map, the demo grid or a lens
model), the candidates matched to the injected lenses (SearchResult.match_injections), and the
found lenses added up per search space.

    scripts/injection-study.py [--seeds 20] [--first-seed 1] [--lenses 12] [--trees]
                               [--model M.fits] [--python-dir build/release/python]
    scripts/injection-study.py --ntt [--seeds 20] [--lenses 6] [--snr-min 10] [--trees]

With --trees, every field is searched twice, with the grid (SELECTION_METHOD GRID) and with the
model (TREES), and the completeness is also given against the spurious candidates per deg2 as
LENS_SCORE's threshold falls ("Completeness against spurious candidates"): both methods in one
table.

--ntt injects into the real NTT/EMMI R frame of ../shared/data/real/ntt-emmi instead
(octarc.inject_lenses: its own sky, noise, objects and PSF). Its header has no WCS, gain or zero
point, so the study assumes 0.35"/px (EMMI red), 1.2" seeing (SExtractor's test configuration),
a gain of 1.7 e-/ADU (sky level over sky variance) and the zero point that gives the frame a
5-sigma limit of 26 mag in a 2 x FWHM aperture, as the demo's fields have; it first makes a
grid and a lens model for that setup (150 000 simulated lenses of the `dls` population the
fields inject, seed 11; the model trained against the frame's own objects). That calibration
is the one step run as commands (`octarc detect`, `octarc simulate lenses`, `octarc calibrate`,
with --octarc): the module has no calibration.

The module is imported from --python-dir when it is not installed. The figures are those
`octarc demo` gives for the same seeds (the same field, search and matching, in memory).

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

from injection_curves import threshold_at, wilson

# The report spaces of the default SEARCH_SPACE, by bit; "all" is the grid selection alone.
SPACES = [("probability selection alone", None), ("A015: a > 0.15, e > 0.6, S/N > 40", 0),
          ("A010_015: 0.10 < a <= 0.15, e > 0.6, S/N > 40", 1)]
THETA_BINS = [(1.5, 2.0), (2.0, 2.5), (2.5, 99.0)]
MAG_BINS = [(0.0, 22.0), (22.0, 23.0), (23.0, 99.0)]


HERE = os.path.dirname(os.path.abspath(__file__))
SHIPPED_MODEL = os.path.join(HERE, "..", "params", "demo.model.fits")
NTT_IMAGE = os.path.join(HERE, "..", "..", "shared", "data", "real", "ntt-emmi", "galaxies.fits")
NTT_SCALE, NTT_SEEING, NTT_GAIN, LIMIT_MAG = 0.35, 1.2, 1.7, 26.0
# The demo's field and search (src/app/DemoCommand.cpp, search/InjectionDemo.h).
FIELD_SIZE, FIELD_SCALE, FIELD_SEEING, FIELD_ZERO, FIELD_GAIN = 2048, 0.257, 0.9, 30.0, 54.0
MIN_EINSTEIN_RADIUS = 1.5


def import_octarc(python_dir):
    """The octarc module: installed, else the one built in python_dir."""
    try:
        import octarc
    except ImportError:
        sys.path.insert(0, os.path.abspath(python_dir))
        import octarc
    return octarc


def ntt_setup(octarc, command, work, snr_min):
    """The NTT frame's sky sigma (octarc's own background estimate), the zero point of a 26 mag
    5-sigma limit, and a grid and a lens model for that setup (the model trained against the
    frame's own objects, rows above snr_min). Returns the frame's settings and the paths of the
    grid and the model."""
    image = fits.getdata(NTT_IMAGE)
    sigma = octarc.detect(image, 1.5, config={"PIXEL_SCALE": NTT_SCALE}).sigma
    aperture = np.pi * (NTT_SEEING / NTT_SCALE) ** 2  # diameter 2 x FWHM
    zero_point = LIMIT_MAG + 2.5 * np.log10(5 * sigma * np.sqrt(aperture))
    # The frame's own objects, detected and measured as the search does (the shipped octarc.sex,
    # 15 levels): the other rows the model is trained against.
    catalog = os.path.join(work, "ntt.ldac")
    subprocess.run([command, "detect", NTT_IMAGE, "-c", "octarc.sex", "-CATALOG_TYPE",
                    "FITS_LDAC", "-CATALOG_NAME", catalog, "-PIXEL_SCALE", str(NTT_SCALE),
                    "-SEEING_FWHM", str(NTT_SEEING), "-GAIN", str(NTT_GAIN), "-MAG_ZEROPOINT",
                    "%.4f" % zero_point], check=True, capture_output=True)
    sim, grid = os.path.join(work, "ntt-sim.fits"), os.path.join(work, "ntt.grid.fits")
    subprocess.run([command, "simulate", "lenses", "-n", "150000", "--seed", "11", "--preset",
                    "dls", "--pixel-scale", str(NTT_SCALE), "--seeing", str(NTT_SEEING),
                    "--gain", str(NTT_GAIN), "--zero-point", "%.4f" % zero_point, "--sky-sigma",
                    "%.4f" % sigma, "-o", sim, "--quiet"], check=True)
    model = os.path.join(work, "ntt.model.fits")
    subprocess.run([command, "calibrate", sim, "-GRID_AXES", "ARCNESS,E_IMAGE,log10(SNR_ISO)",
                    "-NOISE_STUDY", "N", "-CHECKPLOT_TYPE", "NONE", "-CALIBRATION_NAME",
                    os.path.join(work, "ntt-cal.fits"), "-GRID_NAME", grid, "-SURVEY_CATALOG",
                    catalog, "-MODEL_NAME", model, "-MODEL_SNR_MIN", str(snr_min)], check=True,
                   stdout=subprocess.DEVNULL, cwd=work)
    print("NTT frame: sky sigma %.2f ADU, zero point %.2f" % (sigma, zero_point), file=sys.stderr)
    # The demo's keys come out of "%.4f" % zero_point when it is given on its command line.
    setup = {"pixel_scale": NTT_SCALE, "seeing": NTT_SEEING, "gain": NTT_GAIN,
             "mag_zero": float("%.4f" % zero_point)}
    return setup, grid, model


def make_field(octarc, seed, lenses, ntt):
    """The seed's field with its injected lenses, as `octarc demo` makes it (with --into for the
    NTT frame)."""
    if ntt is None:
        return octarc.simulate_field(FIELD_SIZE, seed=seed, lenses=lenses,
                                     min_einstein_radius=MIN_EINSTEIN_RADIUS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the frame's ESO-LOG cards are not standard FITS
        header = fits.getheader(NTT_IMAGE)
    return octarc.inject_lenses(fits.getdata(NTT_IMAGE), header=header, lenses=lenses, seed=seed,
                                min_einstein_radius=MIN_EINSTEIN_RADIUS, **ntt)


def search_field(octarc, field, lenses, selector, snr_min, ntt):
    """The demo's search of the field, every candidate kept (SCORE_MIN 0, so that the curve runs
    down to the lowest score); the prior of LENS_SCORE is the injected lenses' density over the
    image, as the demo sets it."""
    setup = ntt or {"pixel_scale": FIELD_SCALE, "seeing": FIELD_SEEING, "mag_zero": FIELD_ZERO,
                    "gain": FIELD_GAIN}
    height, width = field.image.shape
    field_deg2 = width * height * (setup["pixel_scale"] / 3600.0) ** 2
    config = {"LENS_DENSITY": "%.10g" % (lenses / field_deg2), "SCORE_MIN": 0,
              "PIXEL_SCALE": "%.10g" % setup["pixel_scale"],
              "SEEING_FWHM": "%.10g" % setup["seeing"],
              "MAG_ZEROPOINT": "%.10g" % setup["mag_zero"], "GAIN": "%.10g" % setup["gain"],
              "SNR_MIN": "%.10g" % snr_min}
    # As the demo: a real image without a weight map is searched with a uniform one.
    weight = np.ones_like(field.image) if field.weight is None else field.weight
    return octarc.search(field.image, weight=weight, wcs=field.header, config_file="octarc.sex",
                         config=config, **selector)


def run_seed(octarc, field, lenses, selector, snr_min, ntt):
    """Per injected system: system, theta_E, arc magnitude, candidate (1-based, 0: not found),
    spaces, lens right, theta_E estimate, and the candidate's LENS_SCORE (-1 when not found);
    per candidate: its number, system (0: spurious), spaces and LENS_SCORE; the searched area."""
    found = search_field(octarc, field, lenses, selector, snr_min, ntt)
    matched, candidate_system = found.match_injections(field.truth)
    table = found.to_table(["NUMBER", "SPACES", "LENS_SCORE"])
    cands = np.column_stack([table["NUMBER"], candidate_system, table["SPACES"],
                             table["LENS_SCORE"]]).astype(float).reshape(-1, 4)
    candidate = np.asarray(matched["CANDIDATE"])
    score = np.where(candidate >= 0, np.asarray(table["LENS_SCORE"])[np.maximum(candidate, 0)]
                     if len(table) else -1.0, -1.0)
    systems = np.column_stack([matched["SYSTEM"], matched["THETA_E"], matched["ARC_MAG"],
                               candidate + 1, matched["SPACES"], matched["LENS_RIGHT"],
                               matched["THETA_E_ESTIMATE"], score]).astype(float)
    return systems, cands, table.meta["SRCHAREA"]


def completeness_at(systems, cands, area, per_deg2):
    """Completeness when LENS_SCORE's threshold is the lowest that keeps the spurious candidates
    at most per_deg2 (None: every candidate)."""
    spurious_scores = cands[cands[:, 1] == 0, 3]
    threshold = threshold_at(spurious_scores, area, per_deg2)
    found = (systems[:, 7] >= threshold) & (systems[:, 3] > 0)
    spurious = (spurious_scores >= threshold).sum()
    return found.sum(), spurious


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
    parser.add_argument("--trees", action="store_true",
                        help="also search with a lens model (SELECTION_METHOD TREES): --model, "
                        "the shipped demo model, or with --ntt one trained for the frame")
    parser.add_argument("--model", help="the lens model of --trees on simulated fields")
    parser.add_argument("--lenses", type=int, default=None)
    parser.add_argument("--ntt", action="store_true", help="inject into the real NTT frame")
    parser.add_argument("--snr-min", type=float, default=40.0, help="the search's S/N floor")
    parser.add_argument("--python-dir", default=os.path.join(HERE, "..", "build", "release",
                                                             "python"),
                        help="where the octarc module was built (when it is not installed)")
    parser.add_argument("--octarc", default=os.path.join(HERE, "..", "build", "release", "bin",
                                                         "octarc"),
                        help="the octarc command, for the --ntt calibration")
    args = parser.parse_args()
    octarc = import_octarc(args.python_dir)
    if args.lenses is None:
        args.lenses = 6 if args.ntt else 12
    systems, cands, area = [], [], 0.0
    tree_systems, tree_cands = [], []
    with tempfile.TemporaryDirectory() as work:
        ntt, grid = None, "demo.grid.fits"
        if args.ntt:
            ntt, grid, ntt_model = ntt_setup(octarc, args.octarc, work, args.snr_min)
            if args.trees:
                args.model = ntt_model
        elif args.trees and not args.model:
            args.model = SHIPPED_MODEL
        grid = octarc.Grid.read(grid)
        model = octarc.Model.read(args.model) if args.trees else None
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            field = make_field(octarc, seed, args.lenses, ntt)
            s, c, a = run_seed(octarc, field, args.lenses, {"grid": grid}, args.snr_min, ntt)
            systems.append(s)
            cands.append(c)
            area += a
            print("seed %d: %d systems, %d candidates" % (seed, len(s), len(c)), file=sys.stderr)
            if args.trees:
                s, c, _ = run_seed(octarc, field, args.lenses, {"model": model}, args.snr_min,
                                   ntt)
                tree_systems.append(s)
                tree_cands.append(c)
    systems = np.vstack(systems)
    cands = np.vstack(cands)
    theta, mag, found = systems[:, 1], systems[:, 2], systems[:, 3] > 0
    spaces, lens_right, estimate = systems[:, 4], systems[:, 5] == 1, systems[:, 6]
    where = "the NTT/EMMI frame" if args.ntt else "simulated 2048^2 fields"
    print("%d seeds (%d-%d) x %d injected lenses (theta_E >= 1.5\") in %s, %.4f deg2 searched, "
          "SNR_MIN %g\n" % (args.seeds, args.first_seed, args.first_seed + args.seeds - 1,
                             args.lenses, where, area, args.snr_min))
    curves = [("GRID", systems, cands)]
    if args.trees:
        curves.append(("TREES", np.vstack(tree_systems), np.vstack(tree_cands)))
    levels = [30, 100, 400, 1000, None]
    print("Completeness against spurious candidates per deg2 (LENS_SCORE threshold lowered until "
          "the spurious candidates reach the density; 68% Wilson intervals):\n")
    print("| method | " + " | ".join("<= %d / deg2" % v if v else "every candidate"
                                    for v in levels) + " |")
    print("|---|" + "---|" * len(levels))
    for name, sy, ca in curves:
        row = [name]
        for v in levels:
            k, spurious = completeness_at(sy, ca, area, v)
            lo, hi = wilson(k, len(sy))
            row.append("%d/%d (%.0f%%, %.0f-%.0f%%) at %.0f" % (
                k, len(sy), 100.0 * k / len(sy), 100 * lo, 100 * hi, spurious / area))
        print("| " + " | ".join(row) + " |")
    print()
    # LENS_SCORE reads as the expected fraction of lens arcs among rows of that score (for the
    # prior the demo sets: its injected lens density): the candidates binned by score, their mean
    # score against the fraction that are injected arcs.
    print("LENS_SCORE against the fraction of candidates that are injected arcs:\n")
    print("| method | LENS_SCORE | candidates | mean LENS_SCORE | injected arcs |")
    print("|---|---|---|---|---|")
    for name, _, ca in curves:
        for lo, hi in [(0.0, 0.01), (0.01, 0.1), (0.1, 0.5), (0.5, 1.01)]:
            sel = (ca[:, 3] >= lo) & (ca[:, 3] < hi)
            if not sel.any():
                continue
            arcs = (ca[sel, 1] > 0).sum()
            print("| %s | %g-%g | %d | %.3f | %d (%.3f) |" % (
                name, lo, min(hi, 1.0), sel.sum(), ca[sel, 3].mean(), arcs, arcs / sel.sum()))
    print()
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
