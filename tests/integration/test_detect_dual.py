"""Dual-image mode: `octarc detect DETECT.fits,MEASURE.fits` (and `octarc search`) detect on the
first image and measure on the second, as source-extractor does with the same syntax.

What source-extractor 2.25 does (checked by these tests): footprints, pixel positions and shapes
(X_IMAGE ... THETA_IMAGE, XPEAK, ISOAREAF_IMAGE) come from the detection image, with its own
background, noise and filter; photometry (FLUX_ISO, FLUXERR_ISO, FLUX_MAX, MAG_ISO), the
saturation flag and ISOAREA_IMAGE (pixels above the analysis threshold, t_k times the measurement
image's sigma) from the measurement image, with its own background and noise. SEXBKGND and
SEXBKDEV are the measurement image's, SEXTHLD the detection threshold, SEXATHLD the analysis
threshold on the measurement image, FITSFILE the measurement image. octarc's own columns (the
octopole moments) are measured on the measurement image's pixels over the detection footprints.

The measurement image is made in the test from the real NTT/EMMI frame: 0.6 times its pixels, a
different sky (a constant plus a gradient), extra Gaussian noise and a few Gaussian sources that
only it holds.
"""
import os
import subprocess
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (OCTARC, SEX_SHARE, WorkDirTest, card_text, fitsverify_errors,
                            ldac_imhead, ldac_objects, require_shared, run_octarc, run_sextractor,
                            write_param)
from test_detect_vs_sextractor import (BACKGROUND_ARGS, CONV, DETECT_NLEVELS, DETECT_THRESH,
                                       DETECT_THRESH_MAX, MINAREA, SEX_COLUMNS, assert_rows_agree,
                                       default_levels_sigma, label_correspondence)
from test_detect_weights import write_weight_map


def write_measurement_image(source, path, seed=7):
    """The modified measurement image of the NTT frame (see the module's docstring), with the
    frame's header (so its WCS, if any, is the same)."""
    with fits.open(source) as f:
        pixels = f[0].data.astype(np.float64)
        header = f[0].header.copy()
    rng = np.random.default_rng(seed)
    ny, nx = pixels.shape
    yy, xx = np.mgrid[0:ny, 0:nx]
    image = 0.6 * pixels + 300.0 + 0.02 * xx - 0.01 * yy + rng.normal(0.0, 4.0, pixels.shape)
    for _ in range(25):
        x0, y0 = rng.uniform(20, nx - 20), rng.uniform(20, ny - 20)
        s = rng.uniform(1.0, 3.0)
        image += rng.uniform(500, 20000) * np.exp(-0.5 * ((xx - x0) ** 2 + (yy - y0) ** 2) / s**2)
    for key in ("BZERO", "BSCALE", "BITPIX"):
        header.remove(key, ignore_missing=True)
    fits.PrimaryHDU(image.astype(np.float32), header=header).writeto(path, output_verify="silentfix")
    return path


def all_columns():
    """Every column octarc can write (`octarc detect -dp`), but the ASSOC ones."""
    text = subprocess.run([OCTARC, "detect", "-dp"], check=True, capture_output=True,
                          text=True).stdout
    names = [line[1:].split()[0] for line in text.splitlines() if line.startswith("#")]
    return [n for n in names if "ASSOC" not in n]


def octarc_detect(test, images, tag, columns, filter_on=True, extra=(), checks=("SEGMENTATION",)):
    param = write_param(test.path("%s.param" % tag), columns)
    out = test.path("%s.ldac" % tag)
    paths = {t: test.path("%s.%s.fits" % (tag, t.lower())) for t in checks}
    args = ["detect", *images, "-c", os.path.join(SEX_SHARE, "default.sex"),
            "-PARAMETERS_NAME", param, "-FILTER", "Y" if filter_on else "N", "-FILTER_NAME", CONV,
            "-DETECT_THRESH", DETECT_THRESH, "-DETECT_THRESH_MAX", DETECT_THRESH_MAX,
            "-DETECT_NLEVELS", DETECT_NLEVELS, "-DETECT_MINAREA", MINAREA,
            "-THRESH_TYPE", "RELATIVE", "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
            "-VERBOSE_TYPE", "QUIET", *BACKGROUND_ARGS, *extra]
    if checks:
        args += ["-CHECKIMAGE_TYPE", ",".join(checks),
                 "-CHECKIMAGE_NAME", ",".join(paths[t] for t in checks)]
    run_octarc(*args)
    return out, paths


