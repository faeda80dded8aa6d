"""`octarc search` with a colour band, on the two-band example of testdata/ (made by
scripts/make-multiband-example.py, whose injected positions and colours are in
testdata/multiband.truth.txt): the blue arc's lens and colours against the injected ones, the
dark-lens pair (CAND_FLAGS 32, no lens, the counter-image's position), the colour cut and its
count, the colour stamps' hues against the injected colours and the vetting page's colour box
(in headless Chromium); and bad colour input."""
import os
import shutil
import tempfile
import unittest

import numpy as np
from astropy.io import fits
from astropy.wcs import WCS
from PIL import Image

from octarc_testlib import (SOURCE_DIR, WorkDirTest, have_program, run_octarc,
                            run_page_in_chromium)
from test_search import known_grid

SEX = os.path.join(SOURCE_DIR, "params", "octarc.sex")
TESTDATA = os.path.join(SOURCE_DIR, "testdata")
R_IMAGE = os.path.join(TESTDATA, "multiband.r.fits.gz")
G_IMAGE = os.path.join(TESTDATA, "multiband.g.fits.gz")
G_ZEROPOINT = "29.5"  # the g image's MAGZERO; r has MAG_ZEROPOINT 30 of octarc.sex
# A measured colour agrees with the injected one within 3 sigma and 0.05 mag (light of the lens
# inside the arc's footprint makes arcs slightly redder).
SIGMAS, FLOOR = 3.0, 0.05


def truth():
    """name -> (x, y, r mag, g - r) of what the example holds (1-based pixels)."""
    out = {}
    with open(os.path.join(TESTDATA, "multiband.truth.txt")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            name, x, y, r_mag, g_r = line.split()
            out[name] = (float(x), float(y), float(r_mag), float(g_r))
    return out


class ColourFixture(WorkDirTest):
    """A grid of known contents (0.05 <= ARCNESS < 0.30, so that lenses and round galaxies are
    never candidates), made once."""

    @classmethod
    def setUpClass(cls):
        cls.data = tempfile.mkdtemp(prefix="octarc-colours-")
        cls.grid = os.path.join(cls.data, "grid.fits")
        known_grid(os.path.join(SOURCE_DIR, "params", "demo.grid.fits"), cls.grid)
        cls.truth = truth()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.data, ignore_errors=True)

    def search(self, *args, out="out", check=True, colours=True):
        colour_args = ["-COLOUR_IMAGE", G_IMAGE, "-COLOUR_BAND", "g", "-COLOUR_ZEROPOINT",
                       G_ZEROPOINT] if colours else []
        return run_octarc("search", R_IMAGE, "-c", SEX, "-GRID_NAME", self.grid,
                          "-OUTPUT_DIR", self.path(out), "-NTHREADS", "2", *colour_args, *args,
                          check=check, cwd=self.work)

    def candidates(self, out="out"):
        return fits.getdata(self.path(os.path.join(out, "candidates.fits")), "LDAC_OBJECTS")

    def near(self, cand, name, radius_pix):
        """The candidates within radius_pix of the injected object `name`."""
        x, y = self.truth[name][:2]
        return cand[np.hypot(cand["X_IMAGE"] - x, cand["Y_IMAGE"] - y) < radius_pix]

    def assert_colour(self, measured, error, name):
        injected = self.truth[name][3]
        self.assertTrue(np.isfinite(measured) and error > 0, name)
        self.assertLess(abs(measured - injected), SIGMAS * error + FLOOR,
                        "%s: g - r %.3f +- %.3f, injected %.2f" % (name, measured, error, injected))


