"""The Python module's simulations (the simulation stage): octarc.simulate_lenses
against `octarc simulate lenses` (both tables, every column, bit for bit; the header's OCT*
keywords) and on any number of threads, bad input as ValueError, Ctrl-C; octarc.simulate_field
against `octarc simulate field` (image, weight map, WCS, truth list); octarc.inject_lenses
against `octarc demo --into` (test_python.py runs the simulation example of docs/python.md).

ctest puts <build>/python on PYTHONPATH (the module just built)."""
import os
import unittest

import numpy as np
from astropy import units as u
from astropy.io import fits

from octarc_testlib import (WorkDirTest, assert_one_line_error, interrupted_python, ldac_imhead,
                            run_octarc)
import octarc


def same_bits(a, b):
    """Equal arrays, NaN included, compared as their bytes."""
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def assert_same_table(test, mine, theirs, what):
    """`mine` (an astropy Table) holds the columns of FITS table `theirs` in its order, with
    their units, and every value bit for bit in the file's storage type."""
    test.assertEqual(mine.colnames, list(theirs.columns.names), what)
    for column in theirs.columns:
        name = column.name
        values = np.asarray(theirs[name])
        values = values.astype(values.dtype.newbyteorder("="))
        test.assertTrue(same_bits(np.asarray(mine[name]), values), "%s %s" % (what, name))
        unit = u.Unit(column.unit, parse_strict="silent") if column.unit else None
        test.assertEqual(mine[name].unit, unit, "%s %s unit" % (what, name))


