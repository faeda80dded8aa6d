"""`octarc simulate field`: the image, weight map and truth list as fitsverify, astropy and
`octarc detect` (ASSOC) see them; reproducibility; bad input (issue 4, acceptance 5)."""
import os
import unittest

import numpy as np
from astropy.io import fits
from astropy.stats import sigma_clipped_stats
from astropy.wcs import WCS

from octarc_testlib import (SOURCE_DIR, WorkDirTest, fitsverify_errors, ldac_objects,
                            require_shared, run_octarc, write_param)

KIND_LENS, KIND_ARC, KIND_GALAXY, KIND_STAR = 1, 2, 3, 4


def read_truth(path):
    rows = np.loadtxt(path, comments="#", ndmin=2)
    return {"id": rows[:, 0].astype(int), "x": rows[:, 1], "y": rows[:, 2], "ra": rows[:, 3],
            "dec": rows[:, 4], "kind": rows[:, 5].astype(int), "mag": rows[:, 6],
            "theta_e": rows[:, 7], "system": rows[:, 8].astype(int)}


class SmallField(WorkDirTest):
    """One 512 x 512 field with three lenses, checked from every side."""

    @classmethod
    def setUpClass(cls):
        import tempfile
        cls.dir = tempfile.mkdtemp(prefix="octarc-field-")
        cls.image = os.path.join(cls.dir, "field.fits")
        cls.proc = run_octarc("simulate", "field", "-o", cls.image, "--size", 512, "--lenses", 3,
                              "--seed", 7, "--ra", 210.5, "--dec", -12.25, "--quiet")
        cls.weight = os.path.join(cls.dir, "field.weight.fits")
        cls.truth = os.path.join(cls.dir, "field.truth.txt")

    @classmethod
    def tearDownClass(cls):
        import shutil
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_files_exist_and_pass_fitsverify(self):
        self.assertEqual(self.proc.stderr, "")  # --quiet
        for path in (self.image, self.weight, self.truth):
            self.assertTrue(os.path.isfile(path), path)
        for path in (self.image, self.weight):
            code, text = fitsverify_errors(path)
            self.assertEqual(code, 0, text)

    def test_header_keywords_and_wcs(self):
        h = fits.getheader(self.image)
        self.assertEqual((h["NAXIS1"], h["NAXIS2"], h["BITPIX"]), (512, 512, -32))
        self.assertEqual(h["GAIN"], 54.0)
        self.assertEqual(h["MAGZERO"], 30.0)
        self.assertEqual(h["SATURATE"], 30000.0)
        self.assertEqual((h["CTYPE1"], h["CTYPE2"]), ("RA---TAN", "DEC--TAN"))
        self.assertEqual((h["CRVAL1"], h["CRVAL2"]), (210.5, -12.25))
        # 0.257"/px, north up, east left.
        self.assertAlmostEqual(h["CD1_1"], -0.257 / 3600, 15)
        self.assertAlmostEqual(h["CD2_2"], 0.257 / 3600, 15)
        # The truth RA/Dec is the WCS of the header, as astropy computes it.
        truth = read_truth(self.truth)
        world = WCS(h).all_pix2world(truth["x"], truth["y"], 1)
        np.testing.assert_allclose(world[0], truth["ra"], atol=2e-7)
        np.testing.assert_allclose(world[1], truth["dec"], atol=2e-7)

    def test_noise_and_weight_map(self):
        data = fits.getdata(self.image)
        h = fits.getheader(self.image)
        weight = fits.getdata(self.weight)
        sigma = h["SKYSIGMA"]
        # Default 5-sigma limit 26 in a 1.8" aperture: 10^(-0.4 (26 - 30)) / (5 sqrt(pi 0.9^2 /
        # 0.257^2)) = 1.2828 ADU.
        self.assertAlmostEqual(sigma, 10 ** 1.6 / (5 * np.sqrt(np.pi * 0.81 / 0.257 ** 2)), 4)
        # 1/variance, half of it in the chip gap (a strip of columns in the middle).
        gap = weight[0] < 0.75 / sigma ** 2
        self.assertGreaterEqual(gap.sum(), 4)
        self.assertTrue(np.all(np.diff(np.flatnonzero(gap)) == 1))
        np.testing.assert_allclose(weight[:, ~gap], 1 / sigma ** 2, rtol=1e-6)
        np.testing.assert_allclose(weight[:, gap], 0.5 / sigma ** 2, rtol=1e-6)
        # The pixels' noise matches: sigma outside, sqrt(2) sigma in the gap (clipped statistics
        # keep the objects out).
        _, _, std = sigma_clipped_stats(data[:, ~gap], sigma=3, maxiters=10)
        self.assertAlmostEqual(std / sigma, 1.0, delta=0.05)
        _, _, std_gap = sigma_clipped_stats(data[:, gap], sigma=3, maxiters=10)
        self.assertAlmostEqual(std_gap / sigma, np.sqrt(2), delta=0.1)

    def test_truth_list(self):
        truth = read_truth(self.truth)
        with open(self.truth) as f:
            header = [l for l in f if l.startswith("#")]
        self.assertTrue(any("ASSOC_PARAMS 2,3" in l for l in header))
        self.assertEqual(list(truth["id"]), list(range(1, len(truth["id"]) + 1)))
        lenses = truth["kind"] == KIND_LENS
        arcs = truth["kind"] == KIND_ARC
        self.assertEqual(sorted(truth["system"][lenses]), [1, 2, 3])
        self.assertTrue(set(truth["system"][arcs]) <= {1, 2, 3})
        self.assertGreaterEqual(arcs.sum(), 3)
        self.assertTrue(np.all(truth["theta_e"][lenses | arcs] > 0))
        self.assertTrue(np.all(truth["theta_e"][~(lenses | arcs)] == 0))
        self.assertTrue(np.all(truth["system"][~(lenses | arcs)] == 0))
        # Lens magnitudes from the population (21 < m < 23); lenses away from the edges.
        self.assertTrue(np.all((truth["mag"][lenses] > 21) & (truth["mag"][lenses] < 23)))
        for x, y in zip(truth["x"][lenses], truth["y"][lenses]):
            self.assertTrue(30 < x < 482 and 30 < y < 482, (x, y))
        # Each lensed image lies within a few Einstein radii of its lens.
        for i in np.flatnonzero(arcs):
            lens = np.flatnonzero(lenses & (truth["system"] == truth["system"][i]))[0]
            dist = np.hypot(truth["x"][i] - truth["x"][lens], truth["y"][i] - truth["y"][lens])
            self.assertLess(dist * 0.257, 3 * truth["theta_e"][i] + 1.0)
        # Galaxies and stars: a few hundred galaxies (about 3e5 per deg^2 to m = 26.5 over
        # 0.0013 deg^2), all inside the image.
        galaxies = truth["kind"] == KIND_GALAXY
        self.assertGreater(galaxies.sum(), 200)
        self.assertLess(galaxies.sum(), 600)
        self.assertTrue(np.all((truth["x"] > 0.5) & (truth["x"] < 512.5)))

    def test_truth_list_loads_as_assoc_list_and_lenses_are_detected(self):
        param = write_param(self.path("t.param"), ["NUMBER", "THRESH_LEVEL", "X_IMAGE", "Y_IMAGE",
                                                   "VECTOR_ASSOC(5)", "NUMBER_ASSOC"])
        catalog = self.path("t.ldac")
        run_octarc("detect", self.image, "-c", os.path.join(SOURCE_DIR, "params", "octarc.sex"),
                   "-PARAMETERS_NAME", param, "-CATALOG_NAME", catalog,
                   "-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE", self.weight,
                   "-ASSOC_NAME", self.truth, "-ASSOC_PARAMS", "2,3", "-ASSOC_DATA", "1,6,7,8,9",
                   "-ASSOC_RADIUS", "3", "-ASSOCSELEC_TYPE", "MATCHED", "-VERBOSE_TYPE", "QUIET")
        rows, _ = ldac_objects(catalog)
        truth = read_truth(self.truth)
        self.assertGreater(len(rows), 100)
        self.assertTrue(np.all(rows["NUMBER_ASSOC"] >= 1))
        # VECTOR_ASSOC holds the truth entry's id, kind, mag, theta_E, system, and that entry
        # lies within the ASSOC radius.
        ids = rows["VECTOR_ASSOC"][:, 0].astype(int)
        self.assertTrue(np.all(ids >= 1))
        np.testing.assert_array_equal(rows["VECTOR_ASSOC"][:, 1], truth["kind"][ids - 1])
        np.testing.assert_array_equal(rows["VECTOR_ASSOC"][:, 4], truth["system"][ids - 1])
        dist = np.hypot(rows["X_IMAGE"] - truth["x"][ids - 1],
                        rows["Y_IMAGE"] - truth["y"][ids - 1])
        self.assertTrue(np.all(dist < 3.0))
        # Every injected lens galaxy (m < 23, 3+ magnitudes above the limit) has an object
        # within 3 pixels (by position: ASSOC NEAREST may give a close arc's entry instead).
        for i in np.flatnonzero(truth["kind"] == KIND_LENS):
            d = np.hypot(rows["X_IMAGE"] - truth["x"][i], rows["Y_IMAGE"] - truth["y"][i])
            self.assertLess(d.min(), 3.0, "system %d" % truth["system"][i])