def stamp_flux_ratio(stamp_dir, number, x, y):
    """Blue over red and green over red of the colour stamp of candidate `number` in the 3 x 3
    image pixels around the image's 1-based pixel (x, y): each pixel's colour is read at its
    centre in the PNG, placed through the FITS cut-out's LTV (cut-out = image + LTV) and the
    stamp's layout (a frame of 1.5 % of the side, the cut-out filling the rest)."""
    png = Image.open(os.path.join(stamp_dir, "%04d.colour.png" % number)).convert("RGB")
    cut = fits.getheader(os.path.join(stamp_dir, "%04d.fits" % number))
    side = png.size[0]
    margin = 0.015 * side
    per_pixel = (side - 2 * margin) / max(cut["NAXIS1"], cut["NAXIS2"])
    total = np.zeros(3)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            xc = round(x) + dx + cut["LTV1"]
            yc = round(y) + dy + cut["LTV2"]
            u = int(margin + (xc - 0.5) * per_pixel)
            v = int(side - margin - (yc - 0.5) * per_pixel)
            total += png.getpixel((u, v))
    return total[2] / total[0], total[1] / total[0]


class SearchColours(ColourFixture):

    def assert_colour_stamps(self, out):
        """A colour stamp beside every grey one, offered by the vetting page; its hue at the blue
        arc and at its red lens that of the injected colours: on the searched band's (r) flux
        scale, blue (g) over red (r) is 10^(-0.4 (g - r)), green their mean."""
        cand = self.candidates(out)
        stamps = self.path(os.path.join(out, "stamps"))
        for n in cand["NUMBER"]:
            self.assertTrue(os.path.isfile(os.path.join(stamps, "%04d.colour.png" % n)), n)
        with open(self.path(os.path.join(out, "index.html"))) as f:
            page = f.read()
        self.assertIn('"colour":"stamps/0001.colour.png"', page)
        self.assertIn('id="colour-toggle"', page)
        number = self.near(cand, "a.arc", 4.0)["NUMBER"][0]
        for name, tolerance in (("a.arc", 0.15), ("a.lens", 0.05)):
            x, y, _, g_r = self.truth[name]
            blue, green = stamp_flux_ratio(stamps, number, x, y)
            self.assertAlmostEqual(blue, 10 ** (-0.4 * g_r), delta=tolerance, msg=name)
            self.assertAlmostEqual(green, 0.5 * (1 + 10 ** (-0.4 * g_r)), delta=tolerance,
                                   msg=name)
        arc_blue = stamp_flux_ratio(stamps, number, *self.truth["a.arc"][:2])[0]
        lens_blue = stamp_flux_ratio(stamps, number, *self.truth["a.lens"][:2])[0]
        self.assertGreater(arc_blue, 2 * lens_blue)


    def test_lens_and_colours_of_the_blue_arc(self):
        self.search()
        cand = self.candidates()
        arc = self.near(cand, "a.arc", 4.0)
        self.assertEqual(len(arc), 1, cand["X_IMAGE"])
        arc = arc[0]
        lens_x, lens_y = self.truth["a.lens"][:2]
        self.assertLess(np.hypot(arc["LENS_X"] - lens_x, arc["LENS_Y"] - lens_y), 1.0)
        self.assertEqual(arc["CAND_FLAGS"] & 33, 0)
        self.assert_colour(arc["ARC_COLOUR_g"], arc["ARC_COLOURERR_g"], "a.arc")
        self.assert_colour(arc["LENS_COLOUR_g"], arc["LENS_COLOURERR_g"], "a.lens")
        # The colours are the g magnitudes minus the r ones of the same footprints.
        self.assertAlmostEqual(arc["ARC_COLOUR_g"], arc["MAG_g"] - arc["MAG_ISO"], delta=1e-3)
        self.assertAlmostEqual(arc["LENS_COLOUR_g"], arc["LENS_MAG_g"] - arc["LENS_MAG"],
                               delta=1e-3)
        self.assertAlmostEqual(arc["ARC_COLOURERR_g"],
                               np.hypot(arc["MAGERR_g"], arc["MAGERR_ISO"]), delta=1e-4)
        # The arc is blue and the lens red by the injected difference, 1.1 mag.
        self.assertLess(arc["ARC_COLOUR_g"] - arc["LENS_COLOUR_g"], -0.8)
        h = fits.getheader(self.path("out/candidates.fits"), "LDAC_OBJECTS")
        self.assertEqual((h["NCOLBAND"], h["COLBAND1"], h["NCOLCUT"]), (1, "g", 0))
        with open(self.path("out/index.html")) as f:
            self.assertIn('"bands":["g"]', f.read())
        self.assert_colour_stamps("out")

    def test_dark_lens_pair_has_no_lens_and_flag_32(self):
        self.search()
        cand = self.candidates()
        primary = self.near(cand, "b.arc", 4.0)
        self.assertEqual(len(primary), 1)
        primary = primary[0]
        self.assertEqual(primary["CAND_FLAGS"] & 33, 33)
        self.assertEqual(primary["LENS_NUMBER"], 0)
        self.assertTrue(np.isnan(primary["LENS_X"]))
        sec_x, sec_y = self.truth["b.counter"][:2]
        self.assertLess(np.hypot(primary["SEC_X"] - sec_x, primary["SEC_Y"] - sec_y), 2.0)
        ra, dec = WCS(fits.getheader(R_IMAGE)).all_pix2world(primary["SEC_X"], primary["SEC_Y"], 1)
        self.assertAlmostEqual(primary["SEC_ALPHA"], float(ra), delta=1e-6)
        self.assertAlmostEqual(primary["SEC_DELTA"], float(dec), delta=1e-6)
        self.assert_colour(primary["ARC_COLOUR_g"], primary["ARC_COLOURERR_g"], "b.arc")
        # No other candidate is a pair, and candidates without one have no counter-image.
        self.assertEqual(int(np.sum(cand["CAND_FLAGS"] & 32 > 0)), 1)
        self.assertTrue(np.all(np.isnan(cand["SEC_X"][(cand["CAND_FLAGS"] & 32) == 0])))
        h = fits.getheader(self.path("out/candidates.fits"), "LDAC_OBJECTS")
        self.assertEqual(h["NDARKPR"], 1)
        with open(self.path("out/summary.txt")) as f:
            self.assertIn("1 dark-lens pair(s)", f.read())
        # Without the colour band the counter-image is the only galaxy on the concave side,
        # and becomes the lens.
        self.search(out="plain", colours=False)
        plain = self.near(self.candidates("plain"), "b.arc", 4.0)[0]
        self.assertEqual(plain["CAND_FLAGS"] & 33, 0)
        self.assertLess(np.hypot(plain["LENS_X"] - sec_x, plain["LENS_Y"] - sec_y), 2.0)
        self.assertNotIn("MAG_g", self.candidates("plain").columns.names)
        # No colour stamp without a colour band.
        self.assertEqual([f for f in os.listdir(self.path("plain/stamps")) if "colour" in f], [])
        with open(self.path("plain/index.html")) as f:
            self.assertNotIn('"colour":', f.read())

    def test_colour_cut_removes_the_arc_of_its_lens_colour(self):
        self.search()
        before = self.candidates()
        red = self.near(before, "c.arc", 4.0)
        self.assertEqual(len(red), 1)
        lens_x, lens_y = self.truth["c.lens"][:2]
        self.assertLess(np.hypot(red[0]["LENS_X"] - lens_x, red[0]["LENS_Y"] - lens_y), 1.0)
        # Injected: the blue arc 1.1 mag bluer than its lens, the red arc of its lens's colour.
        self.search("-COLOUR_CUT", "g,-0.5", out="cut")
        after = self.candidates("cut")
        self.assertEqual(len(self.near(after, "c.arc", 4.0)), 0)
        self.assertEqual(len(self.near(after, "a.arc", 4.0)), 1)
        self.assertEqual(len(self.near(after, "b.arc", 4.0)), 1)  # no lens: kept
        self.assertEqual(len(after), len(before) - 1)
        h = fits.getheader(self.path("cut/candidates.fits"), "LDAC_OBJECTS")
        self.assertEqual((h["NCOLCUT"], h["COLCUTBD"], h["COLCUTMX"]), (1, "g", -0.5))
        self.assertEqual(h["NCANDID"], len(after))
        with open(self.path("cut/summary.txt")) as f:
            self.assertIn("Colour cut COLOUR_CUT g,-0.5: %d candidate(s) before the cut, 1 removed "
                          "(arc minus lens colour in g above -0.5 mag), %d after it; every other "
                          "count is after the cut" % (len(before), len(after)), f.read())


