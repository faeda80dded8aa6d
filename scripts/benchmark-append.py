#!/usr/bin/python3
"""Benchmark of `octarc measure` appending its columns to a SExtractor catalog (APPEND_COLUMNS Y)
against the SExtractor run that made the catalog, and against writing a new catalog
(APPEND_COLUMNS N).

Usage: /usr/bin/python3 scripts/benchmark-append.py [--octarc PATH] [--workdir DIR] [--runs N]
                                                    [--large] [--shared DIR]
1. The real NTT/EMMI image (shared data, ntt-emmi/galaxies.fits): one pure-thresholding
   source-extractor run (FILTER N, DETECT_THRESH 1.15, DETECT_MINAREA 3, no deblending or
   cleaning) with the columns PSFEx and SCAMP read, VIGNET(35,35) among them, writing its
   FITS_LDAC catalog and segmentation map; then octarc measure with the shipped octarc.param on
   that segmentation map, appending to that catalog, and writing a new catalog.
2. With --large, the same on a 10000^2 field made by `octarc simulate field` (without VIGNET:
   its catalog would be several GB).
Every command starts after a sync; each figure is the median of --runs runs (default 5). Prints
a Markdown table for the README. Builds nothing: build build/release first.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

from astropy.io import fits

HERE = os.path.dirname(os.path.abspath(__file__))
SEX_COLUMNS = ["NUMBER", "X_IMAGE", "Y_IMAGE", "XWIN_IMAGE", "YWIN_IMAGE", "ERRAWIN_IMAGE",
               "ERRBWIN_IMAGE", "ERRTHETAWIN_IMAGE", "X_WORLD", "Y_WORLD", "ERRA_WORLD",
               "ERRB_WORLD", "ERRTHETA_WORLD", "FLUX_AUTO", "FLUXERR_AUTO", "MAG_AUTO",
               "MAGERR_AUTO", "FLUX_APER(1)", "FLUXERR_APER(1)", "FLUX_RADIUS", "ELONGATION",
               "SNR_WIN", "FLAGS"]
PURE = ["-FILTER", "N", "-DEBLEND_NTHRESH", "1", "-DEBLEND_MINCONT", "1.0", "-CLEAN", "N",
        "-MASK_TYPE", "NONE", "-BACK_TYPE", "AUTO", "-MEMORY_PIXSTACK", "30000000",
        "-MEMORY_OBJSTACK", "65000", "-MEMORY_BUFSIZE", "4096", "-VERBOSE_TYPE", "QUIET",
        "-WRITE_XML", "N", "-CATALOG_TYPE", "FITS_LDAC"]


def timed(cmd, cwd):
    """Runs cmd after a sync; returns (wall s, user+sys s, peak RSS MiB)."""
    os.sync()
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    err = proc.stderr.read().decode()
    if status != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), err))
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def median_run(cmd, cwd, runs):
    results = sorted(timed(cmd, cwd) for _ in range(max(1, runs)))
    return results[len(results) // 2]


def case(label, tag, image, columns, sex_extra, args, work, octarc, rows):
    param = os.path.join(work, tag + ".sex.param")
    open(param, "w").write("\n".join(columns) + "\n")
    cat = os.path.join(work, tag + ".ldac")
    seg = os.path.join(work, tag + ".seg.fits")
    sex = ["source-extractor", image, "-c", "/usr/share/source-extractor/default.sex",
           "-PARAMETERS_NAME", param, "-CATALOG_NAME", cat,
           "-CHECKIMAGE_TYPE", "SEGMENTATION", "-CHECKIMAGE_NAME", seg] + PURE + sex_extra
    base = median_run(sex, work, args.runs)
    with fits.open(cat) as f:
        n = len(f["LDAC_OBJECTS"].data)
    size_mb = os.path.getsize(cat) / 1e6
    rows.append((label, "source-extractor (catalog + segmentation)", base, n, size_mb, None))
    shipped = os.path.join(os.path.dirname(octarc), "..", "share", "octarc", "octarc.param")
    measure = [octarc, "measure", image, "-c", "/usr/share/source-extractor/default.sex",
               "-PARAMETERS_NAME", shipped, "-SEGMENTATION_NAME", seg, "-INPUT_CATALOG", cat,
               "-FILTER", "N", "-VERBOSE_TYPE", "QUIET"]
    for mode, out in (("Y", tag + ".appended.ldac"), ("N", tag + ".octarc.ldac")):
        out = os.path.join(work, out)
        r = median_run(measure + ["-APPEND_COLUMNS", mode, "-CATALOG_TYPE", "FITS_LDAC",
                                  "-CATALOG_NAME", out], work, args.runs)
        what = ("octarc measure, APPEND_COLUMNS Y (appended to that catalog)" if mode == "Y" else
                "octarc measure, APPEND_COLUMNS N (new catalog)")
        rows.append((label, what, r, n, os.path.getsize(out) / 1e6, r[0] / base[0]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--octarc", default=os.path.join(HERE, "..", "build", "release", "bin",
                                                     "octarc"))
    ap.add_argument("--workdir", default=None)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--large", action="store_true", help="also the 10000^2 simulated field")
    ap.add_argument("--shared", default=os.environ.get("OCTARC_SHARED_DIR",
                                                       os.path.join(HERE, "..", "..", "shared")))
    args = ap.parse_args()
    octarc = os.path.abspath(args.octarc)
    work = args.workdir or tempfile.mkdtemp(prefix="octarc-bench-append-")
    os.makedirs(work, exist_ok=True)
    rows = []
    ntt = os.path.join(args.shared, "data", "real", "ntt-emmi", "galaxies.fits")
    if not os.path.exists(ntt):
        sys.exit(ntt + ": the shared NTT/EMMI image is needed (set --shared)")
    case("NTT/EMMI 1024²", "ntt", ntt, SEX_COLUMNS + ["VIGNET(35,35)"],
         ["-DETECT_THRESH", "1.15", "-ANALYSIS_THRESH", "1.15", "-DETECT_MINAREA", "3"],
         args, work, octarc, rows)
    if args.large:
        field = os.path.join(work, "field10000.fits")
        if not os.path.exists(field):
            subprocess.run([octarc, "simulate", "field", "-o", field, "--size", "10000",
                            "--seed", "3", "--quiet"], check=True)
        case("simulated 10000²", "field", field, SEX_COLUMNS,
             ["-DETECT_THRESH", "2.5", "-ANALYSIS_THRESH", "2.5", "-DETECT_MINAREA", "5"],
             args, work, octarc, rows)

    print("| image | run | wall (s) | CPU (s) | peak RSS (MiB) | rows | catalog (MB) | "
          "wall / SExtractor's |")
    print("|---|---|---|---|---|---|---|---|")
    for label, what, (w, c, r), n, mb, ratio in rows:
        print("| %s | %s | %.2f | %.2f | %.0f | %d | %.0f | %s |" %
              (label, what, w, c, r, n, mb, "%.2f" % ratio if ratio is not None else ""))


if __name__ == "__main__":
    main()
