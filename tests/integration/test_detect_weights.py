"""Weight maps in `octarc detect` (WEIGHT_IMAGE, WEIGHT_TYPE, WEIGHT_THRESH, RESCALE_WEIGHTS),
against source-extractor run with the same map (SEXTRACTOR.md section 4), at each of the 15
levels of params/octarc.sex (2.5 to 20 sigma, given explicitly): one source-extractor run per
level.

The weight map is made in the test for the real NTT/EMMI image: a smooth gain in weight across
the field, a quarter of the field with a quarter of the weight (twice the noise), and a stripe
of zero weight (bad pixels). With RELATIVE thresholds a pixel is above level k when its
background-subtracted value exceeds t_k sqrt(var_i), bad pixels never join an object, and
FLUXERR_ISO sums the per-pixel variances (WEIGHT_GAIN Y).

source-extractor runs with INTERP_TYPE NONE: its default (ALL) fills bad-weight pixels with
their neighbours' values and variances (up to INTERP_MAXXLAG/YLAG pixels away), so that they can
join objects; octarc keeps them out, as issue 3 asks. With that, the pixel partitions are
identical level by level (with FILTER Y the thresholds follow the variance filtered by the same
kernel, as in SExtractor) and the columns agree within the tolerances of
test_measure_vs_sextractor.py, FLUXERR_ISO included, except THRESHOLD: with weights SExtractor
writes a local threshold per object, octarc the level's t_k * SEXBKDEV. The BACKGROUND and
BACKGROUND_RMS check-images are SExtractor's bit for bit: with a weight map source-extractor
2.25 still writes the interpolated mesh RMS (SEXTRACTOR.md section 2 says sqrt of the
variance; the program does not).

The plain MAP_WEIGHT case is compared at all 15 levels; the variants (gain, filter, RMS and
variance maps, WEIGHT_THRESH) change only how the variance enters, which every level takes the
same way, and are compared at the lowest, middle and highest level (three source-extractor runs
each instead of fifteen).
"""
import os
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (WorkDirTest, card_text, ldac_imhead, ldac_objects, require_shared,
                            run_octarc, run_sextractor, write_param)
from test_detect_vs_sextractor import (BACKGROUND_ARGS, CONV, DETECT_NLEVELS, DETECT_THRESH,
                                       DETECT_THRESH_MAX, SEX_COLUMNS, assert_rows_agree,
                                       default_levels_sigma, label_correspondence)