class SearchColoursPage(ColourFixture):

    def test_colour_box_swaps_the_stamps(self):
        if not have_program("chromium") and os.environ.get("CI", "").lower() != "true":
            self.skipTest("program not installed: chromium")
        self.search()
        driver = """
        const $ = id => document.getElementById(id);
        const images = () => Array.from(document.querySelectorAll('#grid .card img'));
        const sources = () => images().map(i => i.getAttribute('src'));
        const shown = !$('colour-toggle').hidden;
        const grey = sources();
        $('colour').checked = true;
        $('colour').dispatchEvent(new Event('change'));
        const colour = sources();
        const lazy = images().every(i => i.loading === 'lazy');
        $('colour').checked = false;
        $('colour').dispatchEvent(new Event('change'));
        report({shown, grey, colour, lazy, back: sources(), pageErrors});
        """
        result, _ = run_page_in_chromium(self.path("out/index.html"), driver, self.work)
        self.assertEqual(result["pageErrors"], [])
        self.assertTrue(result["shown"])
        self.assertEqual(len(result["grey"]), len(self.candidates()))
        self.assertTrue(all(s.endswith(".png") and ".colour" not in s for s in result["grey"]))
        self.assertEqual(result["colour"],
                         [s[:-len(".png")] + ".colour.png" for s in result["grey"]])
        self.assertTrue(result["lazy"])
        self.assertEqual(result["back"], result["grey"])