class DetectDualImage(WorkDirTest):

    def setUp(self):
        super().setUp()
        self.detection = require_shared(self, "ntt-emmi", "galaxies.fits")
        self.measurement = write_measurement_image(self.detection, self.path("measure.fits"))

    def test_same_file_twice_equals_one_image(self):
        # Every column, every level, and the run's header cards: `IMAGE,IMAGE` is `IMAGE`.
        columns = ["THRESH_LEVEL", "PARENT_NUMBER"] + [
            c for c in all_columns() if c not in ("THRESH_LEVEL", "PARENT_NUMBER")]
        single, _ = octarc_detect(self, [self.detection], "single", columns, checks=())
        dual, _ = octarc_detect(self, [self.detection + "," + self.detection], "dual", columns,
                                checks=())
        ours, _ = ldac_objects(dual)
        reference, _ = ldac_objects(single)
        self.assertGreater(len(reference), 1000)
        self.assertEqual(ours.dtype.names, reference.dtype.names)
        for name in reference.dtype.names:
            np.testing.assert_array_equal(ours[name], reference[name], err_msg=name)
        head, reference_head = ldac_imhead(dual), ldac_imhead(single)
        for key in ("SEXBKGND", "SEXBKDEV", "SEXTHLD", "SEXATHLD", "FITSFILE", "OCTTH15"):
            self.assertEqual(card_text(head, key), card_text(reference_head, key), key)
        self.assertAlmostEqual(head["OCTDTDEV"] / reference_head["SEXBKDEV"], 1.0, places=11)

    def test_versus_sextractor_dual_image_run(self):
        # Each of the 15 levels against a source-extractor run DETECT,MEASURE at that threshold:
        # the same footprints, then the SExtractor columns matched row by row.
        self.compare(filter_on=True, octarc_extra=(), sex_extra=())

    def test_versus_sextractor_with_two_weight_maps(self):
        # WEIGHT_IMAGE w1,w2: the detection thresholds follow w1, FLUXERR_ISO and ISOAREA_IMAGE
        # the measurement image's w2 (a different map: the same field, one less bad stripe).
        shape = fits.getdata(self.detection).shape
        w1 = write_weight_map(self.path("w1.fits"), shape)
        w2 = self.path("w2.fits")
        weights = fits.getdata(w1)
        weights[500:510, :] = 1.0
        fits.PrimaryHDU((weights[:, ::-1] * 0.7).astype(np.float32)).writeto(w2)
        args = ["-WEIGHT_TYPE", "MAP_WEIGHT,MAP_WEIGHT", "-WEIGHT_IMAGE", w1 + "," + w2,
                "-GAIN", "4"]
        self.compare(filter_on=False, octarc_extra=args,
                     sex_extra=args + ["-INTERP_TYPE", "NONE"], skip=("THRESHOLD",),
                     weight_scales=True)

    def compare(self, filter_on, octarc_extra, sex_extra, skip=(), weight_scales=False):
        columns = ["THRESH_LEVEL", "PARENT_NUMBER"] + SEX_COLUMNS
        out, checks = octarc_detect(self, [self.detection + "," + self.measurement], "octarc",
                                    columns, filter_on, octarc_extra)
        ours, _ = ldac_objects(out)
        imhead = ldac_imhead(out)
        self.assertEqual(imhead["FITSFILE"], "measure.fits")
        param = write_param(self.path("sex.param"), SEX_COLUMNS)
        extra = ["-FILTER", "Y" if filter_on else "N", "-DETECT_MINAREA", str(MINAREA),
                 "-THRESH_TYPE", "RELATIVE"] + BACKGROUND_ARGS + list(sex_extra)
        total = 0
        with fits.open(checks["SEGMENTATION"]) as seg:
            for k, t in enumerate(default_levels_sigma(), start=1):
                what = "dual-image level %d (%.6g sigma)" % (k, t)
                cat, sex = run_sextractor(self.detection + "," + self.measurement, self.work,
                                          "level%d" % k, param, repr(t), extra, ["SEGMENTATION"])
                theirs, _ = ldac_objects(cat)
                sex_head = ldac_imhead(cat)
                for key in ("SEXBKGND", "SEXBKDEV") + (
                        ("SEXDWSCL", "SEXMWSCL") if weight_scales else ()):
                    self.assertEqual(card_text(imhead, key), card_text(sex_head, key),
                                     what + " " + key)
                # Thresholds: SExtractor's in single precision, octarc's in double; within one
                # float32 ulp. SEXATHLD (t_1 times the measurement image's sigma) is the lowest
                # level's in octarc's header.
                pairs = [("OCTTH%d" % k, "SEXTHLD")] + ([("SEXATHLD", "SEXATHLD")] if k == 1 else [])
                for mine_key, their_key in pairs:
                    theirs_t = np.float32(sex_head[their_key])
                    self.assertLessEqual(abs(np.float32(imhead[mine_key]) - theirs_t),
                                         np.spacing(theirs_t), what + " " + their_key)
                mapping = label_correspondence(self, seg[k].data,
                                               fits.getdata(sex["SEGMENTATION"]), what)
                mine = ours[ours["THRESH_LEVEL"] == k]
                assert_rows_agree(self, mine, theirs, mapping, what, skip)
                total += len(theirs)
                os.remove(sex["SEGMENTATION"])
        self.assertEqual(len(ours), total)
        self.assertGreater(total, 1000)
        code, text = fitsverify_errors(out)
        self.assertEqual(code, 0, text)

    def test_two_names_as_two_arguments(self):
        # `octarc detect DETECT MEASURE` is the same run as `DETECT,MEASURE`, as in SExtractor.
        columns = ["THRESH_LEVEL", "NUMBER", "X_IMAGE", "FLUX_ISO", "ARCNESS"]
        joined, _ = octarc_detect(self, [self.detection + "," + self.measurement], "joined",
                                  columns, checks=())
        apart, _ = octarc_detect(self, [self.detection, self.measurement], "apart", columns,
                                 checks=())
        a, b = ldac_objects(joined)[0], ldac_objects(apart)[0]
        for name in columns:
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)
        # The fluxes are the measurement image's, not the detection image's.
        single, _ = octarc_detect(self, [self.detection], "single", columns, checks=())
        s = ldac_objects(single)[0]
        np.testing.assert_array_equal(a["X_IMAGE"], s["X_IMAGE"])
        self.assertFalse(np.array_equal(a["FLUX_ISO"], s["FLUX_ISO"]))


