"""Importance sampling of `octarc simulate lenses` against a plain run of the same seed.

With the same seed the importance-sampled run renders a subset of the plain run's systems,
identical to them (the render decision has a random stream of its own); its weights stand for
the systems it leaves out. Checked here: the header's counts and sums against the tables, the
rendered rows against the plain rows of the same systems, and the weighted figures of
scripts/sampling_study.py (Table-1 fractions, arc rate per drawn system, medians) against the
plain ones within their combined errors. README "Simulations" has the same study at scale.
"""
import importlib.util
import os
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import SOURCE_DIR, WorkDirTest, ldac_imhead, run_octarc

SYSTEMS = 2000
SEED = 9


def load_study():
    path = os.path.join(SOURCE_DIR, "scripts", "sampling_study.py")
    spec = importlib.util.spec_from_file_location("sampling_study", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class Sampling(WorkDirTest):
    def simulate(self, sampling):
        out = self.path(sampling + ".fits")
        run_octarc("simulate", "lenses", "-n", SYSTEMS, "--seed", SEED, "--preset", "dls",
                   "--sampling", sampling, "-o", out, "--quiet")
        with fits.open(out) as f:
            return out, f["LDAC_OBJECTS"].data.copy(), ldac_imhead(out)

    def test_weighted_figures_are_the_plain_ones(self):
        plain_path, plain, plain_head = self.simulate("plain")
        imp_path, imp, imp_head = self.simulate("importance")

        # Plain: every system above the skip limit rendered, weight 1.
        self.assertEqual(plain_head["OCTSAMPL"], "PLAIN")
        self.assertEqual(plain_head["OCTNSYS"], SYSTEMS)
        self.assertTrue(np.all(plain["SIM_WEIGHT"] == 1.0))
        self.assertEqual(plain_head["OCTNREND"], len(plain))
        self.assertEqual(plain_head["OCTNSKIP"] + len(plain), SYSTEMS)
        self.assertTrue(np.all(plain["EINSTEIN_RADIUS"] >= plain_head["OCTSKIPT"]))

        # Importance: the header's counts and sums are the table's.
        self.assertEqual(imp_head["OCTSAMPL"], "IMPORTANCE")
        self.assertEqual(imp_head["OCTNSYS"], SYSTEMS)
        self.assertEqual(imp_head["OCTNREND"], len(imp))
        self.assertLess(len(imp), len(plain) / 3)
        w = np.asarray(imp["SIM_WEIGHT"], float)
        self.assertTrue(np.all(w >= 1.0))
        self.assertAlmostEqual(imp_head["OCTSUMW"], w.sum(), delta=1e-9 * w.sum())
        arc_w = w[imp["ARC_FOUND"] == 1]
        self.assertEqual(imp_head["OCTNARC"], len(arc_w))
        self.assertAlmostEqual(imp_head["OCTNEFF"], arc_w.sum() ** 2 / (arc_w ** 2).sum(),
                               delta=1e-9 * len(arc_w))
        # The weights stand for the systems above the skip limit (within 4 of the estimate's
        # standard errors, sqrt(sum (1 - r) / r^2) with r = 1 / w).
        above = SYSTEMS - imp_head["OCTNSKIP"]
        sigma = np.sqrt(np.sum((1.0 - 1.0 / w) * w * w))
        self.assertLess(abs(w.sum() - above), 4 * sigma)

        # Every rendered system is the plain run's system of that index, value for value.
        by_system = {int(s): i for i, s in enumerate(plain["SYSTEM"])}
        for name in ("EINSTEIN_RADIUS", "SOURCE_X", "SOURCE_Y", "MAGNIFICATION", "ARC_FOUND",
                     "ARCNESS", "E_IMAGE", "SNR_ISO"):
            p = np.asarray(plain[name], float)[[by_system[int(s)] for s in imp["SYSTEM"]]]
            np.testing.assert_array_equal(np.asarray(imp[name], float), p, err_msg=name)

        # The weighted figures are the plain ones within their combined errors.
        rows, summary = load_study().compare(plain_path, imp_path)
        self.assertGreater(summary["plain arcs"], 5)
        for name, pv, ps, wv, ws, pull, _, _ in rows:
            if np.isnan(pull):
                continue
            self.assertLessEqual(abs(pull), 1.0, "%s: plain %.4f +- %.4f, weighted %.4f +- %.4f"
                                 % (name, pv, ps, wv, ws))


if __name__ == "__main__":
    unittest.main()