class SearchColoursBadInput(ColourFixture):

    def assert_refused(self, result, *words):
        self.assertNotEqual(result.returncode, 0)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        for w in words:
            self.assertIn(w, result.stderr)
        self.assertFalse(os.path.exists(self.path("out")))

    def test_colour_image_on_another_pixel_grid_names_both_files(self):
        with fits.open(G_IMAGE) as f:
            fits.PrimaryHDU(f[0].data[:, 1:], f[0].header).writeto(self.path("narrow.fits"))
            shifted = f[0].header.copy()
            shifted["CRPIX1"] += 1.0
            fits.PrimaryHDU(f[0].data, shifted).writeto(self.path("shifted.fits"))
        for image, why in (("narrow.fits", "299x300"), ("shifted.fits", "WCS")):
            r = self.search("-COLOUR_IMAGE", self.path(image), "-VERBOSE_TYPE", "QUIET",
                            check=False)
            self.assert_refused(r, image, "multiband.r.fits.gz", why)

    def test_band_counts_must_agree(self):
        r = self.search("-COLOUR_IMAGE", "%s,%s" % (G_IMAGE, G_IMAGE), check=False)
        self.assert_refused(r, "COLOUR_BAND", "2 COLOUR_IMAGE")
        r = self.search("-COLOUR_ZEROPOINT", "29.5,29.5", check=False)
        self.assert_refused(r, "COLOUR_ZEROPOINT")
        r = self.search("-COLOUR_CUT", "i,0", check=False)
        self.assert_refused(r, "COLOUR_CUT", "'i'")
        r = self.search("-COLOUR_CUT", "g", check=False)
        self.assert_refused(r, "COLOUR_CUT")
        r = self.search("-COLOUR_BAND", "g-r", check=False)
        self.assert_refused(r, "COLOUR_BAND")

    def test_manual_background_other_than_zero(self):
        # The measurement image's constant sky is not another band's; 0 (subtracted) is allowed.
        r = self.search("-BACK_TYPE", "MANUAL", "-BACK_VALUE", "10", check=False)
        self.assert_refused(r, "COLOUR_IMAGE", "BACK_VALUE 10", "BACK_TYPE AUTO")

    def test_no_colours_from_an_input_catalog(self):
        r = self.search("-INPUT_CATALOG", self.path("levels.ldac"), check=False)
        self.assert_refused(r, "COLOUR_IMAGE", "INPUT_CATALOG")


if __name__ == "__main__":
    unittest.main()
