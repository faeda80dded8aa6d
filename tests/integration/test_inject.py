"""`octarc inject`: on a small simulated field without lenses, searched with both the shipped
demo grid and model, the completeness table recomputed here from the truth and candidate lists
it writes (thresholds, counts per bin, Wilson intervals from the formula, spurious candidates per
deg2 of the field's area from its size and pixel scale); its candidate lists are those of
`octarc search` on the image and on the injected image; the injection leaves the rest of the
image untouched. Bad input: one line naming the file, no output."""
import os
import shutil
import tempfile
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import SOURCE_DIR, WorkDirTest, run_octarc

PIXEL_SCALE = 0.257  # octarc simulate field's default
SIZE = 512
THETA_EDGES, MAG_EDGES = (2.0, 2.5), (22.0, 23.0)


SEX = os.path.join(SOURCE_DIR, "params", "octarc.sex")


def wilson(k, n):
    """Wilson score interval at z = 1 (written out here from the formula)."""
    p = k / n
    centre = (p + 1 / (2 * n)) / (1 + 1 / n)
    half = np.sqrt(p * (1 - p) / n + 1 / (4 * n * n)) / (1 + 1 / n)
    return max(0.0, centre - half), min(1.0, centre + half)


def search_keys(field):
    return ["-c", SEX, "-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE",
            field[:-5] + ".weight.fits", "-SEEING_FWHM", 0.9, "-MAG_ZEROPOINT", 30, "-GAIN", 54,
            "-NTHREADS", 1, "-VERBOSE_TYPE", "QUIET"]


