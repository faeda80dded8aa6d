"""`octarc detect` against source-extractor, level by level (issue 3, acceptance 1 to 3).

One `octarc detect` run with the 15 default levels (DETECT_THRESH 2.5, DETECT_THRESH_MAX 20,
DETECT_NLEVELS 15, RELATIVE) must give, at every level, exactly the objects of a
source-extractor run at that threshold in the pure-thresholding configuration (DEBLEND_NTHRESH 1,
CLEAN N) with the same AUTO background (BACK_SIZE 64, BACK_FILTERSIZE 3): the same pixel
partition (octarc's SEGMENTATION HDU k against SExtractor's segmentation map, equal up to a
renumbering that must be a bijection) and the SExtractor-named columns within the tolerances of
test_measure_vs_sextractor.py, rows matched through that renumbering. On the real NTT/EMMI image
and on a synthetic 2048x2048 field, with FILTER N and with FILTER Y (default.conv).
"""
import math
import os
import subprocess
import unittest

import numpy as np
import sep
from astropy import log as astropy_log
from astropy.io import fits
from scipy import ndimage

from octarc_testlib import (SEX_SHARE, WorkDirTest, card_text, fitsverify_errors, ldac_imhead,
                            ldac_objects, require_program, require_shared, run_octarc,
                            run_sextractor, write_param)
from test_measure_vs_sextractor import EXACT, SEX_COLUMNS, assert_float_columns_agree

DETECT_THRESH, DETECT_THRESH_MAX, DETECT_NLEVELS, MINAREA = 2.5, 20.0, 15, 5
BACKGROUND_ARGS = ["-BACK_TYPE", "AUTO", "-BACK_SIZE", "64", "-BACK_FILTERSIZE", "3"]
CONV = os.path.join(SEX_SHARE, "default.conv")
astropy_log.setLevel("ERROR")  # the ESO-LOG cards of the real image are not FITS keywords


def default_levels_sigma():
    """The 15 default levels in units of sigma, log-spaced from 2.5 to 20 (README, "Levels")."""
    ratio = DETECT_THRESH_MAX / DETECT_THRESH
    return [DETECT_THRESH * ratio ** (k / (DETECT_NLEVELS - 1)) for k in range(DETECT_NLEVELS)]


