"""`octarc calibrate` on a `simulate lenses` output: its tables against the same quantities
computed with numpy from the simulation's systems table (weighted by SIM_WEIGHT, the intervals
from scipy's Beta quantiles), the grid file, the check-plots, a run with too few arcs for the
grid asked for (still reported), GRID_NAME NONE, a default run in an empty folder, and bad input
(one-line errors, no output)."""
import os
import shutil
import unittest

import numpy as np
from astropy.io import fits
from scipy.stats import beta

from octarc_testlib import SOURCE_DIR, WorkDirTest, card_text, ldac_imhead, run_octarc
from test_hostile_input import with_card

# A few thousand systems of the `dls` preset give some tens of arcs (importance sampled: a few
# hundred rendered): enough for a 2-D grid.
SYSTEMS = "6000"
GRID = ["-GRID_AXES", "ARCNESS,E_IMAGE", "-GRID_LEVEL", "0.9"]
QUICK_NOISE = ["-NOISE_REALISATIONS", "10", "-NOISE_SIZE", "128"]


def clopper_pearson(k, n, confidence=0.6827):
    """The central Clopper-Pearson interval of k successes in n trials (both may be real)."""
    tail = (1 - confidence) / 2
    lo = beta.ppf(tail, k, n - k + 1) if k > 0 else 0.0
    hi = beta.ppf(1 - tail, k + 1, n - k) if k < n else 1.0
    return lo, hi


def kish(w):
    return w.sum() ** 2 / (w ** 2).sum() if len(w) else 0.0


