"""`octarc measure` appending its columns to real SExtractor catalogs (APPEND_COLUMNS Y): every
original HDU, header card and cell is kept (compared byte for byte and as astropy reads them),
the new columns land in the right rows, checksums stay valid, and the run's provenance cards are
those of the same run written as a new catalog (APPEND_COLUMNS N)."""
import os
import re
import unittest
import warnings

import numpy as np
from astropy.io import fits

from octarc_testlib import (SEX_SHARE, SOURCE_DIR, WorkDirTest, fitsverify_errors, ldac_imhead,
                            require_shared, run_octarc, run_sextractor, write_param)

# What SExtractor writes: vectors (FLUX_APER), an image per row with TDIM (VIGNET), integer,
# float and double columns.
SEX_COLUMNS = ["NUMBER", "X_IMAGE", "Y_IMAGE", "A_IMAGE", "B_IMAGE", "ISOAREA_IMAGE",
               "FLUX_APER(2)", "FLAGS", "X_WORLD", "VIGNET(9,9)"]
# What octarc is asked for: the columns SExtractor has are not appended again.
OCTARC_COLUMNS = ["NUMBER", "X_IMAGE", "X2_IMAGE", "Y2_IMAGE", "ARCNESS", "ARC_SIDE",
                  "OCT_FLAGS", "THRESH_LEVEL"]
APPENDED = ["X2_IMAGE", "Y2_IMAGE", "ARCNESS", "ARC_SIDE", "OCT_FLAGS", "THRESH_LEVEL"]
# The keys whose values change when a table grows.
GROWING = {"NAXIS1", "TFIELDS", "TFORM1", "TDIM1", "CHECKSUM", "DATASUM"}
PURE = ["-FILTER", "N", "-DETECT_MINAREA", "5", "-BACK_TYPE", "AUTO", "-PHOT_APERTURES", "5,10"]

TESTDATA = os.path.join(SOURCE_DIR, "testdata")


def raw_hdus(path):
    """(header bytes, data bytes) of every HDU, as they are in the file."""
    with open(path, "rb") as f:
        raw = f.read()
    out = []
    with fits.open(path) as f:
        for i in range(len(f)):
            info = f.fileinfo(i)
            out.append((raw[info["hdrLoc"]:info["datLoc"]],
                        raw[info["datLoc"]:info["datLoc"] + info["datSpan"]]))
    return out


def cards_of(header_bytes):
    cards = [header_bytes[k:k + 80].decode("ascii") for k in range(0, len(header_bytes), 80)]
    return cards[:[c[:8] for c in cards].index("END     ")]


def key(card):
    return card[:8].strip()


def column_of(card):
    """The column number of a column keyword card (TTYPE12 -> 12), else 0."""
    m = re.match(r"T[A-Z]+(\d+)$", key(card))
    return int(m.group(1)) if m else 0


def imhead_cells(path):
    with fits.open(path) as f:
        return [list(h.data[0][0]) for h in f if h.name == "LDAC_IMHEAD"]


