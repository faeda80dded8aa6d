"""`octarc search` with the lens modelled in a redder band (LENS_LIGHT_BAND): two images of one
lens drawn here with numpy (a renderer independent of octarc's), a red de Vaucouleurs galaxy
with a blue arc close to it. In the searched band g the arc is bright; in the colour band i the
galaxy is 2.5 times brighter and the arc ten times fainter, and the seeing is sharper. The
residual keeps the arc's injected light where the one-band fit (LENS_LIGHT LOCAL alone) takes
much of it into the model; the galaxy's light is gone; the fitted flux ratio is the injected one
(LOCAL and IMAGE); and bad settings are refused with one line naming the key."""
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
FWHM_PER_SIGMA = 2.3548200450309493

SIZE, SCALE, SIGMA = 200, 0.257, 5.0
# Seeing FWHM (arcsec) of the searched band g and of the colour band i.
SEEING_G, SEEING_I = 1.0, 0.7
# The lens (1-based centre): de Vaucouleurs, its total flux in each band (g / i = 0.4, R = 18.5
# in g at the zero point 30).
LENS_X, LENS_Y, LENS_RE, LENS_N, LENS_Q, LENS_THETA = 100.3, 99.6, 6.0, 4.0, 0.75, 0.5
LENS_FLUX_G, LENS_FLUX_I = 4.0e4, 1.0e5
# The arc: a ridge of Gaussian width 1.2 px along +-90 degrees of a circle of 6 px (1.5") about
# the lens, its flux in each band: bright in g (0.375 of the lens's), a tenth of that in i (a
# blue source: g - i = -2.5 mag against the lens's +1 mag). Close and bright, it draws the g fit
# (its index and radius) far enough to take in much of the arc.
ARC_RADIUS, ARC_HALF, ARC_ANGLE = 6.0, np.radians(90.0), 0.3
ARC_FLUX_G, ARC_FLUX_I = 15000.0, 1500.0


def sersic(dx, dy, flux):
    """The lens profile at 0-based pixel offsets from its centre, per pixel^2."""
    b = gammaincinv(2 * LENS_N, 0.5)
    c, s = np.cos(LENS_THETA), np.sin(LENS_THETA)
    major, minor = c * dx + s * dy, (-s * dx + c * dy) / LENS_Q
    r = np.hypot(major, minor) / LENS_RE
    norm = 2 * np.pi * LENS_N * LENS_Q * LENS_RE ** 2 * np.exp(b) * b ** (-2 * LENS_N) * \
        np.exp(math.lgamma(2 * LENS_N))
    return flux / norm * np.exp(-b * (r ** (1 / LENS_N) - 1))


def offsets():
    y, x = np.mgrid[0:SIZE, 0:SIZE].astype(float)
    return x - (LENS_X - 1), y - (LENS_Y - 1)


def galaxy(flux):
    """The galaxy integrated over each pixel: 8 x 8 sub-pixels, 32 x 32 near the centre."""
    dx, dy = offsets()
    image = np.zeros((SIZE, SIZE))
    for k, where in ((8, np.hypot(dx, dy) >= 3), (32, np.hypot(dx, dy) < 3)):
        steps = (np.arange(k) + 0.5) / k - 0.5
        part = np.zeros(where.sum())
        for oy in steps:
            for ox in steps:
                part += sersic(dx[where] + ox, dy[where] + oy, flux)
        image[where] = part / k ** 2
    return image


def arc(flux):
    dx, dy = offsets()
    r = np.hypot(dx, dy)
    along = np.abs(np.remainder(np.arctan2(dy, dx) - ARC_ANGLE + np.pi, 2 * np.pi) - np.pi)
    taper = np.where(along < ARC_HALF, 1.0, np.exp(-0.5 * ((along - ARC_HALF) * r / 1.2) ** 2))
    ridge = taper * np.exp(-0.5 * ((r - ARC_RADIUS) / 1.2) ** 2)
    return ridge * flux / ridge.sum()


def seen(sky, seeing_arcsec):
    return gaussian_filter(sky, seeing_arcsec / SCALE / FWHM_PER_SIGMA, mode="constant")


def write_image(path, pixels):
    h = fits.Header()
    h["CTYPE1"], h["CTYPE2"] = "RA---TAN", "DEC--TAN"
    h["CRPIX1"], h["CRPIX2"] = SIZE / 2, SIZE / 2
    h["CRVAL1"], h["CRVAL2"] = 150.0, 2.0
    h["CD1_1"], h["CD2_2"] = -SCALE / 3600, SCALE / 3600
    h["CD1_2"], h["CD2_1"] = 0.0, 0.0
    h["GAIN"] = 0.0
    fits.PrimaryHDU(pixels.astype(np.float32), h).writeto(path)


