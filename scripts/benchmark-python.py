#!/usr/bin/python3
"""Benchmark: three ways to get a 15-level catalog of the benchmark field (the synthetic 4096^2
field of scripts/benchmark-detect.py, made by its make_field with its seed and number of
sources): `octarc.detect` in Python on the numpy array, `sep.extract` called once per threshold
on the same array, and one `octarc detect` command on the FITS file.

Usage: /usr/bin/python3 scripts/benchmark-python.py make-field DIR
       /usr/bin/python3 scripts/benchmark-python.py module DIR [--nthreads N]
       /usr/bin/python3 scripts/benchmark-python.py sep DIR
       /usr/bin/python3 scripts/benchmark-python.py command DIR [--octarc PATH] [--nthreads N]
                                                        [--segmentation]
       /usr/bin/python3 scripts/benchmark-python.py check DIR [--octarc PATH]
make-field writes DIR/field.fits, DIR/field.npy (the same float32 pixels) and DIR/field.json
(the seed, the number of sources, the GAIN and the 15 thresholds), once. Each of module, sep
and command is one whole process, to be timed from outside (`/usr/bin/time -v`); it prints the
time of the work alone (time.perf_counter around the detection: the imports and the reading of
the .npy are left out; for command, the octarc process alone, not the reading of its catalog
that counts the rows per level afterwards) and the objects per level. check runs the three once
and stops with an error if octarc.detect's objects per level differ from the command's rows per
THRESH_LEVEL (or, these being equal, if a few of their columns are not identical), or if SEP's
differ from them by more than 1% at a level (smaller differences are printed: SEP's background
estimate is not exactly SExtractor's).

The levels are benchmark-detect.py's: LEVELS thresholds from T_MIN to T_MAX sigma, spaced
geometrically as DETECT_THRESH / DETECT_THRESH_MAX / DETECT_NLEVELS space them, which the
command is given (octarc.detect gets the same numbers as a list). The settings are those of
benchmark-detect.py: no filtering (kernel=None, FILTER N), DETECT_MINAREA 5, mesh background
(64 px meshes, 3x3 median filter), thresholds relative to the global noise sigma, no
deblending. octarc.detect measures every column and keeps the 15 segmentations; the command
writes a FITS_LDAC catalog of every column (all of `octarc detect -dp` but ASSOC) to a
temporary directory, and, with --segmentation, the 15-level SEGMENTATION check-image too. SEP:
sep.Background, subtracted, then sep.extract at each threshold times bkg.globalrms with
filter_kernel=None, minarea=5, deblend_cont=1.0 and deblend_nthresh=1 (no deblending, as
benchmark-detect.py's source-extractor runs: DEBLEND_NTHRESH 1), clean=False (CLEAN N) and
segmentation_map=True; the 15 catalogs and segmentation maps are all kept until the end. SEP
runs on one core; octarc uses every core unless --nthreads is given.
"""
import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DETECT_SCRIPT = os.path.join(HERE, "benchmark-detect.py")
SIZE = 4096
MINAREA = 5
SEP_PIXSTACK = 1000000   # enough for this field (SEP stops with an error if not)


