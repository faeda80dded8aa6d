"""The octarc command on hostile input (found by mutation fuzzing of every reader): sizes no
file can hold, impossible header and catalog values, corrupt catalog structure, empty lists and
control characters in the configuration. Each run must end with a one-line error naming the file
or the key, a non-zero exit status and no output file; or, where the input only carries a value
that cannot be used (a header GAIN of -1), with a warning saying what is used instead."""
import gzip
import os
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (SOURCE_DIR, WorkDirTest, fitsverify_errors, full_allocation_stacks,
                            ldac_imhead, ldac_objects, run_octarc, write_param)

TESTDATA = os.path.join(SOURCE_DIR, "testdata")
IMAGE = os.path.join(TESTDATA, "example.fits.gz")
SEG = os.path.join(TESTDATA, "example.seg1.fits.gz")
CATALOG = os.path.join(TESTDATA, "example.cat1.ldac")


def card(key, value):
    return ("%-8s= %s" % (key, value)).ljust(80).encode()


def raw_fits(path, bitpix, axes, extra=(), data_bytes=0):
    """A primary HDU written byte by byte: astropy and cfitsio refuse to write such sizes."""
    cards = [b"SIMPLE  =                    T".ljust(80), card("BITPIX", bitpix),
             card("NAXIS", len(axes))]
    cards += [card("NAXIS%d" % (k + 1), n) for k, n in enumerate(axes)]
    cards += [card(k, v) for k, v in extra] + [b"END".ljust(80)]
    header = b"".join(cards)
    header += b" " * (-len(header) % 2880)
    data = b"\0" * data_bytes
    data += b"\0" * (-len(data) % 2880)
    with open(path, "wb") as f:
        f.write(header + data)
    return path


def read(path):
    """The bytes of a file, gunzipped when its name ends in .gz."""
    with open(path, "rb") as f:
        data = f.read()
    return gzip.decompress(data) if path.endswith(".gz") else data


def patched(source, path, old, new, start=0):
    """A copy of `source` (gunzipped) with the first `old` from byte `start` on replaced by
    `new`, padded with blanks to the length of `old`."""
    data = read(source)
    at = data.index(old, start)
    assert len(new) <= len(old)
    data = data[:at] + new.ljust(len(old)) + data[at + len(old):]
    with open(path, "wb") as f:
        f.write(data)
    return path


def with_card(source, path, key, value):
    """`source` with its first card `key` (the LDAC_IMHEAD cell's, in a catalog) holding
    `value` instead."""
    data = read(source)
    old = data[data.index(("%-8s=" % key).encode()):][:80]
    return patched(source, path, old, card(key, value))


class HostileInput(WorkDirTest):

    def setUp(self):
        super().setUp()
        self.param = write_param(self.path("p.param"),
                                 ["NUMBER", "FLUX_ISO", "FLUXERR_ISO", "ISOAREA_IMAGE",
                                  "ARCNESS"])
        self.out = self.path("out.ldac")

    def detect(self, image, *args):
        return run_octarc("detect", image, "-PARAMETERS_NAME", self.param, "-FILTER", "N",
                          "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", self.out,
                          "-DETECT_NLEVELS", "2", "-VERBOSE_TYPE", "QUIET", *args, check=False)

    def measure(self, image, *args):
        return run_octarc("measure", image, "-PARAMETERS_NAME", self.param, "-FILTER", "N",
                          "-SEGMENTATION_NAME", SEG, "-CATALOG_TYPE", "FITS_LDAC",
                          "-CATALOG_NAME", self.out, "-VERBOSE_TYPE", "QUIET", *args,
                          check=False)

    def assert_fails(self, proc, *fragments):
        """Exit status 1, one printable stderr line holding every fragment, no output left."""
        self.assertEqual(proc.returncode, 1, proc.stderr)
        lines = [l for l in proc.stderr.splitlines() if l.strip()]
        self.assertEqual(len(lines), 1, proc.stderr)
        self.assertTrue(lines[0].startswith("octarc "), lines[0])
        self.assertTrue(lines[0].isprintable(), repr(lines[0]))
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(self.out), "output left behind after: " + lines[0])
        self.assertEqual([n for n in os.listdir(self.work) if n.startswith(".")], [])
        return lines[0]


