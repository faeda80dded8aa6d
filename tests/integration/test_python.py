"""The Python module (`import octarc`, issue 30): octarc.detect and octarc.measure on numpy
arrays against the `octarc detect` command on the same array written to FITS (every column, bit
for bit, and every level's segmentation), against source-extractor (one threshold, FILTER N,
no deblending) and SEP object by object; arrays read without a copy, the GIL released, Ctrl-C,
bad input as ValueError / OSError, and the example of docs/python.md.

ctest puts <build>/python on PYTHONPATH (the module just built)."""
import contextlib
import io
import math
import os
import re
import subprocess
import sys
import threading
import time
import tracemalloc
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (MISSING_PROGRAM, SEX_SHARE, SOURCE_DIR, WorkDirTest,
                            assert_one_line_error, interrupted_python, ldac_objects, run_octarc,
                            run_sextractor, write_param)
import octarc

LEVELS = [2.5, 5.0, 10.0]


def synthetic_image(size=384, sources=120, seed=30):
    """A float32 field: a sloped sky of 1000 ADU, Gaussian noise of 8 ADU and elliptical
    Gaussian sources with log-uniform fluxes (each drawn on a stamp of 41 x 41 pixels)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:size, 0:size]
    image = 1000.0 + 0.01 * xx - 0.005 * yy + rng.normal(0.0, 8.0, (size, size))
    half = 20
    sy, sx = np.mgrid[-half:half + 1, -half:half + 1]
    for _ in range(sources):
        x0, y0 = rng.uniform(0, size, 2)
        flux = 10.0 ** rng.uniform(2.5, 4.5)
        s = rng.uniform(0.8, 3.0)
        q = rng.uniform(0.4, 1.0)
        theta = rng.uniform(0, math.pi)
        ix, iy = int(x0), int(y0)
        dx, dy = sx + ix - x0, sy + iy - y0
        u = dx * math.cos(theta) + dy * math.sin(theta)
        v = (-dx * math.sin(theta) + dy * math.cos(theta)) / q
        profile = np.exp(-0.5 * (u * u + v * v) / (s * s))
        profile *= flux / profile.sum()
        x1, x2 = max(ix - half, 0), min(ix + half + 1, size)
        y1, y2 = max(iy - half, 0), min(iy + half + 1, size)
        image[y1:y2, x1:x2] += profile[y1 - (iy - half):y2 - (iy - half),
                                       x1 - (ix - half):x2 - (ix - half)]
    return image.astype(np.float32)


def same_bits(a, b):
    """Equal arrays, NaN included, compared as their bytes."""
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


class PythonVersusPeers(WorkDirTest):
    """octarc.detect equals `octarc detect` on the same array written to FITS: the same
    columns in the same order, every value bit for bit, and every level's segmentation. At one
    threshold with FILTER N it finds the objects of source-extractor in the pure-thresholding
    configuration (no deblending, no cleaning) and of sep.extract (deblend_cont 1, clean off),
    object by object."""

    def compare(self, image, command_args, **detect_args):
        found = octarc.detect(image, LEVELS, **detect_args)
        path = self.path("image.fits")
        fits.PrimaryHDU(image).writeto(path, overwrite=True)
        param = write_param(self.path("all.param"), found.column_names)
        out, seg = self.path("cli.ldac"), self.path("cli.seg.fits")
        run_octarc("detect", path, "-PARAMETERS_NAME", param, "-DETECT_LEVELS",
                   ",".join(repr(t) for t in LEVELS), "-THRESH_TYPE", "RELATIVE",
                   "-DETECT_MINAREA", "5", "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
                   "-CHECKIMAGE_TYPE", "SEGMENTATION", "-CHECKIMAGE_NAME", seg,
                   "-VERBOSE_TYPE", "QUIET", *command_args, cwd=self.work)
        rows, _ = ldac_objects(out)
        table = found.to_table()
        self.assertEqual(table.colnames, list(rows.columns.names))
        self.assertGreater(len(table), 100)
        for name in table.colnames:
            self.assertTrue(same_bits(np.asarray(table[name]),
                                      np.asarray(rows[name]).astype(table[name].dtype)), name)
        with fits.open(seg) as levels:
            for k in range(1, len(LEVELS) + 1):
                np.testing.assert_array_equal(found.segmentation(k), levels[k].data,
                                              err_msg="level %d" % k)
        return found

    def test_mesh_background_no_filter(self):
        found = self.compare(synthetic_image(), ["-FILTER", "N"])
        self.assertEqual(found.objects_per_level, [int(np.sum(found.column("THRESH_LEVEL") == k))
                                                   for k in (1, 2, 3)])

    def test_weights_and_kernel_file(self):
        # A weight map with bad pixels and FILTER Y: the thresholds follow the filtered
        # variance, the measurements the variance read again from the map.
        image = synthetic_image(seed=31)
        weights = np.ones_like(image)
        weights[:, :40] = 0.25
        weights[200:210, 100:140] = 0.0
        fits.PrimaryHDU(weights).writeto(self.path("weights.fits"))
        conv = os.path.join(SEX_SHARE, "default.conv")
        self.compare(image, ["-FILTER", "Y", "-FILTER_NAME", conv, "-WEIGHT_TYPE", "MAP_WEIGHT",
                             "-WEIGHT_IMAGE", self.path("weights.fits")],
                     weight=weights, kernel=conv)

    def test_constant_background_and_gain(self):
        image = synthetic_image(seed=32)
        self.compare(image, ["-FILTER", "N", "-BACK_TYPE", "MANUAL", "-BACK_VALUE", "1000",
                             "-GAIN", "4"],
                     background=1000.0, config={"GAIN": 4.0})


    THRESHOLD = 3.0

    def test_same_objects_as_sextractor_and_sep(self):
        image = synthetic_image(seed=33)
        found = octarc.detect(image, self.THRESHOLD)
        ours = found.to_table()
        labels = found.segmentation(1)
        path = self.path("image.fits")
        fits.PrimaryHDU(image).writeto(path)

        # Imported here: they bring scipy and sep, which the other cases do not need.
        from test_detect_vs_sextractor import assert_rows_agree, label_correspondence
        from test_measure_vs_sextractor import SEX_COLUMNS
        param = write_param(self.path("sex.param"), SEX_COLUMNS)
        cat, checks = run_sextractor(path, self.work, "sex", param, repr(self.THRESHOLD),
                                     ["-FILTER", "N", "-DETECT_MINAREA", "5", "-THRESH_TYPE",
                                      "RELATIVE", "-BACK_TYPE", "AUTO", "-BACK_SIZE", "64",
                                      "-BACK_FILTERSIZE", "3"], ["SEGMENTATION"])
        theirs, _ = ldac_objects(cat)
        mapping = label_correspondence(self, labels, fits.getdata(checks["SEGMENTATION"]),
                                       "source-extractor")
        assert_rows_agree(self, ours, theirs, mapping, "source-extractor")

        try:
            import sep
        except ImportError:
            raise unittest.SkipTest(MISSING_PROGRAM + " python3-sep (module sep)")
        background = sep.Background(image, bw=64, bh=64, fw=3, fh=3)
        self.assertEqual(np.float32(background.globalrms), np.float32(found.sigma))
        objects, seg = sep.extract(image - background.back(), self.THRESHOLD,
                                   err=background.globalrms, minarea=5, filter_kernel=None,
                                   deblend_cont=1.0, clean=False, segmentation_map=True)
        mapping = label_correspondence(self, labels, seg, "sep")
        row_of = {int(n): i for i, n in enumerate(ours["NUMBER"])}
        self.assertEqual(len(objects), len(ours))
        for number, sep_label in mapping.items():
            mine, other = ours[row_of[number]], objects[sep_label - 1]
            what = "object %d" % number
            self.assertEqual(mine["ISOAREA_IMAGE"], other["npix"], what)
            self.assertEqual(mine["XMIN_IMAGE"] - 1, other["xmin"], what)
            self.assertEqual(mine["YMAX_IMAGE"] - 1, other["ymax"], what)
            self.assertAlmostEqual(float(mine["X_IMAGE"]) - 1, other["x"], delta=1e-4, msg=what)
            self.assertAlmostEqual(float(mine["Y_IMAGE"]) - 1, other["y"], delta=1e-4, msg=what)
            self.assertLessEqual(abs(mine["FLUX_ISO"] - other["flux"]),
                                 1e-5 * abs(other["flux"]) + 1e-3, what)


class PythonArrays(unittest.TestCase):
    """Arrays read without a copy, the GIL released while octarc works, Ctrl-C."""

    def test_float32_read_without_a_copy(self):
        image = synthetic_image(size=512, seed=35)
        tracemalloc.start()
        try:
            found = octarc.detect(image, 3.0, segmentation=False)
            _, peak_float32 = tracemalloc.get_traced_memory()
            tracemalloc.reset_peak()
            converted = octarc.detect(image.astype(np.int32), 3.0, segmentation=False)
            _, peak_int32 = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        # numpy reports its buffers to tracemalloc: no image-sized array was made for float32.
        self.assertFalse(found.data_converted)
        self.assertIs(found.data, image)
        self.assertLess(peak_float32, image.nbytes / 4)
        self.assertTrue(converted.data_converted)
        self.assertGreaterEqual(peak_int32, image.nbytes)
        self.assertTrue(octarc.detect(image.astype(np.float64), 3.0).data_converted is False)
        self.assertTrue(octarc.detect(np.asfortranarray(image), 3.0).data_converted)
        self.assertTrue(octarc.detect(image.astype(">f4"), 3.0).data_converted)

    def test_gil_released(self):
        image = synthetic_image(size=1536, sources=300, seed=36)
        intervals = {}

        def work(tag):
            start = time.perf_counter()
            octarc.detect(image, np.geomspace(2.5, 20.0, 15), config={"NTHREADS": 1})
            intervals[tag] = (start, time.perf_counter())

        threads = [threading.Thread(target=work, args=(t,)) for t in "ab"]
        for t in threads:
            t.start()
        # A heartbeat of this thread: with the GIL held by a call for its whole duration, the
        # largest gap would be as long as the call.
        beats = [time.perf_counter()]
        while any(t.is_alive() for t in threads):
            beats.append(time.perf_counter())
        for t in threads:
            t.join()
        (a0, a1), (b0, b1) = intervals["a"], intervals["b"]
        overlap = min(a1, b1) - max(a0, b0)
        shortest = min(a1 - a0, b1 - b0)
        self.assertGreater(overlap, 0.5 * shortest, intervals)
        self.assertLess(max(np.diff(beats)), 0.5 * shortest)

    def test_ctrl_c_interrupts_a_call(self):
        # The KeyboardInterrupt must come out of the compiled call itself (octarc looks at
        # Python's signals while it works), not after it returned; the process then goes on.
        out = interrupted_python(
            self, "import numpy as np, octarc\n"
            "image = np.random.default_rng(1).standard_normal((3000, 3000), dtype='f4')",
            "octarc.detect(image, np.geomspace(1, 20, 15), config={'NTHREADS': 1})",
            "octarc.detect(image[:64, :64], 3.0).objects_per_level", 0.2)
        self.assertRegex(out, r"^interrupted in detect: raw = _octarc\._detect\(\n\[\d+\]\n$")

class PythonApi(WorkDirTest):
    """octarc.detect gives the same rows on any number of threads; octarc.measure on detect's
    own segmentation gives detect's rows, and with a catalog the catalog's rows with octarc's
    columns appended; bad input is a Python exception with octarc's one-line message, never a
    crash; the example of docs/python.md runs as it is; `python3 -m octarc --version`; every
    public name has a docstring."""

    def test_measure_equals_detect(self):
        image = synthetic_image(seed=34)
        found = octarc.detect(image, LEVELS)
        measured = octarc.measure(image, [found.segmentation(k) for k in (1, 2, 3)],
                                  thresholds=LEVELS)
        a, b = found.to_table(), measured.to_table()
        self.assertEqual(a.colnames, b.colnames)
        for name in a.colnames:
            self.assertTrue(same_bits(np.asarray(a[name]), np.asarray(b[name])), name)
        self.assertEqual(b["FLUX_ISO"].unit, a["FLUX_ISO"].unit)
        # The rows do not depend on the thread count.
        for threads in (1, 3):
            c = octarc.detect(image, LEVELS, config={"NTHREADS": threads}).to_table()
            for name in a.colnames:
                self.assertTrue(same_bits(np.asarray(a[name]), np.asarray(c[name])), name)

        one = octarc.detect(image, 3.0)
        catalog = one.to_table(["NUMBER", "X_IMAGE"])[::-1]
        catalog["MINE"] = np.arange(len(catalog))
        joined = octarc.measure(image, one.segmentation(), thresholds=3.0,
                                catalog=catalog).to_table(["NUMBER", "ARCNESS", "FLUX_ISO"])
        self.assertEqual(joined.colnames, ["NUMBER", "X_IMAGE", "MINE", "ARCNESS", "FLUX_ISO"])
        np.testing.assert_array_equal(joined["NUMBER"], catalog["NUMBER"])
        expected = one.to_table()[::-1]
        np.testing.assert_array_equal(joined["ARCNESS"], expected["ARCNESS"])

    def assert_raises(self, kind, pattern, call, *args, **kwargs):
        assert_one_line_error(self, kind, pattern, call, *args, **kwargs)

    def test_bad_input(self):
        image = synthetic_image(size=64, sources=3)
        detect = octarc.detect
        self.assert_raises(ValueError, r"^data: dtype complex64 is not a real number type$",
                           detect, image.astype(np.complex64))
        self.assert_raises(ValueError, r"^data: dtype <U1 is not a real number type$",
                           detect, np.array([["a"]]))
        self.assert_raises(ValueError, r"^data: a 2-D array is needed, not one of 1 dim",
                           detect, image.ravel())
        self.assert_raises(ValueError, r"^data: a 2-D array is needed, not one of 3 dim",
                           detect, image[None])
        self.assert_raises(ValueError, r"^data: the array is empty \(shape \(0, 5\)\)$",
                           detect, np.zeros((0, 5), dtype=np.float32))
        self.assert_raises(ValueError, r"^data: no finite pixel \(all NaN or Inf\)$",
                           detect, np.full((32, 32), np.nan, dtype=np.float32))
        self.assert_raises(ValueError, r"^data: no finite pixel outside the mask",
                           detect, image, mask=np.ones(image.shape, dtype=bool))
        self.assert_raises(ValueError, r"^weight: shape \(64, 32\) but data has shape \(64, 64\)$",
                           detect, image, weight=np.ones((64, 32), dtype=np.float32))
        self.assert_raises(ValueError, r"^mask: shape \(8, 8\) but data has shape",
                           detect, image, mask=np.zeros((8, 8), dtype=bool))
        self.assert_raises(ValueError, r"^weight: give either an error map or weights",
                           detect, image, error=np.ones_like(image), weight=np.ones_like(image))
        self.assert_raises(ValueError, r"DETECT_LEVELS", detect, image, [5.0, 2.0])
        self.assert_raises(ValueError, r"^error: the noise sigma must be a finite number > 0",
                           detect, image, error=-1.0)
        self.assert_raises(ValueError, r"BACK_SIZ", detect, image, config={"BACK_SIZ": 3})
        self.assert_raises(ValueError, r"^thresh_type: RELATIVE or ABSOLUTE", detect, image,
                           thresh_type="SIGMA")
        self.assert_raises(ValueError, r"^kernel: shape \(2, 2\) has an even side",
                           detect, image, kernel=np.ones((2, 2)))
        self.assert_raises(OSError, r"nothere\.conv", detect, image, kernel="nothere.conv")
        found = detect(image, 3.0)
        self.assert_raises(ValueError, r"^to_table: the table has no column NOPE$",
                           found.to_table, ["NUMBER", "NOPE"])
        self.assert_raises(ValueError, r"^segmentation: level 2 is not in 1\.\.1$",
                           found.segmentation, 2)
        self.assert_raises(ValueError, r"^segmentation\[0\]: not a 2-D array of the shape",
                           octarc.measure, image, np.zeros((8, 8), dtype=np.int32))
        self.assert_raises(ValueError, r"^thresholds: several segmentation levels",
                           octarc.measure, image, [found.segmentation(1)] * 2)


    def test_configuration_warnings(self):
        # A key octarc ignores is said, as the command says it, naming the key.
        image = synthetic_image(size=64, sources=3, seed=36)
        found = octarc.detect(image, 3.0, config={"DEBLEND_NTHRESH": 32})
        self.assertIn("config: DEBLEND_NTHRESH is ignored by octarc (setting it has no effect)",
                      found.warnings)
        self.assertEqual(octarc.detect(image, 3.0).warnings, [])

    def test_docs_example_runs(self):
        with open(os.path.join(SOURCE_DIR, "docs", "python.md")) as f:
            blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
        self.assertTrue(blocks)
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            # The blocks in order, as a reader runs them one after the other.
            namespace = {"__name__": "example"}
            for block in blocks:
                exec(compile(block, "docs/python.md", "exec"), namespace)
        self.assertRegex(printed.getvalue(), r"objects per level: \[\d+, \d+, \d+\]")
        # The simulations' example, and the search's: the summary line and the candidates'
        # table with its first row, the arc (drawn at x 120-200, y 150 +- 40, 1-based).
        self.assertRegex(printed.getvalue(), r"\d+ of 20 systems rendered")
        self.assertRegex(printed.getvalue(), r"\n2 objects \(\d+ rows at all levels\) searched")
        self.assertRegex(printed.getvalue(), r"NUMBER +LENS_SCORE +X_IMAGE +Y_IMAGE.*\n.*\n"
                                             r".*\n +1 +[0-9.e-]+ +(1[2-9]\d|20\d)\.\d+ ")

    def test_version(self):
        proc = subprocess.run([sys.executable, "-m", "octarc", "--version"],
                              capture_output=True, text=True, check=True)
        self.assertEqual(proc.stdout, "octarc version %s\n" % octarc.__version__)
        self.assertEqual(octarc.__version__,
                         run_octarc("-v").stdout.split()[-1])
        for name in octarc.__all__:
            self.assertTrue(getattr(octarc, name).__doc__, name)


if __name__ == "__main__":
    unittest.main()