class BandFixture(WorkDirTest):
    DRAW = True  # the lens and arc; without, noise only (settings refused before any pixel)

    @classmethod
    def setUpClass(cls):
        cls.data = tempfile.mkdtemp(prefix="octarc-lenslight-band-")
        noise_g = np.random.default_rng(3).normal(0.0, SIGMA, (SIZE, SIZE))
        noise_i = np.random.default_rng(4).normal(0.0, SIGMA, (SIZE, SIZE))
        cls.g_image = os.path.join(cls.data, "lens_g.fits")
        cls.i_image = os.path.join(cls.data, "lens_i.fits")
        if cls.DRAW:
            unit_galaxy, unit_arc = galaxy(1.0), arc(1.0)
            cls.lens_g = seen(LENS_FLUX_G * unit_galaxy, SEEING_G)
            cls.arc_g = seen(ARC_FLUX_G * unit_arc, SEEING_G)
            write_image(cls.g_image, cls.lens_g + cls.arc_g + noise_g)
            write_image(cls.i_image, seen(LENS_FLUX_I * unit_galaxy + ARC_FLUX_I * unit_arc,
                                          SEEING_I) + noise_i)
        else:
            write_image(cls.g_image, noise_g)
            write_image(cls.i_image, noise_i)
        cls.grid = os.path.join(cls.data, "grid.fits")
        known_grid(DEMO_GRID, cls.grid)  # 0.05 <= ARCNESS < 0.30

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.data, ignore_errors=True)

    def search(self, out, *args, check=True):
        return run_octarc("search", self.g_image, "-c", SEX, "-GRID_NAME", self.grid,
                          "-SEEING_FWHM", str(SEEING_G), "-BACK_TYPE", "MANUAL", "-BACK_VALUE",
                          "0", "-OUTPUT_DIR", self.path(out), "-STAMPS", "N", "-NTHREADS", "2",
                          "-COLOUR_IMAGE", self.i_image, "-COLOUR_BAND", "i", *args, check=check,
                          cwd=self.work)

    def arc_pixels(self):
        """Where the seen arc holds at least a tenth of its peak."""
        return self.arc_g > 0.1 * self.arc_g.max()

    def kept_arc_fraction(self, residual):
        """The residual's sum over the arc's pixels over the arc's own light there."""
        where = self.arc_pixels()
        return residual[where].sum() / self.arc_g[where].sum()