class Calibrate(WorkDirTest):

    @classmethod
    def setUpClass(cls):
        cls.sim_dir = os.path.join(os.environ.get("TMPDIR", "/tmp"),
                                   "octarc-calibrate-%d" % os.getpid())
        os.makedirs(cls.sim_dir, exist_ok=True)
        cls.sim = os.path.join(cls.sim_dir, "sim.fits")
        run_octarc("simulate", "lenses", "-n", SYSTEMS, "--seed", "5", "--preset", "dls", "-o",
                   cls.sim, "--quiet")

    @classmethod
    def tearDownClass(cls):
        for name in os.listdir(cls.sim_dir):
            os.remove(os.path.join(cls.sim_dir, name))
        os.rmdir(cls.sim_dir)

    def calibrate(self, *args, check=True):
        return run_octarc("calibrate", self.sim, "-CALIBRATION_NAME", self.path("cal.fits"),
                          "-GRID_NAME", self.path("grid.fits"), *GRID, *QUICK_NOISE, *args,
                          check=check, cwd=self.work)

    def test_lensing_fractions_match_the_systems_table(self):
        self.calibrate("-CHECKPLOT_TYPE", "NONE")
        systems = fits.getdata(self.sim, "LDAC_OBJECTS")
        arc = systems["ARC_FOUND"] == 1
        n = arc.sum()
        w = systems["SIM_WEIGHT"][arc]
        self.assertGreater(w.max(), 1.0)  # importance sampling: weights beyond 1
        a, e, snr = systems["ARCNESS"][arc], systems["E_IMAGE"][arc], systems["SNR_ISO"][arc]
        table = fits.getdata(self.path("cal.fits"), "LENSING_FRACTION")
        header = fits.getheader(self.path("cal.fits"), "LENSING_FRACTION")
        self.assertEqual(header["NARCSYS"], n)
        self.assertAlmostEqual(header["WARCSYS"], w.sum(), delta=1e-9 * w.sum())
        self.assertAlmostEqual(header["NEFFARC"], kish(w), delta=1e-9 * n)
        self.assertEqual(len(table), 6)
        for row in table:
            hi = row["ARCNESS_HI"] if np.isfinite(row["ARCNESS_HI"]) else np.inf
            inside = (a >= row["ARCNESS_LO"]) & (a < hi)
            if row["DISTORTED"]:
                inside &= (e > 0.6) & (snr > 40)
            self.assertEqual(row["N_SYSTEMS"], inside.sum())
            f = w[inside].sum() / w.sum()
            self.assertAlmostEqual(row["FRACTION"], f, places=12)
            lo, hi = clopper_pearson(f * kish(w), kish(w))
            self.assertAlmostEqual(row["FRACTION_LO"], lo, places=8)
            self.assertAlmostEqual(row["FRACTION_HI"], hi, places=8)
            self.assertAlmostEqual(row["FRACTION_ERR"], (hi - lo) / 2, places=8)

    def test_grid_holds_every_arc_and_its_binning_search(self):
        self.calibrate("-CHECKPLOT_TYPE", "NONE")
        systems = fits.getdata(self.sim, "LDAC_OBJECTS")
        arcs = (systems["ARC_FOUND"] == 1).sum()
        binning = fits.getheader(self.path("cal.fits"), "GRID_BINNING")
        self.assertEqual(binning["NSAMPLES"], arcs)
        self.assertEqual(binning["NDROPAX"], 0)
        self.assertEqual(binning["GRIDAX1"], "ARCNESS")
        grid = fits.open(self.path("grid.fits"))["OCC_GRID"]
        self.assertEqual(grid.header["AXEXPR1"], "ARCNESS")
        self.assertEqual(grid.header["AXBINS1"], binning["FINEST"])
        self.assertEqual(grid.header["NDROPAX"], 0)
        # Every arc is in a bin, outside the axis ranges (their tails) or undefined.
        h = grid.header
        self.assertEqual(h["NBINNED"] + h["NOUTSIDE"] + h["NUNDEF"], arcs)
        self.assertEqual(grid.data["COUNT"].sum(), h["NBINNED"])
        # The probabilities are the bins' SIM_WEIGHT sums over the binned weight.
        self.assertAlmostEqual(grid.data["WEIGHT"].sum(), h["WBINNED"], delta=1e-9 * h["WBINNED"])
        np.testing.assert_allclose(grid.data["PROB"], grid.data["WEIGHT"] / h["WBINNED"],
                                   rtol=1e-12)
        self.assertGreaterEqual(h["PSELECT"], 0.9)
        # The survey setup of the simulation is carried into the grid.
        cell = fits.getdata(self.sim, "LDAC_IMHEAD")[0][0]
        cards = fits.Header.fromstring("".join(c.ljust(80) for c in cell), sep="")
        self.assertAlmostEqual(h["PIXSCALE"], cards["OCTPIXSC"], places=9)
        self.assertAlmostEqual(h["SKYSIGMA"], cards["OCTSKYSG"], places=9)
        self.assertEqual(h["MINAREA"], cards["OCTMINAR"])
        self.assertEqual(h["NSYSTEMS"], cards["OCTNSYS"])  # drawn, not rendered

    def test_distributions_are_normalised_histograms_of_the_arcs(self):
        self.calibrate("-CHECKPLOT_TYPE", "NONE", "-HISTOGRAM_NBINS", "20")
        systems = fits.getdata(self.sim, "LDAC_OBJECTS")
        sel = (systems["ARC_FOUND"] == 1) & (systems["E_IMAGE"] > 0.6) & (systems["SNR_ISO"] > 40)
        dist = fits.getdata(self.path("cal.fits"), "DIST_ARCNESS")
        w = systems["SIM_WEIGHT"][sel]
        counts, _ = np.histogram(systems["ARCNESS"][sel], bins=20, range=(0.0, 0.3))
        weights, _ = np.histogram(systems["ARCNESS"][sel], bins=20, range=(0.0, 0.3), weights=w)
        np.testing.assert_allclose(dist["SIM_FRACTION"], weights / weights.sum(), rtol=0,
                                   atol=1e-12)
        header = fits.getheader(self.path("cal.fits"), "DIST_ARCNESS")
        self.assertEqual(header["NSIM"], sel.sum())
        self.assertEqual(header["NSIMOUT"], sel.sum() - counts.sum())
        self.assertAlmostEqual(header["NEFFSIM"], kish(w), delta=1e-9 * sel.sum())

    def test_noise_only_threshold_table(self):
        self.calibrate("-CHECKPLOT_TYPE", "NONE")
        noise = fits.open(self.path("cal.fits"))["NOISE_THRESHOLD"]
        t = noise.header["NOISETHR"]
        rows = noise.data
        self.assertTrue(np.all(rows["N_WITH_OBJECTS"][rows["THRESHOLD"] >= t - 1e-9] == 0))
        self.assertGreater(rows["N_WITH_OBJECTS"][rows["THRESHOLD"] < t - 1e-9][-1], 0)

    def test_threshold_count_study_remakes_the_simulation(self):
        # At the simulation's own number of levels, with its seed and number of systems, the
        # study simulates the same systems again: its counts are those of the input.
        self.calibrate("-CHECKPLOT_TYPE", "THRESHOLD_COUNT", "-CHECKPLOT_NAME", "tc",
                       "-NOISE_STUDY", "N", "-THRESHOLD_STUDY", "Y", "-THRESHOLD_SYSTEMS",
                       SYSTEMS, "-THRESHOLD_NLEVELS", "3,15")
        # The remake samples as the simulation did (importance sampling): the same systems
        # rendered, with the same weights.
        systems = fits.getdata(self.sim, "LDAC_OBJECTS")
        arcs = fits.getdata(self.sim, "ARCS")
        with_arcness = np.unique(arcs["SYSTEM"][arcs["ARCNESS"] > 0.10])
        weight = dict(zip(systems["SYSTEM"], systems["SIM_WEIGHT"]))
        weight_sum = sum(weight[s] for s in with_arcness)
        curve = fits.getdata(self.path("cal.fits"), "THRESHOLD_COUNT")
        self.assertEqual(list(curve["NLEVELS"]), [3, 15])
        row = curve[1]
        self.assertEqual(row["N_SYSTEMS"], int(SYSTEMS))  # drawn
        self.assertEqual(row["N_RENDERED"], len(systems))
        self.assertEqual(row["N_ARC"], (systems["ARC_FOUND"] == 1).sum())
        self.assertEqual(row["N_ARCNESS"], len(with_arcness))
        self.assertAlmostEqual(row["WEIGHT"], weight_sum, delta=1e-6 * weight_sum)
        w = np.array([weight[s] for s in with_arcness])
        self.assertAlmostEqual(row["NEFF_ARCNESS"], kish(w), delta=1e-6 * len(w))
        self.assertAlmostEqual(row["FRACTION"], weight_sum / int(SYSTEMS), delta=1e-9)
        self.assertLessEqual(row["FRACTION_LO"], row["FRACTION"])
        self.assertGreater(row["FRACTION_HI"], row["FRACTION"])
        self.assertTrue(os.path.exists(self.path("tc.png")))

    def test_snr_floor_study(self):
        proc = self.calibrate("-NOISE_STUDY", "N", "-SNR_STUDY", "Y", "-SNR_ARCS", "3",
                              "-SNR_REALISATIONS", "10", "-SNR_NOISE", "0.5,4,4",
                              "-SNR_MINPERBIN", "1", "-CHECKPLOT_TYPE", "SNR_FLOOR",
                              "-CHECKPLOT_NAME", "snr")
        self.assertIn("arcness unreliable below S/N", proc.stdout)
        systems = fits.getdata(self.sim, "LDAC_OBJECTS")
        taken = (systems["ARC_FOUND"] == 1) & (systems["ARCNESS"] >= 0.05) & \
            (systems["ARCNESS"] <= 0.20)
        table = fits.open(self.path("cal.fits"))["SNR_FLOOR"]
        rows, header = table.data, table.header
        self.assertEqual(header["NARCS"], min(3, taken.sum()))
        self.assertIn("arcs (", proc.stdout)  # the count and the effective number
        self.assertLessEqual(rows["N_MEASURED"].sum(), header["NMEASURE"])
        self.assertLessEqual(header["NMEASURE"], header["NARCS"] * 10 * 4)
        full = rows[rows["N_MEASURED"] > 0]
        self.assertTrue(np.all(full["ARCNESS_Q20"] <= full["ARCNESS_MEDIAN"]))
        self.assertTrue(np.all(full["ARCNESS_MEDIAN"] <= full["ARCNESS_Q80"]))
        # The default bins: 16 log-spaced from S/N 5 to 1280.
        np.testing.assert_allclose(rows["SNR_LO"], 5 * 2 ** (np.arange(16) / 2), rtol=1e-12)
        # The criterion and the floor, recomputed from the table.
        reliable = (rows["N_MEASURED"] >= 1) & \
            (np.abs(rows["ARCNESS_MEDIAN"] - 0.10) <= 0.01 + 1e-12) & \
            (rows["ARCNESS_Q80"] - rows["ARCNESS_Q20"] <= 0.05 + 1e-12)
        np.testing.assert_array_equal(rows["RELIABLE"] == 1, reliable)
        floor = np.nan
        for row, ok in zip(rows[::-1], reliable[::-1]):
            if row["N_MEASURED"] < 1:
                continue
            if not ok:
                break
            floor = row["SNR_LO"]
        if np.isnan(floor):
            self.assertIsNone(header["SNRFLOOR"])
        else:
            self.assertAlmostEqual(header["SNRFLOOR"], floor, places=9)
        with open(self.path("snr.png"), "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_skewness_widths_are_those_of_a_gaussian_fit(self):
        # scipy's least-squares fit of the same histogram is the independent oracle; a run of
        # massive lenses and bright sources gives enough arcs of arcness > 0.10 (27) for a
        # histogram to fit. Any histogram serves: rays traced on a 0.06" grid instead of 0.03"
        # take a third off the run.
        from scipy.optimize import curve_fit
        bright = os.path.join(self.sim_dir, "bright-arcs.fits")
        if not os.path.exists(bright):
            run_octarc("simulate", "lenses", "-n", "600", "--seed", "2", "--preset", "dls",
                       "--source-mag-min", "20", "--source-mag-max", "21", "--sigma-min", "360",
                       "--sigma-max", "450", "--lens-mag-min", "19", "--lens-mag-max", "23",
                       "--fine-scale", "0.06", "-o", bright, "--quiet")
        run_octarc("calibrate", bright, "-CALIBRATION_NAME", self.path("cal.fits"),
                   "-GRID_NAME", self.path("grid.fits"), "-GRID_AXES", "ARCNESS",
                   "-HISTOGRAM_NBINS", "12", "-NOISE_STUDY", "N", "-CHECKPLOT_TYPE", "NONE",
                   cwd=self.work)
        for name in ("DIST_SKEW_MAJOR", "DIST_SKEW_MINOR"):
            hdu = fits.open(self.path("cal.fits"))[name]
            x = 0.5 * (hdu.data["BIN_LO"] + hdu.data["BIN_HI"])
            y = hdu.data["SIM_FRACTION"]
            self.assertGreaterEqual(hdu.header["NSIM"], 20, name)
            def gauss(v, a, m, s):
                return a * np.exp(-0.5 * ((v - m) / s) ** 2)
            mean = np.sum(x * y) / np.sum(y)
            start = (y.max(), mean, np.sqrt(np.sum(y * (x - mean) ** 2) / np.sum(y)))
            (a, m, s), _ = curve_fit(gauss, x, y, p0=start, maxfev=20000)
            self.assertTrue(hdu.header["GAUSCONV"], name)
            self.assertAlmostEqual(hdu.header["GAUSSIG"], abs(s), delta=1e-3 * abs(s))
            self.assertAlmostEqual(hdu.header["GAUSMEAN"], m, delta=1e-3 * abs(s))
            # The same relative agreement as sigma's: FWHM = 2 sqrt(2 ln 2) sigma.
            fwhm = 2 * np.sqrt(2 * np.log(2)) * abs(s)
            self.assertAlmostEqual(hdu.header["GAUSFWHM"], fwhm, delta=1e-3 * fwhm)

    def test_a_seed_above_2_to_the_63_reaches_the_grid_exactly(self):
        # simulate lenses writes OCTSEED as a signed integer card (-9223372036854775807 for
        # 2^63 + 1); read as a double it came back rounded to 2^63.
        seed = 2 ** 63 + 1
        run_octarc("simulate", "lenses", "-n", "100", "--seed", str(seed), "--preset", "dls",
                   "--source-mag-min", "20", "--source-mag-max", "21", "--sigma-min", "360",
                   "--sigma-max", "450", "--lens-mag-min", "19", "--lens-mag-max", "23",
                   "-o", "big-seed.fits", "--quiet", cwd=self.work)
        run_octarc("calibrate", "big-seed.fits", "-GRID_AXES", "ARCNESS", "-NOISE_STUDY", "N",
                   "-CHECKPLOT_TYPE", "NONE", "-GRID_NAME", "g.fits", "-CALIBRATION_NAME",
                   "c.fits", cwd=self.work)
        self.assertEqual(fits.getheader(self.path("g.fits"), "OCC_GRID")["SEED"], seed)

    def test_check_plots(self):
        self.calibrate("-CHECKPLOT_TYPE", "ARCNESS,LENSING_FRACTION,NOISE_THRESHOLD",
                       "-CHECKPLOT_NAME", "a,lf,noise", "-CHECKPLOT_RES", "640,480")
        for name in ("a.png", "lf.png", "noise.png"):
            with open(self.path(name), "rb") as f:
                head = f.read(24)
            self.assertEqual(head[:8], b"\x89PNG\r\n\x1a\n", name)
            self.assertEqual(int.from_bytes(head[16:20], "big"), 640)
            self.assertEqual(int.from_bytes(head[20:24], "big"), 480)
        self.calibrate("-CHECKPLOT_TYPE", "GRID_BINNING", "-CHECKPLOT_NAME", "g",
                       "-CHECKPLOT_DEV", "PDF")
        with open(self.path("g.pdf"), "rb") as f:
            self.assertEqual(f.read(5), b"%PDF-")

    def test_too_few_arcs_for_the_grid_still_report(self):
        # No binning keeps this contour connected on four axes: the studies and plots are
        # written, the grid is made on fewer axes (or none), with a WARNING that says so.
        proc = self.calibrate("-GRID_AXES", "ARCNESS,E_IMAGE,SKEW_MAJOR,SKEW_MINOR",
                              "-GRID_LEVEL", "0.999", "-GRID_NBINS", "20,30", "-NOISE_STUDY",
                              "N", "-CHECKPLOT_TYPE", "ARCNESS,GRID_BINNING", "-CHECKPLOT_NAME",
                              "a,g")
        warnings = [l for l in proc.stderr.splitlines() if l.startswith("WARNING")]
        self.assertEqual(len(warnings), 1, proc.stderr)
        for fragment in ("arcs (", "effective)", "20 to 30 bins per axis", "GRID_NAME NONE",
                         "fewer GRID_AXES", "more systems"):
            self.assertIn(fragment, warnings[0])
        self.assertTrue(os.path.exists(self.path("a.png")))
        self.assertTrue(os.path.exists(self.path("g.png")))
        binning = fits.open(self.path("cal.fits"))["GRID_BINNING"]
        self.assertGreater(binning.header["NDROPAX"], 0)
        self.assertEqual(binning.data["NAXES"][0], 4)
        self.assertEqual(binning.data["AXES"][0], "ARCNESS,E_IMAGE,SKEW_MAJOR,SKEW_MINOR")
        if binning.header["GRIDMADE"]:
            grid = fits.getheader(self.path("grid.fits"), "OCC_GRID")
            self.assertEqual(grid["GRIDDIM"] + grid["NDROPAX"], 4)
            self.assertEqual(grid["DROPAX1"], binning.header["DROPAX1"])
            self.assertIn("dropped " + grid["DROPAX1"], warnings[0])
        else:
            self.assertFalse(os.path.exists(self.path("grid.fits")))
        # A search space no arc falls in: every study, no grid, the warning counts 0 arcs.
        proc = self.calibrate("-SEARCH_CUT", "ARCNESS > 5", "-NOISE_STUDY", "N",
                              "-CHECKPLOT_TYPE", "NONE", "-GRID_NAME", "nogrid.fits")
        self.assertIn("WARNING: no occupation grid: 0 arcs (0 effective)", proc.stderr)
        self.assertFalse(os.path.exists(self.path("nogrid.fits")))
        self.assertIn("LENSING_FRACTION", [h.name for h in fits.open(self.path("cal.fits"))])

    def test_grid_name_none_makes_no_grid(self):
        proc = self.calibrate("-GRID_NAME", "NONE", "-NOISE_STUDY", "N", "-CHECKPLOT_TYPE",
                              "GRID_BINNING", "-CHECKPLOT_NAME", "g")
        self.assertNotIn("WARNING", proc.stderr)
        self.assertIn("Occupation grid: none (GRID_NAME NONE)", proc.stdout)
        self.assertEqual(sorted(os.listdir(self.work)), ["cal.fits", "g.png"])
        self.assertFalse(fits.getheader(self.path("cal.fits"), "GRID_BINNING")["GRIDMADE"])

    def test_a_default_run_in_an_empty_folder_writes_everything(self):
        # The defaults of both commands (importance sampling, every check-plot): exit 0, the
        # fractions with intervals, the distributions, the check-plots and a grid. The class's
        # simulation is one with simulate's defaults.
        shutil.copy(self.sim, self.path("s.fits"))
        proc = run_octarc("calibrate", "s.fits", *QUICK_NOISE, cwd=self.work)
        names = os.listdir(self.work)
        for name in ("calibration.fits", "arcs.grid.fits", "arcness.png", "snr_iso.png",
                     "lensing_fraction.png", "grid_binning.png", "noise_threshold.png"):
            self.assertIn(name, names)
        hdus = [h.name for h in fits.open(self.path("calibration.fits"))]
        for name in ("LENSING_FRACTION", "DIST_ARCNESS", "DIST_SNR_ISO", "GRID_BINNING"):
            self.assertIn(name, hdus)
        fractions = fits.getdata(self.path("calibration.fits"), "LENSING_FRACTION")
        self.assertTrue(np.all(fractions["FRACTION_HI"] > fractions["FRACTION"]))
        drawn = fits.Header.fromstring("".join(c.ljust(80) for c in fits.getdata(
            self.path("s.fits"), "LDAC_IMHEAD")[0][0]), sep="")["OCTNSYS"]
        self.assertIn("%d simulated systems" % drawn, proc.stdout)
        self.assertRegex(proc.stdout, r"\d\.\d{4} \+\d\.\d{4} -\d\.\d{4}")
        self.assertRegex(proc.stdout, r"Occupation grid: \d+ arcs \(\d+ effective\)")

    def assert_fails(self, proc, *fragments):
        self.assertEqual(proc.returncode, 1, proc.stderr)
        # Progress lines ("> ...") may come first; then the error, one line.
        lines = [l for l in proc.stderr.splitlines() if l.strip() and not l.startswith("> ")]
        self.assertEqual(len(lines), 1, proc.stderr)
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertEqual(sorted(os.listdir(self.work)), [])

    def test_check_plot_names_follow_their_types(self):
        self.calibrate("-CHECKPLOT_TYPE", "LENSING_FRACTION", "-NOISE_STUDY", "N")
        self.assertTrue(os.path.exists(self.path("lensing_fraction.png")))
        self.assertFalse(os.path.exists(self.path("arcness.png")))

    def test_bad_input(self):
        not_sim = os.path.join(SOURCE_DIR, "testdata", "example.cat1.ldac")
        self.assert_fails(run_octarc("calibrate", not_sim, check=False, cwd=self.work),
                          not_sim, "not an octarc simulate lenses output")
        self.assert_fails(self.calibrate("-SEARCH_CUT", "ARCNESS >", check=False),
                          "search space")
        self.assert_fails(self.calibrate("-SEARCH_CUT", "NO_SUCH_COLUMN > 1", check=False),
                          "NO_SUCH_COLUMN")
        self.assert_fails(self.calibrate("-CHECKPLOT_DEV", "XWIN", check=False), "CHECKPLOT_DEV")
        self.assert_fails(self.calibrate("-CHECKPLOT_TYPE", "ARCNESS,E_IMAGE", "-CHECKPLOT_NAME",
                                         "one", check=False), "CHECKPLOT_NAME")
        self.assert_fails(self.calibrate("-NOISE_THRESH", "3,2,0.1", check=False), "NOISE_THRESH")
        self.assert_fails(self.calibrate("-SNR_STUDY", "Y", "-SNR_NOISE", "4,2,3", check=False),
                          "SNR_NOISE")
        self.assert_fails(self.calibrate("-SNR_STUDY", "Y", "-SNR_ARCNESS", "5,6", check=False),
                          "no chosen arc")
        # A simulation whose systems the recorded options do not remake (here: its Einstein
        # radii altered) is refused by the studies that simulate again.
        altered = os.path.join(self.sim_dir, "altered.fits")
        with fits.open(self.sim) as f:
            f["LDAC_OBJECTS"].data["EINSTEIN_RADIUS"] *= 1.01
            f.writeto(altered, overwrite=True)
        self.assert_fails(run_octarc("calibrate", altered, "-THRESHOLD_STUDY", "Y",
                                     "-NOISE_STUDY", "N", *GRID, check=False, cwd=self.work),
                          altered, "cannot be remade")
        other = os.path.join(self.sim_dir, "bright.fits")
        run_octarc("simulate", "lenses", "-n", "20", "--seed", "7", "-o", other, "--quiet",
                   "--source-mag-min", "20", "--source-mag-max", "21")
        # Outputs of another population or other sources do not combine.
        self.assert_fails(run_octarc("calibrate", self.sim, other, check=False, cwd=self.work),
                          other, "population or sources")
        # Several outputs: SYSTEM restarts in each, the S/N study takes one.
        second = os.path.join(self.sim_dir, "seed6.fits")
        run_octarc("simulate", "lenses", "-n", "50", "--seed", "6", "--preset", "dls", "-o",
                   second, "--quiet")
        self.assert_fails(run_octarc("calibrate", self.sim, second, "-SNR_STUDY", "Y",
                                     "-NOISE_STUDY", "N", *GRID, check=False, cwd=self.work),
                          "SNR_STUDY takes one")
        self.assert_fails(self.calibrate("-SNR_STUDY", "Y", "-SNR_NOISE", "0.5,4,2.5",
                                         check=False), "whole number")
        # The same simulation twice would count its systems twice.
        self.assert_fails(run_octarc("calibrate", self.sim, self.sim, check=False, cwd=self.work),
                          "seed", "twice")
        # Setup cards that simulate lenses never writes would go on into the grid's setup.
        for key, value, expected in (("OCTSKYSG", "-1.0", "OCTSKYSG = -1 is not a finite "
                                      "number > 0"),
                                     ("OCTMINAR", "0", "OCTMINAR = 0 is not a whole number >= 1"),
                                     ("OCTNLEV", "100", "OCTNLEV = 100 is not a whole number from "
                                      "1 to 99 (a grid or lens model records at most 99 "
                                      "levels)")):
            bad = with_card(self.sim, os.path.join(self.sim_dir, key + ".fits"), key, value)
            self.assert_fails(run_octarc("calibrate", bad, check=False, cwd=self.work),
                              bad + ": LDAC_IMHEAD card " + expected)
        # The levels are spaced from OCTTHLO to OCTTHHI and must increase.
        head = ldac_imhead(self.sim)
        self.assertGreater(head["OCTNLEV"], 1)
        bad = with_card(self.sim, os.path.join(self.sim_dir, "OCTTHHI.fits"), "OCTTHHI",
                        card_text(head, "OCTTHLO"))
        self.assert_fails(run_octarc("calibrate", bad, check=False, cwd=self.work),
                          bad + ": LDAC_IMHEAD card OCTTHHI = ",
                          "is not above OCTTHLO (OCTNLEV > 1)")
        # The cards the studies that simulate again remake the stamps from: in the range
        # simulate lenses accepts for their options.
        for key, value, expected in (("OCTSTAMP", "8", "OCTSTAMP = 8 is not a whole number from "
                                      "9 to 2147483647"),
                                     ("OCTSUBS", "4.5", "OCTSUBS = 4.5 is not a whole number "
                                      "from 1 to 2147483647"),
                                     ("OCTFINE", "0.0", "OCTFINE = 0 is not a finite number > 0"),
                                     ("OCTSSTEP", "-1.0", "OCTSSTEP = -1 is not a finite number "
                                      ">= 0"),
                                     ("OCTSKIPT", "-0.5", "OCTSKIPT = -0.5 is not a finite "
                                      "number >= 0")):
            bad = with_card(self.sim, os.path.join(self.sim_dir, key + ".fits"), key, value)
            self.assert_fails(run_octarc("calibrate", bad, "-THRESHOLD_STUDY", "Y",
                                         "-NOISE_STUDY", "N", *GRID, check=False, cwd=self.work),
                              bad + ": LDAC_IMHEAD card " + expected)


if __name__ == "__main__":
    unittest.main()