class AppendCase(WorkDirTest):

    def sextractor(self, image, tag, extra=(), checkimages=("SEGMENTATION",)):
        param = write_param(self.path(tag + ".sex.param"), SEX_COLUMNS)
        return run_sextractor(image, self.work, tag, param, 3.0, PURE + list(extra), checkimages)

    def measure(self, image, segs, cats, outs, append="Y", extra=()):
        param = write_param(self.path("octarc.param"), OCTARC_COLUMNS)
        run_octarc("measure", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
                   "-PARAMETERS_NAME", param, "-SEGMENTATION_NAME", ",".join(segs),
                   "-INPUT_CATALOG", ",".join(cats), "-CATALOG_NAME", ",".join(outs),
                   "-APPEND_COLUMNS", append, "-CATALOG_TYPE", "FITS_LDAC", "-FILTER", "N",
                   "-VERBOSE_TYPE", "QUIET", *extra)

    def assert_appended(self, original, appended, provenance_in_objects=False):
        """Every HDU of `original` is in `appended`: headers card for card (only NAXIS1, TFIELDS,
        TFORM1/TDIM1 of LDAC_IMHEAD and checksums take new values; the new cards are the new
        columns' and the provenance), every original byte of every row, and the same cells as
        astropy reads them. Returns the provenance cards added per objects table."""
        before, after = raw_hdus(original), raw_hdus(appended)
        self.assertEqual(len(before), len(after))
        provenance = []
        with fits.open(original) as old, fits.open(appended) as new:
            for i, ((hb, db), (ha, da)) in enumerate(zip(before, after)):
                name = old[i].name
                self.assertEqual(new[i].name, name)
                cb, ca = cards_of(hb), cards_of(ha)
                old_keys = {key(c) for c in cb}
                kept = [c for c in ca if key(c) in old_keys]
                self.assertEqual([key(c) for c in kept], [key(c) for c in cb], name)
                for x, y in zip(cb, kept):
                    if key(x) not in GROWING:
                        self.assertEqual(x, y, name)
                added = [c for c in ca if key(c) not in old_keys]
                if name in ("LDAC_OBJECTS", "OBJECTS"):
                    rows, w0, w1 = (old[i].header["NAXIS2"], old[i].header["NAXIS1"],
                                    new[i].header["NAXIS1"])
                    n0 = old[i].header["TFIELDS"]
                    # The requested columns the catalog lacks, in .param order.
                    appended_names = [c for c in OCTARC_COLUMNS if c not in old[i].columns.names]
                    self.assertEqual(new[i].header["NAXIS2"], rows)
                    self.assertEqual(new[i].header["TFIELDS"], n0 + len(appended_names))
                    self.assertEqual(new[i].columns.names[n0:], appended_names)
                    self.assertEqual(w1 - w0, sum(new[i].columns[c].dtype.itemsize
                                                  for c in appended_names))
                    # The new columns' cards: TTYPEn first for each n, right after the cards of
                    # the last original column; then the provenance.
                    column_cards = [c for c in added if c.startswith("T")]
                    firsts = [key(c) for c in column_cards if c.startswith("TTYPE")]
                    self.assertEqual(firsts, ["TTYPE%d" % (n0 + 1 + k)
                                              for k in range(len(appended_names))])
                    last_original = max(k for k, c in enumerate(ca) if column_of(c) == n0)
                    self.assertEqual(ca[last_original + 1:last_original + 1 + len(column_cards)],
                                     column_cards)
                    provenance.append([c for c in added if not c.startswith("T")])
                    if not provenance_in_objects:
                        self.assertEqual(provenance[-1], [])
                    # Every original byte of every row, the new columns after them.
                    a = np.frombuffer(db[:rows * w0], np.uint8).reshape(rows, w0)
                    b = np.frombuffer(da[:rows * w1], np.uint8).reshape(rows, w1)
                    np.testing.assert_array_equal(a, b[:, :w0])
                    self.assertFalse(np.any(np.frombuffer(da[rows * w1:], np.uint8)))
                    # The same cells, units, formats and shapes for astropy.
                    for c in old[i].columns:
                        n = new[i].columns[c.name]
                        self.assertEqual((c.format, c.unit, c.dim), (n.format, n.unit, n.dim))
                        np.testing.assert_array_equal(old[i].data[c.name], new[i].data[c.name])
                elif name == "LDAC_IMHEAD":
                    self.assertEqual(added, [])
                    cells = [list(old[i].data[0][0]), list(new[i].data[0][0])]
                    self.assertEqual(cells[1][:len(cells[0]) - 1], cells[0][:-1])
                    self.assertEqual(cells[1][-1], "END")
                    ncards = len(cells[1])
                    self.assertEqual(new[i].header["TFORM1"], "%dA" % (80 * ncards))
                    self.assertEqual(new[i].header["TDIM1"], "(80, %d)" % ncards)
                else:
                    self.assertEqual(added, [])
                    self.assertEqual(db, da, name)
        code, text = fitsverify_errors(appended)
        self.assertEqual(code, 0, text)
        return provenance


