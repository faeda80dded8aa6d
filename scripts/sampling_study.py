#!/usr/bin/python3
"""Importance-sampled against plain lens simulations: do the weights give the plain figures?

Runs `octarc simulate lenses` twice on the same setup, once with `--sampling plain` (every drawn
system rendered, weight 1) and once with `--sampling importance` (each system rendered with a
probability r, weight SIM_WEIGHT = 1 / r), or reads two outputs made that way, and compares the
figures of the population that both estimate, each with its 1-sigma error:

  - the Table-1 lensing fractions (METHOD.md section 3: of the systems with an arc, those whose
    chosen arc has ARCNESS in 0.05-0.10, 0.10-0.15, > 0.15, each also with E_IMAGE > 0.6 and
    SNR_ISO > 40);
  - the arc rate per drawn system;
  - the medians of the chosen arcs' ARCNESS, E_IMAGE and SNR_ISO.

Errors: a fraction f of n rows takes the half-width of the Wilson score interval at z = 1,
sqrt(f (1 - f) n + 1/4) / (n + 1) (binomial for large n, not 0 for 0 of n), with n Kish's
effective number (sum w)^2 / sum w^2 for weighted rows; the weighted arc rate sum(w y) / N over N
drawn systems has variance (sum(w^2 y) / N - rate^2) / N; medians (weighted medians for the
importance run) take the standard deviation of 300 bootstrap resamples of the arcs. The pull of
each figure is its difference over the combined error sqrt(sigma_plain^2 + sigma_weighted^2).

With the same seed the importance run renders a subset of the plain run's systems, identical to
them (the render decision has a random stream of its own): the comparison then isolates the
sampling by the render probabilities, and the combined error, which treats the runs as
independent, is an upper bound of the error of the difference. With different seeds the runs
are independent. As a control the script also gives the importance run's figures without the
weights, which are biased towards the systems the sampling favours.

    scripts/sampling_study.py --octarc build/release/bin/octarc -n 150000 --seed 31
    scripts/sampling_study.py --plain plain.fits --importance importance.fits
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
from astropy.io import fits

ARCNESS_BINS = [(0.05, 0.10), (0.10, 0.15), (0.15, math.inf)]
ELLIP_MIN, SNR_MIN = 0.6, 40.0


def read(path):
    """The systems table (rendered systems), its weights and the number of systems drawn."""
    with fits.open(path) as hdus:
        systems = hdus["LDAC_OBJECTS"].data
        cards = hdus["LDAC_IMHEAD"].data[0][0]
        header = fits.Header.fromstring("".join(c.ljust(80) for c in cards))
        drawn = int(header["OCTNSYS"])
        weights = np.asarray(systems["SIM_WEIGHT"], float)
        columns = {name: np.asarray(systems[name], float)
                   for name in ("ARC_FOUND", "ARCNESS", "E_IMAGE", "SNR_ISO")}
    return columns, weights, drawn


def weighted_fraction(y, w):
    """sum(w y) / sum(w) and its 1-sigma error: the half-width of the Wilson score interval at
    z = 1 for Kish's effective number n = sum(w)^2 / sum(w^2) of the rows (n itself for a plain
    run), so that 0 of n has an error too."""
    total = w.sum()
    if total <= 0:
        return math.nan, math.nan
    f = float((w * y).sum() / total)
    n = float(total ** 2 / (w * w).sum())
    return f, math.sqrt(f * (1.0 - f) * n + 0.25) / (n + 1.0)


def weighted_median(values, w):
    order = np.argsort(values)
    cumulative = np.cumsum(w[order])
    return float(values[order][np.searchsorted(cumulative, 0.5 * cumulative[-1])])


def bootstrap_median_sigma(values, w, rng, repeats=300):
    n = len(values)
    medians = [weighted_median(values[i], w[i])
               for i in (rng.integers(0, n, n) for _ in range(repeats))]
    return float(np.std(medians, ddof=1))


def figures(columns, weights, drawn, seed=12345):
    """Every compared figure as {name: (value, sigma)}; `weights` of ones for a plain run."""
    rng = np.random.default_rng(seed)
    arc = columns["ARC_FOUND"] == 1
    w = weights[arc]
    a, e, snr = (columns[k][arc] for k in ("ARCNESS", "E_IMAGE", "SNR_ISO"))
    out = {}
    for lo, hi in ARCNESS_BINS:
        in_bin = (a >= lo) & (a < hi)
        label = "%.2f-%.2f" % (lo, hi) if math.isfinite(hi) else "> %.2f" % lo
        out["fraction " + label] = weighted_fraction(in_bin.astype(float), w)
        bright = in_bin & (e > ELLIP_MIN) & (snr > SNR_MIN)
        out["fraction %s, e > 0.6, S/N > 40" % label] = weighted_fraction(bright.astype(float), w)
    rate = float(w.sum() / drawn)
    out["arcs per drawn system"] = (rate, math.sqrt(max((w * w).sum() / drawn - rate ** 2, 0.0)
                                                    / drawn))
    for name, values in (("ARCNESS", a), ("E_IMAGE", e), ("SNR_ISO", snr)):
        out["median " + name] = (weighted_median(values, w),
                                 bootstrap_median_sigma(values, w, rng))
    return out


def effective(weights, found):
    w = weights[found == 1]
    return float(w.sum() ** 2 / (w * w).sum()) if len(w) else 0.0


def compare(plain_path, importance_path):
    """Rows (name, plain, sigma, weighted, sigma, pull, unweighted) and a summary dict."""
    p_cols, p_w, p_drawn = read(plain_path)
    i_cols, i_w, i_drawn = read(importance_path)
    plain = figures(p_cols, p_w, p_drawn)
    weighted = figures(i_cols, i_w, i_drawn)
    unweighted = figures(i_cols, np.ones_like(i_w), i_drawn)
    rows = []
    for name in plain:
        (pv, ps), (wv, ws) = plain[name], weighted[name]
        combined = math.hypot(ps, ws)
        pull = (wv - pv) / combined if combined > 0 else math.nan
        rows.append((name, pv, ps, wv, ws, pull, unweighted[name][0],
                     (unweighted[name][0] - pv) / combined if combined > 0 else math.nan))
    summary = {"plain arcs": int((p_cols["ARC_FOUND"] == 1).sum()), "plain drawn": p_drawn,
               "plain rendered": len(p_w),
               "importance arcs": int((i_cols["ARC_FOUND"] == 1).sum()),
               "importance effective arcs": effective(i_w, i_cols["ARC_FOUND"]),
               "importance drawn": i_drawn, "importance rendered": len(i_w)}
    return rows, summary


def print_table(rows, summary, out=sys.stdout):
    out.write("plain: %(plain drawn)d drawn, %(plain rendered)d rendered, %(plain arcs)d arcs; "
              "importance: %(importance drawn)d drawn, %(importance rendered)d rendered, "
              "%(importance arcs)d arcs (%(importance effective arcs).1f effective)\n\n" % summary)
    out.write("| figure | plain | importance, weighted | pull | importance, unweighted | pull |\n")
    out.write("|---|---|---|---|---|---|\n")
    for name, pv, ps, wv, ws, pull, uv, upull in rows:
        out.write("| %s | %.4f ± %.4f | %.4f ± %.4f | %+.2f | %.4f | %+.2f |\n"
                  % (name, pv, ps, wv, ws, pull, uv, upull))


def simulate(octarc, n, seed, sampling, path, extra):
    subprocess.run([octarc, "simulate", "lenses", "-n", str(n), "--seed", str(seed), "--preset",
                    "dls", "--sampling", sampling, "-o", path, "--timing"] + extra, check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--octarc", default="build/release/bin/octarc")
    parser.add_argument("-n", type=int, default=150000, help="systems drawn in each run")
    parser.add_argument("--seed", type=int, default=31, help="seed of the plain run")
    parser.add_argument("--importance-seed", type=int, help="seed of the importance run "
                        "(default: the plain run's, a paired comparison)")
    parser.add_argument("--plain", help="an existing plain output instead of simulating")
    parser.add_argument("--importance", help="an existing importance-sampled output")
    parser.add_argument("--keep", help="folder to keep the simulated outputs in")
    args = parser.parse_args()
    folder = args.keep or tempfile.mkdtemp(prefix="octarc-sampling-")
    os.makedirs(folder, exist_ok=True)
    plain = args.plain or os.path.join(folder, "plain.fits")
    importance = args.importance or os.path.join(folder, "importance.fits")
    if not args.plain:
        simulate(args.octarc, args.n, args.seed, "plain", plain, [])
    if not args.importance:
        simulate(args.octarc, args.n, args.importance_seed or args.seed, "importance",
                 importance, [])
    rows, summary = compare(plain, importance)
    print_table(rows, summary)
    worst = max(abs(r[5]) for r in rows)
    print("\nlargest |pull| of the weighted figures: %.2f" % worst)
    return 0


if __name__ == "__main__":
    sys.exit(main())
