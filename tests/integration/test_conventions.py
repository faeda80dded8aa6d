"""What a SExtractor user expects of octarc's configuration: keys octarc does not act on are
warned of when set; SExtractor's catalog parameters octarc does not measure are named as such;
WRITE_XML writes SExtractor's XML run summary (compared with the one source-extractor writes for
the same image, and read back with astropy); every command's -d / -dd template loads back with -c
from an empty directory."""
import gzip
import os
import shutil
import subprocess
import unittest
import warnings
import xml.etree.ElementTree as ET

import numpy as np
from astropy.io import fits
from astropy.io.votable import parse as parse_votable
from regions import CirclePixelRegion, PixCoord, PointPixelRegion, Regions

from octarc_testlib import (OCTARC, SEX_SHARE, SOURCE_DIR, WorkDirTest, require_program,
                            run_octarc, write_param)

IMAGE = os.path.join(SOURCE_DIR, "testdata", "example.fits.gz")
SEG1 = os.path.join(SOURCE_DIR, "testdata", "example.seg1.fits.gz")


def warnings_of(stderr):
    return [line for line in stderr.splitlines() if line.startswith("WARNING")]


class IgnoredKeys(WorkDirTest):

    def test_each_ignored_key_set_warns_once(self):
        proc = run_octarc("detect", IMAGE, "-DEBLEND_NTHRESH", "64", "-CLEAN", "Y",
                          "-CLEAN", "N", "-PHOT_APERTURES", "5,10", "-CATALOG_NAME", "a.cat",
                          "-PARAMETERS_NAME", write_param(self.path("p.param"), ["NUMBER"]),
                          cwd=self.work)
        self.assertEqual(
            [w for w in warnings_of(proc.stderr) if "ignored by octarc" in w],
            ["WARNING: command line: -%s is ignored by octarc (setting it has no effect)" % k
             for k in ("DEBLEND_NTHRESH", "CLEAN", "PHOT_APERTURES")])
        # Keys octarc acts on are not warned of.
        self.assertNotIn("DETECT", "".join(w for w in warnings_of(proc.stderr)
                                           if "ignored" in w and "DEBLEND" not in w))

    def test_files_warn_only_for_values_other_than_the_default(self):
        # SExtractor's own default.sex sets every key to its default: no warning.
        require_program("source-extractor")
        shutil.copy(os.path.join(SEX_SHARE, "default.sex"), self.path("default.sex"))
        write_param(self.path("default.param"), ["NUMBER", "X_IMAGE"])
        proc = run_octarc("detect", IMAGE, "-CATALOG_NAME", "b.cat", cwd=self.work)
        self.assertEqual(warnings_of(proc.stderr), [])
        with open(self.path("default.sex"), "a") as f:
            f.write("\nDEBLEND_MINCONT 0.1\n")
        with open(self.path("default.sex")) as f:
            lines = len(f.read().splitlines())
        proc = run_octarc("detect", IMAGE, "-CATALOG_NAME", "c.cat", cwd=self.work)
        self.assertEqual(warnings_of(proc.stderr),
                         ["WARNING: default.sex:%d: DEBLEND_MINCONT is ignored by octarc "
                          "(setting it has no effect)" % lines])

    def test_quiet_runs_do_not_warn(self):
        proc = run_octarc("detect", IMAGE, "-DEBLEND_NTHRESH", "64", "-VERBOSE_TYPE", "QUIET",
                          "-CATALOG_NAME", "q.cat", cwd=self.work)
        self.assertEqual(proc.stderr, "")

    def test_quiet_is_silent_on_both_streams_as_sextractor(self):
        """VERBOSE_TYPE QUIET: nothing on stdout nor stderr, as source-extractor on the same
        image (its own streams are the reference), for detect, measure and search."""
        require_program("source-extractor")
        param = write_param(self.path("q.param"), ["NUMBER", "X_IMAGE"])
        image = self.path("example.fits")  # source-extractor reads no gzip
        with gzip.open(IMAGE) as src, open(image, "wb") as dst:
            shutil.copyfileobj(src, dst)
        theirs = subprocess.run(
            ["source-extractor", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
             "-PARAMETERS_NAME", param, "-FILTER", "N", "-CATALOG_NAME", self.path("s.cat"),
             "-VERBOSE_TYPE", "QUIET"], capture_output=True, text=True, cwd=self.work, check=True)
        self.assertEqual((theirs.stdout, theirs.stderr), ("", ""))
        runs = {
            "detect": ("detect", IMAGE, "-PARAMETERS_NAME", param, "-CATALOG_NAME", "d.cat"),
            "measure": ("measure", IMAGE, "-SEGMENTATION_NAME", SEG1, "-PARAMETERS_NAME", param,
                        "-CATALOG_NAME", "m.cat"),
            "search": ("search", IMAGE, "-GRID_NAME", "demo.grid.fits", "-STAMPS", "N",
                       "-PIXEL_SCALE", "0.3", "-OUTPUT_DIR", "s-out"),
        }
        for name, args in runs.items():
            ours = run_octarc(*args, "-VERBOSE_TYPE", "QUIET", cwd=self.work)
            self.assertEqual((ours.stdout, ours.stderr), ("", ""), name)
            loud = run_octarc(*args, "-VERBOSE_TYPE", "NORMAL", cwd=self.work)
            self.assertNotEqual(loud.stdout + loud.stderr, "", name)  # the check can fail

    def test_search_warns_of_write_xml(self):
        # A search writes its own summary (summary.txt), not SExtractor's XML.
        proc = run_octarc("search", IMAGE, "-WRITE_XML", "Y", "-GRID_NAME", "no.grid.fits",
                          cwd=self.work, check=False)
        self.assertIn("WARNING: command line: -WRITE_XML is ignored by octarc", proc.stderr)


