"""`octarc simulate lenses` end to end: the output tables as astropy and fitsverify read them,
the arc statistics of found arcs, survey settings from a .sex file, bad input, and Ctrl-C
(issue 4: "octarc simulate lenses", acceptance 2, 3, 5)."""
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (OCTARC, SOURCE_DIR, WorkDirTest, fitsverify_errors, ldac_imhead,
                            require_shared, run_octarc)

TRUTH = {"SYSTEM": "", "Z_LENS": "", "Z_SOURCE": "", "SIGMA_V": "km/s", "LENS_MAG": "mag",
         "EINSTEIN_RADIUS": "arcsec", "SOURCE_MAG": "mag", "SOURCE_RHALF": "arcsec",
         "SOURCE_X": "arcsec", "SOURCE_Y": "arcsec", "MAGNIFICATION": "", "ARC_FOUND": "",
         "LENS_DISTANCE": "arcsec"}
MEASURED = {"ARCNESS": "", "ANTIARCNESS": "", "SKEW_MAJOR": "", "SKEW_MINOR": "",
            "E_IMAGE": "", "SIZE_IMAGE": "pixel", "SNR_ISO": "", "THRESH_LEVEL": "",
            "X_IMAGE": "pixel", "FLUX_ISO": "count"}


class SimulatedCatalog(WorkDirTest):

    @classmethod
    def setUpClass(cls):
        # One run shared by the checks below: a velocity-dispersion cut that makes big Einstein
        # radii, so that a small N already holds arcs.
        cls.dir = tempfile.mkdtemp(prefix="octarc-sim-")
        cls.out = os.path.join(cls.dir, "lenses.fits")
        cls.stamps = os.path.join(cls.dir, "stamps.fits")
        # The Deep Lens Survey preset (the paper's windows).
        dls = os.path.join(SOURCE_DIR, "params", "simulation", "population-dls.txt")
        cls.proc = run_octarc("simulate", "lenses", "-n", "80", "--seed", "5", "-o", cls.out,
                              "--population", dls, "--sigma-min", "320", "--stamps", cls.stamps,
                              "--stamp-count", "4", "--threads", "2")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_layout_columns_and_units(self):
        with fits.open(self.out) as f:
            self.assertEqual([h.name for h in f], ["PRIMARY", "LDAC_IMHEAD", "LDAC_OBJECTS",
                                                   "ARCS"])
            systems, arcs = f[2], f[3]
            # One row per rendered system (importance sampling, the default): a subset of the
            # 80 drawn, in order, each with its weight 1 / render probability >= 1.
            head = ldac_imhead(self.out)
            self.assertEqual(len(systems.data), head["OCTNREND"])
            self.assertGreater(len(systems.data), 0)
            index = systems.data["SYSTEM"]
            self.assertTrue(np.all(np.diff(index) > 0))
            self.assertTrue(np.all((index >= 0) & (index < 80)))
            self.assertTrue(np.all(systems.data["SIM_WEIGHT"] >= 1.0))
            self.assertAlmostEqual(head["OCTSUMW"], systems.data["SIM_WEIGHT"].sum(), places=3)
            self.assertEqual(head["OCTSAMPL"], "IMPORTANCE")
            for name, unit in list(TRUTH.items()) + list(MEASURED.items()):
                self.assertIn(name, systems.columns.names)
                self.assertEqual(systems.columns[name].unit or "", unit, name)
            for name in ["SYSTEM", "CHOSEN", "LENS_DISTANCE"] + list(MEASURED):
                self.assertIn(name, arcs.columns.names)
            # Every column is declared with a description (TTYPE comment) and a display format.
            for i, name in enumerate(systems.columns.names, start=1):
                self.assertTrue(systems.header.comments["TTYPE%d" % i], name)
                self.assertIn("TDISP%d" % i, systems.header, name)
        self.assertEqual(fitsverify_errors(self.out)[0], 0)
        head = ldac_imhead(self.out)
        self.assertEqual(head["OCTSEED"], 5)
        self.assertEqual(head["OCTNSYS"], 80)
        self.assertEqual(head["OCTNLEV"], 15)
        # The summary line names the per-stage costs.
        self.assertIn("ray trace", self.proc.stderr)
        self.assertIn("detection", self.proc.stderr)

    def test_truth_follows_the_population_rules(self):
        s = fits.getdata(self.out, 2)
        self.assertTrue(np.all((s["SIGMA_V"] > 320) & (s["SIGMA_V"] < 400)))
        self.assertTrue(np.all(s["Z_SOURCE"] > s["Z_LENS"]))
        self.assertTrue(np.all((s["SOURCE_MAG"] > 22) & (s["SOURCE_MAG"] < 25)))
        self.assertTrue(np.all((s["LENS_MAG"] > 21) & (s["LENS_MAG"] < 23)))
        # Sources lie inside the cut, which reaches b sqrt(1 + eps) on the minor axis.
        beta = np.hypot(s["SOURCE_X"], s["SOURCE_Y"])
        self.assertTrue(np.all(beta <= s["EINSTEIN_RADIUS"] * np.sqrt(1 + s["LENS_EPSILON"]) *
                               (1 + 1e-6)))
        # A multiply imaged source is magnified; systems below the skip limit are not rendered
        # (no row), nor those importance sampling leaves out.
        head = ldac_imhead(self.out)
        self.assertTrue(np.all(s["EINSTEIN_RADIUS"] >= head["OCTSKIPT"]))
        self.assertTrue(np.all(s["MAGNIFICATION"] > 1.0))
        self.assertLessEqual(head["OCTNSKIP"] + head["OCTNREND"], head["OCTNSYS"])

    def test_found_arcs_obey_the_rules_and_have_plausible_arcness(self):
        s = fits.getdata(self.out, 2)
        a = fits.getdata(self.out, 3)
        found = s[s["ARC_FOUND"] == 1]
        self.assertGreater(len(found), 0)
        self.assertTrue(np.all(found["LENS_DISTANCE"] >= 1.0))
        self.assertTrue(np.all(np.sqrt(2) * found["SIZE_IMAGE"] * 0.257 > 1.0))
        # At most the maximum of a uniform thin circular arc, 0.2314 (METHOD.md section 1): the
        # seeing's blur adds second moments and no third, so a lensed arc of a smooth source
        # stays below it (arbitrary light has no bound: Octopole.ArcnessHasNoUpperBound).
        self.assertTrue(np.all((found["ARCNESS"] >= 0) & (found["ARCNESS"] <= 0.2314)))
        self.assertTrue(np.all(np.isnan(s["ARCNESS"][s["ARC_FOUND"] == 0])))
        # One chosen row per found system in the arc table, which holds every arc row.
        chosen = a[a["CHOSEN"] == 1]
        np.testing.assert_array_equal(np.sort(chosen["SYSTEM"]), found["SYSTEM"])
        np.testing.assert_array_equal(np.bincount(a["SYSTEM"], minlength=80)[s["SYSTEM"]],
                                      s["N_ARC_ROWS"])
        for row in found:
            c = chosen[chosen["SYSTEM"] == row["SYSTEM"]][0]
            self.assertEqual(c["ARCNESS"], row["ARCNESS"])
            self.assertEqual(c["THRESH_LEVEL"], row["THRESH_LEVEL"])

    def test_plain_sampling_renders_every_system_above_the_skip_limit(self):
        out = os.path.join(self.dir, "plain.fits")
        dls = os.path.join(SOURCE_DIR, "params", "simulation", "population-dls.txt")
        run_octarc("simulate", "lenses", "-n", "30", "--seed", "5", "-o", out, "--population",
                   dls, "--sigma-min", "320", "--sampling", "plain", "--quiet")
        s = fits.getdata(out, 2)
        head = ldac_imhead(out)
        self.assertEqual(head["OCTSAMPL"], "PLAIN")
        self.assertEqual(head["OCTNSYS"], 30)
        self.assertEqual(len(s), head["OCTNREND"])
        self.assertEqual(head["OCTNSKIP"] + len(s), 30)
        np.testing.assert_array_equal(s["SIM_WEIGHT"], 1.0)
        self.assertTrue(np.all(s["EINSTEIN_RADIUS"] >= head["OCTSKIPT"]))
        # The rendered systems are those of the importance-sampled run of the same seed.
        imp = fits.getdata(self.out, 2)
        both = np.intersect1d(imp["SYSTEM"][imp["SYSTEM"] < 30], s["SYSTEM"])
        self.assertEqual(len(both), np.sum(imp["SYSTEM"] < 30))
        for system in both:
            self.assertEqual(imp["EINSTEIN_RADIUS"][imp["SYSTEM"] == system][0],
                             s["EINSTEIN_RADIUS"][s["SYSTEM"] == system][0])

    def test_stamps_cube(self):
        with fits.open(self.stamps) as f:
            self.assertEqual(f[0].data.shape, (4, 101, 101))
            self.assertAlmostEqual(f[0].header["PIXSCALE"], 0.257)
            # Background-subtracted noise: the median of a stamp is near zero.
            self.assertLess(abs(np.median(f[0].data[0])), 0.5)