class PythonSimulateLenses(WorkDirTest):
    """octarc.simulate_lenses equals `octarc simulate lenses` on the same seed; its tables do
    not depend on the thread count; bad input is a ValueError with octarc's message."""

    def compare(self, command_args, **simulate_args):
        """simulate_lenses(12, **simulate_args) against `octarc simulate lenses -n 12
        *command_args`: both tables, the counts and the header's OCT* keywords."""
        out = self.path("lenses.fits")
        run_octarc("simulate", "lenses", "-n", "12", "-o", out, "--quiet", *command_args)
        sim = octarc.simulate_lenses(12, **simulate_args)
        with fits.open(out) as f:
            self.assertEqual([h.name for h in f][1:], ["LDAC_IMHEAD", "LDAC_OBJECTS", "ARCS"])
            systems, arcs = f["LDAC_OBJECTS"].data, f["ARCS"].data
            assert_same_table(self, sim.to_table(), systems, "systems")
            assert_same_table(self, sim.arcs_table(), arcs, "arcs")
            self.assertEqual(len(sim), len(systems))
            self.assertEqual(sim.systems_with_arc, int(np.sum(systems["ARC_FOUND"] == 1)))
        self.assertEqual(sim.drawn, 12)
        header = ldac_imhead(out)
        self.assertTrue(sim.meta)
        for key, value in sim.meta.items():
            self.assertEqual(header[key], value, key)
        return sim

    def test_equals_the_command(self):
        stamps = self.path("stamps.fits")
        sim = self.compare(["--seed", "5", "--preset", "dls", "--stamps", stamps,
                            "--stamp-count", "2"], seed=5, stamps=2)
        with fits.open(stamps) as f:
            self.assertTrue(same_bits(sim.stamps, f[0].data.astype(np.float32)))
        self.assertEqual(sim.meta["OCTSAMPL"], "IMPORTANCE")
        self.assertEqual(sim.stamps.shape, (2, 101, 101))
        self.assertEqual(sim.stamps.dtype, np.float32)
        self.assertFalse(sim.stamps.flags.writeable)
        table = sim.to_table(["SYSTEM", "EINSTEIN_RADIUS"])
        self.assertEqual(table.colnames, ["SYSTEM", "EINSTEIN_RADIUS"])
        self.assertEqual(str(table["EINSTEIN_RADIUS"].unit), "arcsec")
        self.assertTrue(table["EINSTEIN_RADIUS"].description)
        self.assertEqual(table["EINSTEIN_RADIUS"].meta["ucd"],
                         sim.to_table()["EINSTEIN_RADIUS"].meta["ucd"])

    def test_setup_options_equal_the_command_options(self):
        # Every system rendered, big Einstein radii and bright sources: several arc rows.
        sim = self.compare(
            ["--seed", "1", "--preset", "physical", "--sampling", "plain", "--sigma-min", "320",
             "--nlevels", "10", "--seeing", "0.8", "--source-mag-max", "23.5"],
            seed=1, preset="physical", sampling="plain",
            setup={"sigma_min": 320, "nlevels": 10, "seeing": 0.8, "source_mag_max": 23.5})
        self.assertEqual(sim.rendered, 12)
        self.assertGreater(len(sim.arcs_table()), 2)
        self.assertEqual(sim.meta["OCTNLEV"], 10)

    def test_threads(self):
        one = octarc.simulate_lenses(12, seed=7, threads=1, stamps=3)
        two = octarc.simulate_lenses(12, seed=7, threads=2, stamps=3)
        for a, b in ((one.to_table(), two.to_table()), (one.arcs_table(), two.arcs_table())):
            self.assertEqual(a.colnames, b.colnames)
            for name in a.colnames:
                self.assertTrue(same_bits(np.asarray(a[name]), np.asarray(b[name])), name)
        self.assertTrue(same_bits(one.stamps, two.stamps))
        self.assertEqual(one.meta, two.meta)

    def assert_raises(self, kind, pattern, call, *args, **kwargs):
        assert_one_line_error(self, kind, pattern, call, *args, **kwargs)

    def test_bad_input(self):
        simulate = octarc.simulate_lenses
        self.assert_raises(ValueError, r"^n: the number of systems must be positive, got 0$",
                           simulate, 0)
        self.assert_raises(ValueError, r"^n: an integer from 0 to 9223372036854775807 is needed, "
                           r"not -3$", simulate, -3)
        # Beyond a C int, or a seed beyond 64 bits: one line, not pybind11's TypeError.
        self.assert_raises(ValueError, r"^stamps: an integer from 0 to 2147483647 is needed",
                           simulate, 4, stamps=2 ** 40)
        self.assert_raises(ValueError, r"^seed: an integer from 0 to 18446744073709551615",
                           simulate, 4, seed=2 ** 64)
        self.assert_raises(ValueError, r"^setup: unknown key pixelscale$", simulate, 2,
                           setup={"pixelscale": 0.2})
        self.assert_raises(ValueError, r"^setup: seeing must be a number, not str$", simulate, 2,
                           setup={"seeing": "1"})
        self.assert_raises(ValueError, r"^setup: nlevels must be an integer, not float$",
                           simulate, 2, setup={"nlevels": 3.5})
        self.assert_raises(ValueError, r"preset.*nope", simulate, 2, preset="nope")
        self.assert_raises(ValueError, r"sampling", simulate, 2, sampling="some")
        self.assert_raises(ValueError, r"seeing", simulate, 2, setup={"seeing": -1.0})
        self.assert_raises(ValueError, r"^source_colour", simulate, 2, band="g",
                           source_colour="1")
        self.assert_raises(OSError, r"nothere\.sex", simulate, 2, setup={"config": "nothere.sex"})
        self.assert_raises(ValueError, r"^noise_sigma and limiting_mag: give one",
                           octarc.simulate_field, 64, noise_sigma=3.0, limiting_mag=25.0)
        # octarc's message, naming the keyword rather than the command's option (--size).
        self.assert_raises(ValueError, r"^size: must be between 64 and 16384 pixels, got 0$",
                           octarc.simulate_field, 0)

    def test_ctrl_c_interrupts_a_simulation(self):
        # The KeyboardInterrupt comes out of the compiled call while it simulates (its progress
        # function looks at Python's signals), not after it returned; the module works
        # afterwards. The innermost Python frame is the one that calls the compiled function.
        out = interrupted_python(self, "import octarc",
                                 "octarc.simulate_lenses(100000, threads=1)",
                                 "octarc.simulate_lenses(2, seed=3).drawn", 1.0)
        self.assertRegex(out, r"^interrupted in _python_names: return call\(\*args\)\n2\n$")

