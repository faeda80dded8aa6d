"""`octarc search` with lens-light subtraction (LENS_LIGHT): an arc inside the halo of a bright
de Vaucouleurs galaxy, drawn here with numpy (a renderer independent of octarc's), is no
candidate of the plain search and is found, with that galaxy as its lens and the expected
Einstein radius, in the residual (LOCAL and IMAGE); the fitted galaxy's parameters against the
ones drawn; the check-images; bad input."""
import math
import os
import shutil
import tempfile
import unittest

import numpy as np
from astropy.io import fits
from scipy.ndimage import gaussian_filter
from scipy.special import gammaincinv

from octarc_testlib import SOURCE_DIR, WorkDirTest, run_octarc
from test_search import known_grid

SEX = os.path.join(SOURCE_DIR, "params", "octarc.sex")
DEMO_GRID = os.path.join(SOURCE_DIR, "params", "demo.grid.fits")

SIZE, SCALE, SEEING, SIGMA = 200, 0.257, 0.9, 5.0
# The lens (1-based centre) and its profile; 2e5 ADU is R = 16.7 at the zero point 30.
LENS_X, LENS_Y, LENS_FLUX, LENS_RE, LENS_N, LENS_Q, LENS_THETA = 100.3, 99.6, 2.0e5, 6.0, 4.0, \
    0.7, 0.5
# The arc: a ridge of Gaussian width 1.2 px along +-40 degrees of a circle of 11 px about the
# lens, centred on the direction 0.3 rad; its flux centroid lies at 11 sin(phi)/phi px.
ARC_RADIUS, ARC_HALF, ARC_ANGLE, ARC_FLUX = 11.0, np.radians(40.0), 0.3, 6000.0


def sersic(x, y):
    """The profile at 0-based pixel offsets from the lens centre, per pixel^2."""
    b = gammaincinv(2 * LENS_N, 0.5)
    c, s = np.cos(LENS_THETA), np.sin(LENS_THETA)
    major, minor = c * x + s * y, (-s * x + c * y) / LENS_Q
    r = np.hypot(major, minor) / LENS_RE
    norm = 2 * np.pi * LENS_N * LENS_Q * LENS_RE ** 2 * np.exp(b) * b ** (-2 * LENS_N) * \
        np.exp(math.lgamma(2 * LENS_N))
    return LENS_FLUX / norm * np.exp(-b * (r ** (1 / LENS_N) - 1))


def galaxy_image():
    """The galaxy integrated over each pixel: 8 x 8 sub-pixels, 32 x 32 near the centre."""
    y, x = np.mgrid[0:SIZE, 0:SIZE].astype(float)
    dx, dy = x - (LENS_X - 1), y - (LENS_Y - 1)
    image = np.zeros((SIZE, SIZE))
    for k, where in ((8, np.hypot(dx, dy) >= 3), (32, np.hypot(dx, dy) < 3)):
        offsets = (np.arange(k) + 0.5) / k - 0.5
        part = np.zeros(where.sum())
        for oy in offsets:
            for ox in offsets:
                part += sersic(dx[where] + ox, dy[where] + oy)
        image[where] = part / k ** 2
    return image


def arc_image():
    y, x = np.mgrid[0:SIZE, 0:SIZE].astype(float)
    dx, dy = x - (LENS_X - 1), y - (LENS_Y - 1)
    r = np.hypot(dx, dy)
    along = np.abs(np.remainder(np.arctan2(dy, dx) - ARC_ANGLE + np.pi, 2 * np.pi) - np.pi)
    taper = np.where(along < ARC_HALF, 1.0,
                     np.exp(-0.5 * ((along - ARC_HALF) * r / 1.2) ** 2))
    arc = taper * np.exp(-0.5 * ((r - ARC_RADIUS) / 1.2) ** 2)
    return arc * ARC_FLUX / arc.sum()


