"""The Python module's selection and search stages (issue 30): octarc.search on arrays against
the `octarc search` command on the same FITS files (every candidate column bit for bit, with the
grid and with the lens model); octarc.Grid.score against the grid file read with astropy and
binned by hand; octarc.Model.score against XGBoost's own Python package predicting from the
model file's JSON; bad input as ValueError / OSError.

ctest puts <build>/python on PYTHONPATH (the module just built)."""
import os
import shutil
import tempfile
import unittest

import numpy as np
from astropy import units as u
from astropy.io import fits

from octarc_testlib import WorkDirTest, ldac_objects, run_octarc
import octarc

SHARE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(octarc.__file__))), "..",
                     "share", "octarc")


def simulated_field(work, size=1024, seed=3, lenses=4):
    """A survey field with injected lenses made by `octarc simulate field`: the image, its
    weight map and their paths."""
    image = os.path.join(work, "field.fits")
    run_octarc("simulate", "field", "-o", image, "--size", size, "--seed", seed, "--lenses",
               lenses)
    weight = os.path.join(work, "field.weight.fits")
    return image, weight


def same_column(a, b):
    """Equal columns: numbers as their bits (NaN = NaN), strings without trailing blanks."""
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind in "US" or b.dtype.kind in "US":
        return [str(x).rstrip() for x in a] == [str(x).rstrip() for x in b]
    return a.shape == b.shape and np.array_equal(a, b, equal_nan=True)