class Reproducibility(WorkDirTest):

    def simulate(self, name, *extra):
        path = self.path(name)
        run_octarc("simulate", "field", "-o", path, "--size", 256, "--lenses", 1, "--quiet",
                   *extra)
        with open(path.replace(".fits", ".truth.txt")) as f:
            return fits.getdata(path), f.read()

    def test_same_seed_same_field_whatever_the_threads(self):
        a, ta = self.simulate("a.fits", "--seed", 5, "--threads", 1)
        b, tb = self.simulate("b.fits", "--seed", 5, "--threads", 2)
        c, _ = self.simulate("c.fits", "--seed", 6, "--threads", 2)
        np.testing.assert_array_equal(a, b)
        self.assertEqual(ta.splitlines()[1:], tb.splitlines()[1:])  # line 1 names the file
        self.assertFalse(np.array_equal(a, c))

    def test_saturation_level_clips_and_is_written(self):
        image, _ = self.simulate("s.fits", "--seed", 5, "--saturate", 20)
        self.assertEqual(fits.getheader(self.path("s.fits"))["SATURATE"], 20.0)
        self.assertEqual(image.max(), 20.0)
        self.assertGreater((image == 20.0).sum(), 10)

    def test_survey_settings_from_a_sex_file(self):
        sex = self.path("survey.sex")
        with open(sex, "w") as f:
            f.write("PIXEL_SCALE 0.2\nSEEING_FWHM 1.1\nGAIN 4.0\nMAG_ZEROPOINT 27.5\n"
                    "SATUR_LEVEL 60000\n")
        path = self.path("cfg.fits")
        # The command line wins over the file.
        run_octarc("simulate", "field", "-o", path, "--size", 128, "--config", sex, "--gain", 2.5,
                   "--quiet")
        h = fits.getheader(path)
        self.assertEqual((h["PIXSCALE"], h["SEEING"], h["GAIN"], h["MAGZERO"], h["SATURATE"]),
                         (0.2, 1.1, 2.5, 27.5, 60000.0))
        self.assertAlmostEqual(h["CD2_2"], 0.2 / 3600, 15)


