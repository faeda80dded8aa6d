"""The learned selection: `octarc calibrate -MODEL_NAME` trains gradient-boosted trees on simulated
arcs against a survey catalog's rows, `octarc search -SELECTION_METHOD TREES` scores with them.

Checked against numpy on the same files: which rows the model was trained on (the counts, the
weights, the Kish number, the arc rows per system in its header), that training is reproducible
and independent of the thread count, that the candidates are in LENS_SCORE order with LENS_RANK
1..N, that SCORE_MIN keeps exactly the rows at or above it, that LENS_DENSITY moves every score's
log-odds by the change of the prior's log-odds (written in the header), and the errors for a
file that is no model and a training without a survey catalog."""
import os
import shutil
import tempfile
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import SOURCE_DIR, WorkDirTest, run_octarc

SCALE = 0.257  # the demo field's pixel scale, arcsec


def logit(p):
    return np.log(p / (1 - p))


class SearchTrees(WorkDirTest):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="octarc-trees-")
        cls.sim = os.path.join(cls.dir, "sim.fits")
        run_octarc("simulate", "lenses", "-n", "8000", "--seed", "7", "--preset", "dls",
                   "--sky-sigma", "1.283", "-o", cls.sim, "--quiet")
        cls.sim2 = os.path.join(cls.dir, "sim2.fits")
        run_octarc("simulate", "lenses", "-n", "4000", "--seed", "8", "--preset", "dls",
                   "--sky-sigma", "1.283", "-o", cls.sim2, "--quiet")
        cls.field_dir = os.path.join(cls.dir, "field")
        run_octarc("demo", "--size", "1024", "--lenses", "4", "--seed", "3", "--out",
                   cls.field_dir, "--quiet")
        cls.field = os.path.join(cls.field_dir, "field.fits")
        cls.catalog = os.path.join(cls.field_dir, "field.ldac")
        cls.model = os.path.join(cls.dir, "lens.model.fits")
        cls.train(cls.model)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir)

    @classmethod
    def train(cls, model, *extra, sims=None):
        return run_octarc("calibrate", *(sims or [cls.sim]), "-SURVEY_CATALOG", cls.catalog, "-MODEL_NAME",
                          model, "-MODEL_TREES", "60,4", "-GRID_NAME", "NONE", "-NOISE_STUDY",
                          "N", "-CHECKPLOT_TYPE", "NONE", "-CALIBRATION_NAME",
                          os.path.join(cls.dir, "cal-%d.fits" % os.getpid()), *extra,
                          cwd=cls.dir)

    def search(self, out, *extra, check=True):
        return run_octarc("search", self.field, "-WEIGHT_IMAGE",
                          os.path.join(self.field_dir, "field.weight.fits"), "-WEIGHT_TYPE",
                          "MAP_WEIGHT", "-SELECTION_METHOD", "TREES", "-MODEL_NAME", self.model,
                          "-OUTPUT_DIR", self.path(out), "-STAMPS", "N", *extra, check=check,
                          cwd=self.work)

    def usable_arcs(self, sim):
        """The arc rows a model is trained on, their weights, and the ARCROWS sums."""
        systems = fits.getdata(sim, "LDAC_OBJECTS")
        arcs = fits.getdata(sim, "ARCS")
        found = systems["ARC_FOUND"] == 1
        weight = dict(zip(systems["SYSTEM"][found], systems["SIM_WEIGHT"][found].astype(float)))
        # Every arc row (every level) above the floor and resolved; each arc system weighs its
        # SIM_WEIGHT, shared among its rows.
        usable = np.array([s in weight for s in arcs["SYSTEM"]]) & (arcs["SNR_ISO"] > 40) & (
            np.sqrt(2) * arcs["SIZE_IMAGE"] * SCALE > 1.0)
        systems_used, per_system = np.unique(arcs["SYSTEM"][usable], return_counts=True)
        count = dict(zip(systems_used, per_system))
        w = np.array([weight[s] / count[s] for s in arcs["SYSTEM"][usable]])
        return w, sum(weight[s] * count[s] for s in count), sum(weight.values())

    def test_model_header_counts_the_rows_trained_on(self):
        h = fits.getheader(self.model, "LENS_MODEL")
        w, rows_weight, systems_weight = self.usable_arcs(self.sim)
        rows = fits.getdata(self.catalog, "LDAC_OBJECTS")
        others = (rows["SNR_ISO"] > 40) & (np.sqrt(2) * rows["SIZE_IMAGE"] * SCALE > 1.0)
        self.assertGreater(len(w), 10)
        self.assertEqual(h["NARC"], len(w))
        self.assertEqual(h["NOTHER"], others.sum())
        # The classes weigh the same: the arcs' weights scaled to the other rows' count.
        self.assertEqual(h["ARCWEIGH"], others.sum())
        self.assertEqual(h["OTHWEIGH"], others.sum())
        self.assertAlmostEqual(h["NEFFARC"], w.sum() ** 2 / (w ** 2).sum(), places=6)
        # ARCROWS: the usable rows per arc system, every arc system counted.
        self.assertAlmostEqual(h["ARCROWS"], rows_weight / systems_weight, places=9)

        # Two outputs together (their SYSTEM numbers repeat): each arc row is weighed by its
        # own output's system.
        both = self.path("both.model.fits")
        self.train(both, sims=[self.sim, self.sim2])
        hb = fits.getheader(both, "LENS_MODEL")
        w2, rows2, systems2 = self.usable_arcs(self.sim2)
        self.assertEqual(hb["NARC"], len(w) + len(w2))
        wb = np.concatenate([w, w2])
        self.assertAlmostEqual(hb["NEFFARC"], wb.sum() ** 2 / (wb ** 2).sum(), places=6)
        self.assertAlmostEqual(hb["ARCROWS"], (rows_weight + rows2) / (systems_weight + systems2),
                               places=9)
        self.assertEqual(h["ROUNDS"], 60)
        self.assertEqual(h["DEPTH"], 4)
        self.assertEqual([h["FEAT%d" % i] for i in range(1, h["NFEAT"] + 1)][:4],
                         ["ARCNESS", "ANTIARCNESS", "E_IMAGE", "log10(SNR_ISO)"])
        # The simulated arcs carry the context columns the model reads.
        self.assertIn("CTX_NB_DIST", fits.getdata(self.sim, "ARCS").columns.names)

    def test_training_is_reproducible(self):
        # Trained again from the same files and seed (on one thread, always): the same model.
        again = self.path("again.model.fits")
        self.train(again)
        a = fits.getdata(self.model, "LENS_MODEL")["MODEL"]
        b = fits.getdata(again, "LENS_MODEL")["MODEL"]
        self.assertEqual(list(a), list(b))

    def test_candidates_in_score_order_and_score_min(self):
        self.search("all")
        t = fits.getdata(self.path("all/candidates.fits"), "LDAC_OBJECTS")
        h = fits.getheader(self.path("all/candidates.fits"), "LDAC_OBJECTS")
        self.assertEqual(h["SELMETH"], "TREES")
        self.assertGreater(len(t), 5)
        score = t["LENS_SCORE"]
        self.assertTrue(np.all(np.diff(score) <= 0))
        self.assertTrue(np.all((score > 0) & (score < 1)))
        self.assertEqual(list(t["LENS_RANK"]), list(range(1, len(t) + 1)))
        self.assertEqual(list(t["NUMBER"]), list(t["LENS_RANK"]))
        # The same scores with the trees predicting on one thread (NTHREADS).
        self.search("one", "-NTHREADS", "1")
        np.testing.assert_array_equal(
            fits.getdata(self.path("one/candidates.fits"), "LDAC_OBJECTS")["LENS_SCORE"], score)
        # SCORE_MIN at the median candidate's score keeps the rows at or above it: every
        # candidate above it again, and nothing below. (A row below the cut no longer joins the
        # rows above it into one candidate, so there may be more candidates than before.)
        cut = float(np.median(score))
        self.search("cut", "-SCORE_MIN", repr(cut))
        kept = fits.getdata(self.path("cut/candidates.fits"), "LDAC_OBJECTS")
        self.assertTrue(np.all(kept["LENS_SCORE"] >= cut))
        above = score >= cut
        self.assertGreaterEqual(len(kept), above.sum())
        positions = set(zip(kept["X_IMAGE"], kept["Y_IMAGE"]))
        for x, y in zip(t["X_IMAGE"][above], t["Y_IMAGE"][above]):
            self.assertIn((x, y), positions)

    def test_lens_density_moves_the_log_odds_by_the_prior(self):
        self.search("d1", "-LENS_DENSITY", "1")
        self.search("d100", "-LENS_DENSITY", "100")
        t1 = fits.getdata(self.path("d1/candidates.fits"), "LDAC_OBJECTS")
        t100 = fits.getdata(self.path("d100/candidates.fits"), "LDAC_OBJECTS")
        p1 = fits.getheader(self.path("d1/candidates.fits"), "LDAC_OBJECTS")["SCOREPRI"]
        p100 = fits.getheader(self.path("d100/candidates.fits"), "LDAC_OBJECTS")["SCOREPRI"]
        self.assertAlmostEqual(p100 / p1, 100.0, places=9)
        self.assertEqual(list(t1["X_IMAGE"]), list(t100["X_IMAGE"]))  # the same order
        np.testing.assert_allclose(logit(t100["LENS_SCORE"]) - logit(t1["LENS_SCORE"]),
                                   logit(p100) - logit(p1), rtol=0, atol=1e-9)

    def test_bad_model_and_training_without_survey(self):
        grid = os.path.join(SOURCE_DIR, "params", "demo.grid.fits")
        r = run_octarc("search", self.field, "-SELECTION_METHOD", "TREES", "-MODEL_NAME", grid,
                       "-OUTPUT_DIR", self.path("bad"), check=False, cwd=self.work)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn(grid, r.stderr)
        self.assertIn("not an octarc lens model", r.stderr)
        errors = [line for line in r.stderr.splitlines() if "error" in line]
        self.assertEqual(len(errors), 1, r.stderr)
        self.assertFalse(os.path.exists(self.path("bad")))
        r = run_octarc("calibrate", self.sim, "-MODEL_NAME", self.path("m.fits"), "-GRID_NAME",
                       "NONE", "-NOISE_STUDY", "N", "-CHECKPLOT_TYPE", "NONE", check=False,
                       cwd=self.work)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("MODEL_NAME", r.stderr)
        self.assertIn("SURVEY_CATALOG", r.stderr)
        self.assertFalse(os.path.exists(self.path("m.fits")))


if __name__ == "__main__":
    unittest.main()
