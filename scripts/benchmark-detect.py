#!/usr/bin/python3
"""Benchmark: the paper's way to get a 15-level catalog (15 consecutive source-extractor runs,
each writing its catalog and segmentation map) against one `octarc detect` run with 15 levels.

Usage: /usr/bin/python3 scripts/benchmark-detect.py [--octarc PATH] [--workdir DIR]
                                                    [--sizes 4096,10000] [--repeats N]
                                                    [--octarc-runs N] [--sex-pixstack N]
                                                    [--no-sync]
Generates reproducible synthetic fields (seeded), runs both ways on the same file in the same
run, and prints a Markdown table (wall time, CPU time, peak memory, objects) for the README.
Every command starts after a sync (not with --no-sync); the octarc figures are those of the
median of --octarc-runs runs (default 5), the source-extractor figures the sum of its 15 runs.
Both must find the same number of objects at every level (octarc's rows per THRESH_LEVEL
against the rows of each source-extractor run): the script stops with an error naming the
levels that differ.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from astropy.io import fits

LEVELS = 15
T_MIN, T_MAX = 2.5, 20.0   # sigma
SEED = 42


def make_field(path, size, n_sources, seed):
    """Sky 100 ADU + Gaussian noise (sigma 5) + elliptical Gaussian sources (sigma 1-3 px,
    flux 1e2-1e5 ADU log-uniform), float32, GAIN 1.5."""
    rng = np.random.default_rng(seed)
    image = rng.normal(100.0, 5.0, (size, size)).astype(np.float32)
    xs = rng.uniform(0, size, n_sources)
    ys = rng.uniform(0, size, n_sources)
    sig = rng.uniform(1.0, 3.0, n_sources)
    q = rng.uniform(0.3, 1.0, n_sources)
    th = rng.uniform(0, np.pi, n_sources)
    flux = 10 ** rng.uniform(2, 5, n_sources)
    for x0, y0, s, qq, t, f in zip(xs, ys, sig, q, th, flux):
        r = int(np.ceil(5 * s))
        x1, x2 = max(int(x0) - r, 0), min(int(x0) + r + 1, size)
        y1, y2 = max(int(y0) - r, 0), min(int(y0) + r + 1, size)
        yy, xx = np.mgrid[y1:y2, x1:x2]
        dx, dy = xx - x0, yy - y0
        u = dx * np.cos(t) + dy * np.sin(t)
        v = -dx * np.sin(t) + dy * np.cos(t)
        g = np.exp(-0.5 * (u * u / (s * s) + v * v / (s * s * qq * qq)))
        image[y1:y2, x1:x2] += (f * g / (2 * np.pi * s * s * qq)).astype(np.float32)
    hdr = fits.Header()
    hdr["GAIN"] = 1.5
    fits.PrimaryHDU(image, hdr).writeto(path, overwrite=True)


def timed(cmd, cwd, sync=True):
    """Runs cmd; returns (wall s, user+sys s, peak RSS MiB). Dirty pages left by the previous
    command (segmentation maps, catalogs) are flushed first (unless sync is False), so that no
    command pays for the write-back of another one."""
    if sync:
        os.sync()
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    err = proc.stderr.read().decode()
    if status != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), err))
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


PARAMS = ["NUMBER", "X_IMAGE", "Y_IMAGE", "X2_IMAGE", "Y2_IMAGE", "XY_IMAGE", "A_IMAGE", "B_IMAGE",
          "THETA_IMAGE", "ISOAREA_IMAGE", "FLUX_ISO", "FLUXERR_ISO", "FLUX_MAX", "FLAGS"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--octarc", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                     "release", "bin", "octarc"))
    ap.add_argument("--workdir", default=None)
    ap.add_argument("--sizes", default="4096,10000")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--octarc-runs", type=int, default=5,
                    help="octarc runs per measurement; the median run is reported")
    ap.add_argument("--sex-pixstack", type=int, default=30000000,
                    help="source-extractor's MEMORY_PIXSTACK (it allocates and clears the whole "
                         "stack at every run: enough for a 10000^2 field by default)")
    ap.add_argument("--no-sync", action="store_true",
                    help="do not flush the disks before each command (for checking the object "
                         "counts only: the times are then not comparable)")
    args = ap.parse_args()
    sync = not args.no_sync
    octarc = os.path.abspath(args.octarc)
    work = args.workdir or tempfile.mkdtemp(prefix="octarc-bench-")
    os.makedirs(work, exist_ok=True)
    sex_param = os.path.join(work, "sex.param")
    open(sex_param, "w").write("\n".join(PARAMS) + "\n")
    # Every octarc column (all of -dp but the ASSOC ones).
    dp = subprocess.run([octarc, "detect", "-dp"], capture_output=True, text=True, check=True)
    names = [l[1:].split()[0] for l in dp.stdout.splitlines()
             if l.startswith("#") and "ASSOC" not in l]
    octarc_param = os.path.join(work, "octarc.param")
    open(octarc_param, "w").write("\n".join(names) + "\n")
    thresholds = [T_MIN * (T_MAX / T_MIN) ** (k / (LEVELS - 1)) for k in range(LEVELS)]
    common = ["-FILTER", "N", "-DETECT_MINAREA", "5", "-THRESH_TYPE", "RELATIVE",
              "-BACK_TYPE", "AUTO", "-BACK_SIZE", "64", "-BACK_FILTERSIZE", "3",
              "-VERBOSE_TYPE", "QUIET"]

    rows = []
    for size in [int(s) for s in args.sizes.split(",")]:
        image = os.path.join(work, "field%d.fits" % size)
        n_sources = int(20000 * (size / 4096.0) ** 2)
        if not os.path.exists(image):
            make_field(image, size, n_sources, SEED + size)
        mpix = size * size / 1e6
        for _ in range(args.repeats):
            # The paper's way: one SExtractor run per threshold, catalog + segmentation each.
            wall = cpu = rss = 0.0
            for k, t in enumerate(thresholds):
                w, c, r = timed(["source-extractor", image, "-c", "/usr/share/source-extractor/default.sex",
                                 "-PARAMETERS_NAME", sex_param, "-CATALOG_TYPE", "FITS_LDAC",
                                 "-CATALOG_NAME", os.path.join(work, "sex%d.ldac" % k),
                                 "-DETECT_THRESH", "%.6f" % t, "-ANALYSIS_THRESH", "%.6f" % t,
                                 "-DEBLEND_NTHRESH", "1", "-CLEAN", "N", "-MASK_TYPE", "NONE",
                                 "-MEMORY_PIXSTACK", str(args.sex_pixstack), "-MEMORY_OBJSTACK", "65000",
                                 "-CHECKIMAGE_TYPE", "SEGMENTATION",
                                 "-CHECKIMAGE_NAME", os.path.join(work, "sex%d.seg.fits" % k),
                                 "-WRITE_XML", "N"] + common, work, sync)
                wall, cpu, rss = wall + w, cpu + c, max(rss, r)
            sex_per_level = [len(fits.getdata(os.path.join(work, "sex%d.ldac" % k), 2))
                             for k in range(LEVELS)]
            n_sex = sum(sex_per_level)
            rows.append((size, "15 x source-extractor (catalog + segmentation)", wall, cpu, rss, n_sex))
            base = wall
            for label, extra in [("octarc detect, 15 levels, all columns", []),
                                 ("octarc detect, 15 levels, all columns + segmentation",
                                  ["-CHECKIMAGE_TYPE", "SEGMENTATION", "-CHECKIMAGE_NAME",
                                   os.path.join(work, "octarc.seg.fits")])]:
                out = os.path.join(work, "octarc.ldac")
                runs = sorted(timed([octarc, "detect", image, "-PARAMETERS_NAME", octarc_param,
                                     "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
                                     "-DETECT_THRESH", str(T_MIN), "-DETECT_THRESH_MAX",
                                     str(T_MAX), "-DETECT_NLEVELS", str(LEVELS)] + common + extra,
                                    work, sync) for _ in range(max(1, args.octarc_runs)))
                w, c, r = runs[len(runs) // 2]
                levels = fits.getdata(out, 2)["THRESH_LEVEL"]
                per_level = [int(np.sum(levels == k + 1)) for k in range(LEVELS)]
                if per_level != sex_per_level:
                    sys.exit("%d^2, %s: objects per level differ from source-extractor's: %s" % (
                        size, label, ", ".join("level %d: %d vs %d" % (k + 1, a, b) for k, (a, b)
                                               in enumerate(zip(per_level, sex_per_level))
                                               if a != b)))
                rows.append((size, label, w, c, r, len(levels), base / w))
        image_mib = size * size * 4 / 2**20
        print("image %d x %d: %.0f MiB as float32, %d sources injected" % (size, size, image_mib,
                                                                          n_sources), file=sys.stderr)

    print("| image | method | wall (s) | CPU (s) | peak RSS (MiB) | rows | speed-up |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        speed = "%.1f×" % r[6] if len(r) > 6 else ""
        print("| %d² | %s | %.2f | %.2f | %.0f | %d | %s |" % (r[0], r[1], r[2], r[3], r[4], r[5], speed))


if __name__ == "__main__":
    main()