class AppendToRealCatalogs(AppendCase):

    def setUp(self):
        super().setUp()
        self.image = require_shared(self, "ntt-emmi", "galaxies.fits")

    def test_ldac_keeps_every_card_and_cell(self):
        cat, checks = self.sextractor(self.image, "ntt", checkimages=["SEGMENTATION", "BACKGROUND"])
        out = self.path("ntt+oct.ldac")
        # With SExtractor's background map, octarc's moments are SExtractor's.
        background = ["-BACKGROUND_NAME", checks["BACKGROUND"]]
        self.measure(self.image, [checks["SEGMENTATION"]], [cat], [out], extra=background)
        self.assert_appended(cat, out)
        with fits.open(cat) as sex, fits.open(out) as ours:
            theirs, mine = sex[2].data, ours[2].data
            self.assertGreater(len(mine), 500)
            # The new values sit in the rows of their objects: X2 + Y2 = A^2 + B^2 with
            # SExtractor's A_IMAGE, B_IMAGE of the same row.
            np.testing.assert_allclose(mine["X2_IMAGE"] + mine["Y2_IMAGE"],
                                       theirs["A_IMAGE"].astype(float) ** 2 +
                                       theirs["B_IMAGE"].astype(float) ** 2, rtol=2e-5)
            self.assertTrue(np.all(mine["THRESH_LEVEL"] == 1))
        # The same values as the run written as a new catalog, row for row by NUMBER.
        new = self.path("new.ldac")
        self.measure(self.image, [checks["SEGMENTATION"]], [cat], [new], append="N",
                     extra=background)
        with fits.open(out) as a, fits.open(new) as n:
            order = np.argsort(n[2].data["NUMBER"])
            self.assertTrue(np.array_equal(n[2].data["NUMBER"][order], a[2].data["NUMBER"]))
            for name in APPENDED:
                np.testing.assert_array_equal(a[2].data[name], n[2].data[name][order])

    def test_fits10_gets_its_provenance_in_the_objects_header(self):
        cat, checks = self.sextractor(self.image, "ntt10", ["-CATALOG_TYPE", "FITS_1.0"])
        out = self.path("ntt10+oct.fits")
        self.measure(self.image, [checks["SEGMENTATION"]], [cat], [out])
        provenance = self.assert_appended(cat, out, provenance_in_objects=True)
        # SExtractor keeps SEXGAIN, SEXBKGND and SEXBKDEV in the primary header: octarc's own
        # cards only.
        self.assertEqual([key(c) for c in provenance[0]],
                         ["OCTNLEV", "OCTTH1", "OCTBKSRC", "OCTSGSRC"])
        new = self.path("new.ldac")
        self.measure(self.image, [checks["SEGMENTATION"]], [cat], [new], append="N")
        imhead = ldac_imhead(new)
        for card in provenance[0]:
            header = fits.Header.fromstring(card)
            k = key(card)
            self.assertEqual(header[k], imhead[k], k)
            self.assertEqual(card, imhead.cards[k].image)

    def test_checksums_are_recomputed(self):
        cat, checks = self.sextractor(self.image, "ntt")
        summed = self.path("summed.ldac")
        with fits.open(cat) as f:
            f.writeto(summed, checksum=True)
        out = self.path("summed+oct.ldac")
        self.measure(self.image, [checks["SEGMENTATION"]], [summed], [out])
        self.assert_appended(summed, out)
        with warnings.catch_warnings():
            # astropy warns when a checksum does not match.
            warnings.filterwarnings("error", message="(Checksum|Datasum) verification failed")
            with fits.open(out, checksum=True) as f:
                for h in f:
                    self.assertIn("CHECKSUM", h.header)
                    self.assertIn("DATASUM", h.header)
                    h.data  # noqa: B018 (reading the data verifies DATASUM)
            with fits.open(summed, checksum=True) as a, fits.open(out, checksum=True) as b:
                self.assertEqual(a[0].header["CHECKSUM"], b[0].header["CHECKSUM"])
                self.assertNotEqual(a[2].header["DATASUM"], b[2].header["DATASUM"])

    def test_two_extensions_two_tables(self):
        data = fits.getdata(self.image).astype(np.float32)
        mef = self.path("mef.fits")
        fits.HDUList([fits.PrimaryHDU(), fits.ImageHDU(data[:512], name="CHIP1"),
                      fits.ImageHDU(data[512:], name="CHIP2")]).writeto(mef)
        cat, checks = self.sextractor(mef, "mef")
        out = self.path("mef+oct.ldac")
        self.measure(mef, [checks["SEGMENTATION"]], [cat], [out])
        self.assert_appended(cat, out)
        new = self.path("new.ldac")
        self.measure(mef, [checks["SEGMENTATION"]], [cat], [new], append="N")
        # Each LDAC_IMHEAD gets the provenance of its own extension.
        for hdu in (1, 3):
            ours = [c for c in ldac_imhead(out, hdu).cards if c.keyword.startswith("OCT")]
            theirs = [c for c in ldac_imhead(new, hdu).cards if c.keyword.startswith("OCT")]
            self.assertEqual([c.image for c in ours], [c.image for c in theirs])
        self.assertNotEqual(ldac_imhead(out, 1)["OCTTH1"], ldac_imhead(out, 3)["OCTTH1"])