class SurveyConfig(WorkDirTest):

    def test_settings_from_an_octarc_sex_file(self):
        sex = self.path("survey.sex")
        with open(sex, "w") as f:
            f.write("DETECT_THRESH 3\nDETECT_THRESH_MAX 12\nDETECT_NLEVELS 5\n"
                    "PIXEL_SCALE 0.2\nSEEING_FWHM 1.1\nGAIN 20\nMAG_ZEROPOINT 29\n")
        out = self.path("o.fits")
        run_octarc("simulate", "lenses", "-n", "3", "-o", out, "--config", sex, "--quiet",
                   "--sky-sigma", "2")
        head = ldac_imhead(out)
        self.assertEqual(head["OCTNLEV"], 5)
        self.assertAlmostEqual(head["OCTTHLO"], 6.0)   # 3 sigma of 2 ADU
        self.assertAlmostEqual(head["OCTTHHI"], 24.0)
        self.assertAlmostEqual(head["OCTPIXSC"], 0.2)
        self.assertAlmostEqual(head["OCTSEEIN"], 1.1)
        self.assertAlmostEqual(head["OCTGAIN"], 20.0)
        self.assertAlmostEqual(head["OCTMAGZP"], 29.0)
        # An explicit option wins over the file.
        run_octarc("simulate", "lenses", "-n", "2", "-o", out, "--config", sex, "--quiet",
                   "--nlevels", "3")
        self.assertEqual(ldac_imhead(out)["OCTNLEV"], 3)

    def test_keys_the_file_does_not_set_keep_the_survey_defaults(self):
        sex = self.path("partial.sex")
        with open(sex, "w") as f:
            f.write("DETECT_NLEVELS 4\n")
        out = self.path("o.fits")
        run_octarc("simulate", "lenses", "-n", "2", "-o", out, "--config", sex, "--quiet")
        head = ldac_imhead(out)
        self.assertEqual(head["OCTNLEV"], 4)
        self.assertAlmostEqual(head["OCTMAGZP"], 30.0)
        self.assertAlmostEqual(head["OCTGAIN"], 54.0)
        self.assertAlmostEqual(head["OCTSEEIN"], 0.9)
        self.assertAlmostEqual(head["OCTPIXSC"], 0.257)