class ParameterNames(WorkDirTest):

    def test_sextractor_parameters_not_measured_are_named_so(self):
        require_program("source-extractor")
        theirs = [line.split()[0][1:] for line in subprocess.run(
            ["source-extractor", "-dp"], capture_output=True, text=True).stdout.splitlines()
            if line.startswith("#")]
        ours = set(line.split()[0][1:] for line in run_octarc("detect", "-dp").stdout.splitlines()
                   if line.startswith("#"))
        missing = [n for n in theirs if n not in ours]
        self.assertIn("MAG_AUTO", missing)
        self.assertIn("FLUX_RADIUS", missing)
        param = write_param(self.path("all.param"), ["NUMBER"] + missing + ["NOT_A_PARAMETER"])
        proc = run_octarc("detect", IMAGE, "-PARAMETERS_NAME", param, "-CATALOG_NAME", "x.cat",
                          cwd=self.work)
        self.assertEqual(
            [w for w in warnings_of(proc.stderr) if "catalog parameter" in w],
            ["WARNING: %s: catalog parameter %s not measured by octarc (isophotal only), skipped"
             % (param, n) for n in missing] +
            ["WARNING: %s: catalog parameter NOT_A_PARAMETER unknown, skipped" % param])


def catalog_rows(path):
    with open(path) as f:
        return sum(1 for line in f if line[0] != "#")


def xml_tree(path):
    root = ET.parse(path).getroot()
    for e in root.iter():  # drop the namespace, if any
        e.tag = e.tag.split("}")[-1]
    return root


def resource(root, rid):
    for r in root.iter("RESOURCE"):
        if r.get("ID") == rid:
            return r
    raise AssertionError("no RESOURCE %s" % rid)


def table(root, tid):
    for t in root.iter("TABLE"):
        if t.get("ID") == tid:
            return t
    raise AssertionError("no TABLE %s" % tid)


def child_names(element, tag):
    return [e.get("name") for e in element.findall(tag)]


def extension_row(root):
    t = table(root, "Extension_Data")
    names = child_names(t, "FIELD")
    tds = [td.text for td in t.find("DATA").find("TABLEDATA").find("TR").findall("TD")]
    return dict(zip(names, tds))