class AppendedProvenance(AppendCase):
    """The example field's three SExtractor runs (3, 6 and 12 sigma)."""

    SEGS = [os.path.join(TESTDATA, "example.seg%d.fits.gz" % k) for k in (1, 2, 3)]
    CATS = [os.path.join(TESTDATA, "example.cat%d.ldac" % k) for k in (1, 2, 3)]
    IMAGE = os.path.join(TESTDATA, "example.fits.gz")
    BACKGROUND = ["-BACKGROUND_NAME", os.path.join(TESTDATA, "example.bkg.fits.gz")]

    def test_cards_are_those_of_the_run_as_a_new_catalog(self):
        outs = [self.path("out%d.ldac" % k) for k in (1, 2, 3)]
        self.measure(self.IMAGE, self.SEGS, self.CATS, outs, extra=self.BACKGROUND)
        new = self.path("levels.ldac")
        self.measure(self.IMAGE, self.SEGS, self.CATS, [new], append="N", extra=self.BACKGROUND)
        expected = [c.image for c in ldac_imhead(new).cards if c.keyword.startswith("OCT")]
        self.assertEqual([c[:8].strip() for c in expected],
                         ["OCTNLEV", "OCTTH1", "OCTTH2", "OCTTH3", "OCTBKSRC", "OCTSGSRC"])
        for cat, out in zip(self.CATS, outs):
            cells = imhead_cells(out)[0]
            original = imhead_cells(cat)[0]
            self.assertEqual(cells[:len(original) - 1], original[:-1])
            self.assertEqual([c.ljust(80) for c in cells[len(original) - 1:-1]], expected)

    def test_missing_sextractor_cards_are_added_and_present_ones_kept(self):
        # A catalog whose LDAC_IMHEAD lacks SEXGAIN, SEXBKGND and SEXBKDEV (not SExtractor's,
        # but readable): octarc's own values are added; SEXTHLD, present, stays SExtractor's.
        cat = self.path("stripped.ldac")
        with fits.open(self.CATS[0]) as f:
            cells = [c for c in f[1].data[0][0] if c[:8].strip() not in
                     ("SEXGAIN", "SEXBKGND", "SEXBKDEV")]
            imhead = fits.BinTableHDU.from_columns(
                [fits.Column(name="Field Header Card", format="%dA" % (80 * len(cells)),
                             dim="(80, %d)" % len(cells),
                             array=np.array([[c.ljust(80) for c in cells]]))],
                name="LDAC_IMHEAD")
            fits.HDUList([f[0].copy(), imhead, f[2].copy()]).writeto(cat)
        # astropy pads the cards of the cell with NULs; SExtractor's are blank-padded.
        with fits.open(cat) as f:
            start = f.fileinfo(1)["datLoc"]
        with open(cat, "r+b") as f:
            f.seek(start)
            f.write("".join(c.ljust(80) for c in cells).encode("ascii"))
        out = self.path("out.ldac")
        self.measure(self.IMAGE, self.SEGS[:1], [cat], [out], extra=self.BACKGROUND)
        new = self.path("new.ldac")
        self.measure(self.IMAGE, self.SEGS[:1], [cat], [new], append="N", extra=self.BACKGROUND)
        self.assert_appended(cat, out)
        ours, theirs = ldac_imhead(out), ldac_imhead(new)
        added = [c.keyword for c in ours.cards][len(cells) - 1:]
        self.assertEqual(added, ["SEXBKGND", "SEXBKDEV", "SEXGAIN", "OCTNLEV", "OCTTH1",
                                 "OCTBKSRC", "OCTSGSRC"])
        for k in added:
            self.assertEqual(ours.cards[k].image, theirs.cards[k].image, k)
        self.assertEqual(ours["SEXTHLD"], ldac_imhead(self.CATS[0])["SEXTHLD"])


if __name__ == "__main__":
    unittest.main()