def write_image(path, pixels):
    h = fits.Header()
    h["CTYPE1"], h["CTYPE2"] = "RA---TAN", "DEC--TAN"
    h["CRPIX1"], h["CRPIX2"] = SIZE / 2, SIZE / 2
    h["CRVAL1"], h["CRVAL2"] = 150.0, 2.0
    h["CD1_1"], h["CD2_2"] = -SCALE / 3600, SCALE / 3600
    h["CD1_2"], h["CD2_1"] = 0.0, 0.0
    h["GAIN"] = 0.0
    fits.PrimaryHDU(pixels.astype(np.float32), h).writeto(path)


class LensLightFixture(WorkDirTest):
    @classmethod
    def setUpClass(cls):
        cls.data = tempfile.mkdtemp(prefix="octarc-lenslight-")
        sky = galaxy_image() + arc_image()
        seen = gaussian_filter(sky, SEEING / SCALE / 2.3548200450309493, mode="constant")
        noise = np.random.default_rng(7).normal(0.0, SIGMA, sky.shape)
        cls.image = os.path.join(cls.data, "lens.fits")
        write_image(cls.image, seen + noise)
        # A band g of half the flux everywhere (g - r = 2.5 log10 2 for every object).
        cls.g_image = os.path.join(cls.data, "lens_g.fits")
        write_image(cls.g_image, 0.5 * seen + np.random.default_rng(8).normal(0.0, SIGMA,
                                                                              sky.shape))
        cls.grid = os.path.join(cls.data, "grid.fits")
        known_grid(DEMO_GRID, cls.grid)  # 0.05 <= ARCNESS < 0.30

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.data, ignore_errors=True)

    def search(self, *args, out="out", check=True):
        return run_octarc("search", self.image, "-c", SEX, "-GRID_NAME", self.grid,
                          "-SEEING_FWHM", str(SEEING), "-BACK_TYPE", "MANUAL", "-BACK_VALUE",
                          "0", "-OUTPUT_DIR", self.path(out), "-STAMPS", "N", "-NTHREADS", "2",
                          *args, check=check, cwd=self.work)

    def candidates(self, out="out"):
        return fits.getdata(self.path(os.path.join(out, "candidates.fits")), "LDAC_OBJECTS")


def arc_centroid():
    """The arc's flux centroid (1-based): the ridge's mean radius is R sin(phi) / phi."""
    d = ARC_RADIUS * np.sin(ARC_HALF) / ARC_HALF
    return LENS_X + d * np.cos(ARC_ANGLE), LENS_Y + d * np.sin(ARC_ANGLE)


def near_arc(cands, within_pix=3.0):
    ax, ay = arc_centroid()
    return cands[np.hypot(cands["X_IMAGE"] - ax, cands["Y_IMAGE"] - ay) < within_pix]


