"""`octarc simulate lenses --band` and the colour cut study of `octarc calibrate` (issue 13:
simulations in two bands, so that the search's colour cut can be calibrated): the first band
unchanged by the second, the band's columns against the first band's magnitudes, the injected
colours, reproducibility, the study's table counted by hand with numpy, and bad input."""
import os
import shutil
import tempfile
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import SOURCE_DIR, WorkDirTest, ldac_imhead, run_octarc
from test_hostile_input import with_card

DLS = os.path.join(SOURCE_DIR, "params", "simulation", "population-dls.txt")
# Large Einstein radii and bright sources, so that a few hundred systems hold tens of arcs.
SIMULATION = ["-n", "600", "--seed", "8", "--population", DLS, "--sigma-min", "300",
              "--source-mag-min", "21", "--source-mag-max", "23", "--quiet"]
BAND_COLUMNS = ["MAG_g", "MAGERR_g", "LENS_MAG_g", "LENS_MAGERR_g", "ARC_COLOUR_g",
                "ARC_COLOURERR_g", "LENS_COLOUR_g", "LENS_COLOURERR_g"]


def same_values(a, b):
    if a.dtype.kind == "f":
        return np.array_equal(a, b, equal_nan=True)
    return np.array_equal(a, b)


class TwoBands(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="octarc-two-bands-")
        cls.one = os.path.join(cls.dir, "one.fits")
        cls.two = os.path.join(cls.dir, "two.fits")
        cls.again = os.path.join(cls.dir, "again.fits")
        run_octarc("simulate", "lenses", *SIMULATION, "-o", cls.one, "--threads", "2")
        run_octarc("simulate", "lenses", *SIMULATION, "-o", cls.two, "--threads", "2",
                   "--band", "g")
        # The same seed on another number of threads.
        run_octarc("simulate", "lenses", *SIMULATION, "-o", cls.again, "--threads", "1",
                   "--band", "g")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_first_band_is_the_run_without_a_band(self):
        for table in ("LDAC_OBJECTS", "ARCS"):
            one = fits.getdata(self.one, table)
            two = fits.getdata(self.two, table)
            self.assertEqual(len(one), len(two))
            # Every column of the one-band run, in the same place, with the same values.
            self.assertEqual(two.columns.names[:len(one.columns.names)], one.columns.names)
            for name in one.columns.names:
                self.assertTrue(same_values(one[name], two[name]), "%s %s" % (table, name))
        self.assertGreater((fits.getdata(self.two, "LDAC_OBJECTS")["ARC_FOUND"] == 1).sum(), 10)
        self.assertNotIn("OCTBAND", ldac_imhead(self.one))

    def test_band_columns_and_header(self):
        systems = fits.getdata(self.two, "LDAC_OBJECTS")
        arcs = fits.getdata(self.two, "ARCS")
        for name in BAND_COLUMNS + ["SOURCE_COLOUR_TRUE_g", "LENS_COLOUR_TRUE_g"]:
            self.assertIn(name, systems.columns.names)
            self.assertEqual(systems.columns[name].unit, "mag")
        for name in BAND_COLUMNS:
            self.assertIn(name, arcs.columns.names)
        head = ldac_imhead(self.two)
        self.assertEqual(head["OCTBAND"], "g")
        self.assertEqual((head["OCTSCOLM"], head["OCTSCOLS"]), (0.4, 0.3))
        self.assertEqual((head["OCTLCOLM"], head["OCTLCOLS"]), (1.2, 0.1))

    def test_colours_are_band_minus_measurement_magnitudes(self):
        # The arc's measurement-band magnitude in its own footprint is its MAG_ISO: the colour
        # is MAG_g - MAG_ISO (both stored in single precision).
        arcs = fits.getdata(self.two, "ARCS")
        ok = np.isfinite(arcs["ARC_COLOUR_g"])
        self.assertGreater(ok.sum(), 10)
        np.testing.assert_allclose(arcs["ARC_COLOUR_g"][ok],
                                   (arcs["MAG_g"] - arcs["MAG_ISO"])[ok], rtol=0, atol=2e-5)
        self.assertTrue(np.all(np.isnan(arcs["MAG_g"][~ok]) | np.isnan(arcs["MAG_ISO"][~ok])))
        # The chosen arc's values are those of its row in the arc table.
        systems = fits.getdata(self.two, "LDAC_OBJECTS")
        chosen = arcs[arcs["CHOSEN"] == 1]
        found = systems[systems["ARC_FOUND"] == 1]
        np.testing.assert_array_equal(chosen["SYSTEM"], found["SYSTEM"])
        for name in BAND_COLUMNS:
            self.assertTrue(same_values(chosen[name], found[name]), name)

    def test_injected_colours_follow_the_options(self):
        s = fits.getdata(self.two, "LDAC_OBJECTS")
        n = len(s)
        for name, mean, sigma in (("SOURCE_COLOUR_TRUE_g", 0.4, 0.3),
                                  ("LENS_COLOUR_TRUE_g", 1.2, 0.1)):
            values = s[name].astype(float)
            self.assertTrue(np.all(np.isfinite(values)), name)
            self.assertLess(abs(values.mean() - mean), 4 * sigma / np.sqrt(n), name)
            self.assertLess(abs(values.std() / sigma - 1), 0.15, name)
        # Bright arcs far from the lens give back their injected colour; the lens light in
        # their footprint reddens them a little (the lens is redder by about 0.8 mag).
        found = s[(s["ARC_FOUND"] == 1) & (s["SNR_ISO"] > 40)]
        offset = found["ARC_COLOUR_g"] - found["SOURCE_COLOUR_TRUE_g"]
        self.assertLess(abs(np.nanmedian(offset)), 0.15)

    def test_same_seed_same_band(self):
        for table in ("LDAC_OBJECTS", "ARCS"):
            a = fits.getdata(self.two, table)
            b = fits.getdata(self.again, table)
            self.assertEqual(a.columns.names, b.columns.names)
            for name in a.columns.names:
                self.assertTrue(same_values(a[name], b[name]), "%s %s" % (table, name))

    def test_calibrate_colour_cut_study(self):
        work = tempfile.mkdtemp(dir=self.dir)
        cal = os.path.join(work, "cal.fits")
        proc = run_octarc("calibrate", self.two, "-CALIBRATION_NAME", cal, "-GRID_NAME",
                          os.path.join(work, "grid.fits"), "-NOISE_STUDY", "N",
                          "-GRID_AXES", "ARCNESS,ARC_COLOUR_g", "-GRID_LEVEL", "0.9",
                          "-COLOUR_CUT_MAX", "-1.5,2.5,0.25", "-CHECKPLOT_TYPE",
                          "COLOUR_CUT,COLOUR_DIFF", "-CHECKPLOT_NAME", "cut,diff", cwd=work)
        s = fits.getdata(self.two, "LDAC_OBJECTS")
        arc = (s["ARC_FOUND"] == 1) & (s["ARCNESS"] > 0.1) & (s["SNR_ISO"] > 40)
        # In double, as calibrate subtracts the stored values.
        diff = (s["ARC_COLOUR_g"].astype(float) - s["LENS_COLOUR_g"].astype(float))[arc]
        w = s["SIM_WEIGHT"][arc].astype(float)
        n = arc.sum()
        self.assertGreater(n, 5)
        with fits.open(cal) as f:
            table, header = f["COLOUR_CUT"].data, f["COLOUR_CUT"].header
            dist = f["DIST_COLOUR_DIFF"].header
        self.assertEqual(header["BAND"], "g")
        self.assertEqual(header["NARCS"], n)
        self.assertAlmostEqual(header["NEFFARCS"], w.sum() ** 2 / (w ** 2).sum(), places=6)
        self.assertEqual(header["NCOLOUR"], np.isfinite(diff).sum())
        np.testing.assert_allclose(table["COLOUR_MAX"], np.arange(17) * 0.25 - 1.5, atol=1e-12)
        for row in table:
            # Kept: the difference at most MAX, or no difference (the search keeps those); the
            # completeness is their weight over that of every arc.
            kept = ~np.isfinite(diff) | (diff <= row["COLOUR_MAX"])
            self.assertEqual(row["N_KEPT"], kept.sum(), row["COLOUR_MAX"])
            f = w[kept].sum() / w.sum()
            self.assertAlmostEqual(row["FRACTION"], f, places=12)
            self.assertLessEqual(row["FRACTION_LO"], f)
            self.assertGreaterEqual(row["FRACTION_HI"], f)
            if f < 1:
                self.assertGreater(row["FRACTION_HI"], f)  # exact intervals: never of width 0
        # The smallest MAX keeping 95 % of the weight: from the sorted differences.
        colourless = w[~np.isfinite(diff)].sum()
        order = np.argsort(diff[np.isfinite(diff)], kind="stable")
        sorted_diff = diff[np.isfinite(diff)][order]
        cumulative = colourless + np.cumsum(w[np.isfinite(diff)][order])
        if colourless < 0.95 * w.sum():
            reach = np.searchsorted(cumulative, 0.95 * w.sum() * (1 - 1e-12))
            self.assertAlmostEqual(header["MAXC95"], sorted_diff[reach], places=5)
        self.assertEqual(dist["NSIM"], np.isfinite(diff).sum())
        self.assertEqual(dist["VALUE"], "ARC_COLOUR_g - LENS_COLOUR_g")
        self.assertTrue(os.path.exists(os.path.join(work, "cut.png")))
        self.assertTrue(os.path.exists(os.path.join(work, "diff.png")))
        self.assertIn("Colour cut COLOUR_CUT g,MAX", proc.stdout)
        self.assertIn("95% of the arcs kept from MAX", proc.stdout)
        # The grid's second axis is the new column.
        grid = fits.getheader(os.path.join(work, "grid.fits"), "OCC_GRID")
        self.assertEqual(grid["AXEXPR2"], "ARC_COLOUR_g")

    def test_calibrate_without_a_band_has_no_colour_study(self):
        work = tempfile.mkdtemp(dir=self.dir)
        cal = os.path.join(work, "cal.fits")
        run_octarc("calibrate", self.one, "-CALIBRATION_NAME", cal, "-GRID_NAME",
                   os.path.join(work, "grid.fits"), "-NOISE_STUDY", "N", "-GRID_AXES",
                   "ARCNESS", "-CHECKPLOT_TYPE", "COLOUR_CUT", "-CHECKPLOT_NAME", "cut", cwd=work)
        with fits.open(cal) as f:
            names = [h.name for h in f]
        self.assertNotIn("COLOUR_CUT", names)
        self.assertNotIn("DIST_COLOUR_DIFF", names)
        self.assertFalse(os.path.exists(os.path.join(work, "cut.png")))


