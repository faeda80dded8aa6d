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

# What each column reaches against source-extractor 2.25 on the same pixels, measured on every
# row of the end-to-end comparisons (measure at 3 levels with FILTER N and Y, detect at 15 levels
# on the real and the synthetic image, weight maps; 74 000 rows), and asserted as such:
# - EXACT, bit for bit: the integer columns, and X/Y_IMAGE, X2/Y2/XY_IMAGE, A/B/THETA_IMAGE,
#   CXX/CYY/CXY_IMAGE, FLUX_ISO and FLUX_MAX: the same products summed in the same order and in
#   the same precision as SExtractor;
# - ULPS, within n float32 ulps of SExtractor's value: the columns SExtractor derives from those
#   in mixed single and double precision where octarc works in double (reached: ELONGATION 2,
#   FLUXERR_ISO 1, MAG_ISO 1, MAGERR_ISO 2, THRESHOLD 1);
# - ELLIPTICITY = 1 - B/A: SExtractor forms B/A in single precision from its single-precision
#   A and B before subtracting it from 1, so the two differ by up to about one float32 ulp of 1
#   however small the ellipticity (reached: 1.34e-7 = 1.13 * 2**-23; allowed: 2 * 2**-23).
EXACT = ["NUMBER", "XMIN_IMAGE", "YMIN_IMAGE", "XMAX_IMAGE", "YMAX_IMAGE", "XPEAK_IMAGE",
         "YPEAK_IMAGE", "ISOAREA_IMAGE", "ISOAREAF_IMAGE", "FLAGS", "X_IMAGE", "Y_IMAGE",
         "X2_IMAGE", "Y2_IMAGE", "XY_IMAGE", "A_IMAGE", "B_IMAGE", "THETA_IMAGE", "CXX_IMAGE",
         "CYY_IMAGE", "CXY_IMAGE", "FLUX_ISO", "FLUX_MAX"]
ULPS = {"ELONGATION": 2, "FLUXERR_ISO": 1, "MAG_ISO": 1, "MAGERR_ISO": 2, "THRESHOLD": 1}
ABSOLUTE = {"ELLIPTICITY": 2.0 ** -22}


SEX_COLUMNS = EXACT + list(ULPS) + list(ABSOLUTE)


def assert_float_columns_agree(ours, theirs, what, skip=()):
    """The ULPS and ABSOLUTE columns of matched rows (float32 in both catalogs)."""
    for name, n in ULPS.items():
        if name in skip:
            continue
        reference = np.asarray(theirs[name], dtype=np.float32)
        ulp = np.spacing(np.abs(reference)).astype(float)
        d = np.abs(np.asarray(ours[name], dtype=float) - reference.astype(float))
        worst = np.max(d / ulp, initial=0.0)
        assert worst <= n, "%s column %s: %.3g float32 ulps apart (%d allowed)" % (
            what, name, worst, n)
    for name, atol in ABSOLUTE.items():
        if name in skip:
            continue
        np.testing.assert_allclose(np.asarray(ours[name], dtype=float),
                                   np.asarray(theirs[name], dtype=float), rtol=0, atol=atol,
                                   err_msg="%s column %s" % (what, name))


def assert_catalogs_agree(test, ours, theirs, level):
    """Every SExtractor row has an octarc row of the same NUMBER at `level`, and the columns
    agree as stated above."""
    mine = ours[ours["THRESH_LEVEL"] == level]
    test.assertEqual(sorted(mine["NUMBER"]), sorted(theirs["NUMBER"]),
                     "level %d: NUMBERs differ" % level)
    order_mine = np.argsort(mine["NUMBER"])
    order_theirs = np.argsort(theirs["NUMBER"])
    for name in EXACT:
        np.testing.assert_array_equal(mine[name][order_mine], theirs[name][order_theirs],
                                      err_msg="level %d column %s" % (level, name))
    assert_float_columns_agree(mine[order_mine], theirs[order_theirs], "level %d" % level)


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