class SearchLensLight(LensLightFixture):
    def test_plain_search_misses_the_arc(self):
        self.search()
        self.assertEqual(len(near_arc(self.candidates())), 0)
        self.assertFalse(os.path.exists(self.path("out/lensfit.fits")))

    def check_found(self, mode):
        proc = self.search("-LENS_LIGHT", mode, "-COLOUR_IMAGE", self.g_image, "-COLOUR_BAND", "g",
                           out=mode)
        cands = self.candidates(mode)
        arc = near_arc(cands)
        self.assertEqual(len(arc), 1, cands)
        arc = arc[0]
        self.assertEqual(arc["CAND_FLAGS"] & 16, 16)
        self.assertEqual(arc["CAND_FLAGS"] & 1, 0)  # it has a lens
        # The lens is the galaxy: its level-1 row, at its fitted centre (the row's centroid is
        # pulled by the arc's 3 % of the light, by 0.3 px along the arc's direction).
        self.assertLess(np.hypot(arc["LENS_X"] - LENS_X, arc["LENS_Y"] - LENS_Y), 0.05)
        self.assertEqual(arc["LENS_LEVEL"], 1)
        # The arc centroid's distance from the lens, inside the ridge by sin(phi) / phi.
        d = np.hypot(arc["X_IMAGE"] - arc["LENS_X"], arc["Y_IMAGE"] - arc["LENS_Y"]) * SCALE
        self.assertAlmostEqual(arc["LENS_DIST"], d, delta=0.01)
        expected = ARC_RADIUS * np.sin(ARC_HALF) / ARC_HALF * SCALE
        self.assertAlmostEqual(arc["LENS_DIST"], expected, delta=0.25)
        # theta_E: the arc's circle is centred on the lens, so its radius, the ring's within 10 %
        # (the circle fitted to the residual's pixels, flux-weighted, comes out 0.9 R).
        self.assertEqual(arc["THETA_E_METHOD"], 2)
        self.assertAlmostEqual(arc["THETA_E"], arc["CURV_RADIUS"] * SCALE, delta=1e-3)
        self.assertAlmostEqual(arc["THETA_E"], ARC_RADIUS * SCALE, delta=0.1 * ARC_RADIUS * SCALE)
        self.assertGreater(arc["ARCNESS"], 0.05)
        # No residual candidate at the galaxy's own centre (closer than 1").
        lens_core = np.hypot(cands["X_IMAGE"] - LENS_X, cands["Y_IMAGE"] - LENS_Y) * SCALE < 1.0
        self.assertFalse(lens_core.any())

        # The fitted galaxy: one (the only object brighter than 20.5), its parameters as drawn.
        fit = fits.getdata(self.path(mode + "/lensfit.fits"), "LENSFIT")
        self.assertEqual(len(fit), 1)
        g = fit[0]
        self.assertEqual(g["LENSFIT_FLAGS"], 0)
        self.assertAlmostEqual(g["SERSIC_X"], LENS_X, delta=0.05)
        self.assertAlmostEqual(g["SERSIC_Y"], LENS_Y, delta=0.05)
        self.assertAlmostEqual(g["SERSIC_N"], LENS_N, delta=0.4)
        self.assertAlmostEqual(g["SERSIC_Q"], LENS_Q, delta=0.02)
        self.assertAlmostEqual(g["SERSIC_RE"] / LENS_RE, 1.0, delta=0.1)
        self.assertAlmostEqual(g["SERSIC_THETA"], np.degrees(LENS_THETA), delta=2.0)
        self.assertLess(g["SERSIC_CHI2NU"], 1.3)
        # The candidate's lens is this galaxy under the number the candidates give it (IMAGE:
        # appended past the residual's objects), and its footprint gives it colours in both modes.
        self.assertEqual(g["LENS_NUMBER"], arc["LENS_NUMBER"])
        if mode == "LOCAL":
            self.assertEqual(g["LENS_NUMBER"], g["NUMBER"])
        self.assertTrue(np.isfinite(arc["LENS_MAG_g"]))
        self.assertAlmostEqual(arc["LENS_COLOUR_g"], 2.5 * np.log10(2.0),
                               delta=3 * arc["LENS_COLOURERR_g"] + 0.01)
        # The check-images: the model in the 20" cut-out only, the residual = image - model.
        model = fits.getdata(self.path(mode + "/lensmodel.fits"))
        residual = fits.getdata(self.path(mode + "/lensresidual.fits"))
        image = fits.getdata(self.image)
        self.assertEqual(model.shape, image.shape)
        half = int(np.ceil(10.0 / SCALE))
        # Centred on the pixel nearest the galaxy's catalog centroid (0-based).
        cx, cy = int(round(g["X_IMAGE"] - 1)), int(round(g["Y_IMAGE"] - 1))
        outside = np.ones_like(model, bool)
        outside[cy - half:cy + half + 1, cx - half:cx + half + 1] = False
        self.assertEqual(np.abs(model[outside]).max(), 0.0)
        np.testing.assert_allclose(residual, image - model, atol=1e-3)
        self.assertEqual(fits.getheader(self.path(mode + "/lensmodel.fits"))["CTYPE1"],
                         "RA---TAN")
        # The galaxy is gone from the residual: away from the arc, only noise remains.
        y, x = np.mgrid[0:SIZE, 0:SIZE]
        ring = (np.hypot(x - (LENS_X - 1), y - (LENS_Y - 1)) < 20) & \
            (np.abs(np.hypot(x - (LENS_X - 1), y - (LENS_Y - 1)) - ARC_RADIUS) > 5)
        self.assertLess(np.sqrt(np.mean(residual[ring] ** 2)), 1.3 * SIGMA)
        self.assertIn("1 galaxies fitted", proc.stderr + proc.stdout)
        return arc

    def test_local_subtraction_finds_the_arc(self):
        self.check_found("LOCAL")

    def test_image_subtraction_finds_the_arc(self):
        self.check_found("IMAGE")

    def test_batch_keeps_the_residual_arc_without_check_images(self):
        # A one-tile batch: the survey catalog holds the residual's arc; the tile has its
        # lensfit.fits but, unless asked for, not the two image-sized check-images.
        manifest = self.path("survey.csv")
        with open(manifest, "w") as f:
            f.write("image\n%s\n" % self.image)
        run_octarc("batch", manifest, "-c", SEX, "-GRID_NAME", self.grid, "-SEEING_FWHM",
                   str(SEEING), "-BACK_TYPE", "MANUAL", "-BACK_VALUE", "0", "-LENS_LIGHT", "LOCAL",
                   "-OUTPUT_DIR", self.path("batch"), "-NTHREADS", "2", cwd=self.work)
        arc = near_arc(fits.getdata(self.path("batch/candidates.fits"), "LDAC_OBJECTS"))
        self.assertEqual(len(arc), 1)
        self.assertEqual(arc[0]["CAND_FLAGS"] & 16, 16)
        tile = self.path("batch/tiles/lens")
        self.assertEqual(len(fits.getdata(os.path.join(tile, "lensfit.fits"), "LENSFIT")), 1)
        self.assertFalse(os.path.exists(os.path.join(tile, "lensmodel.fits")))
        self.assertFalse(os.path.exists(os.path.join(tile, "lensresidual.fits")))