# The 15 levels of params/octarc.sex, given explicitly (2.5 to 20 sigma, log-spaced).
LEVELS_SIGMA = default_levels_sigma()
EVERY_LEVEL = tuple(range(1, len(LEVELS_SIGMA) + 1))
# The lowest, middle and highest level (1-based, as THRESH_LEVEL).
SAMPLED_LEVELS = (1, (len(LEVELS_SIGMA) + 1) // 2, len(LEVELS_SIGMA))


def write_weight_map(path, shape, kind="MAP_WEIGHT", zero_below=0.0, var_scale=1.0):
    """A MAP_WEIGHT map (or the equivalent MAP_RMS / MAP_VAR map, up to a constant factor);
    weights at or below `zero_below` are set to 0; MAP_VAR values are multiplied by
    `var_scale`."""
    ny, nx = shape
    yy, xx = np.mgrid[0:ny, 0:nx]
    weight = 0.8 + 0.4 * xx / nx
    weight[: ny // 2, : nx // 2] *= 0.25
    weight[500:510, :] = 0.0
    weight[weight <= zero_below] = 0.0
    if kind == "MAP_RMS":  # not rescaled: in ADU, near the image's noise
        with np.errstate(divide="ignore"):
            data = np.where(weight > 0, 60.0 / np.sqrt(weight), 1e31)
    elif kind == "MAP_VAR":
        with np.errstate(divide="ignore"):
            data = np.where(weight > 0, var_scale / weight, 1e31)
    else:
        data = weight
    fits.PrimaryHDU(data.astype(np.float32)).writeto(path, overwrite=True)
    return path


class DetectWeightMaps(WorkDirTest):

    def detect(self, image, weight_args, filter_on, tag, checks=("SEGMENTATION",)):
        param = write_param(self.path("%s.param" % tag),
                            ["THRESH_LEVEL", "PARENT_NUMBER"] + SEX_COLUMNS)
        out = self.path("%s.ldac" % tag)
        paths = {t: self.path("%s.%s.fits" % (tag, t.lower())) for t in checks}
        run_octarc("detect", image, "-c", "/usr/share/source-extractor/default.sex",
                   "-PARAMETERS_NAME", param, "-FILTER", "Y" if filter_on else "N",
                   "-FILTER_NAME", CONV, "-DETECT_THRESH", DETECT_THRESH,
                   "-DETECT_THRESH_MAX", DETECT_THRESH_MAX, "-DETECT_NLEVELS", DETECT_NLEVELS,
                   "-DETECT_MINAREA", 5, "-THRESH_TYPE", "RELATIVE", "-CATALOG_TYPE",
                   "FITS_LDAC", "-CATALOG_NAME", out, "-VERBOSE_TYPE", "QUIET",
                   "-CHECKIMAGE_TYPE", ",".join(checks),
                   "-CHECKIMAGE_NAME", ",".join(paths[t] for t in checks),
                   *BACKGROUND_ARGS, *weight_args)
        return out, paths

    def compare(self, kind, filter_on, extra_args=(), var_scale=1.0, sex_zero_below=None,
                levels=SAMPLED_LEVELS):
        """octarc and source-extractor with the same weight map and options, at `levels`; with
        `sex_zero_below`, source-extractor gets instead a map whose weights at or below it are 0
        (and no extra options), which is what WEIGHT_THRESH means for octarc."""
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        weight = write_weight_map(self.path("weight.fits"), (1024, 1024), kind,
                                  var_scale=var_scale)
        weight_args = ["-WEIGHT_TYPE", kind, "-WEIGHT_IMAGE", weight] + list(extra_args)
        sex_weight_args = weight_args
        if sex_zero_below is not None:
            sex_weight = write_weight_map(self.path("weight0.fits"), (1024, 1024), kind,
                                          zero_below=sex_zero_below)
            sex_weight_args = ["-WEIGHT_TYPE", kind, "-WEIGHT_IMAGE", sex_weight]
        out, checks = self.detect(image, weight_args, filter_on, "octarc",
                                  ("SEGMENTATION", "BACKGROUND", "BACKGROUND_RMS"))
        ours, _ = ldac_objects(out)
        imhead = ldac_imhead(out)
        param = write_param(self.path("sex.param"), SEX_COLUMNS)
        extra = ["-FILTER", "Y" if filter_on else "N", "-DETECT_MINAREA", "5",
                 "-THRESH_TYPE", "RELATIVE", "-INTERP_TYPE", "NONE"] + BACKGROUND_ARGS + \
            sex_weight_args
        with fits.open(checks["SEGMENTATION"]) as seg:
            for k in levels:
                t = LEVELS_SIGMA[k - 1]
                what = "%s FILTER %s level %d" % (kind, "Y" if filter_on else "N", k)
                # The background maps do not depend on the threshold: compared at level 1.
                sex_checks = ["SEGMENTATION"]
                if k == 1:
                    sex_checks += ["BACKGROUND", "BACKGROUND_RMS"]
                cat, sex = run_sextractor(image, self.work, "level%d" % k, param, repr(t), extra,
                                          sex_checks)
                theirs, _ = ldac_objects(cat)
                sex_head = ldac_imhead(cat)
                self.assertEqual(card_text(imhead, "SEXBKDEV"), card_text(sex_head, "SEXBKDEV"),
                                 what)
                self.assertEqual(card_text(imhead, "SEXDWSCL"), card_text(sex_head, "SEXDWSCL"),
                                 what)
                labels = seg[k].data
                self.assertFalse(np.any(labels[500:510, :]), what + ": bad pixels in objects")
                mapping = label_correspondence(self, labels, fits.getdata(sex["SEGMENTATION"]),
                                               what)
                mine = ours[ours["THRESH_LEVEL"] == k]
                # THRESHOLD: SExtractor reports a local threshold of each object with weights;
                # octarc reports the level's global one, t_k * SEXBKDEV.
                assert_rows_agree(self, mine, theirs, mapping, what, skip=("THRESHOLD",))
                # THRESHOLD is the level's threshold stored in single precision.
                np.testing.assert_array_equal(mine["THRESHOLD"],
                                              np.float32(imhead["OCTTH%d" % k]))
                if k == 1:
                    self.assertGreater(len(theirs), 100)
                    np.testing.assert_array_equal(fits.getdata(checks["BACKGROUND"]),
                                                  fits.getdata(sex["BACKGROUND"]))
                    np.testing.assert_array_equal(fits.getdata(checks["BACKGROUND_RMS"]),
                                                  fits.getdata(sex["BACKGROUND_RMS"]))

    def test_map_weight_filter_n(self):
        self.compare("MAP_WEIGHT", filter_on=False, levels=EVERY_LEVEL)

    def test_map_weight_gain_per_pixel_poisson_term(self):
        # WEIGHT_GAIN Y: the Poisson term of FLUXERR_ISO is weighted pixel by pixel.
        self.compare("MAP_WEIGHT", filter_on=False, extra_args=["-GAIN", "4", "-WEIGHT_GAIN", "Y"])

    def test_map_weight_filter_y(self):
        self.compare("MAP_WEIGHT", filter_on=True)

    def test_map_rms(self):
        self.compare("MAP_RMS", filter_on=False)

    def test_map_var(self):
        self.compare("MAP_VAR", filter_on=False)

    def test_map_var_in_adu_without_rescaling(self):
        # RESCALE_WEIGHTS N: the variances are taken as they are, in ADU^2 (SEXDWSCL 1).
        self.compare("MAP_VAR", filter_on=True, extra_args=["-RESCALE_WEIGHTS", "N"],
                     var_scale=3600.0)

    def test_weight_thresh(self):
        # WEIGHT_THRESH 0.25 makes part of the low-weight quarter bad, exactly as zero weights.
        self.compare("MAP_WEIGHT", filter_on=False, extra_args=["-WEIGHT_THRESH", "0.25"],
                     sex_zero_below=0.25)

    def test_measure_command_with_weight_map(self):
        # `octarc measure` gets the same variances through the same image preparation: on
        # SExtractor's own segmentation of a weighted run it reproduces FLUXERR_ISO (with the
        # per-pixel Poisson term of GAIN 4) and ISOAREA_IMAGE (per-pixel analysis threshold).
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        weight = write_weight_map(self.path("weight.fits"), (1024, 1024))
        weight_args = ["-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE", weight, "-GAIN", "4"]
        param = write_param(self.path("sex.param"), SEX_COLUMNS)
        cat, sex = run_sextractor(image, self.work, "sex", param, "3.0",
                                  ["-FILTER", "N", "-DETECT_MINAREA", "5", "-INTERP_TYPE", "NONE"]
                                  + BACKGROUND_ARGS + weight_args, ["SEGMENTATION", "BACKGROUND"])
        out = self.path("measure.ldac")
        run_octarc("measure", image, "-c", "/usr/share/source-extractor/default.sex",
                   "-PARAMETERS_NAME", write_param(self.path("octarc.param"), SEX_COLUMNS),
                   "-SEGMENTATION_NAME", sex["SEGMENTATION"], "-INPUT_CATALOG", cat,
                   "-APPEND_COLUMNS", "N", "-BACKGROUND_NAME", sex["BACKGROUND"], "-FILTER", "N",
                   "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out, "-VERBOSE_TYPE", "QUIET",
                   *weight_args)
        ours, _ = ldac_objects(out)
        theirs, _ = ldac_objects(cat)
        self.assertGreater(len(theirs), 100)
        mapping = {int(n): int(n) for n in theirs["NUMBER"]}
        assert_rows_agree(self, ours, theirs, mapping, "octarc measure with weights",
                          skip=("THRESHOLD",))


if __name__ == "__main__":
    unittest.main()