class DualImageBadInput(WorkDirTest):
    """Images that do not share a pixel grid, and dual-image runs where they cannot be."""

    def setUp(self):
        super().setUp()
        rng = np.random.default_rng(3)
        self.a = self.path("a.fits")
        header = fits.Header()
        for key, value in (("CTYPE1", "RA---TAN"), ("CTYPE2", "DEC--TAN"), ("CRPIX1", 32.0),
                           ("CRPIX2", 32.0), ("CRVAL1", 150.0), ("CRVAL2", 2.0),
                           ("CD1_1", -7e-5), ("CD2_2", 7e-5), ("CD1_2", 0.0), ("CD2_1", 0.0)):
            header[key] = value
        fits.PrimaryHDU(rng.normal(100, 5, (64, 64)).astype(np.float32),
                        header=header).writeto(self.a)
        self.bigger = self.path("bigger.fits")
        fits.PrimaryHDU(rng.normal(100, 5, (64, 80)).astype(np.float32)).writeto(self.bigger)
        self.shifted = self.path("shifted.fits")
        header["CRPIX1"] = 34.0  # the same size, two pixels off on the sky
        fits.PrimaryHDU(rng.normal(100, 5, (64, 64)).astype(np.float32),
                        header=header).writeto(self.shifted)

    def fails(self, *args):
        out = self.path("out.ldac")
        proc = run_octarc(*args, "-CATALOG_NAME", out, "-CHECKIMAGE_TYPE", "NONE",
                          "-VERBOSE_TYPE", "QUIET", check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertFalse(os.path.exists(out), "partial output left behind")
        lines = proc.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, proc.stderr)
        return lines[0]

    def test_different_sizes(self):
        line = self.fails("detect", self.a + "," + self.bigger)
        self.assertIn(self.a, line)
        self.assertIn(self.bigger, line)
        self.assertIn("64x64 and 80x64", line)
        self.assertIn("pixel grid", line)

    def test_same_size_other_wcs(self):
        line = self.fails("detect", self.a + "," + self.shifted)
        self.assertIn(self.shifted, line)
        self.assertIn("WCS", line)

    def test_three_images(self):
        line = self.fails("detect", self.a, self.a, self.a)
        self.assertIn("one image, or a detection and a measurement image", line)

    def test_measure_takes_one_image(self):
        line = self.fails("measure", self.a + "," + self.a, "-SEGMENTATION_NAME", self.a)
        self.assertIn("dual-image mode", line)
        self.assertIn("octarc measure takes one image", line)

    def test_background_map_is_for_one_image(self):
        line = self.fails("detect", self.a + "," + self.a, "-BACKGROUND_NAME", self.a)
        self.assertIn("BACKGROUND_NAME", line)

    def test_missing_measurement_weight_map(self):
        line = self.fails("detect", self.a + "," + self.a, "-WEIGHT_TYPE", "NONE,MAP_WEIGHT",
                          "-WEIGHT_IMAGE", self.path("none.fits,missing.fits"))
        self.assertIn("missing.fits", line)


if __name__ == "__main__":
    unittest.main()