class PythonSearch(WorkDirTest):
    """octarc.search gives the candidates of `octarc search` on the same pixels, column by
    column and bit for bit, with the grid and with the lens model; the same on any number of
    threads; bad input is a Python exception with octarc's message."""

    @classmethod
    def setUpClass(cls):
        cls.field_dir = tempfile.mkdtemp(prefix="octarc-test-")
        cls.field = simulated_field(cls.field_dir)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.field_dir, ignore_errors=True)

    def search_both_ways(self, selector_keys, python_kwargs, out):
        image, weight = self.field
        run_octarc("search", image, "-c", "octarc.sex", "-WEIGHT_IMAGE", weight,
                   "-WEIGHT_TYPE", "MAP_WEIGHT", "-OUTPUT_DIR", self.path(out), "-STAMPS", "N",
                   "-VERBOSE_TYPE", "QUIET", *selector_keys)
        command = fits.open(os.path.join(self.path(out), "candidates.fits"))["LDAC_OBJECTS"]
        found = octarc.search(fits.getdata(image), weight=fits.getdata(weight),
                              wcs=fits.getheader(image), config_file="octarc.sex",
                              **python_kwargs)
        return command, found

    def check_equal(self, command, found):
        table = found.to_table()
        self.assertGreater(len(table), 0)  # something to compare
        self.assertEqual(table.colnames, list(command.columns.names))
        for name in table.colnames:
            self.assertTrue(same_column(table[name], command.data[name]), name)
            unit = command.columns[name].unit
            if unit:
                self.assertEqual(table[name].unit, u.Unit(unit, parse_strict="silent"), name)
            else:
                self.assertIsNone(table[name].unit, name)
        for key in ("NCANDID", "NROWSRCH", "NOBJSRCH", "NROWSEL", "SRCHPIX", "SRCHAREA",
                    "CANDDEG2", "NSPACES", "SPCAND1", "SPCAND2"):
            self.assertEqual(table.meta[key], command.header[key], key)
        self.assertEqual(len(found), command.header["NCANDID"])

    def test_trees_equal_the_command(self):
        command, found = self.search_both_ways(
            ["-SELECTION_METHOD", "TREES", "-MODEL_NAME", "demo.model.fits", "-SCORE_MIN", "0"],
            {"model": octarc.Model.read("demo.model.fits"), "config": {"SCORE_MIN": 0}},
            "trees")
        self.check_equal(command, found)
        self.assertTrue(np.all(np.diff(found.to_table()["LENS_SCORE"]) <= 0))
        self.assertAlmostEqual(found.pixel_scale, 0.257, places=4)  # the field's WCS

    def test_grid_equals_the_command_on_any_thread_count(self):
        command, found = self.search_both_ways(
            ["-GRID_NAME", "demo.grid.fits"], {"grid": "demo.grid.fits"}, "grid")
        self.check_equal(command, found)
        image, weight = self.field
        again = octarc.search(fits.getdata(image), weight=fits.getdata(weight),
                              wcs=fits.getheader(image), config_file="octarc.sex",
                              grid="demo.grid.fits", config={"NTHREADS": 1})
        a, b = found.to_table(), again.to_table()
        for name in a.colnames:
            self.assertTrue(same_column(a[name], b[name]), name)
        # Every row searched: the command's detection of the same file, row for row.
        rows = found.catalog_table(["NUMBER", "THRESH_LEVEL", "X_IMAGE", "ARCNESS"])
        catalog = self.path("field.ldac")
        run_octarc("detect", image, "-c", "octarc.sex", "-WEIGHT_IMAGE", weight, "-WEIGHT_TYPE",
                   "MAP_WEIGHT", "-CATALOG_NAME", catalog, "-VERBOSE_TYPE", "QUIET")
        detected, _ = ldac_objects(catalog)
        for name in rows.colnames:
            self.assertTrue(same_column(rows[name], detected[name]), name)

    def test_lens_light_equals_the_command(self):
        # LENS_LIGHT LOCAL: the galaxies fitted and subtracted, the residual detected again, in
        # memory as from the file.
        command, found = self.search_both_ways(
            ["-GRID_NAME", "demo.grid.fits", "-LENS_LIGHT", "LOCAL", "-LENS_CHECKIMAGES", "N"],
            {"grid": "demo.grid.fits", "config": {"LENS_LIGHT": "LOCAL"}}, "light")
        self.check_equal(command, found)

    def test_injections_match_as_the_demo(self):
        # octarc demo simulates a field with injected lenses, searches it and lists which
        # lenses it found; the same field searched and matched from Python gives its lists.
        out = self.path("demo")
        run_octarc("demo", "--seed", "2", "--size", "1024", "--lenses", "4", "--method", "GRID",
                   "--score-min", "0", "--out", out, "--quiet")
        image = os.path.join(out, "field.fits")
        field_deg2 = (1024 * 0.257 / 3600.0) ** 2
        found = octarc.search(
            fits.getdata(image), weight=fits.getdata(os.path.join(out, "field.weight.fits")),
            wcs=fits.getheader(image), config_file="octarc.sex", grid="demo.grid.fits",
            config={"LENS_DENSITY": "%.10g" % (4 / field_deg2), "SCORE_MIN": 0,
                    "PIXEL_SCALE": 0.257, "SEEING_FWHM": 0.9, "MAG_ZEROPOINT": 30, "GAIN": 54,
                    "SNR_MIN": 40})
        systems, candidate_system = found.match_injections(
            os.path.join(out, "field.truth.txt"))
        listed = np.loadtxt(os.path.join(out, "injection-systems.txt"), ndmin=2)
        self.assertEqual(len(systems), 4)
        np.testing.assert_array_equal(systems["SYSTEM"], listed[:, 0])
        np.testing.assert_allclose(systems["THETA_E"], listed[:, 1], atol=5e-5)
        np.testing.assert_allclose(systems["ARC_MAG"], listed[:, 2], atol=5e-4)
        np.testing.assert_array_equal(systems["CANDIDATE"] + 1, listed[:, 3])  # 1-based there
        np.testing.assert_array_equal(systems["SPACES"], listed[:, 4])
        np.testing.assert_array_equal(systems["LENS_RIGHT"], listed[:, 5] == 1)
        np.testing.assert_allclose(systems["THETA_E_ESTIMATE"], listed[:, 6], atol=5e-5)
        self.assertGreater(np.count_nonzero(systems["CANDIDATE"] >= 0), 0)  # one was found
        candidates = np.loadtxt(os.path.join(out, "injection-candidates.txt"), ndmin=2)
        np.testing.assert_array_equal(candidate_system, candidates[:, 1])
        np.testing.assert_allclose(found.to_table()["LENS_SCORE"], candidates[:, 3], rtol=1e-6)

    def test_files_headers_and_warnings(self):
        # A grid read from a path with a blank and a comma; a long-string (CONTINUE) header
        # card; a misspelt key of the .sex file reaches the warnings, as the command prints it.
        folder = self.path("a dir, with blanks")
        os.makedirs(folder)
        grid_path = os.path.join(folder, "my grid.fits")
        shutil.copy(os.path.join(SHARE, "demo.grid.fits"), grid_path)
        image, weight = self.field
        header = fits.getheader(image)
        header["LONGTXT"] = "x" * 120  # two cards: CONTINUE
        sex = self.path("survey.sex")
        with open(os.path.join(SHARE, "octarc.sex")) as f, open(sex, "w") as out:
            out.write(f.read() + "SNR_MN 20\n")
        found = octarc.search(fits.getdata(image), weight=fits.getdata(weight), wcs=header,
                              grid=octarc.Grid.read(grid_path), config_file=sex)
        self.assertIn(grid_path, found.summary[0])
        self.assertTrue(any("SNR_MN" in w for w in found.warnings), found.warnings)
        again = octarc.search(fits.getdata(image), weight=fits.getdata(weight), wcs=header,
                              grid=grid_path, config_file=sex)
        a, b = found.to_table(), again.to_table()
        self.assertGreater(len(a), 0)
        for name in a.colnames:
            self.assertTrue(same_column(a[name], b[name]), name)

    def test_bad_input(self):
        image = np.random.default_rng(2).normal(0.0, 1.0, (128, 128)).astype(np.float32)
        cases = [
            (dict(grid="demo.grid.fits", model="demo.model.fits"), ValueError, "not both"),
            (dict(grid="no-such.grid.fits"), OSError, "no-such.grid.fits"),
            (dict(grid="demo.grid.fits", config={"PIXEL_SCALE": 0}), ValueError,
             "data: no WCS to take the pixel scale from"),
            (dict(grid="demo.grid.fits", config={"PIXEL_SCALE": 0.2, "COLOUR_IMAGE": "g.fits",
                                                 "COLOUR_BAND": "g"}),
             ValueError, "COLOUR_IMAGE: not available for an image in memory"),
            (dict(grid="demo.grid.fits", weight=np.ones((64, 64), np.float32)), ValueError,
             "weight"),
            (dict(grid="demo.grid.fits", config={"NO_SUCH_KEY": 1}), ValueError, "NO_SUCH_KEY"),
            (dict(grid="demo.grid.fits", config={"WEIGHT_TYPE": "MAP_WEIGHT"}), ValueError,
             "WEIGHT_TYPE: the configuration asks for a weight map; give it as weight="),
        ]
        for kwargs, error, text in cases:
            with self.assertRaises(error, msg=str(kwargs)) as caught:
                octarc.search(image, **kwargs)
            self.assertIn(text, str(caught.exception))
            self.assertNotIn("\n", str(caught.exception))
        # A truth list whose KIND is no whole number (NaN) is refused, naming the column.
        found = octarc.search(image, grid="demo.grid.fits", config={"PIXEL_SCALE": 0.2})
        truth = {"ID": [1.0], "X_IMAGE": [10.0], "Y_IMAGE": [10.0], "ALPHA_J2000": [0.0],
                 "DELTA_J2000": [0.0], "KIND": [float("nan")], "MAG": [20.0],
                 "THETA_E": [1.0], "SYSTEM": [1.0]}
        with self.assertRaisesRegex(ValueError, "^truth: KIND in row 1 is not a whole number$"):
            found.match_injections(truth)