def write_synthetic_field(path, size=2048, sources=3000, seed=20261125):
    """A reproducible float32 field: a sloped sky of 1000 ADU, Gaussian noise of 8 ADU and
    `sources` Gaussian or exponential (elliptical) profiles with log-uniform fluxes."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:size, 0:size]
    image = 1000.0 + 0.01 * xx - 0.005 * yy
    image += rng.normal(0.0, 8.0, (size, size))
    half = 20
    sy, sx = np.mgrid[-half:half + 1, -half:half + 1]
    for _ in range(sources):
        x0, y0 = rng.uniform(0, size, 2)
        flux = 10.0 ** rng.uniform(2.3, 5.0)
        q = rng.uniform(0.3, 1.0)
        theta = rng.uniform(0, math.pi)
        ix, iy = int(x0), int(y0)
        dx = sx + ix - x0
        dy = sy + iy - y0
        u = dx * math.cos(theta) + dy * math.sin(theta)
        v = (-dx * math.sin(theta) + dy * math.cos(theta)) / q
        r2 = u * u + v * v
        if rng.uniform() < 0.5:
            s = rng.uniform(0.8, 3.0)
            profile = np.exp(-0.5 * r2 / (s * s))
        else:
            h = rng.uniform(0.7, 3.5)
            profile = np.exp(-np.sqrt(r2) / h)
        profile *= flux / profile.sum()
        x1, x2 = max(ix - half, 0), min(ix + half + 1, size)
        y1, y2 = max(iy - half, 0), min(iy + half + 1, size)
        image[y1:y2, x1:x2] += profile[y1 - (iy - half):y2 - (iy - half),
                                       x1 - (ix - half):x2 - (ix - half)]
    fits.PrimaryHDU(image.astype(np.float32)).writeto(path, overwrite=True)
    return path


def label_correspondence(test, ours, theirs, what):
    """Checks that two segmentation maps hold the same pixel partition and returns the map
    octarc NUMBER -> SExtractor NUMBER, after checking that it is a bijection."""
    np.testing.assert_array_equal(ours > 0, theirs > 0,
                                  err_msg="%s: footprints differ" % what)
    mask = ours > 0
    pairs = np.unique(np.stack([ours[mask], theirs[mask]]), axis=1)
    test.assertEqual(len(np.unique(pairs[0])), pairs.shape[1],
                     "%s: an octarc object covers several SExtractor objects" % what)
    test.assertEqual(len(np.unique(pairs[1])), pairs.shape[1],
                     "%s: a SExtractor object covers several octarc objects" % what)
    return dict(zip(pairs[0].tolist(), pairs[1].tolist()))


def assert_rows_agree(test, mine, theirs, mapping, what, skip=()):
    """octarc rows `mine` (one level) against SExtractor's catalog, matched through `mapping`;
    the columns in `skip` are left out."""
    test.assertEqual(len(mine), len(theirs), "%s: object counts differ" % what)
    test.assertEqual(sorted(mine["NUMBER"].tolist()), sorted(mapping))
    row_of = {int(n): i for i, n in enumerate(theirs["NUMBER"])}
    order_theirs = np.array([row_of[mapping[int(n)]] for n in mine["NUMBER"]], dtype=int)
    other = theirs[order_theirs]
    for name in EXACT:
        if name == "NUMBER" or name in skip:
            continue
        np.testing.assert_array_equal(mine[name], other[name],
                                      err_msg="%s column %s" % (what, name))
    assert_float_columns_agree(mine, other, what, skip)


def run_detect(test, image, work, filter_on, extra=(), checks=("SEGMENTATION",), tag="octarc"):
    """`octarc detect` with the default levels; returns the catalog and the check-image paths."""
    param = write_param(os.path.join(work, "%s.param" % tag),
                        ["THRESH_LEVEL", "PARENT_NUMBER"] + SEX_COLUMNS)
    out = os.path.join(work, "%s.ldac" % tag)
    paths = {t: os.path.join(work, "%s.%s.fits" % (tag, t.lower())) for t in checks}
    args = ["detect", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
            "-PARAMETERS_NAME", param, "-FILTER", "Y" if filter_on else "N", "-FILTER_NAME", CONV,
            "-DETECT_THRESH", DETECT_THRESH, "-DETECT_THRESH_MAX", DETECT_THRESH_MAX,
            "-DETECT_NLEVELS", DETECT_NLEVELS, "-DETECT_MINAREA", MINAREA,
            "-THRESH_TYPE", "RELATIVE", "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
            "-VERBOSE_TYPE", "QUIET"] + BACKGROUND_ARGS + list(extra)
    if checks:
        args += ["-CHECKIMAGE_TYPE", ",".join(checks),
                 "-CHECKIMAGE_NAME", ",".join(paths[t] for t in checks)]
    run_octarc(*args)
    return out, paths


class DetectLevelsVersusSExtractor(WorkDirTest):

    def check(self, image, filter_on):
        out, checks = run_detect(self, image, self.work, filter_on)
        ours, _ = ldac_objects(out)
        imhead = ldac_imhead(out)
        self.assertEqual(imhead["OCTNLEV"], DETECT_NLEVELS)
        param = write_param(self.path("sex.param"), SEX_COLUMNS)
        extra = ["-FILTER", "Y" if filter_on else "N", "-DETECT_MINAREA", str(MINAREA),
                 "-THRESH_TYPE", "RELATIVE"] + BACKGROUND_ARGS
        with fits.open(checks["SEGMENTATION"]) as seg:
            self.assertEqual(len(seg), DETECT_NLEVELS + 1)  # empty primary + one HDU per level
            total = 0
            for k, t in enumerate(default_levels_sigma(), start=1):
                what = "%s level %d (%.6g sigma)" % (os.path.basename(image), k, t)
                cat, sex_checks = run_sextractor(image, self.work, "level%d" % k, param, repr(t),
                                                 extra, ["SEGMENTATION"])
                theirs, _ = ldac_objects(cat)
                sex_head = ldac_imhead(cat)
                self.assertEqual(card_text(imhead, "SEXBKDEV"), card_text(sex_head, "SEXBKDEV"),
                                 what)
                # SEXTHLD is SExtractor's threshold in single precision (t * sigma formed in
                # float), OCTTHk octarc's in double: rounded to float they agree within one ulp
                # (as THRESHOLD does).
                theirs_t = np.float32(sex_head["SEXTHLD"])
                self.assertLessEqual(abs(np.float32(imhead["OCTTH%d" % k]) - theirs_t),
                                     np.spacing(theirs_t), what)
                self.assertEqual(seg[k].header["THRLEVEL"], k)
                theirs_seg = fits.getdata(sex_checks["SEGMENTATION"])
                mapping = label_correspondence(self, seg[k].data, theirs_seg, what)
                mine = ours[ours["THRESH_LEVEL"] == k]
                assert_rows_agree(self, mine, theirs, mapping, what)
                total += len(theirs)
                os.remove(sex_checks["SEGMENTATION"])
            self.assertEqual(len(ours), total)
        self.assertGreater(total, 100)
        code, text = fitsverify_errors(out)
        self.assertEqual(code, 0, text)

    def test_real_image_filter_n(self):
        self.check(require_shared(self, "ntt-emmi", "galaxies.fits"), filter_on=False)

    def test_real_image_filter_y(self):
        self.check(require_shared(self, "ntt-emmi", "galaxies.fits"), filter_on=True)

    def test_synthetic_2048_filter_n(self):
        self.check(write_synthetic_field(self.path("field.fits")), filter_on=False)

    def test_synthetic_2048_filter_y(self):
        self.check(write_synthetic_field(self.path("field.fits")), filter_on=True)


class DetectBackgroundMaps(WorkDirTest):
    """BACKGROUND and BACKGROUND_RMS check-images of `octarc detect` on galaxies.fits.

    Bit-identical to source-extractor's check-images and to python3-sep's sep.Background with
    the same mesh (bw = bh = 64, fw = fh = 3) on the same float32 pixels, as the README says; the
    test asserts exactly that (issue 3 asked for 0.1 % of the noise).
    """

    def test_background_and_rms_maps(self):
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        out, checks = run_detect(self, image, self.work, False,
                                 checks=("BACKGROUND", "BACKGROUND_RMS"))
        sigma = ldac_imhead(out)["SEXBKDEV"]
        ours_back = fits.getdata(checks["BACKGROUND"])
        ours_rms = fits.getdata(checks["BACKGROUND_RMS"])
        self.assertEqual(ours_back.shape, (1024, 1024))

        param = write_param(self.path("sex.param"), ["NUMBER"])
        _, sex = run_sextractor(image, self.work, "sex", param, 2.5, BACKGROUND_ARGS,
                                ["BACKGROUND", "BACKGROUND_RMS"])
        np.testing.assert_array_equal(ours_back, fits.getdata(sex["BACKGROUND"]))
        np.testing.assert_array_equal(ours_rms, fits.getdata(sex["BACKGROUND_RMS"]))

        with fits.open(image) as f:  # astropy scales BITPIX 16 to float32, as SExtractor does
            pixels = np.ascontiguousarray(f[0].data, dtype=np.float32)
        reference = sep.Background(pixels, bw=64, bh=64, fw=3, fh=3)
        np.testing.assert_array_equal(ours_back, reference.back())
        np.testing.assert_array_equal(ours_rms, reference.rms())
        # SEXBKDEV is sep's global rms, printed with 13 digits ("%.12E").
        self.assertEqual("%.12E" % reference.globalrms, "%.12E" % sigma)


class DetectReferenceCatalog(WorkDirTest):
    """The independent catalog sep-reference/image.cat, made by SExtractor with the default.sex
    of that folder: AUTO background (BACK_SIZE 64, BACK_FILTERSIZE 3), FILTER Y with its
    default.conv, DETECT_THRESH 1.5, DETECT_MINAREA 5, DEBLEND_NTHRESH 32 with DEBLEND_MINCONT 1.0
    (so no object is ever split: deblending is effectively off) and CLEAN Y.

    `octarc detect` at one level with that configuration finds 71 objects; image.cat has 65. Each
    of the 65 matches an octarc object to the precision image.cat is printed with: X_IMAGE and
    Y_IMAGE within half a unit of the 4th decimal (5e-5 pixel; reached 4.9e-5), X2_IMAGE,
    Y2_IMAGE and XY_IMAGE within half a unit of the 11th significant digit (5e-11 relative;
    reached 3.7e-11). The 6 others are the faint detections in the wings of bright neighbours that
    SExtractor's CLEAN removes: a source-extractor run with the same file and CLEAN N finds
    exactly octarc's 71 objects.
    """

    def test_positions_and_second_moments(self):
        folder = os.path.dirname(require_shared(self, "sep-reference", "image.cat"))
        require_program("source-extractor")
        image = os.path.join(folder, "image.fits")
        names = ["NUMBER", "X_IMAGE", "Y_IMAGE", "X2_IMAGE", "Y2_IMAGE", "XY_IMAGE"]
        param = write_param(self.path("octarc.param"), names)
        out = self.path("octarc.ldac")
        run_octarc("detect", image, "-c", os.path.join(folder, "default.sex"),
                   "-DETECT_NLEVELS", 1, "-FILTER_NAME", os.path.join(folder, "default.conv"),
                   "-PARAMETERS_NAME", param, "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
                   "-CHECKIMAGE_TYPE", "NONE", "-VERBOSE_TYPE", "QUIET")
        ours, _ = ldac_objects(out)
        reference = np.loadtxt(os.path.join(folder, "image.cat"))
        self.assertEqual(reference.shape[0], 65)
        self.assertEqual(len(ours), 71)
        matched = set()
        for row in reference:
            d = np.hypot(ours["X_IMAGE"] - row[1], ours["Y_IMAGE"] - row[2])
            i = int(np.argmin(d))
            what = "reference object %d" % row[0]
            self.assertNotIn(i, matched, what)
            matched.add(i)
            self.assertLessEqual(abs(ours["X_IMAGE"][i] - row[1]), 5e-5 + 1e-9, what)
            self.assertLessEqual(abs(ours["Y_IMAGE"][i] - row[2]), 5e-5 + 1e-9, what)
            for col, name in ((5, "X2_IMAGE"), (6, "Y2_IMAGE"), (7, "XY_IMAGE")):
                self.assertLessEqual(abs(ours[name][i] - row[col]), 5e-11 * abs(row[col]),
                                     what + " " + name)

        # The unmatched objects are those SExtractor's CLEAN removed.
        sex_param = write_param(self.path("sex.param"), names)
        sex_cat = self.path("clean_n.ldac")
        subprocess.run(["source-extractor", image, "-c", os.path.join(folder, "default.sex"),
                        "-FILTER_NAME", os.path.join(folder, "default.conv"),
                        "-PARAMETERS_NAME", sex_param, "-CATALOG_TYPE", "FITS_LDAC",
                        "-CATALOG_NAME", sex_cat, "-CLEAN", "N", "-CHECKIMAGE_TYPE", "NONE",
                        "-STARNNW_NAME", os.path.join(SEX_SHARE, "default.nnw"),
                        "-VERBOSE_TYPE", "QUIET", "-WRITE_XML", "N"],
                       check=True, capture_output=True, cwd=self.work)
        unclean, _ = ldac_objects(sex_cat)
        self.assertEqual(len(unclean), len(ours))
        for i in set(range(len(ours))) - matched:
            d = np.hypot(unclean["X_IMAGE"] - ours["X_IMAGE"][i],
                         unclean["Y_IMAGE"] - ours["Y_IMAGE"][i])
            self.assertEqual(np.min(d), 0.0, "octarc object %d" % ours["NUMBER"][i])


def check_nesting(test, catalog, seg_path, detection, what):
    """Per-level segmentation HDUs against the catalog and the detection image: every object's
    pixels lie inside its parent (PARENT_NUMBER, one level down), and level k covers exactly the
    pixels above t_k that belong to 8-connected components of at least MINAREA pixels."""
    rows, _ = ldac_objects(catalog)
    imhead = ldac_imhead(catalog)
    eight = np.ones((3, 3), dtype=bool)
    with fits.open(seg_path) as seg:
        levels = imhead["OCTNLEV"]
        for k in range(1, levels + 1):
            labels = seg[k].data
            threshold = np.float32(imhead["OCTTH%d" % k])
            above = detection > threshold  # single precision, as the detector compares
            components, count = ndimage.label(above, structure=eight)
            area = np.bincount(components.ravel(), minlength=count + 1)
            big = area >= MINAREA
            big[0] = False
            kept = big[components]
            np.testing.assert_array_equal(labels > 0, kept,
                                          err_msg="%s level %d: coverage" % (what, k))
            test.assertEqual(len(np.unique(labels[kept])), int(big.sum()),
                             "%s level %d: one object per component" % (what, k))
            mine = rows[rows["THRESH_LEVEL"] == k]
            test.assertEqual(len(mine), int(big.sum()))
            if k == 1:
                test.assertTrue(np.all(mine["PARENT_NUMBER"] == 0))
                continue
            parent_of = np.zeros(labels.max() + 1, dtype=np.int64)
            parent_of[mine["NUMBER"]] = mine["PARENT_NUMBER"]
            mask = labels > 0
            below = seg[k - 1].data
            np.testing.assert_array_equal(below[mask], parent_of[labels[mask]],
                                          err_msg="%s level %d: parent links" % (what, k))


class DetectParentLinks(WorkDirTest):

    def test_real_image_filter_n(self):
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        out, checks = run_detect(self, image, self.work, False,
                                 checks=("SEGMENTATION", "FILTERED"))
        check_nesting(self, out, checks["SEGMENTATION"], fits.getdata(checks["FILTERED"]),
                      "galaxies.fits")

    def test_real_image_filter_y(self):
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        out, checks = run_detect(self, image, self.work, True,
                                 checks=("SEGMENTATION", "FILTERED"))
        # The filtered detection image is SExtractor's own (FILTERED check-image).
        param = write_param(self.path("sex.param"), ["NUMBER"])
        _, sex = run_sextractor(image, self.work, "sex", param, 2.5,
                                ["-FILTER", "Y"] + BACKGROUND_ARGS, ["FILTERED"])
        filtered = fits.getdata(checks["FILTERED"])
        np.testing.assert_array_equal(filtered, fits.getdata(sex["FILTERED"]))
        check_nesting(self, out, checks["SEGMENTATION"], filtered, "galaxies.fits FILTER Y")

    def test_random_synthetic_images(self):
        for seed in (1, 2, 3):
            rng = np.random.default_rng(seed)
            size = 300
            image = rng.normal(100.0, 5.0, (size, size))
            yy, xx = np.mgrid[0:size, 0:size]
            for _ in range(40):
                x0, y0 = rng.uniform(0, size, 2)
                s = rng.uniform(1.0, 6.0)
                image += rng.uniform(20, 2000) * np.exp(-0.5 * ((xx - x0) ** 2 + (yy - y0) ** 2)
                                                        / (s * s))
            path = self.path("random%d.fits" % seed)
            fits.PrimaryHDU(image.astype(np.float32)).writeto(path)
            out, checks = run_detect(self, path, self.work, seed == 2,
                                     checks=("SEGMENTATION", "FILTERED"), tag="r%d" % seed)
            check_nesting(self, out, checks["SEGMENTATION"], fits.getdata(checks["FILTERED"]),
                          "random field %d" % seed)



class DetectThreadCount(WorkDirTest):
    """Detection and measurement run on several threads: the catalog must not depend on how
    many (every row and value equal, in the same order)."""

    def test_same_catalog_for_any_thread_count(self):
        image = write_synthetic_field(self.path("field.fits"), size=1024, sources=800)
        catalogs = []
        for threads in (1, 2, 5):
            out, _ = run_detect(self, image, self.work, False, checks=(),
                                extra=["-NTHREADS", str(threads)],
                                tag="t%d" % threads)
            catalogs.append(ldac_objects(out)[0])
        self.assertGreater(len(catalogs[0]), 1000)
        for other in catalogs[1:]:
            self.assertEqual(len(other), len(catalogs[0]))
            for name in catalogs[0].dtype.names:
                np.testing.assert_array_equal(other[name], catalogs[0][name], err_msg=name)

if __name__ == "__main__":
    unittest.main()
