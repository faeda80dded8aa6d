"""`octarc measure` outputs: appending to SExtractor catalogs, the declared column metadata as
astropy and fitsverify see it, the other catalog types, and the README example
(issue: foundation, acceptance 3)."""
import csv
import io
import os
import shutil
import re
import subprocess
import unittest

import numpy as np
from astropy.io import fits
from astropy.table import Table

from octarc_testlib import (SEX_SHARE, SOURCE_DIR, WorkDirTest, fitsverify_errors, ldac_imhead,
                            ldac_objects, require_program, run_octarc, run_sextractor,
                            write_param)

TESTDATA = os.path.join(SOURCE_DIR, "testdata")
SEGS = ",".join(os.path.join(TESTDATA, "example.seg%d.fits.gz" % k) for k in (1, 2, 3))
CATS = [os.path.join(TESTDATA, "example.cat%d.ldac" % k) for k in (1, 2, 3)]
IMAGE = os.path.join(TESTDATA, "example.fits.gz")
BACKGROUND = os.path.join(TESTDATA, "example.bkg.fits.gz")

OCTOPOLE = ["ARCNESS", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR", "I_AAB_IMAGE", "I_ABB_IMAGE",
            "I_AAA_IMAGE", "I_BBB_IMAGE", "ARC_SIDE", "E1_IMAGE", "E2_IMAGE", "E_IMAGE",
            "SIZE_IMAGE", "SNR_ISO", "THRESH_LEVEL", "PARENT_NUMBER", "OCT_FLAGS"]


def declared_columns():
    """name -> (description, unit) as `octarc measure -dp` lists them."""
    out = run_octarc("measure", "-dp").stdout
    columns = {}
    for line in out.splitlines():
        m = re.match(r"#(\S+)\s+(.*?)\s*(?:\[(.*)\])?$", line)
        if m:
            columns[m.group(1)] = (m.group(2).strip(), m.group(3) or "")
    return columns