class PythonSelection(WorkDirTest):
    """octarc.Grid.score bins rows as the grid file says (read with astropy, binned by hand);
    octarc.Model.score gives the log-odds XGBoost's own Python package predicts from the model
    file's trees."""

    def test_grid_score_against_the_file(self):
        image, weight = simulated_field(self.work, size=512, seed=5, lenses=2)
        rows = octarc.detect(fits.getdata(image), list(np.geomspace(2.5, 20, 15)),
                             weight=fits.getdata(weight), wcs=fits.getheader(image)).to_table()
        grid = octarc.Grid.read("demo.grid.fits")
        scored = grid.score(rows)
        self.assertEqual(len(scored), len(rows))
        hdu = fits.open(os.path.join(SHARE, "demo.grid.fits"))["OCC_GRID"]
        header, data = hdu.header, hdu.data
        values = {"ARCNESS": np.asarray(rows["ARCNESS"], float),
                  "E_IMAGE": np.asarray(rows["E_IMAGE"], float),
                  "log10(SNR_ISO)": np.log10(np.asarray(rows["SNR_ISO"], float))}
        bins = []
        for axis in range(1, header["GRIDDIM"] + 1):
            v = values[header["AXEXPR%d" % axis]]
            lo, hi, n = header["AXLO%d" % axis], header["AXHI%d" % axis], header["AXBINS%d" % axis]
            with np.errstate(invalid="ignore"):
                k = np.floor((v - lo) * n / (hi - lo))
                bins.append(np.where((v >= lo) & (v < hi), np.minimum(k, n - 1), -1))
        bins = np.array(bins).T
        occupied = {tuple(b): r for r, b in enumerate(data["BIN"])}
        inside = occupied_rows = 0
        for r, b in enumerate(bins):
            key = tuple(int(x) for x in b)
            if min(key) < 0:
                self.assertEqual(scored["GRID_STATUS"][r] in (2, 3), True, r)
                self.assertEqual(scored["PROBABILITY"][r], 0.0)
                continue
            inside += 1
            if key in occupied:
                occupied_rows += 1
                g = occupied[key]
                self.assertEqual(scored["GRID_STATUS"][r], 0)
                self.assertEqual(scored["PROBABILITY"][r], data["PROB"][g])
                self.assertEqual(scored["CONTOUR_LEVEL"][r], data["CUMPROB"][g])
                self.assertEqual(bool(scored["SELECTED"][r]), bool(data["SELECTED"][g]))
            else:
                self.assertEqual(scored["GRID_STATUS"][r], 1)
                self.assertFalse(scored["SELECTED"][r])
        self.assertGreater(occupied_rows, 10)  # the comparison covers many rows
        self.assertGreater(inside, occupied_rows)
        self.assertEqual(grid.level, header["PLEVEL"])
        self.assertEqual([a[0] for a in grid.axes], ["ARCNESS", "E_IMAGE", "log10(SNR_ISO)"])
        with self.assertRaisesRegex(ValueError, "SNR_ISO"):
            grid.score(rows["ARCNESS", "E_IMAGE"])

    def test_model_score_against_xgboost(self):
        import xgboost
        lenses = self.path("lenses.fits")
        # Massive lenses and bright sources: many arcs from few systems.
        run_octarc("simulate", "lenses", "-n", "100", "--seed", "2", "--preset", "dls", "-o",
                   lenses, "--quiet", "--sigma-min", "300", "--source-mag-max", "23")
        arcs = fits.getdata(lenses, "ARCS")
        self.assertGreater(len(arcs), 20)
        path = os.path.join(SHARE, "demo.model.fits")
        hdu = fits.open(path)["LENS_MODEL"]
        scale = hdu.header["PIXSCALE"]
        features = []
        for k in range(1, hdu.header["NFEAT"] + 1):
            name = hdu.header["FEAT%d" % k]
            if name == "log10(SNR_ISO)":
                with np.errstate(invalid="ignore", divide="ignore"):
                    column = np.log10(arcs["SNR_ISO"].astype(float))
            elif name == "SIZE_ARCSEC":
                column = np.sqrt(2.0) * arcs["SIZE_IMAGE"].astype(float) * scale
            else:
                column = arcs[name].astype(float)
            features.append(column.astype(np.float32))
        booster = xgboost.Booster()
        booster.load_model(bytearray("".join(hdu.data["MODEL"]).encode()))
        expected = booster.predict(xgboost.DMatrix(np.array(features).T, missing=np.nan),
                                   output_margin=True)
        model = octarc.Model.read("demo.model.fits")
        from astropy.table import Table
        scored = model.score(Table(arcs), prior=0.01)
        np.testing.assert_allclose(scored["LOG_ODDS"], expected, rtol=1e-6, atol=1e-6)
        self.assertTrue(np.all((scored["LENS_SCORE"] > 0) & (scored["LENS_SCORE"] < 1)))
        # A higher prior moves every score up.
        higher = model.score(Table(arcs), prior=0.1)["LENS_SCORE"]
        self.assertTrue(np.all(higher > scored["LENS_SCORE"]))
        with self.assertRaisesRegex(ValueError, "prior"):
            model.score(Table(arcs), prior=1.5)
        with self.assertRaises(OSError):
            octarc.Model.read(self.path("missing.model.fits"))


if __name__ == "__main__":
    unittest.main()