class InjectSmallField(unittest.TestCase):
    """One run, made once: 4 lenses into a 512^2 field, searched with the grid and the model."""

    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="octarc-inject-")
        cls.field = os.path.join(cls.work, "f.fits")
        run_octarc("simulate", "field", "-o", cls.field, "--size", SIZE, "--lenses", 0,
                   "--seed", 3, "--quiet", "--threads", 1)
        cls.out = os.path.join(cls.work, "inj")
        run_octarc("inject", cls.field, *search_keys(cls.field), "-GRID_NAME", "demo.grid.fits",
                   "-MODEL_NAME", "demo.model.fits", "-INJECT_NUMBER", 4, "-INJECT_SEED", 2,
                   "-INJECT_DIR", cls.out)
        cls.truth = np.loadtxt(os.path.join(cls.out, "injected.truth.txt"), ndmin=2)
        cls.cands = np.genfromtxt(os.path.join(cls.out, "candidates.txt"), dtype=None,
                                  encoding="ascii", names=["method", "image", "x", "y", "score",
                                                            "system"])
        with fits.open(os.path.join(cls.out, "completeness.fits")) as f:
            cls.header = f["COMPLETENESS"].header
            cls.table = f["COMPLETENESS"].data

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.work, name)

    def test_outputs_together(self):
        names = sorted(os.listdir(self.out))
        self.assertEqual(names, [".octarc-inject", "candidates.txt", "completeness.fits",
                                 "completeness.png", "injected.fits", "injected.truth.txt",
                                 "summary.txt"])
        with open(os.path.join(self.out, "completeness.png"), "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        with open(os.path.join(self.out, "summary.txt")) as f:
            summary = f.read()
        for level in ("<= 30 ", "<= 100 ", "<= 400 ", "<= 1000 ", "every cand"):
            self.assertEqual(summary.count(level), 2, level)  # GRID and TREES

    def test_injected_lenses_apart_and_the_rest_untouched(self):
        lenses = self.truth[self.truth[:, 1] == 1]
        self.assertEqual(len(lenses), 4)
        self.assertTrue((lenses[:, 5] >= 1.5).all())
        for i in range(4):
            for j in range(i):
                apart = np.hypot(*(lenses[i, 2:4] - lenses[j, 2:4])) * PIXEL_SCALE
                self.assertGreaterEqual(apart, 30.0)
        before = fits.getdata(self.field)
        after = fits.getdata(os.path.join(self.out, "injected.fits"))
        y, x = np.mgrid[1:SIZE + 1, 1:SIZE + 1]
        near = np.zeros(before.shape, bool)
        for lens in lenses:
            near |= np.hypot(x - lens[2], y - lens[3]) * PIXEL_SCALE < 15.0
        self.assertTrue(np.array_equal(before[~near], after[~near]))
        self.assertGreater(np.abs(after[near] - before[near]).sum(), 0)

    def test_candidates_are_those_of_search(self):
        keys = search_keys(self.field) + ["-SCORE_MIN", 0, "-STAMPS", "N"]
        for method, selection in (("GRID", ["-GRID_NAME", "demo.grid.fits"]),
                                  ("TREES", ["-MODEL_NAME", "demo.model.fits"])):
            for image, path in (("PLAIN", self.field),
                                ("INJECTED", os.path.join(self.out, "injected.fits"))):
                out = self.path("c-%s-%s" % (method, image))
                run_octarc("search", path, *keys, "-SELECTION_METHOD", method, *selection,
                           "-OUTPUT_DIR", out)
                rows = fits.getdata(os.path.join(out, "candidates.fits"), "LDAC_OBJECTS")
                mine = self.cands[(self.cands["method"] == method) & (self.cands["image"] == image)]
                self.assertEqual(len(mine), len(rows), (method, image))
                order = np.lexsort((rows["Y_IMAGE"], rows["X_IMAGE"]))
                mine = mine[np.lexsort((mine["y"], mine["x"]))]
                np.testing.assert_allclose(mine["x"], rows["X_IMAGE"][order], atol=1e-3)
                np.testing.assert_allclose(mine["score"], rows["LENS_SCORE"][order], rtol=1e-6)
        # A candidate that is an injected arc lies by one of that system's lensed images.
        arcs = self.cands[self.cands["system"] > 0]
        for c in arcs:
            images = self.truth[(self.truth[:, 0] == c["system"]) & (self.truth[:, 1] == 2)]
            distance = np.hypot(images[:, 2] - c["x"], images[:, 3] - c["y"]).min()
            self.assertLess(distance * PIXEL_SCALE, 3.0)
        self.assertTrue((self.cands["system"][self.cands["image"] == "PLAIN"] == 0).all())

    def test_table_recomputed_from_the_lists(self):
        area = SIZE * SIZE * (PIXEL_SCALE / 3600.0) ** 2
        self.assertAlmostEqual(self.header["AREA"] / area, 1.0, places=3)
        systems = sorted(set(self.truth[:, 0].astype(int)))
        theta = {s: self.truth[(self.truth[:, 0] == s) & (self.truth[:, 1] == 1), 5][0]
                 for s in systems}
        mag = {s: self.truth[(self.truth[:, 0] == s) & (self.truth[:, 1] == 2), 4].min()
               for s in systems}
        rows_seen = 0
        for method in ("GRID", "TREES"):
            mine = self.cands[self.cands["method"] == method]
            plain = mine["score"][mine["image"] == "PLAIN"]
            injected = mine[mine["image"] == "INJECTED"]
            best = {s: injected["score"][injected["system"] == s].max()
                    if (injected["system"] == s).any() else -np.inf for s in systems}
            other = injected["score"][injected["system"] == 0]
            thresholds = sorted(set(plain) | set(other) | {b for b in best.values()
                                                           if np.isfinite(b)}, reverse=True)
            table = self.table[self.table["METHOD"] == method]
            self.assertEqual(len(table), len(thresholds), method)
            rows_seen += len(table)
            for row, t in zip(table, thresholds):
                self.assertAlmostEqual(row["SCORE_MIN"] / t, 1.0, places=12)
                found = [s for s in systems if best[s] >= t]
                self.assertEqual(row["SPURIOUS"], (plain >= t).sum())
                spurious = (plain >= t).sum()
                self.assertLess(abs(row["SPURIOUS_PER_DEG2"] * area - spurious),
                                1e-3 * max(spurious, 1))
                self.assertEqual(row["SPURIOUS_INJ"], (other >= t).sum())
                self.assertEqual(row["FOUND"], len(found))
                self.assertEqual(row["INJECTED"], len(systems))
                lo, hi = wilson(len(found), len(systems))
                self.assertAlmostEqual(row["COMPL_LO"], lo, places=12)
                self.assertAlmostEqual(row["COMPL_HI"], hi, places=12)
                for column, values, edges in (("THETA", theta, THETA_EDGES),
                                              ("MAG", mag, MAG_EDGES)):
                    bins = {s: int(np.searchsorted(edges, values[s], side="right"))
                            for s in systems}
                    for b in range(3):
                        n = sum(1 for s in systems if bins[s] == b)
                        k = sum(1 for s in found if bins[s] == b)
                        self.assertEqual(row["INJECTED_" + column][b], n)
                        self.assertEqual(row["FOUND_" + column][b], k)
                        if n:
                            self.assertAlmostEqual(row["COMPL_%s_LO" % column][b],
                                                   wilson(k, n)[0], places=12)
        self.assertEqual(rows_seen, len(self.table))


class InjectBadInput(WorkDirTest):

    def check_refused(self, args, named):
        out = self.path("inj")
        proc = run_octarc("inject", *args, "-INJECT_DIR", out, check=False)
        self.assertEqual(proc.returncode, 1)
        lines = proc.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, proc.stderr)
        self.assertIn(named, lines[0])
        self.assertFalse(os.path.exists(out))
        self.assertEqual(proc.stdout, "")

    def test_missing_image_and_grid(self):
        missing = self.path("nothing.fits")
        self.check_refused([missing, "-c", SEX], missing)
        field = self.path("f.fits")
        run_octarc("simulate", "field", "-o", field, "--size", 128, "--lenses", 0, "--quiet",
                   "--threads", 1)
        grid = self.path("no.grid.fits")
        self.check_refused([field, "-c", SEX, "-GRID_NAME", grid], grid)
        # The injected light needs the image's zero point.
        self.check_refused([field, "-c", SEX, "-GRID_NAME", "demo.grid.fits", "-MAG_ZEROPOINT",
                            0], "MAG_ZEROPOINT")
        # Other bands would hold no injected lens.
        self.check_refused([field, "-c", SEX, "-GRID_NAME", "demo.grid.fits", "-COLOUR_IMAGE",
                            field, "-COLOUR_BAND", "g"], "COLOUR_IMAGE: octarc inject injects")
        # A user's own folder as INJECT_DIR is refused before any work and left as it was.
        mine = self.path("mine")
        os.mkdir(mine)
        with open(os.path.join(mine, "summary.txt"), "w") as f:
            f.write("my notes\n")
        proc = run_octarc("inject", field, "-c", SEX, "-GRID_NAME", "demo.grid.fits",
                          "-INJECT_DIR", mine, check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
        self.assertIn(mine, proc.stderr)
        self.assertEqual(os.listdir(mine), ["summary.txt"])
        with open(os.path.join(mine, "summary.txt")) as f:
            self.assertEqual(f.read(), "my notes\n")