class SharedDatabases(WorkDirTest):
    """Lensed sources from the RealGalaxyCatalog files kept in ../shared/data/real."""

    def test_aegis_sources_and_a_catalog_naming_a_missing_image(self):
        aegis = require_shared(self, "hst-galaxies", "aegis", "AEGIS_F606w_catalog.fits")
        out = self.path("f.fits")
        run_octarc("simulate", "field", "-o", out, "--size", 256, "--lenses", 2, "--quiet",
                   "--database", aegis)
        truth = read_truth(self.path("f.truth.txt"))
        self.assertEqual(sorted(truth["system"][truth["kind"] == KIND_LENS]), [1, 2])
        self.assertGreaterEqual(np.sum(truth["kind"] == KIND_ARC), 2)
        # GalSim's example catalog names an image file that is not there: one clear line.
        example = require_shared(self, "hst-galaxies", "real_galaxy_catalog_23.5_example.fits")
        proc = run_octarc("simulate", "field", "-o", self.path("g.fits"), "--size", 256,
                          "--lenses", 1, "--quiet", "--database", example, check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertIn("real_galaxy_images.fits", proc.stderr)
        self.assertFalse(os.path.exists(self.path("g.fits")))


class BadInput(WorkDirTest):

    def check_error(self, words, *args):
        out = self.path("f.fits")
        proc = run_octarc("simulate", "field", "-o", out, "--quiet", *args, check=False)
        self.assertNotEqual(proc.returncode, 0, proc.stderr)
        lines = proc.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, proc.stderr)
        for w in words:
            self.assertIn(w, lines[0])
        self.assertEqual(os.listdir(self.work), [])

    def test_nonsense_ranges(self):
        self.check_error(["--size", "0"], "--size", 0)
        self.check_error(["--lenses", "-1"], "--lenses", -1)
        self.check_error(["--seeing", "-1"], "--seeing", -1)
        self.check_error(["--pixel-scale"], "--pixel-scale", 0)
        self.check_error(["--noise-sigma"], "--noise-sigma", -2)
        self.check_error(["--dec"], "--dec", 95)
        self.check_error(["--noise-sigma", "--limiting-mag"], "--noise-sigma", 2,
                         "--limiting-mag", 25)
        self.check_error(["--lenses", "do not fit"], "--size", 128, "--lenses", 50)
        self.check_error(["--lenses", "too small"], "--size", 64, "--lenses", 1)
        self.check_error(["--threads"], "--threads", -2)
        self.check_error(["size"], "--size", "big")
        self.check_error(["--bogus"], "--bogus", 1)

    def test_missing_output_name_and_unwritable_directory(self):
        proc = run_octarc("simulate", "field", "--size", 64, check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("-o", proc.stderr)
        for target in (os.path.join(self.work, "missing", "f.fits"),
                       os.path.join(self.work, "file.txt", "f.fits")):
            with open(self.path("file.txt"), "w") as f:
                f.write("x")
            proc = run_octarc("simulate", "field", "-o", target, "--size", 64, "--quiet",
                              check=False)
            self.assertNotEqual(proc.returncode, 0)
            self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
            self.assertIn(target, proc.stderr)
            self.assertEqual(sorted(os.listdir(self.work)), ["file.txt"])

    def test_missing_database_and_config(self):
        self.check_error(["nothere.fits"], "--lenses", 1, "--size", 256, "--database",
                         self.path("nothere.fits"))
        self.check_error(["nothere.sex"], "--config", self.path("nothere.sex"))


if __name__ == "__main__":
    unittest.main()