class XmlSummary(WorkDirTest):

    def run_both(self, *extra):
        require_program("source-extractor")
        param = write_param(self.path("p.param"), ["NUMBER", "X_IMAGE", "Y_IMAGE", "FLUX_ISO"])
        common = ["-PARAMETERS_NAME", param, "-FILTER", "N", "-DETECT_THRESH", "3",
                  "-ANALYSIS_THRESH", "3", "-CATALOG_TYPE", "ASCII_HEAD", "-WRITE_XML", "Y"]
        os.mkdir(self.path("sex"))
        # source-extractor reads no gzip-compressed image.
        image = self.path("example.fits")
        with gzip.open(IMAGE, "rb") as src, open(image, "wb") as dst:
            shutil.copyfileobj(src, dst)
        subprocess.run(["source-extractor", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
                        "-STARNNW_NAME", os.path.join(SEX_SHARE, "default.nnw"),
                        "-DEBLEND_NTHRESH", "1", "-CLEAN", "N", "-VERBOSE_TYPE", "QUIET"] +
                       common, cwd=self.path("sex"), check=True, capture_output=True)
        proc = run_octarc("detect", image, *common, *extra, cwd=self.work)
        return os.path.join(self.path("sex"), "sex.xml"), self.path("sex.xml"), proc

    def test_layout_and_values_follow_sextractor(self):
        theirs_path, ours_path, _ = self.run_both()
        theirs, ours = xml_tree(theirs_path), xml_tree(ours_path)
        self.assertEqual(ours.tag, "VOTABLE")
        self.assertEqual(ours.get("version"), theirs.get("version"))
        # The same tables and resources, nested the same way.
        for root in (theirs, ours):
            top = root.find("RESOURCE")
            self.assertEqual([t.get("ID") for t in top.findall("TABLE")], ["Source_List"])
            meta = top.find("RESOURCE")
            self.assertEqual(meta.get("ID"), "MetaData")
            self.assertEqual([t.get("ID") for t in meta.findall("TABLE")],
                             ["Extension_Data", "Warnings"])
            self.assertEqual(meta.find("RESOURCE").get("ID"), "Config")
        # The catalog's columns as FIELDs of Source_List, as SExtractor lists them.
        self.assertEqual(child_names(table(ours, "Source_List"), "FIELD"),
                         child_names(table(theirs, "Source_List"), "FIELD"))
        # Every field, meta-data and configuration name SExtractor writes, octarc writes too
        # (but SExtractor's software credits).
        self.assertLessEqual(set(child_names(table(theirs, "Extension_Data"), "FIELD")),
                             set(child_names(table(ours, "Extension_Data"), "FIELD")))
        self.assertLessEqual(
            set(child_names(resource(theirs, "MetaData"), "PARAM")) -
            {"Soft_URL", "Soft_Auth", "Soft_Ref"},
            set(child_names(resource(ours, "MetaData"), "PARAM")))
        self.assertLessEqual(set(child_names(resource(theirs, "Config"), "PARAM")),
                             set(child_names(resource(ours, "Config"), "PARAM")))
        # One level at 3 sigma, unfiltered, no deblending: SExtractor's background, noise,
        # threshold and number of sources.
        t, o = extension_row(theirs), extension_row(ours)
        for name in ("Background_Mean", "Background_StDev", "Threshold"):
            self.assertAlmostEqual(float(o[name]), float(t[name]), delta=1e-4 * float(t[name]),
                                   msg=name)
        self.assertEqual(o["NSextracted"], t["NSextracted"])
        self.assertEqual(int(o["NSextracted"]),
                         catalog_rows(self.path("test.cat")))
        self.assertEqual(o["NLevels"], "1")
        self.assertEqual(o["Gain"], t["Gain"])
        self.assertEqual(o["Satur_Level"], t["Satur_Level"])
        config = {p.get("name"): p.get("value") for p in resource(ours, "Config").findall("PARAM")}
        self.assertEqual(config["Detect_Thresh"], "3")
        self.assertEqual(config["Filter"], "F")
        self.assertEqual(config["Write_XML"], "T")
        self.assertEqual(config["Detect_Nlevels"], "1")
        self.assertTrue(config["Command_Line"].startswith("octarc detect " +
                                                          self.path("example.fits")))

    def test_astropy_reads_it(self):
        _, ours_path, _ = self.run_both("-DETECT_NLEVELS", "3", "-DEBLEND_NTHRESH", "8")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            votable = parse_votable(ours_path, verify="warn")
        self.assertEqual([str(w.message) for w in caught], [])
        top = votable.resources[0]
        self.assertEqual(top.ID, "octarc")
        self.assertEqual(top.tables[0].ID, "Source_List")
        # Three levels: THRESH_LEVEL is added after NUMBER.
        self.assertEqual(top.tables[0].array.dtype.names,
                         ("NUMBER", "THRESH_LEVEL", "X_IMAGE", "Y_IMAGE", "FLUX_ISO"))
        meta = top.resources[0]
        ext = meta.tables[0].array
        self.assertEqual(len(ext), 1)
        self.assertEqual(int(ext["NLevels"][0]), 3)
        rows = catalog_rows(self.path("test.cat"))
        self.assertEqual(int(ext["NSextracted"][0]), rows)
        # The configuration's warnings are in the Warnings table.
        msgs = [str(m) for m in meta.tables[1].array["Msg"]]
        self.assertEqual(msgs, ["default.sex not found, using internal defaults",
                                "command line: -DEBLEND_NTHRESH is ignored by octarc "
                                "(setting it has no effect)"])
        params = {p.name: p.value for p in meta.resources[0].params}
        self.assertEqual(int(params["Detect_Nlevels"]), 3)
        self.assertEqual(list(params["Phot_AutoParams"]), [2.5, 3.5])

    def test_values_are_escaped(self):
        name = "a&<b>'.cat"  # '"' separates values, as in SExtractor
        run_octarc("detect", IMAGE, "-WRITE_XML", "Y", "-CATALOG_NAME", name, cwd=self.work)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            votable = parse_votable(self.path("sex.xml"), verify="warn")
        self.assertEqual([str(w.message) for w in caught], [])
        params = {p.name: p.value for p in votable.resources[0].resources[0].resources[0].params}
        self.assertEqual(params["Catalog_Name"], name)
        self.assertIn(name, params["Command_Line"])

    def test_measure_writes_it_too(self):
        proc = run_octarc("measure", IMAGE, "-SEGMENTATION_NAME", SEG1, "-DETECT_THRESH", "3",
                          "-WRITE_XML", "Y", "-XML_NAME", "m.xml", "-CATALOG_NAME", "m.cat",
                          cwd=self.work)
        row = extension_row(xml_tree(self.path("m.xml")))
        rows = catalog_rows(self.path("m.cat"))
        self.assertEqual(int(row["NSextracted"]), rows, proc.stderr)

    def test_written_with_the_other_outputs_or_not_at_all(self):
        # An XML_NAME that cannot be written stops the run before anything is read or written.
        proc = run_octarc("detect", IMAGE, "-WRITE_XML", "Y", "-XML_NAME",
                          self.path("nodir/sex.xml"), cwd=self.work, check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("nodir", proc.stderr)
        self.assertEqual(os.listdir(self.work), [])
        # A run that fails on its image leaves no XML either.
        with open(self.path("broken.fits"), "wb") as f:
            f.write(b"SIMPLE  = T" + b" " * 100)
        proc = run_octarc("detect", self.path("broken.fits"), "-WRITE_XML", "Y",
                          cwd=self.work, check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertEqual(sorted(os.listdir(self.work)), ["broken.fits"])
        # The XML is not the catalog.
        proc = run_octarc("detect", IMAGE, "-WRITE_XML", "Y", "-XML_NAME", "x.cat",
                          "-CATALOG_NAME", "x.cat", cwd=self.work, check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("x.cat", proc.stderr)


class Masks(WorkDirTest):
    """The searched pixels of a search with MASK_NAME are those astropy regions puts inside the
    region file by DS9's rule: the union of the include shapes (the whole image without any),
    minus the exclude shapes; points are circles of MASK_POINT_RADIUS."""

    SHAPES = ["circle(60.3,70.8,20.2)", "box(150.2,50.7,40.3,25.6,30)",
              "ellipse(120.4,150.3,30.2,12.7,-20)", "polygon(20.1,120.3,70.6,180.2,10.4,190.7)",
              "annulus(150.6,140.2,10.3,25.9)", "point(100.3,100.8)"]
    POINT_RADIUS_ARCSEC = 3.0
    PIXEL_SCALE = 0.5  # arcsec: points are circles of 6 pixels

    def astropy_count(self, text):
        y, x = np.mgrid[0:200, 0:200]
        pix = PixCoord(x.ravel(), y.ravel())  # 0-based pixel centres
        inc = np.zeros(pix.x.shape, bool)
        exc = np.zeros(pix.x.shape, bool)
        any_include = False
        for r in Regions.parse(text, format="ds9"):
            include = r.meta.get("include", 1) != 0
            if isinstance(r, PointPixelRegion):
                r = CirclePixelRegion(r.center, self.POINT_RADIUS_ARCSEC / self.PIXEL_SCALE)
            r.meta["include"] = 1  # regions inverts contains() of exclude shapes
            if include:
                any_include = True
                inc |= r.contains(pix)
            else:
                exc |= r.contains(pix)
        if not any_include:
            inc[:] = True
        return int(np.sum(inc & ~exc))

    def searched_pixels(self, text, out):
        reg = self.path(out + ".reg")
        with open(reg, "w") as f:
            f.write(text)
        proc = run_octarc("search", IMAGE, "-GRID_NAME", "demo.grid.fits", "-STAMPS", "N",
                          "-MASK_NAME", reg, "-MASK_POINT_RADIUS", str(self.POINT_RADIUS_ARCSEC),
                          "-PIXEL_SCALE", str(self.PIXEL_SCALE), "-OUTPUT_DIR", self.path(out),
                          "-VERBOSE_TYPE", "QUIET", cwd=self.work)
        with fits.open(self.path(out + "/candidates.fits")) as f:
            return f["LDAC_OBJECTS"].header["SRCHPIX"], proc

    def test_every_shape_includes_and_excludes_as_astropy_regions(self):
        header = "# Region file format: DS9 version 4.1\nimage\n"
        files = {"include": header + "\n".join(self.SHAPES) + "\n",
                 "exclude": header + "\n".join("-" + s for s in self.SHAPES) + "\n",
                 "mixed": header + "box(100.3,100.2,180.5,150.5,0)\n" +
                 "\n".join(("-" if i % 2 else "") + s for i, s in enumerate(self.SHAPES)) + "\n"}
        counts = {}
        for name, text in files.items():
            got, _ = self.searched_pixels(text, name)
            want = self.astropy_count(text)
            self.assertEqual(got, want, name)
            counts[name] = got
        # An exclusions-only file searches the rest of the image, not the shapes.
        self.assertEqual(counts["include"] + counts["exclude"], 200 * 200)
        self.assertGreater(counts["include"], 3000)

    def test_points_without_a_radius_are_refused(self):
        reg = self.path("p.reg")
        with open(reg, "w") as f:
            f.write("image\n-point(100,100)\n")
        proc = run_octarc("search", IMAGE, "-GRID_NAME", "demo.grid.fits", "-MASK_NAME", reg,
                          cwd=self.work, check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("p.reg:2", proc.stderr)
        self.assertIn("MASK_POINT_RADIUS", proc.stderr)
        self.assertFalse(os.path.exists(self.path("candidates")))


class Templates(WorkDirTest):
    """octarc COMMAND -d / -dd prints a .sex file that runs as it is, from an empty directory."""

    def template(self, command, full):
        path = self.path("%s%s.sex" % (command, "-full" if full else ""))
        with open(path, "w") as f:
            f.write(run_octarc(command, "-dd" if full else "-d").stdout)
        return path

    def run_from_empty_directory(self, *args):
        run = self.path("run")
        shutil.rmtree(run, ignore_errors=True)
        os.mkdir(run)
        return run_octarc(*args, cwd=run, check=False)

    def test_detect_and_measure(self):
        for full in (False, True):
            sex = self.template("detect", full)
            proc = self.run_from_empty_directory("detect", IMAGE, "-c", sex)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            sex = self.template("measure", full)
            proc = self.run_from_empty_directory("measure", IMAGE, "-c", sex,
                                                 "-SEGMENTATION_NAME", SEG1)
            self.assertEqual(proc.returncode, 0, proc.stderr)

    def test_search_uses_the_arc_search_levels(self):
        text = run_octarc("search", "-d").stdout
        values = {line.split()[0]: line.split()[1] for line in text.splitlines()
                  if line.strip() and not line.startswith("#") and len(line.split()) > 1}
        self.assertEqual(values["DETECT_NLEVELS"], "15")
        self.assertEqual(values["DETECT_THRESH"], "2.5")
        # candidates.fits is FITS-LDAC without a configuration file, not SExtractor's ASCII_HEAD.
        self.assertEqual(values["CATALOG_TYPE"], "FITS_LDAC")
        self.assertEqual(values["FILTER"], "N")
        self.assertEqual(values["PARAMETERS_NAME"], "octarc.param")
        for full in (False, True):
            sex = self.template("search", full)
            proc = self.run_from_empty_directory("search", IMAGE, "-c", sex, "-GRID_NAME",
                                                 "demo.grid.fits", "-STAMPS", "N")
            self.assertEqual(proc.returncode, 0, proc.stderr)
            self.assertIn("> Level 15", proc.stderr)
            self.assertTrue(os.path.isfile(self.path("run/candidates/candidates.fits")))

    def test_batch(self):
        for full in (False, True):
            sex = self.template("batch", full)
            manifest = self.path("tiles.txt")
            with open(manifest, "w") as f:
                f.write(IMAGE + "\n")
            proc = self.run_from_empty_directory("batch", manifest, "-c", sex, "-GRID_NAME",
                                                 "demo.grid.fits", "-STAMPS", "N")
            self.assertEqual(proc.returncode, 0, proc.stderr)

    def test_calibrate(self):
        for full in (False, True):
            sex = self.template("calibrate", full)
            proc = self.run_from_empty_directory("calibrate", self.path("nosim.fits"), "-c", sex)
            # Past the configuration: the first input is what is missing.
            self.assertNotEqual(proc.returncode, 0)
            self.assertIn("nosim.fits", proc.stderr)
            self.assertNotIn(os.path.basename(sex), proc.stderr)

    def test_missing_files_name_both_places(self):
        share = os.path.normpath(os.path.join(os.path.dirname(OCTARC), "..", "share", "octarc"))
        for args, what in ((["detect", IMAGE, "-c", "nothere.sex"], "configuration file"),
                           (["detect", IMAGE, "-PARAMETERS_NAME", "nothere.param"],
                            "PARAMETERS_NAME"),
                           (["detect", IMAGE, "-FILTER", "Y", "-FILTER_NAME", "nothere.conv"],
                            "FILTER_NAME"),
                           (["search", IMAGE, "-GRID_NAME", "nothere.grid.fits"], "GRID_NAME")):
            proc = self.run_from_empty_directory(*args)
            self.assertNotEqual(proc.returncode, 0)
            errors = [line for line in proc.stderr.splitlines() if not line.startswith(
                ("WARNING", ">"))]
            self.assertEqual(len(errors), 1, proc.stderr)
            self.assertIn(what, errors[0])
            self.assertIn("working directory", errors[0])
            self.assertIn(share, errors[0])
        # A shipped file is found by its name alone.
        proc = self.run_from_empty_directory("detect", IMAGE, "-c", "octarc.sex",
                                             "-CATALOG_NAME", "s.ldac")
        self.assertEqual(proc.returncode, 0, proc.stderr)


if __name__ == "__main__":
    unittest.main()
