"""`octarc detect` on bad input (issue 3, acceptance 5): a one-line error naming the file or the
key, a non-zero exit status, and neither a catalog nor any check-image left behind; a constant
image is not an error but gives no object and a warning, as in SExtractor (sigma set to 1)."""
import os
import re
import subprocess
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (SEX_SHARE, WorkDirTest, fitsverify_errors, ldac_imhead,
                            ldac_objects, require_program, require_shared, run_octarc,
                            write_param)


class DetectBadInput(WorkDirTest):

    def setUp(self):
        super().setUp()
        rng = np.random.default_rng(7)
        image = rng.normal(100.0, 5.0, (120, 100))
        image[40:50, 30:40] += 200.0
        self.image = self.path("image.fits")
        fits.PrimaryHDU(image.astype(np.float32)).writeto(self.image)
        self.param = write_param(self.path("detect.param"),
                                 ["THRESH_LEVEL", "NUMBER", "PARENT_NUMBER", "FLUX_ISO"])
        self.catalog = self.path("out.ldac")
        self.segmentation = self.path("seg.fits")

    def detect(self, image, *args):
        return run_octarc("detect", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
                          "-PARAMETERS_NAME", self.param, "-FILTER_NAME",
                          os.path.join(SEX_SHARE, "default.conv"), "-CATALOG_TYPE", "FITS_LDAC",
                          "-CATALOG_NAME", self.catalog, "-CHECKIMAGE_TYPE", "SEGMENTATION",
                          "-CHECKIMAGE_NAME", self.segmentation, *args, check=False)

    def assert_fails(self, proc, *words):
        """Non-zero exit, one error line holding every word, and no output left behind."""
        self.assertNotEqual(proc.returncode, 0, proc.stderr)
        errors = [line for line in proc.stderr.splitlines() if "error" in line.lower()]
        self.assertEqual(len(errors), 1, proc.stderr)
        for word in words:
            self.assertIn(word, errors[0])
        self.assertEqual(sorted(os.listdir(self.work)), self.inputs(),
                         "output left behind after: " + errors[0])
        return errors[0]

    def inputs(self):
        return sorted(n for n in os.listdir(self.work)
                      if n not in ("out.ldac", "seg.fits") and not n.startswith("."))

    def test_good_run_writes_both(self):
        # The reference for the tests below: the same command with good input succeeds.
        proc = self.detect(self.image, "-VERBOSE_TYPE", "QUIET")
        self.assertEqual(proc.returncode, 0, proc.stderr)
        rows, _ = ldac_objects(self.catalog)
        self.assertEqual(len(rows[rows["THRESH_LEVEL"] == 1]), 1)
        self.assertTrue(os.path.exists(self.segmentation))

    def test_levels_not_increasing(self):
        self.assert_fails(self.detect(self.image, "-DETECT_LEVELS", "5,3"), "DETECT_LEVELS",
                          "5", "3")

    def test_minarea_zero(self):
        self.assert_fails(self.detect(self.image, "-DETECT_MINAREA", "0"), "DETECT_MINAREA")

    def test_weight_map_of_wrong_size(self):
        weight = self.path("weight.fits")
        fits.PrimaryHDU(np.ones((120, 99), np.float32)).writeto(weight)
        line = self.assert_fails(self.detect(self.image, "-WEIGHT_TYPE", "MAP_WEIGHT",
                                             "-WEIGHT_IMAGE", weight), weight, "99x120",
                                 "100x120")
        self.assertIn("weight map", line)

    def test_missing_weight_map(self):
        self.assert_fails(self.detect(self.image, "-WEIGHT_TYPE", "MAP_RMS", "-WEIGHT_IMAGE",
                                      self.path("absent.fits")), "absent.fits")

    def test_weight_type_background_unsupported(self):
        self.assert_fails(self.detect(self.image, "-WEIGHT_TYPE", "BACKGROUND"), "WEIGHT_TYPE",
                          "BACKGROUND")

    def test_weight_gain_n_unsupported(self):
        weight = self.path("weight.fits")
        fits.PrimaryHDU(np.ones((120, 100), np.float32)).writeto(weight)
        self.assert_fails(self.detect(self.image, "-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE",
                                      weight, "-WEIGHT_GAIN", "N"), "WEIGHT_GAIN")

    def test_unsupported_checkimage_type(self):
        self.assert_fails(self.detect(self.image, "-CHECKIMAGE_TYPE", "APERTURES"),
                          "CHECKIMAGE_TYPE", "APERTURES")

    def test_all_nan_image(self):
        path = self.path("nan.fits")
        fits.PrimaryHDU(np.full((50, 60), np.nan, np.float32)).writeto(path)
        self.assert_fails(self.detect(path), path, "NaN")

    def test_catalog_cannot_be_written_leaves_no_checkimage(self):
        # The catalog goes first; check-images are written only once it exists.
        proc = run_octarc("detect", self.image, "-c", os.path.join(SEX_SHARE, "default.sex"),
                          "-PARAMETERS_NAME", self.param, "-CATALOG_TYPE", "FITS_LDAC",
                          "-CATALOG_NAME", self.path("missing-dir/out.ldac"),
                          "-CHECKIMAGE_TYPE", "SEGMENTATION,BACKGROUND",
                          "-CHECKIMAGE_NAME", self.segmentation + "," + self.path("bg.fits"),
                          check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("missing-dir/out.ldac", proc.stderr)
        self.assertFalse(os.path.exists(self.segmentation))
        self.assertFalse(os.path.exists(self.path("bg.fits")))

    def test_outputs_over_inputs_are_refused(self):
        weight = self.path("weight.fits")
        fits.PrimaryHDU(np.ones((120, 100), np.float32)).writeto(weight)
        before = open(self.image, "rb").read(), open(weight, "rb").read()
        line = self.assert_fails(
            run_octarc("detect", self.image, "-PARAMETERS_NAME", self.param, "-CATALOG_NAME",
                       self.image, check=False), "CATALOG_NAME", "is also the image")
        self.assertIn(self.image, line)
        self.assert_fails(self.detect(self.image, "-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE",
                                      weight, "-CHECKIMAGE_NAME", weight),
                          "CHECKIMAGE_NAME", "WEIGHT_IMAGE")
        self.assertEqual((open(self.image, "rb").read(), open(weight, "rb").read()), before)

    def test_more_than_two_images(self):
        # One image, or SExtractor's dual-image pair (test_detect_dual.py); never three.
        for images in ([self.image] * 3, [self.image + "," + self.image, self.image]):
            line = self.assert_fails(self.detect(*images), "one image, or a detection and a "
                                     "measurement image")
            self.assertIn("see octarc detect -h", line)

    def test_constant_image_gives_no_object_like_sextractor(self):
        path = self.path("constant.fits")
        fits.PrimaryHDU(np.full((128, 128), 7.0, np.float32)).writeto(path)
        proc = self.detect(path)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("constant", proc.stderr)
        self.assertIn("WARNING", proc.stderr)
        rows, _ = ldac_objects(self.catalog)
        self.assertEqual(len(rows), 0)
        ours = ldac_imhead(self.catalog)
        with fits.open(self.segmentation) as seg:
            self.assertTrue(all(np.all(hdu.data == 0) for hdu in seg[1:]))
        # SExtractor on the same image: background 7, sigma set to 1, no object.
        require_program("source-extractor")
        sex_param = write_param(self.path("sex.param"), ["NUMBER"])
        sex_cat = self.path("sex.ldac")
        subprocess.run(["source-extractor", path, "-c", os.path.join(SEX_SHARE, "default.sex"),
                        "-PARAMETERS_NAME", sex_param, "-CATALOG_TYPE", "FITS_LDAC",
                        "-CATALOG_NAME", sex_cat, "-FILTER_NAME",
                        os.path.join(SEX_SHARE, "default.conv"), "-VERBOSE_TYPE", "QUIET",
                        "-WRITE_XML", "N"], check=True, capture_output=True, cwd=self.work)
        theirs = ldac_imhead(sex_cat)
        self.assertEqual(len(ldac_objects(sex_cat)[0]), 0)
        self.assertEqual(ours["SEXBKDEV"], theirs["SEXBKDEV"])
        self.assertEqual(ours["SEXBKDEV"], 1.0)
        self.assertEqual(ours["SEXBKGND"], theirs["SEXBKGND"])


class DetectWithSExtractorConfiguration(WorkDirTest):
    """SExtractor's test configuration of the NTT/EMMI frame (its default.sex and default.param)
    asks for no levels: octarc then runs one level, like SExtractor, and a run of several levels
    always carries THRESH_LEVEL (with that default.param, NUMBER alone would restart at every
    level)."""

    def setUp(self):
        super().setUp()
        self.folder = os.path.dirname(require_shared(self, "ntt-emmi", "default.sex"))
        self.catalog = self.path("out.ldac")

    def detect(self, *args):
        # Run in the configuration's folder: its file names are relative to it.
        return run_octarc("detect", "galaxies.fits", "-c", "default.sex", "-CATALOG_NAME",
                          self.catalog, *args, cwd=self.folder)

    def test_default_sex_is_one_level(self):
        proc = self.detect()
        self.assertNotIn("THRESH_LEVEL", proc.stderr)
        rows, _ = ldac_objects(self.catalog)
        self.assertEqual(ldac_imhead(self.catalog)["OCTNLEV"], 1)
        self.assertNotIn("THRESH_LEVEL", rows.columns.names)
        self.assertEqual(list(rows["NUMBER"]), list(range(1, len(rows) + 1)))
        self.assertGreater(len(rows), 100)

    def test_several_levels_always_carry_thresh_level(self):
        proc = self.detect("-DETECT_NLEVELS", "3", "-DETECT_THRESH_MAX", "10")
        self.assertIn("THRESH_LEVEL added", proc.stderr)
        rows, _ = ldac_objects(self.catalog)
        self.assertEqual(rows.columns.names[:2], ["NUMBER", "THRESH_LEVEL"])
        self.assertEqual(sorted(set(rows["THRESH_LEVEL"])), [1, 2, 3])
        self.assertEqual(ldac_imhead(self.catalog)["OCTNLEV"], 3)

    def test_multi_level_segmentation_of_the_ntt_frame_passes_fitsverify(self):
        # The frame's primary header holds BLOCKED, which only a primary header may hold: the
        # per-level HDUs must not copy it.
        with fits.open(os.path.join(self.folder, "galaxies.fits")) as f:
            self.assertIn("BLOCKED", f[0].header)
        seg = self.path("seg.fits")
        self.detect("-DETECT_NLEVELS", "15", "-DETECT_THRESH", "2.5", "-DETECT_THRESH_MAX", "20",
                    "-CHECKIMAGE_TYPE", "SEGMENTATION", "-CHECKIMAGE_NAME", seg)
        code, text = fitsverify_errors(seg)
        self.assertEqual(code, 0, text)
        self.assertIn("verification OK", text)
        with fits.open(seg) as f:
            self.assertEqual(len(f), 16)
            self.assertTrue(all("BLOCKED" not in hdu.header for hdu in f[1:]))

    def test_thresh_max_alone_warns_that_it_is_one_level(self):
        proc = self.detect("-DETECT_THRESH_MAX", "10")
        self.assertIn("DETECT_THRESH_MAX is set but DETECT_NLEVELS is 1", proc.stderr)
        self.assertEqual(ldac_imhead(self.catalog)["OCTNLEV"], 1)

class AsciiCatalogForStilts(WorkDirTest):
    """Undefined values in an ASCII catalog read as numbers: STILTS (TOPCAT's engine) types a
    column holding C's "+nan" or "-nan" as text."""

    def test_nan_columns_read_as_floats(self):
        rng = np.random.default_rng(1)
        image = rng.normal(0.0, 1.0, (60, 60)).astype(np.float32)
        image[20:25, 20:26] += 20.0
        image[40:43, 40:42] += 15.0
        path = self.path("nowcs.fits")
        fits.PrimaryHDU(image).writeto(path)  # no WCS: the world columns are NaN
        param = write_param(self.path("a.param"), ["X_IMAGE", "DELTA_J2000", "ALPHA_J2000"])
        cat = self.path("a.cat")
        run_octarc("detect", path, "-PARAMETERS_NAME", param, "-CATALOG_TYPE", "ASCII",
                   "-CATALOG_NAME", cat, "-DETECT_THRESH", "3", "-VERBOSE_TYPE", "QUIET")
        lines = open(cat).read().split("\n")
        self.assertEqual(lines[0].split()[1:], ["nan", "nan"])
        proc = subprocess.run(["stilts", "tpipe", "in=" + cat, "ifmt=ascii", "cmd=meta"],
                              capture_output=True, text=True, check=True)
        classes = re.findall(r"^\| \d+\s+\| \S+\s+\| (\w+)", proc.stdout, re.M)
        self.assertEqual(len(classes), 3, proc.stdout)
        self.assertTrue(all(c in ("Float", "Double") for c in classes), proc.stdout)


if __name__ == "__main__":
    unittest.main()