class PythonSimulateField(WorkDirTest):
    """octarc.simulate_field equals `octarc simulate field` on the same options, and
    octarc.inject_lenses `octarc demo --into` on the same image; the example of docs/python.md
    that simulates runs as it is."""

    def test_equals_the_command(self):
        out = self.path("field.fits")
        run_octarc("simulate", "field", "-o", out, "--size", "256", "--seed", "2", "--lenses",
                   "2", "--quiet")
        field = octarc.simulate_field(256, seed=2, lenses=2)
        with fits.open(out) as f:
            self.assertTrue(same_bits(field.image, f[0].data.astype(np.float32)))
            header = f[0].header
        with fits.open(self.path("field.weight.fits")) as f:
            self.assertTrue(same_bits(field.weight, f[0].data.astype(np.float32)))
        for key in ("CTYPE1", "CTYPE2", "CRVAL1", "CRVAL2", "CRPIX1", "CRPIX2", "CD1_1",
                    "CD1_2", "CD2_1", "CD2_2", "EQUINOX", "RADESYS"):
            if key in header or key in field.header:
                self.assertEqual(field.header[key], header[key], key)
        self.assertIn("CTYPE1", field.header)
        truth = field.truth
        self.assertEqual(truth.colnames, ["ID", "X_IMAGE", "Y_IMAGE", "ALPHA_J2000",
                                          "DELTA_J2000", "KIND", "MAG", "THETA_E", "SYSTEM"])
        self.assertEqual(str(truth["MAG"].unit), "mag")
        with open(self.path("field.truth.txt")) as f:
            lines = [line for line in f if not line.startswith("#")]
        mine = ["%8d %10.3f %10.3f %12.7f %12.7f %d %8.4f %7.4f %5d\n" % tuple(row)
                for row in truth]
        self.assertEqual(mine, lines)
        self.assertEqual(int(np.sum(truth["KIND"] == 1)), 2)
        self.assertGreater(field.sky_sigma, 0)
        # A survey .sex file by its shipped name, as octarc simulate field --config takes it:
        # the same field from both.
        run_octarc("simulate", "field", "-o", self.path("sex.fits"), "--size", "64", "--seed",
                   "3", "--config", "octarc.sex", "--quiet")
        small = octarc.simulate_field(64, seed=3, config="octarc.sex")
        self.assertTrue(same_bits(small.image, fits.getdata(self.path("sex.fits"))
                                  .astype(np.float32)))

    def test_inject_lenses_equals_the_demo(self):
        # A "real" image: a simulated field on a sky of 100 ADU, with its WCS and weights.
        real = octarc.simulate_field(384, seed=4)
        image = real.image + np.float32(100.0)
        fits.PrimaryHDU(image, header=real.header).writeto(self.path("real.fits"))
        fits.PrimaryHDU(real.weight).writeto(self.path("real.weight.fits"))
        run_octarc("demo", "--into", self.path("real.fits"), "--into-weight",
                   self.path("real.weight.fits"), "--lenses", "2", "--seed", "3",
                   "--pixel-scale", "0.257", "--seeing", "0.9", "--mag-zero", "30", "--gain",
                   "54", "--min-einstein-radius", "0", "--out", self.path("demo"), "--quiet")
        injected = octarc.inject_lenses(image, weight=real.weight, header=real.header, lenses=2,
                                        seed=3, pixel_scale=0.257, seeing=0.9, mag_zero=30,
                                        gain=54)
        with fits.open(self.path("demo/field.fits")) as f:
            self.assertTrue(same_bits(injected.image, f[0].data.astype(np.float32)))
            self.assertEqual(injected.header["SIMSEED"], f[0].header["SIMSEED"])
            self.assertEqual(injected.header["CRVAL1"], f[0].header["CRVAL1"])
        self.assertFalse(same_bits(injected.image, image))
        self.assertTrue(same_bits(injected.weight, real.weight))
        with open(self.path("demo/field.truth.txt")) as f:
            lines = [line for line in f if not line.startswith("#")]
        mine = ["%8d %10.3f %10.3f %12.7f %12.7f %d %8.4f %7.4f %5d\n" % tuple(row)
                for row in injected.truth]
        self.assertEqual(mine, lines)
        self.assertEqual(sorted(set(injected.truth["KIND"])), [1, 2])
        self.assertIsNone(octarc.inject_lenses(image, lenses=1, pixel_scale=0.257, seeing=0.9,
                                               mag_zero=30, gain=54).weight)
        with self.assertRaisesRegex(ValueError, r"^weight: shape \(8, 8\) but image has shape"):
            octarc.inject_lenses(image, weight=np.ones((8, 8), np.float32), lenses=1,
                                 pixel_scale=0.257, seeing=0.9, mag_zero=30, gain=54)


if __name__ == "__main__":
    unittest.main()