class AppendToSExtractorCatalogs(WorkDirTest):

    def test_append_keeps_every_original_column_and_header(self):
        param = write_param(self.path("p.param"), ["NUMBER", "X_IMAGE"] + OCTOPOLE)
        outs = [self.path("out%d.ldac" % k) for k in (1, 2, 3)]
        run_octarc("measure", IMAGE, "-PARAMETERS_NAME", param, "-SEGMENTATION_NAME", SEGS,
                   "-INPUT_CATALOG", ",".join(CATS), "-CATALOG_NAME", ",".join(outs),
                   "-BACKGROUND_NAME", BACKGROUND, "-FILTER", "N", "-VERBOSE_TYPE", "QUIET")
        declared = declared_columns()
        for k, (src, out) in enumerate(zip(CATS, outs), start=1):
            with fits.open(src) as a, fits.open(out) as b:
                self.assertEqual(len(a), len(b))
                self.assertEqual(b[1].name, "LDAC_IMHEAD")
                # Every card of the header cell kept; only octarc's provenance added before END
                # (SExtractor's catalog has SEXGAIN, SEXBKGND and SEXBKDEV already).
                old_cards, new_cards = list(a[1].data[0][0]), list(b[1].data[0][0])
                self.assertEqual(new_cards[:len(old_cards) - 1], old_cards[:-1])
                self.assertEqual(new_cards[-1], "END")
                added = [c[:8].strip() for c in new_cards[len(old_cards) - 1:-1]]
                self.assertEqual(added, ["OCTNLEV", "OCTTH1", "OCTTH2", "OCTTH3", "OCTBKSRC",
                                         "OCTSGSRC"])
                old, new = a[2], b[2]
                self.assertEqual(new.name, "LDAC_OBJECTS")
                for name in old.columns.names:
                    np.testing.assert_array_equal(old.data[name], new.data[name])
                    self.assertEqual(old.columns[name].unit, new.columns[name].unit)
                    self.assertEqual(old.columns[name].format, new.columns[name].format)
                appended = [c for c in new.columns.names if c not in old.columns.names]
                # NUMBER and X_IMAGE are already there: they are not appended again.
                self.assertEqual(appended, OCTOPOLE)
                self.assertTrue(np.all(new.data["THRESH_LEVEL"] == k))
                for i, name in enumerate(new.columns.names, start=1):
                    if name in OCTOPOLE:
                        self.assertEqual(new.header.comments["TTYPE%d" % i], declared[name][0])
                        self.assertEqual(new.header.get("TUNIT%d" % i, ""), declared[name][1])
            code, text = fitsverify_errors(out)
            self.assertEqual(code, 0, text)

    def test_input_catalog_is_never_touched_on_failure(self):
        before = open(CATS[0], "rb").read()
        bad_param = write_param(self.path("p.param"), ["NUMBER", "ARCNESS", "NOT_A_COLUMN(0)"])
        proc = run_octarc("measure", IMAGE, "-PARAMETERS_NAME", bad_param,
                          "-SEGMENTATION_NAME", SEGS, "-INPUT_CATALOG", ",".join(CATS),
                          "-CATALOG_NAME", ",".join(CATS), "-BACKGROUND_NAME", BACKGROUND,
                          check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertEqual(open(CATS[0], "rb").read(), before)


    def copies_of_the_catalogs(self):
        copies = []
        for k, src in enumerate(CATS, start=1):
            dst = self.path("cat%d.ldac" % k)
            shutil.copyfile(src, dst)
            copies.append(dst)
        return copies

    def test_catalog_name_equal_to_its_input_needs_replace_input_catalog(self):
        copies = self.copies_of_the_catalogs()
        args = ["measure", IMAGE, "-c", os.path.join(TESTDATA, "example.sex"),
                "-SEGMENTATION_NAME", SEGS, "-INPUT_CATALOG", ",".join(copies),
                "-CATALOG_NAME", ",".join(copies), "-APPEND_COLUMNS", "Y", "-VERBOSE_TYPE", "QUIET"]
        before = [open(c, "rb").read() for c in copies]
        proc = run_octarc(*args, check=False, cwd=SOURCE_DIR)
        self.assertEqual(proc.returncode, 1, proc.stderr)
        self.assertIn("CATALOG_NAME", proc.stderr)
        self.assertIn("INPUT_CATALOG", proc.stderr)
        self.assertIn("REPLACE_INPUT_CATALOG", proc.stderr)
        self.assertEqual([open(c, "rb").read() for c in copies], before)
        # Asked for: each catalog is replaced by its appended version; a second name (hard link)
        # of the old file still reads the old bytes: the input was never modified in place.
        os.link(copies[0], self.path("old1.ldac"))
        run_octarc(*args, "-REPLACE_INPUT_CATALOG", "Y", cwd=SOURCE_DIR)
        self.assertEqual(open(self.path("old1.ldac"), "rb").read(), before[0])
        for c in copies:
            with fits.open(c) as f:
                self.assertIn("ARCNESS", f[2].columns.names)

    def test_catalog_type_is_said_to_be_unused_when_appending(self):
        outs = [self.path("out%d.ldac" % k) for k in (1, 2, 3)]
        proc = run_octarc("measure", IMAGE, "-c", os.path.join(TESTDATA, "example.sex"),
                          "-SEGMENTATION_NAME", SEGS, "-INPUT_CATALOG", ",".join(CATS),
                          "-CATALOG_NAME", ",".join(outs), "-APPEND_COLUMNS", "Y",
                          "-CATALOG_TYPE", "ASCII_HEAD", cwd=SOURCE_DIR)
        self.assertIn("WARNING: CATALOG_TYPE ASCII_HEAD is not used with APPEND_COLUMNS Y",
                      proc.stderr)
        with fits.open(outs[0]) as f:
            self.assertEqual(f[2].name, "LDAC_OBJECTS")


class ExampleField(WorkDirTest):

    def run_example(self, catalog_type, name):
        out = self.path(name)
        run_octarc("measure", IMAGE, "-c", os.path.join(TESTDATA, "example.sex"),
                   "-PARAMETERS_NAME", os.path.join(TESTDATA, "example.param"),
                   "-CATALOG_TYPE", catalog_type, "-CATALOG_NAME", out, "-VERBOSE_TYPE", "QUIET",
                   cwd=SOURCE_DIR)
        return out

    def test_arc_has_the_highest_arcness_once_it_separates(self):
        out = self.run_example("FITS_LDAC", "example.ldac")
        cat, header = ldac_objects(out)
        self.assertEqual(sorted(set(cat["THRESH_LEVEL"])), [1, 2, 3])
        for level in (2, 3):
            rows = cat[cat["THRESH_LEVEL"] == level]
            # METHOD.md: an arc must be resolved, sqrt(2) * size > 1.0" (0.257"/px).
            rows = rows[np.sqrt(2.0) * rows["SIZE_IMAGE"] * 0.257 > 1.0]
            best = rows[np.argmax(rows["ARCNESS"])]
            # The arc is centred about 16 px from the lens at (101.3, 100.6), towards 60 deg.
            d = np.hypot(best["X_IMAGE"] - 101.3, best["Y_IMAGE"] - 100.6)
            self.assertGreater(d, 10.0)
            self.assertLess(d, 20.0)
            self.assertGreater(best["ARCNESS"], 0.05)
            # Its lens lies on its concave side: towards -b or +b as ARC_SIDE says.
            self.assertIn(best["ARC_SIDE"], (-1, 1))
        # At 3 sigma the arc and its lens are one object: its children are the two of them.
        children = cat[cat["THRESH_LEVEL"] == 2]
        self.assertEqual(len(set(children["PARENT_NUMBER"])), len(cat[cat["THRESH_LEVEL"] == 1]) - 1)
        code, text = fitsverify_errors(out)
        self.assertEqual(code, 0, text)

    def test_ascii_head_and_fits_1_0_carry_the_same_values(self):
        ldac, _ = ldac_objects(self.run_example("FITS_LDAC", "a.ldac"))
        fits10 = fits.getdata(self.run_example("FITS_1.0", "a.fits"), "OBJECTS")
        ascii_path = self.run_example("ASCII_HEAD", "a.cat")
        names = []
        with open(ascii_path) as f:
            for line in f:
                if line.startswith("#"):
                    names.append(line.split()[2])
        self.assertEqual(names[:4], ["NUMBER", "THRESH_LEVEL", "PARENT_NUMBER", "X_IMAGE"])
        table = np.loadtxt(ascii_path, comments="#", ndmin=2)
        self.assertEqual(len(table), len(ldac))
        np.testing.assert_array_equal(table[:, 0], ldac["NUMBER"])
        np.testing.assert_allclose(table[:, 3], ldac["X_IMAGE"], atol=1e-4)
        for name in ldac.columns.names:
            np.testing.assert_array_equal(fits10[name], ldac[name])


class VotableCatalogs(WorkDirTest):
    """CATALOG_TYPE ASCII_VOTABLE, as astropy and STILTS read it, against the FITS-LDAC catalog
    of the same run."""

    # VO units and UCDs as SExtractor's param.h declares its columns (SEXTRACTOR.md), and
    # octarc's own.
    EXPECTED = {"NUMBER": ("", "meta.record"),
                "X_IMAGE": ("pix", "pos.cartesian.x;pos.barycenter;instr.det;meta.main"),
                "THETA_IMAGE": ("deg", "pos.posAng;instr.det;meta.main"),
                "ISOAREA_IMAGE": ("pix2", "phys.area"),
                "FLUX_ISO": ("ct", "phot.flux"),
                "MAG_ISO": ("mag", "phot.mag"),
                "THRESH_LEVEL": ("", "meta.id.part"),
                "ARCNESS": ("", "src.morph")}

    def run_pair(self, command, extra=()):
        outs = {}
        for kind, name in (("FITS_LDAC", "a.ldac"), ("ASCII_VOTABLE", "a.xml")):
            outs[kind] = self.path(name)
            run_octarc(command, IMAGE, "-c", os.path.join(TESTDATA, "example.sex"),
                       "-PARAMETERS_NAME", os.path.join(TESTDATA, "example.param"),
                       "-CATALOG_TYPE", kind, "-CATALOG_NAME", outs[kind],
                       "-VERBOSE_TYPE", "QUIET", *extra, cwd=SOURCE_DIR)
        return outs["FITS_LDAC"], outs["ASCII_VOTABLE"]

    def check_same_as_ldac(self, ldac_path, xml_path):
        ldac, _ = ldac_objects(ldac_path)
        table = Table.read(xml_path, format="votable")
        self.assertEqual(table.colnames, ldac.columns.names)
        self.assertGreater(len(table), 10)
        self.assertEqual(len(table), len(ldac))
        for name in ldac.columns.names:
            # Every value as the FITS column holds it: floats written with round-trip digits.
            np.testing.assert_array_equal(np.asarray(table[name]), ldac[name], err_msg=name)
            self.assertEqual(table[name].dtype.newbyteorder("="), ldac[name].dtype.newbyteorder("="),
                             name)
            self.assertTrue(table[name].meta.get("ucd"), name)
        for name, (unit, ucd) in self.EXPECTED.items():
            self.assertEqual(table[name].meta["ucd"], ucd, name)
            self.assertEqual(str(table[name].unit or ""), unit, name)
        return table

    def check_stilts(self, xml_path, names):
        require_program("stilts")
        # omode=meta: the column list STILTS reads, "N: NAME(Class)/unit - description".
        r = subprocess.run(["stilts", "tpipe", "in=" + xml_path, "ifmt=votable", "omode=meta"],
                           capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        listed = re.findall(r"^ *\d+: (\w+)\(\w+\)(?:/(\S+))? - ", r.stdout, re.M)
        self.assertEqual([n for n, _ in listed], list(names))
        units = dict(listed)
        # cmd=meta as CSV: every column's UCD in full.
        r = subprocess.run(["stilts", "tpipe", "in=" + xml_path, "ifmt=votable", "cmd=meta",
                            "ofmt=csv"], capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = {row["Name"]: row for row in csv.DictReader(io.StringIO(r.stdout))}
        for name, (unit, ucd) in self.EXPECTED.items():
            self.assertEqual(units[name], unit, name)
            self.assertEqual(rows[name]["UCD"], ucd, name)

    def test_measure_votable_holds_the_ldac_values_names_units_and_ucds(self):
        ldac_path, xml_path = self.run_pair("measure")
        table = self.check_same_as_ldac(ldac_path, xml_path)
        self.check_stilts(xml_path, table.colnames)
        # The run's cards (LDAC_IMHEAD's SEx/OCT keywords) are the table's PARAMs.
        from astropy.io.votable import parse_single_table
        params = {p.name: p.value for p in parse_single_table(xml_path).params}
        self.assertEqual(params["OCTNLEV"], 3)

    def test_detect_votable_holds_the_ldac_values(self):
        ldac_path, xml_path = self.run_pair("detect", ["-DETECT_NLEVELS", "2"])
        table = self.check_same_as_ldac(ldac_path, xml_path)
        self.assertEqual(sorted(set(table["THRESH_LEVEL"])), [1, 2])
        self.check_stilts(xml_path, table.colnames)


class BadInput(WorkDirTest):
    """Bad input: a clear one-line error naming the file, a non-zero exit, no output file."""

    def expect_error(self, *args, mentions):
        out = self.path("out.ldac")
        proc = run_octarc("measure", *args, "-CATALOG_NAME", out, "-CATALOG_TYPE", "FITS_LDAC",
                          "-VERBOSE_TYPE", "QUIET", check=False)
        self.assertNotEqual(proc.returncode, 0, proc.stderr)
        lines = [l for l in proc.stderr.splitlines() if l.strip()]
        self.assertEqual(len(lines), 1, proc.stderr)
        self.assertIn(mentions, lines[0])
        self.assertFalse(os.path.exists(out))
        self.assertEqual([f for f in os.listdir(self.work) if f.startswith(".out")], [])
        return lines[0]

    def param(self):
        return write_param(self.path("p.param"), ["NUMBER", "ARCNESS"])

    def test_missing_image(self):
        self.expect_error(self.path("nope.fits"), "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", self.param(), mentions="nope.fits")

    def test_not_fits(self):
        junk = self.path("junk.fits")
        open(junk, "w").write("this is not a FITS file\n" * 100)
        self.expect_error(junk, "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", self.param(), mentions="junk.fits")

    def test_truncated_image(self):
        data = fits.getdata(IMAGE)
        full = self.path("full.fits")
        fits.PrimaryHDU(data).writeto(full)
        cut = self.path("cut.fits")
        open(cut, "wb").write(open(full, "rb").read()[:2880 * 10])
        self.expect_error(cut, "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", self.param(), mentions="cut.fits")

    def test_table_where_an_image_is_expected(self):
        self.expect_error(CATS[0] + "[2]", "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", self.param(), mentions="example.cat1.ldac")

    def test_segmentation_not_integer(self):
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", IMAGE, "-PARAMETERS_NAME", self.param(),
                          mentions="example.fits.gz")

    def test_segmentation_wrong_size(self):
        seg = self.path("small.seg.fits")
        fits.PrimaryHDU(np.zeros((10, 12), dtype=np.int32)).writeto(seg)
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", seg, "-PARAMETERS_NAME", self.param(),
                          mentions="small.seg.fits")

    def test_negative_label(self):
        seg = fits.getdata(SEGS.split(",")[0]).astype(np.int32)
        seg[0, 0] = -3
        path = self.path("neg.seg.fits")
        fits.PrimaryHDU(seg).writeto(path)
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", path, "-PARAMETERS_NAME", self.param(),
                          mentions="neg.seg.fits")

    def test_levels_that_do_not_nest(self):
        segs = SEGS.split(",")
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", "%s,%s" % (segs[2], segs[0]),
                          "-DETECT_LEVELS", "1,2", "-PARAMETERS_NAME", self.param(),
                          mentions="example.seg")

    def test_label_without_catalog_row(self):
        seg = fits.getdata(SEGS.split(",")[0]).astype(np.int32)
        seg[0:3, 0:3] = 99
        path = self.path("extra.seg.fits")
        fits.PrimaryHDU(seg).writeto(path)
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", path, "-INPUT_CATALOG", CATS[0],
                          "-APPEND_COLUMNS", "N", "-PARAMETERS_NAME", self.param(),
                          mentions="99")

    def test_catalog_row_without_label(self):
        seg = fits.getdata(SEGS.split(",")[0]).astype(np.int32)
        seg[seg == 2] = 0
        path = self.path("missing.seg.fits")
        fits.PrimaryHDU(seg).writeto(path)
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", path, "-INPUT_CATALOG", CATS[0],
                          "-APPEND_COLUMNS", "N", "-PARAMETERS_NAME", self.param(),
                          mentions="NUMBER 2")

    def test_catalog_without_number(self):
        cat = self.path("nonumber.fits")
        fits.BinTableHDU.from_columns([fits.Column(name="X_IMAGE", format="E",
                                                   array=np.zeros(3))],
                                      name="LDAC_OBJECTS").writeto(cat)
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[0], "-INPUT_CATALOG", cat,
                          "-APPEND_COLUMNS", "N", "-PARAMETERS_NAME", self.param(),
                          mentions="nonumber.fits")

    def test_malformed_param_line(self):
        param = write_param(self.path("bad.param"), ["NUMBER", "VECTOR_ASSOC(0)"])
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", param, mentions="bad.param")

    def test_malformed_sex_value(self):
        sex = self.path("bad.sex")
        open(sex, "w").write("DETECT_MINAREA  lots\n")
        self.expect_error(IMAGE, "-c", sex, "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", self.param(), mentions="DETECT_MINAREA")

    def test_out_of_range_value(self):
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[0], "-DETECT_MINAREA", "0",
                          "-PARAMETERS_NAME", self.param(), mentions="DETECT_MINAREA")

    def test_malformed_assoc_line(self):
        assoc = self.path("list.txt")
        open(assoc, "w").write("1 100.0 100.0 21.5\n2 abc 30.0 22.0\n")
        param = write_param(self.path("a.param"), ["NUMBER", "VECTOR_ASSOC(2)", "NUMBER_ASSOC"])
        self.expect_error(IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[0], "-PARAMETERS_NAME",
                          param, "-ASSOC_NAME", assoc, "-ASSOC_PARAMS", "2,3",
                          "-ASSOC_DATA", "1,4", mentions="list.txt")

    def test_catalog_without_sexthld_names_the_file_and_the_key(self):
        broken = self.path("nothld.ldac")
        with fits.open(CATS[1]) as f:
            cards = [c for c in f[1].data[0][0] if not c.startswith("SEXTHLD ") and c.strip()]
            if not cards[-1].startswith("END"):
                cards.append("END")
            width = 80 * len(cards)
            f[1] = fits.BinTableHDU.from_columns(
                [fits.Column(name="Field Header Card", format="%dA" % width, dim="(80, %d)" %
                             len(cards), array=np.array([[c.ljust(80) for c in cards]]))],
                name="LDAC_IMHEAD")
            f.writeto(broken)
        line = self.expect_error(IMAGE, "-SEGMENTATION_NAME", SEGS, "-INPUT_CATALOG",
                                 ",".join([CATS[0], broken, CATS[2]]), "-APPEND_COLUMNS", "N",
                                 "-BACKGROUND_NAME", BACKGROUND, "-PARAMETERS_NAME", self.param(),
                                 mentions=broken)
        self.assertIn("SEXTHLD", line)
        self.assertIn("DETECT_LEVELS", line)

    def test_output_over_the_image_is_refused(self):
        image = self.path("image.fits")
        shutil.copyfile(IMAGE, image)
        before = open(image, "rb").read()
        proc = run_octarc("measure", image, "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", self.param(), "-CATALOG_NAME", image,
                          "-VERBOSE_TYPE", "QUIET", check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertIn("CATALOG_NAME " + image + " is also the image", proc.stderr)
        self.assertEqual(open(image, "rb").read(), before)

    def test_dual_image_syntax_is_named(self):
        for images in ([IMAGE + "," + IMAGE], [IMAGE, IMAGE]):
            line = self.expect_error(*images, "-SEGMENTATION_NAME", SEGS.split(",")[0],
                                     "-PARAMETERS_NAME", self.param(), mentions="dual-image")
            self.assertIn("for octarc detect and octarc search", line)

    def test_unknown_parameter_only_warns(self):
        param = write_param(self.path("w.param"), ["NUMBER", "NOT_A_COLUMN", "ARCNESS"])
        out = self.path("out.ldac")
        proc = run_octarc("measure", IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[0],
                          "-PARAMETERS_NAME", param, "-CATALOG_NAME", out, "-CATALOG_TYPE",
                          "FITS_LDAC")
        self.assertIn("NOT_A_COLUMN", proc.stderr)
        self.assertEqual(fits.getdata(out, 2).columns.names, ["NUMBER", "ARCNESS"])


class AssocLists(WorkDirTest):

    def test_nearest_match_copies_the_list_columns(self):
        cat, _ = ldac_objects(CATS[1])
        assoc = self.path("truth.txt")
        with open(assoc, "w") as f:
            f.write("# id x y mag\n")
            for i, row in enumerate(cat[:3], start=1):
                f.write("%d %.3f %.3f %.2f\n" % (100 + i, row["X_IMAGE"] + 0.5, row["Y_IMAGE"],
                                                 20.0 + i))
        param = write_param(self.path("a.param"),
                            ["NUMBER", "VECTOR_ASSOC(2)", "NUMBER_ASSOC", "ARCNESS"])
        out = self.path("a.ldac")
        run_octarc("measure", IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[1], "-INPUT_CATALOG",
                   CATS[1], "-APPEND_COLUMNS", "N", "-BACKGROUND_NAME", BACKGROUND,
                   "-PARAMETERS_NAME", param, "-ASSOC_NAME", assoc, "-ASSOC_PARAMS", "2,3",
                   "-ASSOC_DATA", "1,4", "-ASSOC_RADIUS", "2.0", "-ASSOCSELEC_TYPE", "MATCHED",
                   "-CATALOG_NAME", out, "-CATALOG_TYPE", "FITS_LDAC", "-FILTER", "N",
                   "-VERBOSE_TYPE", "QUIET")
        ours, header = ldac_objects(out)
        self.assertEqual(len(ours), 3)
        np.testing.assert_array_equal(sorted(ours["NUMBER"]), sorted(cat["NUMBER"][:3]))
        for row in ours:
            i = list(cat["NUMBER"]).index(row["NUMBER"])
            self.assertEqual(row["VECTOR_ASSOC"][0], 101 + i)
            self.assertAlmostEqual(row["VECTOR_ASSOC"][1], 21.0 + i)
            self.assertEqual(row["NUMBER_ASSOC"], 1)

    def test_append_mode_fills_assoc_columns_of_every_row(self):
        cat, _ = ldac_objects(CATS[1])
        assoc = self.path("truth.txt")
        with open(assoc, "w") as f:
            for i, row in enumerate(cat[:2], start=1):
                f.write("%d %.3f %.3f\n" % (500 + i, row["X_IMAGE"], row["Y_IMAGE"] + 0.3))
        param = write_param(self.path("a.param"), ["NUMBER", "VECTOR_ASSOC(1)", "NUMBER_ASSOC"])
        out = self.path("a.ldac")
        proc = run_octarc("measure", IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[1],
                          "-INPUT_CATALOG", CATS[1], "-CATALOG_NAME", out, "-BACKGROUND_NAME",
                          BACKGROUND, "-PARAMETERS_NAME", param, "-ASSOC_NAME", assoc,
                          "-ASSOC_PARAMS", "2,3", "-ASSOC_DATA", "1", "-FILTER", "N")
        self.assertIn("ASSOCSELEC_TYPE MATCHED does not remove rows", proc.stderr)
        ours, _ = ldac_objects(out)
        np.testing.assert_array_equal(ours["NUMBER"], cat["NUMBER"])  # every row kept
        vector = np.asarray(ours["VECTOR_ASSOC"]).reshape(len(ours), -1)[:, 0]
        np.testing.assert_array_equal(vector[:2], [501, 502])
        np.testing.assert_array_equal(ours["NUMBER_ASSOC"][:2], [1, 1])
        self.assertTrue(np.all(vector[2:] == 0))
        self.assertTrue(np.all(ours["NUMBER_ASSOC"][2:] == 0))
        # A list that does not exist is an error, also when appending.
        proc = run_octarc("measure", IMAGE, "-SEGMENTATION_NAME", SEGS.split(",")[1],
                          "-INPUT_CATALOG", CATS[1], "-CATALOG_NAME", self.path("b.ldac"),
                          "-BACKGROUND_NAME", BACKGROUND, "-PARAMETERS_NAME", param,
                          "-ASSOC_NAME", self.path("absent.txt"), check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertIn("absent.txt", proc.stderr)
        self.assertFalse(os.path.exists(self.path("b.ldac")))

    def test_a_new_catalog_of_several_levels_always_has_thresh_level(self):
        param = write_param(self.path("n.param"), ["NUMBER", "ARCNESS"])
        out = self.path("n.ldac")
        proc = run_octarc("measure", IMAGE, "-SEGMENTATION_NAME", SEGS, "-INPUT_CATALOG",
                          ",".join(CATS), "-APPEND_COLUMNS", "N", "-CATALOG_NAME", out,
                          "-CATALOG_TYPE", "FITS_LDAC", "-BACKGROUND_NAME", BACKGROUND,
                          "-PARAMETERS_NAME", param, "-FILTER", "N")
        self.assertIn("THRESH_LEVEL added", proc.stderr)
        ours, header = ldac_objects(out)
        self.assertEqual(ours.columns.names, ["NUMBER", "THRESH_LEVEL", "ARCNESS"])
        self.assertEqual(sorted(set(ours["THRESH_LEVEL"])), [1, 2, 3])


if __name__ == "__main__":
    unittest.main()
