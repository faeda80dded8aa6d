"""`octarc measure` on the segmentation images of real source-extractor runs reproduces
source-extractor's own isophotal columns (issue: foundation, acceptance 2 and 3).

source-extractor 2.25 runs three times on the real NTT/EMMI image (pure thresholding:
DEBLEND_NTHRESH 1, CLEAN N, at 3, 6 and 12 sigma); octarc reads the three segmentation maps,
the three catalogs (for SEXBKDEV, SEXGAIN, SEXTHLD) and the BACKGROUND check-image, and writes one
catalog of the three levels, which must agree row by row with SExtractor's catalogs.
"""
import os
import unittest

import numpy as np

from octarc_testlib import (SEX_SHARE, WorkDirTest, fitsverify_errors, ldac_imhead, ldac_objects,
                            require_shared, run_octarc, run_sextractor, write_param)

THRESHOLDS_SIGMA = (3.0, 6.0, 12.0)

# Tolerance per column, and why. SExtractor stores X_IMAGE, A, B, THETA, FLUX... as float32
# (TFORM 1E), so those agree to float precision (relative 2**-24 = 6e-8; a few ulps are
# allowed for sums taken in another order). X2/Y2/XY are doubles computed from float pixels:
# only the summation order differs. Integer columns are exact.
EXACT = ["NUMBER", "XMIN_IMAGE", "YMIN_IMAGE", "XMAX_IMAGE", "YMAX_IMAGE", "XPEAK_IMAGE",
         "YPEAK_IMAGE", "ISOAREA_IMAGE", "ISOAREAF_IMAGE", "FLAGS"]
RELATIVE = {  # column: (rtol, atol)
    "X_IMAGE": (0, 2e-4),          # float32 at x ~ 1000 has an ulp of 6e-5 pixel
    "Y_IMAGE": (0, 2e-4),
    "X2_IMAGE": (1e-9, 1e-12),     # double, from the same float products; summation order only
    "Y2_IMAGE": (1e-9, 1e-12),
    "XY_IMAGE": (1e-9, 1e-12),
    "A_IMAGE": (1e-5, 1e-5),       # float32 (F9.3 display, but full float stored)
    "B_IMAGE": (1e-5, 1e-5),
    "CXX_IMAGE": (1e-5, 1e-6),
    "CYY_IMAGE": (1e-5, 1e-6),
    "CXY_IMAGE": (1e-5, 1e-6),
    "ELONGATION": (1e-5, 1e-6),
    "ELLIPTICITY": (1e-5, 1e-6),
    "FLUX_ISO": (1e-6, 1e-3),      # float32 sum of float32 pixels
    "FLUXERR_ISO": (1e-6, 1e-4),
    "MAG_ISO": (0, 1e-5),
    "MAGERR_ISO": (1e-5, 1e-6),
    "FLUX_MAX": (1e-6, 1e-3),
    "THRESHOLD": (1e-6, 0),
}
ANGLE = {"THETA_IMAGE": 1e-3}      # degrees, compared modulo 180


SEX_COLUMNS = EXACT + list(RELATIVE) + list(ANGLE)


def assert_catalogs_agree(test, ours, theirs, level):
    """Every SExtractor row has an octarc row of the same NUMBER at `level`, and the columns
    agree within the tolerances above."""
    mine = ours[ours["THRESH_LEVEL"] == level]
    test.assertEqual(sorted(mine["NUMBER"]), sorted(theirs["NUMBER"]),
                     "level %d: NUMBERs differ" % level)
    order_mine = np.argsort(mine["NUMBER"])
    order_theirs = np.argsort(theirs["NUMBER"])
    for name in EXACT:
        np.testing.assert_array_equal(mine[name][order_mine], theirs[name][order_theirs],
                                      err_msg="level %d column %s" % (level, name))
    for name, (rtol, atol) in RELATIVE.items():
        np.testing.assert_allclose(mine[name][order_mine].astype(float),
                                   theirs[name][order_theirs].astype(float), rtol=rtol, atol=atol,
                                   err_msg="level %d column %s" % (level, name))
    for name, atol in ANGLE.items():
        d = mine[name][order_mine].astype(float) - theirs[name][order_theirs].astype(float)
        d = (d + 90.0) % 180.0 - 90.0
        test.assertLess(np.max(np.abs(d)), atol, "level %d column %s" % (level, name))