def load_detect_script():
    """scripts/benchmark-detect.py as a module (its main() is not run)."""
    spec = importlib.util.spec_from_file_location("benchmark_detect", DETECT_SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def paths(work):
    return {k: os.path.join(work, "field." + k) for k in ("fits", "npy", "json")}


def read_setup(work):
    with open(paths(work)["json"]) as f:
        return json.load(f)


def make_field(work):
    """DIR/field.fits by benchmark-detect.py's make_field, its pixels as DIR/field.npy, and
    DIR/field.json."""
    import numpy as np
    from astropy.io import fits

    bd = load_detect_script()
    os.makedirs(work, exist_ok=True)
    p = paths(work)
    # As benchmark-detect.py does for a field of this size.
    seed = bd.SEED + SIZE
    n_sources = int(20000 * (SIZE / 4096.0) ** 2)
    bd.make_field(p["fits"], SIZE, n_sources, seed)
    with fits.open(p["fits"]) as hdul:
        image = np.ascontiguousarray(hdul[0].data, dtype=np.float32)
        gain = float(hdul[0].header["GAIN"])
    np.save(p["npy"], image)
    thresholds = [bd.T_MIN * (bd.T_MAX / bd.T_MIN) ** (k / (bd.LEVELS - 1))
                  for k in range(bd.LEVELS)]
    setup = {"size": SIZE, "seed": seed, "n_sources": n_sources, "gain": gain,
             "levels": bd.LEVELS, "t_min": bd.T_MIN, "t_max": bd.T_MAX,
             "thresholds": thresholds}
    with open(p["json"], "w") as f:
        json.dump(setup, f, indent=1)
        f.write("\n")
    print("%s: %d x %d, %d sources, seed %d; thresholds (sigma): %s"
          % (p["fits"], SIZE, SIZE, n_sources, seed, " ".join("%.4f" % t for t in thresholds)))


def load_image(work):
    import numpy as np
    return np.load(paths(work)["npy"])


def run_module(image, setup, nthreads=None):
    """octarc.detect on the array; returns (seconds, objects per level, result)."""
    import octarc
    config = {"GAIN": setup["gain"]}
    if nthreads is not None:
        config["NTHREADS"] = nthreads
    t0 = time.perf_counter()
    found = octarc.detect(image, setup["thresholds"], minarea=MINAREA, kernel=None,
                          thresh_type="RELATIVE", segmentation=True, config=config)
    seconds = time.perf_counter() - t0
    return seconds, [int(n) for n in found.objects_per_level], found


def run_sep(image, setup):
    """sep.Background, subtraction and one sep.extract per threshold; returns (seconds, objects
    per level, global RMS)."""
    import sep
    sep.set_extract_pixstack(SEP_PIXSTACK)
    t0 = time.perf_counter()
    bkg = sep.Background(image, bw=64, bh=64, fw=3, fh=3)
    data = image - bkg
    rms = bkg.globalrms
    kept = []
    for t in setup["thresholds"]:
        kept.append(sep.extract(data, t, err=rms, minarea=MINAREA, filter_kernel=None,
                                deblend_nthresh=1, deblend_cont=1.0, clean=False,
                                segmentation_map=True))
    seconds = time.perf_counter() - t0
    return seconds, [len(objects) for objects, _ in kept], rms


def octarc_param(octarc, work):
    """DIR/octarc.param: every column of `octarc detect -dp` but the ASSOC ones (made once)."""
    path = os.path.join(work, "octarc.param")
    if not os.path.exists(path):
        dp = subprocess.run([octarc, "detect", "-dp"], capture_output=True, text=True,
                            check=True)
        names = [line[1:].split()[0] for line in dp.stdout.splitlines()
                 if line.startswith("#") and "ASSOC" not in line]
        with open(path, "w") as f:
            f.write("\n".join(names) + "\n")
    return path


def run_command(octarc, work, setup, nthreads=None, segmentation=False):
    """One `octarc detect` with the levels; returns (seconds, rows per THRESH_LEVEL, catalog
    table)."""
    param = octarc_param(octarc, work)
    with tempfile.TemporaryDirectory(prefix="octarc-bench-") as tmp:
        catalog = os.path.join(tmp, "field.ldac")
        cmd = [octarc, "detect", paths(work)["fits"], "-PARAMETERS_NAME", param,
               "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", catalog,
               "-DETECT_THRESH", repr(setup["t_min"]), "-DETECT_THRESH_MAX",
               repr(setup["t_max"]), "-DETECT_NLEVELS", str(setup["levels"]),
               "-FILTER", "N", "-DETECT_MINAREA", str(MINAREA), "-THRESH_TYPE", "RELATIVE",
               "-BACK_TYPE", "AUTO", "-BACK_SIZE", "64", "-BACK_FILTERSIZE", "3",
               "-VERBOSE_TYPE", "QUIET"]
        if nthreads is not None:
            cmd += ["-NTHREADS", str(nthreads)]
        if segmentation:
            cmd += ["-CHECKIMAGE_TYPE", "SEGMENTATION", "-CHECKIMAGE_NAME",
                    os.path.join(tmp, "field.seg.fits")]
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        seconds = time.perf_counter() - t0
        if proc.returncode != 0:
            sys.exit("failed: %s\n%s" % (" ".join(cmd), proc.stderr.decode()))
        import numpy as np
        from astropy.io import fits
        table = fits.getdata(catalog, 2)
        levels = np.asarray(table["THRESH_LEVEL"])
        per_level = [int(np.sum(levels == k + 1)) for k in range(setup["levels"])]
        return seconds, per_level, table


def report(label, seconds, per_level):
    print("%s: %.3f s (in-process), %d objects; per level: %s"
          % (label, seconds, sum(per_level), " ".join(str(n) for n in per_level)))


def check(work, octarc):
    import numpy as np
    setup = read_setup(work)
    image = load_image(work)
    t_mod, mod, found = run_module(image, setup)
    report("octarc.detect", t_mod, mod)
    t_sep, sep_counts, rms = run_sep(image, setup)
    report("sep.extract x%d" % len(sep_counts), t_sep, sep_counts)
    t_cmd, cmd, table = run_command(octarc, work, setup)
    report("octarc detect", t_cmd, cmd)
    print("noise sigma: octarc %.6f ADU, SEP globalrms %.6f ADU" % (found.sigma, rms))
    errors = []
    if mod != cmd:
        errors.append("octarc.detect's objects per level differ from the command's rows per "
                      "THRESH_LEVEL: " + ", ".join("level %d: %d vs %d" % (k + 1, a, b)
                                                   for k, (a, b) in enumerate(zip(mod, cmd))
                                                   if a != b))
    else:
        print("octarc.detect and octarc detect: the same objects per level at all %d levels"
              % len(mod))
    if len(table) == len(found.column("NUMBER")):
        for name in ("X_IMAGE", "Y_IMAGE", "FLUX_ISO", "ISOAREA_IMAGE"):
            if not np.array_equal(np.asarray(table[name]), found.column(name), equal_nan=True):
                errors.append("column %s differs between octarc.detect and the command" % name)
        if not errors:
            print("octarc.detect and octarc detect: X_IMAGE, Y_IMAGE, FLUX_ISO, ISOAREA_IMAGE "
                  "identical")
    print("level  sigma     octarc   SEP   difference")
    for k, (t, a, b) in enumerate(zip(setup["thresholds"], cmd, sep_counts)):
        rel = (b - a) / a if a else (0.0 if b == 0 else float("inf"))
        print("%5d  %7.4f  %6d  %6d  %+5d (%+.2f%%)" % (k + 1, t, a, b, b - a, 100 * rel))
        if abs(rel) > 0.01:
            errors.append("level %d: SEP finds %d objects, octarc %d (more than 1%% apart)"
                          % (k + 1, b, a))
    if errors:
        sys.exit("\n".join(errors))
    print("check passed")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=["make-field", "module", "sep", "command", "check"])
    ap.add_argument("dir")
    ap.add_argument("--octarc", default=os.path.join(HERE, "..", "build", "release", "bin",
                                                     "octarc"))
    ap.add_argument("--nthreads", type=int, default=None,
                    help="octarc's NTHREADS for module and command (default: every core)")
    ap.add_argument("--segmentation", action="store_true",
                    help="command: also write the SEGMENTATION check-image")
    args = ap.parse_args()
    work = os.path.abspath(args.dir)
    octarc = os.path.abspath(args.octarc)
    if args.what == "make-field":
        make_field(work)
    elif args.what == "check":
        check(work, octarc)
    else:
        setup = read_setup(work)
        if args.what == "command":
            seconds, per_level, _ = run_command(octarc, work, setup, args.nthreads,
                                                args.segmentation)
            report("octarc detect", seconds, per_level)
        else:
            image = load_image(work)
            if args.what == "module":
                seconds, per_level, _ = run_module(image, setup, args.nthreads)
                report("octarc.detect", seconds, per_level)
            else:
                seconds, per_level, _ = run_sep(image, setup)
                report("sep.extract x%d" % len(per_level), seconds, per_level)


if __name__ == "__main__":
    main()