class TwoBandsBadInput(WorkDirTest):

    def expect_error(self, fragment, *args):
        out = self.path("out.fits")
        proc = run_octarc("simulate", "lenses", "-n", "3", "-o", out, "--quiet", *args,
                          check=False)
        self.assertNotEqual(proc.returncode, 0)
        message = proc.stderr.strip()
        self.assertEqual(len(message.splitlines()), 1, message)
        self.assertIn(fragment, message)
        self.assertFalse(os.path.exists(out))

    def test_bad_band_and_colours(self):
        self.expect_error("--band", "--band", "g-r")
        self.expect_error("--band", "--band", "")
        self.expect_error("--source-colour", "--band", "g", "--source-colour", "0.4")
        self.expect_error("--source-colour", "--band", "g", "--source-colour", "blue,0.3")
        self.expect_error("--lens-colour", "--band", "g", "--lens-colour", "1.2,-0.1")
        self.expect_error("--band", "--lens-colour", "1.2,0.1")

    def test_bad_colour_cut_range(self):
        sim = self.path("sim.fits")
        run_octarc("simulate", "lenses", "-n", "20", "--seed", "3", "--population", DLS,
                   "--sigma-min", "330", "-o", sim, "--quiet", "--band", "g")
        proc = run_octarc("calibrate", sim, "-CALIBRATION_NAME", self.path("cal.fits"),
                          "-GRID_NAME", self.path("grid.fits"), "-COLOUR_CUT_MAX", "1,-1,0.1",
                          check=False, cwd=self.work)
        self.assertNotEqual(proc.returncode, 0)
        self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertIn("COLOUR_CUT_MAX", proc.stderr)
        self.assertFalse(os.path.exists(self.path("cal.fits")))

    def test_remade_colour_cards_out_of_their_range(self):
        # A preset (remade by the threshold study), its colours drawn in g; calibrate runs in
        # a folder of its own, which it must leave empty.
        run = self.path("run")
        os.mkdir(run)
        sim = self.path("preset.fits")
        run_octarc("simulate", "lenses", "-n", "20", "--seed", "3", "--preset", "dls", "-o",
                   sim, "--quiet", "--band", "g")
        for key, value, expected in (("OCTSCOLS", "-0.5", "OCTSCOLS = -0.5 is not a finite "
                                      "number >= 0"),
                                     ("OCTLCOLS", "-2.0", "OCTLCOLS = -2 is not a finite "
                                      "number >= 0")):
            bad = with_card(sim, self.path(key + ".fits"), key, value)
            proc = run_octarc("calibrate", bad, "-THRESHOLD_STUDY", "Y", "-NOISE_STUDY", "N",
                              "-GRID_NAME", "NONE", check=False, cwd=run)
            self.assertEqual(proc.returncode, 1, proc.stderr)
            lines = [l for l in proc.stderr.splitlines() if l.strip() and not l.startswith("> ")]
            self.assertEqual(len(lines), 1, proc.stderr)
            self.assertIn(bad + ": LDAC_IMHEAD card " + expected, lines[0])
            self.assertEqual(os.listdir(run), [])


if __name__ == "__main__":
    unittest.main()