class SearchLensLightBand(BandFixture):
    def test_two_band_subtraction_keeps_the_arc(self):
        self.search("one", "-LENS_LIGHT", "LOCAL")
        proc = self.search("two", "-LENS_LIGHT", "LOCAL", "-LENS_LIGHT_BAND", "i",
                           "-COLOUR_SEEING_FWHM", str(SEEING_I))
        one = fits.getdata(self.path("one/lensresidual.fits")).astype(float)
        two = fits.getdata(self.path("two/lensresidual.fits")).astype(float)
        kept_one, kept_two = self.kept_arc_fraction(one), self.kept_arc_fraction(two)
        print("arc light kept: one band %.3f, two bands %.3f" % (kept_one, kept_two))
        # Nearly all of the arc is left where the model came from i; the g fit alone, drawn
        # towards the arc, takes in most of it.
        self.assertGreater(kept_two, 0.9)
        self.assertLess(kept_one, 0.6)

        # The galaxy's light is gone: within 20 px, and within 2", the residual less the arc's
        # own light is a small part of the galaxy's light there (the flux ratio, measured in the
        # core where the arc's seeing wings add a little, over-subtracts it by about as much).
        dx, dy = offsets()
        for radius_pix in (20.0, 2.0 / SCALE):
            disc = np.hypot(dx, dy) < radius_pix
            leftover = (two[disc] - self.arc_g[disc]).sum() / self.lens_g[disc].sum()
            print("galaxy light left within %.1f px: %.4f" % (radius_pix, leftover))
            self.assertLess(abs(leftover), 0.03)
        # Away from the arc, what is left is the noise.
        ring = (np.hypot(dx, dy) < 20) & (np.abs(np.hypot(dx, dy) - ARC_RADIUS) > 5)
        self.assertLess(np.sqrt(np.mean(two[ring] ** 2)), 1.3 * SIGMA)

        # The fit: one galaxy, from band i (flag 32), its flux ratio g / i the injected one, its
        # shape the drawn one, its flux the g band's.
        fit = fits.getdata(self.path("two/lensfit.fits"), "LENSFIT")
        self.assertEqual(len(fit), 1)
        g = fit[0]
        self.assertEqual(g["LENSFIT_FLAGS"], 32)
        # Within 2.5 % (the arc's light in the core raises it a little).
        self.assertAlmostEqual(g["BAND_RATIO"], LENS_FLUX_G / LENS_FLUX_I, delta=0.01)
        self.assertAlmostEqual(g["SERSIC_FLUX"] / LENS_FLUX_G, 1.0, delta=0.05)
        self.assertAlmostEqual(g["SERSIC_X"], LENS_X, delta=0.05)
        self.assertAlmostEqual(g["SERSIC_Y"], LENS_Y, delta=0.05)
        self.assertAlmostEqual(g["SERSIC_N"], LENS_N, delta=0.3)
        self.assertAlmostEqual(g["SERSIC_RE"] / LENS_RE, 1.0, delta=0.1)
        self.assertAlmostEqual(g["SERSIC_Q"], LENS_Q, delta=0.02)
        one_fit = fits.getdata(self.path("one/lensfit.fits"), "LENSFIT")
        self.assertEqual(one_fit["LENSFIT_FLAGS"][0] & 32, 0)
        self.assertTrue(np.isnan(one_fit["BAND_RATIO"][0]))
        self.assertIn("LENS_LIGHT_BAND i", proc.stdout + proc.stderr)

        # The arc is a candidate of the residual, with the galaxy as its lens.
        cands = fits.getdata(self.path("two/candidates.fits"), "LDAC_OBJECTS")
        residual = cands[(cands["CAND_FLAGS"] & 16) == 16]
        self.assertEqual(len(residual), 1, cands)
        self.assertLess(np.hypot(residual[0]["LENS_X"] - LENS_X, residual[0]["LENS_Y"] - LENS_Y),
                        0.1)
        d = np.hypot(residual[0]["X_IMAGE"] - LENS_X, residual[0]["Y_IMAGE"] - LENS_Y)
        self.assertAlmostEqual(d, ARC_RADIUS * np.sin(ARC_HALF) / ARC_HALF, delta=1.5)

    def test_image_mode_subtracts_the_same_model(self):
        # LENS_LIGHT IMAGE searches the residual image: the model is fitted in i there too.
        self.search("image", "-LENS_LIGHT", "IMAGE", "-LENS_LIGHT_BAND", "i",
                    "-COLOUR_SEEING_FWHM", str(SEEING_I))
        residual = fits.getdata(self.path("image/lensresidual.fits")).astype(float)
        self.assertGreater(self.kept_arc_fraction(residual), 0.9)
        fit = fits.getdata(self.path("image/lensfit.fits"), "LENSFIT")
        self.assertEqual(list(fit["LENSFIT_FLAGS"]), [32])
        self.assertAlmostEqual(fit["BAND_RATIO"][0], LENS_FLUX_G / LENS_FLUX_I, delta=0.01)


class LensLightBandBadInput(BandFixture):
    DRAW = False

    def check_refused(self, args, words):
        proc = self.search("out", *args, check=False)
        self.assertNotEqual(proc.returncode, 0)
        message = proc.stderr.strip().splitlines()[-1]
        for w in words:
            self.assertIn(w, message)
        self.assertFalse(os.path.exists(self.path("out")))

    def test_band_not_among_the_colour_bands(self):
        self.check_refused(["-LENS_LIGHT", "LOCAL", "-LENS_LIGHT_BAND", "z"],
                           ["LENS_LIGHT_BAND", "'z'", "COLOUR_BAND"])

    def test_no_colour_image(self):
        proc = run_octarc("search", self.g_image, "-c", SEX, "-GRID_NAME", self.grid,
                          "-LENS_LIGHT", "LOCAL", "-LENS_LIGHT_BAND", "i", "-OUTPUT_DIR",
                          self.path("out"), check=False, cwd=self.work)
        self.assertNotEqual(proc.returncode, 0)
        message = proc.stderr.strip().splitlines()[-1]
        self.assertIn("LENS_LIGHT_BAND", message)
        self.assertIn("COLOUR_IMAGE", message)
        self.assertFalse(os.path.exists(self.path("out")))

    def test_without_lens_light(self):
        self.check_refused(["-LENS_LIGHT_BAND", "i"], ["LENS_LIGHT_BAND", "LENS_LIGHT"])

    def test_one_seeing_per_colour_image(self):
        self.check_refused(["-LENS_LIGHT", "LOCAL", "-LENS_LIGHT_BAND", "i",
                            "-COLOUR_SEEING_FWHM", "0.7,0.8"], ["COLOUR_SEEING_FWHM"])


if __name__ == "__main__":
    unittest.main()