class HostileImages(HostileInput):

    def test_sizes_no_file_can_hold(self):
        # 2^63 - 1 overflowed in Image (UBSan), 2^62 x 4 wrapped to 0 pixels ("no finite
        # pixel"), 100000^2 floats promised by a file of two blocks.
        for name, axes, fragment in (("max.fits", (2**63 - 1, 1), "9223372036854775807 x 1"),
                                     ("wrap.fits", (2**62, 4), "4611686018427387904 x 4"),
                                     ("huge.fits", (100000, 100000), "40000000000 bytes")):
            path = raw_fits(self.path(name), -32, axes, data_bytes=400)
            self.assert_fails(self.detect(path), path + ": HDU 0: ", fragment)

    def test_segmentation_size_no_file_can_hold(self):
        seg = raw_fits(self.path("seg.fits"), 32, (2**63 - 1, 1), data_bytes=400)
        proc = run_octarc("measure", IMAGE, "-PARAMETERS_NAME", self.param, "-FILTER", "N",
                          "-SEGMENTATION_NAME", seg, "-CATALOG_NAME", self.out,
                          "-VERBOSE_TYPE", "QUIET", check=False)
        self.assert_fails(proc, seg + ": HDU 0: ", "9223372036854775807 x 1")

    def test_corrupt_compressed_tile(self):
        # Found by scripts/fuzz.sh (fuzz_fits_image): an HCOMPRESS_1 tile that cfitsio cannot
        # decode (cfitsio then leaks 4 bytes of its own, see tests/lsan.supp).
        path = os.path.join(TESTDATA, "hostile", "hcompress-corrupt-tile.fits")
        with full_allocation_stacks():
            proc = self.detect(path)
        self.assert_fails(proc, path + "[1]: cannot read pixels", "error uncompressing image")

    def test_unterminated_string_in_a_wcs_card(self):
        # Found by scripts/fuzz.sh (fuzz_fits_image): CTYPE2 = 'DEC-CD1_1   = (no closing
        # quote) made wcslib's header parser overflow a buffer and abort the process. The card
        # is left out, and the WCS without it is refused with a message.
        path = os.path.join(TESTDATA, "hostile", "wcs-unterminated-string.fits")
        self.assert_fails(self.detect(path), path + "[1]: invalid WCS")

    def test_zero_axis(self):
        path = raw_fits(self.path("zero.fits"), -32, (0, 10))
        self.assert_fails(self.detect(path), path + ": HDU 0: image is 0 x 10 pixels")

    def test_scaling_that_cannot_be_interpreted(self):
        for bitpix, key, value, shown in ((16, "BZERO", "'x'", "BZERO = 'x'"),
                                          (-32, "BZERO", "'x'", "BZERO = 'x'"),
                                          (16, "BSCALE", "NaN", "BSCALE = 'NaN'"),
                                          (-32, "BSCALE", "NaN", "BSCALE = 'NaN'"),
                                          (32, "BSCALE", "0", "BSCALE = '0'"),
                                          (16, "BLANK", "1.5", "BLANK = '1.5'")):
            path = raw_fits(self.path("scaled%d%s.fits" % (abs(bitpix), key)), bitpix, (10, 10),
                            [(key, value)], 100 * abs(bitpix) // 8)
            self.assert_fails(self.detect(path), path + ": HDU 0: " + shown,
                              "cannot be interpreted")

    def test_extension_of_unknown_type(self):
        # cfitsio reads any XTENSION as an image.
        primary = fits.PrimaryHDU()
        ext = fits.ImageHDU(np.ones((20, 20), np.float32))
        good = self.path("mef.fits")
        fits.HDUList([primary, ext]).writeto(good)
        path = patched(good, self.path("foo.fits"), b"XTENSION= 'IMAGE   '",
                       b"XTENSION= 'FOO     '")
        self.assert_fails(self.detect(path), path + ": HDU 1: XTENSION 'FOO'")

    def gain_run(self, image):
        proc = self.detect(image, "-GAIN", "2", "-VERBOSE_TYPE", "NORMAL")
        self.assertEqual(proc.returncode, 0, proc.stderr)
        rows, _ = ldac_objects(self.out)
        imhead = ldac_imhead(self.out)
        return proc, rows, imhead

    def assert_fluxerr_with_gain(self, rows, imhead, gain):
        # FLUXERR_ISO^2 = A sigma^2 + F / g (SExtractor's isophotal error, no weight map).
        self.assertEqual(imhead["SEXGAIN"], gain)
        rows = rows[rows["FLUX_ISO"] > 0]
        self.assertGreater(len(rows), 5)
        sigma = imhead["SEXBKDEV"]
        expected = np.sqrt(rows["ISOAREA_IMAGE"] * sigma**2 + rows["FLUX_ISO"] / gain)
        np.testing.assert_allclose(rows["FLUXERR_ISO"], expected, rtol=2e-6)

    def test_header_gain_that_cannot_be_a_gain_is_ignored_with_a_warning(self):
        # The example image's header says GAIN = 4.0; that value wins over -GAIN 2.
        _, rows, imhead = self.gain_run(IMAGE)
        self.assert_fluxerr_with_gain(rows, imhead, 4.0)
        # GAIN -1, NaN or 'x' were used or silently dropped: now the configuration's GAIN is
        # used and a warning says so.
        for value, shown in (("-1", "'-1'"), ("NaN", "'NaN'"), ("'x'", "'x'")):
            image = with_card(IMAGE, self.path("gain.fits"), "GAIN", value)
            proc, rows, imhead = self.gain_run(image)
            warnings = [l for l in proc.stderr.splitlines() if l.startswith("WARNING")]
            self.assertIn("WARNING: %s: header GAIN = %s is not a finite number >= 0: ignored, "
                          "using GAIN 2 of the configuration instead" % (image, shown), warnings)
            self.assert_fluxerr_with_gain(rows, imhead, 2.0)

    def test_header_saturation_that_cannot_be_a_level_is_ignored_with_a_warning(self):
        image = with_card(IMAGE, self.path("satur.fits"), "SATURATE", "-5")
        proc = self.detect(image, "-SATUR_LEVEL", "1e6", "-VERBOSE_TYPE", "NORMAL")
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("WARNING: %s: header SATURATE = '-5' is not a finite number >= 0: ignored, "
                      "using SATUR_LEVEL 1e+06 of the configuration instead" % image,
                      proc.stderr)


class HostileCatalogs(HostileInput):

    def test_row_counts_the_file_cannot_hold(self):
        # 2^31 rows in a 20 KB file cost 16 GiB before the error; 2e8 rows cost 1.6 GB.
        data = read(CATALOG)
        objects = data.index(b"LDAC_OBJECTS") - 800
        naxis2 = data[data.index(b"NAXIS2  =", objects):][:30]
        for rows in (2**31, 200000000):
            path = patched(CATALOG, self.path("rows%d.ldac" % rows), naxis2,
                           b"NAXIS2  = %20d" % rows)
            self.assert_fails(self.measure(IMAGE, "-INPUT_CATALOG", path),
                              path + ": HDU 2: file is truncated", "x %d" % rows)

    def test_corrupt_imhead_hdu_is_not_copied_into_an_output(self):
        # XTENSION = 'FOO' was read as an image HDU and copied into an output fitsverify failed.
        path = patched(CATALOG, self.path("foo.ldac"), b"XTENSION= 'BINTABLE'",
                       b"XTENSION= 'FOO     '")
        self.assert_fails(self.measure(IMAGE, "-INPUT_CATALOG", path), path + ": HDU 1: ",
                          "XTENSION 'FOO'")

    def test_imhead_cell_that_cfitsio_cannot_parse(self):
        cell = read(CATALOG).index(b"SIMPLE  =", 5760)
        path = patched(CATALOG, self.path("esc.ldac"), b"OBJECT  = 'octarc", b"OBJECT  = '\x1b[",
                       cell)
        line = self.assert_fails(self.measure(IMAGE, "-INPUT_CATALOG", path),
                                 path + ": LDAC_IMHEAD (HDU 1): card ", "\\x1B[",
                                 "not printable ASCII")
        self.assertNotIn("\x1b", line)

    def test_impossible_run_values(self):
        # SEXBKGND = NaN made every row NaN, SEXGAIN < 0 a wrong FLUXERR; both exit 0 before.
        for key, value, shown in (("SEXBKGND", "NaN", "SEXBKGND = 'NaN'"),
                                  ("SEXBKDEV", "0.0", "SEXBKDEV = '0.0'"),
                                  ("SEXGAIN", "-4.0", "SEXGAIN = '-4.0'"),
                                  ("SEXTHLD", "'x'", "SEXTHLD = 'x'")):
            path = with_card(CATALOG, self.path("%s.ldac" % key), key, value)
            self.assert_fails(self.measure(IMAGE, "-INPUT_CATALOG", path, "-APPEND_COLUMNS", "N"),
                              path + ": LDAC_IMHEAD", shown)

    def test_good_catalog_reference(self):
        # The same commands on the unchanged catalog succeed, and the output verifies.
        proc = self.measure(IMAGE, "-INPUT_CATALOG", CATALOG)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        code, text = fitsverify_errors(self.out)
        self.assertEqual(code, 0, text)


class HostileConfiguration(HostileInput):

    def sex(self, text):
        path = self.path("run.sex")
        with open(path, "wb") as f:
            f.write(text)
        return path

    def test_bare_list_keys_mean_not_given(self):
        # A bare WEIGHT_TYPE or "WEIGHT_THRESH ," was an internal error (exit 3).
        reference = self.detect(IMAGE)
        self.assertEqual(reference.returncode, 0, reference.stderr)
        expected, _ = ldac_objects(self.out)
        os.remove(self.out)
        for text in (b"WEIGHT_TYPE\n", b"WEIGHT_THRESH ,\n", b"WEIGHT_IMAGE\nCHECKIMAGE_TYPE\n"):
            proc = self.detect(IMAGE, "-c", self.sex(text))
            self.assertEqual(proc.returncode, 0, proc.stderr)
            rows, _ = ldac_objects(self.out)
            np.testing.assert_array_equal(rows, expected)
            os.remove(self.out)

    def test_weight_type_with_a_bare_weight_image(self):
        self.assert_fails(self.detect(IMAGE, "-c", self.sex(b"WEIGHT_TYPE MAP_WEIGHT\n"
                                                             b"WEIGHT_IMAGE\n")),
                          "WEIGHT_IMAGE: WEIGHT_TYPE MAP_WEIGHT needs a weight map file")

    def test_control_characters_in_a_sex_value(self):
        # A NUL cut the file name (the catalog went to "out"); an escape went raw to stderr.
        for value, shown in ((b"out\0x.cat", "'out\\x00x.cat'"),
                             (b"\x1b[31mred.cat", "'\\x1B[31mred.cat'")):
            path = self.sex(b"FILTER N\nCATALOG_NAME " + value + b"\n")
            proc = run_octarc("detect", IMAGE, "-c", path, "-PARAMETERS_NAME", self.param,
                              "-VERBOSE_TYPE", "QUIET", check=False, cwd=self.work)
            self.assert_fails(proc, path + ":2: CATALOG_NAME " + shown,
                              "holds a control character")
            self.assertEqual(sorted(os.listdir(self.work)), ["p.param", "run.sex"])

    def test_control_characters_on_the_command_line(self):
        self.assert_fails(self.detect(IMAGE, "-CHECKIMAGE_TYPE", "SEGMENTATION",
                                      "-CHECKIMAGE_NAME", "seg\x07.fits"),
                          "command line: CHECKIMAGE_NAME 'seg\\x07.fits'",
                          "holds a control character")
        self.assert_fails(self.detect("im\x1b.fits"),
                          "command line: image name 'im\\x1B.fits' holds a control character")

    def test_long_values_are_cut_in_messages(self):
        line = self.assert_fails(self.detect(IMAGE, "-c", self.sex(b"BACK_TYPE " + b"X" * 5000
                                                                   + b"\n")),
                                 "run.sex:1: BACK_TYPE 'XXXX", "'... (5000 characters)")
        self.assertLess(len(line), 400)


if __name__ == "__main__":
    unittest.main()