class MeasureVersusSExtractor(WorkDirTest):

    def run_levels(self, image, filter_on):
        param = write_param(self.path("sex.param"), SEX_COLUMNS)
        extra = ["-FILTER", "Y" if filter_on else "N", "-DETECT_MINAREA", "5", "-THRESH_TYPE",
                 "RELATIVE", "-BACK_TYPE", "AUTO", "-BACK_SIZE", "64", "-BACK_FILTERSIZE", "3"]
        cats, segs = [], []
        background = None
        for k, t in enumerate(THRESHOLDS_SIGMA, start=1):
            cat, checks = run_sextractor(image, self.work, "level%d" % k, param, t, extra,
                                         ["SEGMENTATION", "BACKGROUND"])
            cats.append(cat)
            segs.append(checks["SEGMENTATION"])
            background = checks["BACKGROUND"]
        return param, cats, segs, background

    def measure(self, image, param, cats, segs, background, filter_on, out_name):
        octarc_param = write_param(self.path("octarc.param"),
                                   ["THRESH_LEVEL", "PARENT_NUMBER"] + SEX_COLUMNS +
                                   ["ARCNESS", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR", "E_IMAGE",
                                    "SIZE_IMAGE", "SNR_ISO", "OCT_FLAGS"])
        out = self.path(out_name)
        run_octarc("measure", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
                   "-PARAMETERS_NAME", octarc_param, "-SEGMENTATION_NAME", ",".join(segs),
                   "-INPUT_CATALOG", ",".join(cats), "-APPEND_COLUMNS", "N",
                   "-BACKGROUND_NAME", background, "-FILTER", "Y" if filter_on else "N",
                   "-FILTER_NAME", os.path.join(SEX_SHARE, "default.conv"),
                   "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out, "-VERBOSE_TYPE", "QUIET")
        return out

    def check(self, filter_on):
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        param, cats, segs, background = self.run_levels(image, filter_on)
        out = self.measure(image, param, cats, segs, background, filter_on, "octarc.ldac")
        ours, header = ldac_objects(out)
        total = 0
        for k, cat in enumerate(cats, start=1):
            theirs, _ = ldac_objects(cat)
            self.assertGreater(len(theirs), 10)
            assert_catalogs_agree(self, ours, theirs, k)
            total += len(theirs)
        self.assertEqual(len(ours), total)
        # The levels nest: every object above level 1 names an existing parent one level down.
        for k in (2, 3):
            parents = set(ours["NUMBER"][ours["THRESH_LEVEL"] == k - 1])
            children = ours[ours["THRESH_LEVEL"] == k]
            self.assertTrue(set(children["PARENT_NUMBER"]) <= parents)
        self.assertTrue(np.all(ours["PARENT_NUMBER"][ours["THRESH_LEVEL"] == 1] == 0))
        code, text = fitsverify_errors(out)
        self.assertEqual(code, 0, text)

    def test_filter_n_three_thresholds(self):
        self.check(filter_on=False)

    def test_filter_y_default_conv_three_thresholds(self):
        self.check(filter_on=True)


if __name__ == "__main__":
    unittest.main()


class MultiExtensionImage(WorkDirTest):
    """A two-extension image is measured extension by extension, like SExtractor: one
    LDAC_IMHEAD/LDAC_OBJECTS pair per image extension, NUMBER restarting at 1."""

    def test_one_catalog_pair_per_extension(self):
        from astropy.io import fits
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        data = fits.getdata(image).astype(np.float32)
        mef = self.path("mef.fits")
        fits.HDUList([fits.PrimaryHDU(),
                      fits.ImageHDU(data[:512], name="CHIP1"),
                      fits.ImageHDU(data[512:], name="CHIP2")]).writeto(mef)
        param = write_param(self.path("sex.param"), SEX_COLUMNS)
        extra = ["-FILTER", "N", "-DETECT_MINAREA", "5", "-THRESH_TYPE", "RELATIVE",
                 "-BACK_TYPE", "AUTO"]
        cat, checks = run_sextractor(mef, self.work, "mef", param, 5.0, extra,
                                     ["SEGMENTATION", "BACKGROUND"])
        out = self.path("octarc.ldac")
        run_octarc("measure", mef, "-c", os.path.join(SEX_SHARE, "default.sex"),
                   "-PARAMETERS_NAME", write_param(self.path("o.param"),
                                                   ["THRESH_LEVEL"] + SEX_COLUMNS + ["ARCNESS"]),
                   "-SEGMENTATION_NAME", checks["SEGMENTATION"], "-INPUT_CATALOG", cat,
                   "-APPEND_COLUMNS", "N", "-BACKGROUND_NAME", checks["BACKGROUND"],
                   "-FILTER", "N", "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
                   "-VERBOSE_TYPE", "QUIET")
        with fits.open(cat) as theirs, fits.open(out) as ours:
            self.assertEqual([h.name for h in ours],
                             ["PRIMARY", "LDAC_IMHEAD", "LDAC_OBJECTS", "LDAC_IMHEAD",
                              "LDAC_OBJECTS"])
            self.assertEqual(len(theirs), len(ours))
            for hdu in (2, 4):
                self.assertEqual(ours[hdu].data["NUMBER"].min(), 1)
                assert_catalogs_agree(self, ours[hdu].data, theirs[hdu].data, 1)
        code, text = fitsverify_errors(out)
        self.assertEqual(code, 0, text)