class RealDatabases(WorkDirTest):

    def test_aegis_catalog_as_source_database(self):
        cat = require_shared(self, "hst-galaxies", "aegis", "AEGIS_F606w_catalog.fits")
        out = self.path("o.fits")
        run_octarc("simulate", "lenses", "-n", "6", "-o", out, "--database", cat, "--quiet")
        s = fits.getdata(out, 2)
        n = len(fits.getdata(cat, 1))
        self.assertTrue(np.all((s["SOURCE_INDEX"] >= 0) & (s["SOURCE_INDEX"] < n)))


class BadInput(WorkDirTest):

    def assert_fails(self, *args, needle):
        out = self.path("out.fits")
        proc = run_octarc("simulate", "lenses", "-o", out, *args, check=False)
        self.assertNotEqual(proc.returncode, 0)
        lines = proc.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, proc.stderr)
        self.assertIn(needle, lines[0])
        self.assertEqual(os.listdir(self.work), [])

    def test_count_zero_or_negative(self):
        self.assert_fails("-n", "0", needle="-n")
        self.assert_fails("-n", "-4", needle="-n")

    def test_magnitude_range_reversed(self):
        self.assert_fails("-n", "3", "--source-mag-min", "25", "--source-mag-max", "22",
                          needle="--source-mag-min")

    def test_sigma_range_giving_no_lens(self):
        self.assert_fails("-n", "3", "--sigma-min", "800", "--sigma-max", "900",
                          needle="sigma")

    def test_unknown_database_format(self):
        other = os.path.join(SOURCE_DIR, "params", "octarc.sex")
        self.assert_fails("-n", "3", "--database", other, needle="octarc.sex")

    def test_missing_stamp_files(self):
        cat = require_shared(self, "hst-galaxies", "real_galaxy_catalog_23.5_example.fits")
        self.assert_fails("-n", "3", "--database", cat, needle="does not exist")

    def test_unknown_option(self):
        self.assert_fails("-n", "3", "--no-such-option", needle="no-such-option")


class Interrupt(WorkDirTest):

    def test_sigint_stops_cleanly_without_output(self):
        out = self.path("big.fits")
        proc = subprocess.Popen([OCTARC, "simulate", "lenses", "-n", "1000000", "-o", out,
                                 "--threads", "2"], stderr=subprocess.PIPE, text=True)
        time.sleep(2.0)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 130)
        self.assertIn("interrupted", err)
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertEqual(os.listdir(self.work), [])


if __name__ == "__main__":
    unittest.main()