class LensLightBadInput(LensLightFixture):
    def check_refused(self, args, words):
        proc = self.search(*args, check=False)
        self.assertNotEqual(proc.returncode, 0)
        message = proc.stderr.strip().splitlines()[-1]
        for w in words:
            self.assertIn(w, message)
        self.assertFalse(os.path.exists(self.path("out")))

    def test_bad_mode(self):
        self.check_refused(["-LENS_LIGHT", "ALL"], ["LENS_LIGHT", "LOCAL", "IMAGE"])

    def test_bad_expression(self):
        self.check_refused(["-LENS_LIGHT", "LOCAL", "-LENS_SELECT", "MAG_ISO <"], ["LENS_SELECT"])

    def test_unknown_column(self):
        self.check_refused(["-LENS_LIGHT", "LOCAL", "-LENS_SELECT", "FLUX_AUTO < 3"],
                           ["LENS_SELECT", "FLUX_AUTO"])

    def test_not_with_an_input_catalog(self):
        catalog = self.path("in.ldac")
        run_octarc("detect", self.image, "-c", SEX, "-CATALOG_NAME", catalog, cwd=self.work)
        self.check_refused(["-LENS_LIGHT", "IMAGE", "-INPUT_CATALOG", catalog],
                           ["LENS_LIGHT", "INPUT_CATALOG"])

    def test_not_in_dual_image_mode(self):
        proc = run_octarc("search", self.image + "," + self.image, "-c", SEX, "-GRID_NAME",
                          self.grid, "-LENS_LIGHT", "LOCAL", "-OUTPUT_DIR", self.path("out"),
                          check=False, cwd=self.work)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("dual-image", proc.stderr)
        self.assertFalse(os.path.exists(self.path("out")))


if __name__ == "__main__":
    unittest.main()
