"""What the README says about the command line and the configuration, checked through the
commands themselves: -h, -d/-dd, -dp and -v; ./default.sex when there is no -c; the FILTER_NAME
lookup; BACK_TYPE MANUAL and GLOBAL in `octarc detect`; the gain precedence (the input catalog's
SEXGAIN, else the header keyword GAIN_KEY names, else GAIN) and the OCTBKSRC / OCTSGSRC /
SEXGAIN cards of every origin of the background, the noise and the gain.

The references are independent of octarc: source-extractor 2.25 with the same settings, its
-dd and -dp listings, astropy's sigma_clipped_stats, numpy on the check-images, and the README's
own lists of keys and columns.
"""
import os
import re
import shutil
import subprocess
import unittest

import numpy as np
from astropy.io import fits
from astropy.stats import sigma_clipped_stats

from octarc_testlib import (OCTARC, SEX_SHARE, SOURCE_DIR, WorkDirTest, card_text, ldac_imhead,
                            ldac_objects, require_program, run_octarc, run_sextractor,
                            write_param)
from test_detect_vs_sextractor import assert_rows_agree, label_correspondence
from test_measure_vs_sextractor import SEX_COLUMNS, assert_float_columns_agree

TESTDATA = os.path.join(SOURCE_DIR, "testdata")
IMAGE = os.path.join(TESTDATA, "example.fits.gz")   # 200 x 200, sky 100 ADU, header GAIN 4
README = os.path.join(SOURCE_DIR, "README.md")
RUN_CARDS = ("SEXDATE", "SEXTIME", "SEXELAPS")       # differ from run to run


def readme_text():
    with open(README) as f:
        return f.read()


def dump_keys(text):
    """(key, value text) of every key line of a -d / -dd dump or of a .sex file, in order."""
    keys = []
    for line in text.splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        key, _, rest = line.partition(" ")
        keys.append((key, rest.split("#", 1)[0].strip()))
    return keys


def column_listing(text):
    """name -> (description, unit) of a -dp listing ("#NAME  description [unit]")."""
    columns = {}
    for line in text.splitlines():
        m = re.match(r"#(\S+)\s+(.*?)\s*(?:\[(.*)\])?\s*$", line)
        if m:
            columns[m.group(1)] = (m.group(2).strip(), m.group(3) or "")
    return columns


def readme_columns():
    """Every catalog column the README names: the SExtractor-named list ("A/B/THETA_IMAGE" is
    three columns) and the rows of the table of octarc's own columns."""
    text = readme_text().split("## Catalog columns", 1)[1].split("### Flags", 1)[0]
    listed = text.split("and UCD:", 1)[1].split(". As in SExtractor", 1)[0]
    names = set()
    for item in listed.replace("\n", " ").split(","):
        item = item.strip().replace("(n)", "")
        head, _, suffix = item.rpartition("_")
        if "/" in head:
            names.update("%s_%s" % (h, suffix) for h in head.split("/"))
        else:
            names.add(item)
    for row in re.findall(r"^\| (`[A-Z0-9_]+`(?:, `[A-Z0-9_]+`)*) \|", text, re.M):
        names.update(re.findall(r"`([A-Z0-9_]+)`", row))
    return names


def readme_keys():
    """The keys of the README's table of octarc's own keys."""
    text = readme_text().split("octarc's own keys:", 1)[1].split("octarc ships (in `params/`", 1)[0]
    names = set()
    for row in re.findall(r"^\| (`[A-Z_]+`(?:, `[A-Z_]+`)*) \|", text, re.M):
        names.update(re.findall(r"`([A-Z_]+)`", row))
    return names


def imhead_cards(path):
    """The LDAC_IMHEAD cards of every part, the run's date, time and duration left out."""
    with fits.open(path) as f:
        return [c for h in f if h.name == "LDAC_IMHEAD" for c in h.data[0][0]
                if not c.startswith(RUN_CARDS)]


def objects_bytes(path):
    with fits.open(path) as f:
        return [(str(h.header), h.data.tobytes()) for h in f if h.name == "LDAC_OBJECTS"]


def octarc_in(cwd, *args, check=True):
    return run_octarc(*args, check=check, cwd=cwd)


class CommandHelp(WorkDirTest):
    """-h of every command exits 0 with its usage and names its options; every option the help
    of a simulation command lists is accepted (parsed before -h is acted on)."""

    SEX_STYLE = ["-c", "-KEY", "-d", "-dd", "-dp", "-h", "-v"]
    COMMANDS = {
        ("measure",): SEX_STYLE + ["-SEGMENTATION_NAME"],
        ("detect",): SEX_STYLE,
        # The options the README and the tests use.
        ("simulate", "lenses"): ["-n", "--seed", "-o", "--config", "--database", "--stamps",
                                 "--stamp-count", "--threads", "--sigma-min", "--quiet",
                                 "--nlevels", "--sky-sigma", "--source-mag-min"],
        ("simulate", "field"): ["-o", "--size", "--lenses", "--seed", "--config", "--database",
                                "--quiet"],
        ("simulate", "database"): ["-o", "--threshold", "--min-size", "--quiet"],
        ("demo",): ["--size", "--lenses", "--seed", "--out", "--quiet"],
        ("grades",): ["-o", "--page", "--quiet"],
        ("inject",): SEX_STYLE + ["-INJECT_NUMBER", "-INJECT_SEED", "-INJECT_DIR", "-GRID_NAME",
                                  "-MODEL_NAME"],
    }

    def help_text(self, command):
        proc = run_octarc(*command, "-h")
        self.assertEqual(proc.stderr, "")
        self.assertTrue(proc.stdout.startswith("Usage: octarc %s" % " ".join(command)),
                        proc.stdout[:80])
        return proc.stdout

    def test_every_command_describes_its_options(self):
        top = run_octarc("-h")
        for command, options in self.COMMANDS.items():
            self.assertIn("  %s " % " ".join(command), top.stdout)
            text = self.help_text(command)
            for option in options:
                self.assertRegex(text, r"(?<![\w-])%s(?![\w-])" % re.escape(option),
                                 "%s -h does not name %s" % (" ".join(command), option))

    def test_every_listed_simulation_option_is_accepted(self):
        for command in [c for c in self.COMMANDS if c[0] in ("simulate", "demo")]:
            text = self.help_text(command)
            listed = re.findall(r"^  (?:-\w \[ )?--([a-z][\w-]*)(?: \])?( \S+)?", text, re.M)
            self.assertGreater(len(listed), 3, command)
            options = [["--" + name] + (["1"] if argument else [])
                       for name, argument in listed if name != "help"]   # -h is given below
            # Every option in one run; when that run fails, one run per option names it.
            together = run_octarc(*command, *sum(options, []), "-h", check=False)
            if together.returncode == 0:
                continue
            for args in options:
                proc = run_octarc(*command, *args, "-h", check=False)
                self.assertEqual(proc.returncode, 0, "%s %s: %s" % (" ".join(command),
                                                                     " ".join(args), proc.stderr))
            self.fail("%s: its options are accepted one at a time, not together: %s"
                      % (" ".join(command), together.stderr))

    def test_version(self):
        for command in (("measure",), ("detect",)):
            proc = run_octarc(*command, "-v")
            self.assertRegex(proc.stdout, r"^octarc %s version \S+\n$" % command[0])


class EveryCommandTakesTheFlags(WorkDirTest):
    """-h, -v, -d, -dd and -dp on every command, as the README says: the usage, the version, the
    keys with their defaults as a .sex file (the simulations' options among them), the catalog
    columns where the command writes a catalog and one error line where it does not; and a
    simulation's options given as -KEY value make what the long options make."""

    COMMANDS = [("measure",), ("detect",), ("simulate", "lenses"), ("simulate", "field"),
                ("simulate", "database"), ("calibrate",), ("search",), ("batch",), ("demo",),
                ("inject",), ("grades",)]
    # A column each catalog has, named in the README; None: no catalog of chosen columns.
    COLUMN = {("measure",): "ARCNESS", ("detect",): "ARCNESS",
              ("simulate", "lenses"): "SIM_WEIGHT", ("simulate", "field"): None,
              ("simulate", "database"): None, ("calibrate",): None, ("search",): "LENS_SCORE",
              ("batch",): "TILE", ("demo",): "LENS_SCORE", ("inject",): None,
              ("grades",): None}
    # Defaults the README and the -h texts state.
    DEFAULTS = {("simulate", "field"): [("SIZE", "4096"), ("PIXEL_SCALE", "0.257")],
                ("simulate", "lenses"): [("SEED", "1"), ("SAMPLING", "importance"),
                                         ("QUIET", "N")],
                ("simulate", "database"): [("QUIET", "N")],
                ("demo",): [("SIZE", "2048"), ("LENSES", "12"), ("SEED", "1"),
                            ("METHOD", "TREES")],
                ("grades",): [("QUIET", "N")]}

    def test_h_and_v(self):
        for command in self.COMMANDS:
            name = " ".join(command)
            proc = run_octarc(*command, "-h")
            self.assertEqual(proc.stderr, "", name)
            self.assertTrue(proc.stdout.startswith("Usage: octarc " + name), name)
            proc = run_octarc(*command, "-v")
            self.assertRegex(proc.stdout, r"^octarc %s version \S+\n$" % name)

    def test_d_and_dd_print_the_keys_with_their_defaults(self):
        for command in self.COMMANDS:
            name = " ".join(command)
            short = run_octarc(*command, "-d")
            full = run_octarc(*command, "-dd")
            self.assertTrue(short.stdout.startswith("# Configuration file written by octarc"),
                            name)
            full_keys = dict(dump_keys(full.stdout))
            short_keys = dump_keys(short.stdout)
            # octarc grades has three options: -o, --page, --quiet.
            self.assertGreater(len(short_keys), 2 if command == ("grades",) else 3, name)
            for key, value in short_keys:
                self.assertEqual(full_keys.get(key), value, "%s: %s" % (name, key))
            for key, value in self.DEFAULTS.get(command, []):
                self.assertEqual(full_keys.get(key), value, "%s: %s" % (name, key))
            # The -h flag is no key.
            self.assertNotIn("HELP", full_keys, name)

    def test_dp_lists_columns_or_says_there_are_none(self):
        for command, column in self.COLUMN.items():
            name = " ".join(command)
            proc = run_octarc(*command, "-dp", check=False)
            if column is None:
                self.assertEqual(proc.returncode, 1, name)
                self.assertEqual(proc.stdout, "", name)
                lines = proc.stderr.strip().splitlines()
                self.assertEqual(len(lines), 1, proc.stderr)
                self.assertIn("-dp", lines[0])
                self.assertIn("writes no catalog", lines[0])
            else:
                self.assertEqual(proc.returncode, 0, proc.stderr)
                self.assertIn(column, column_listing(proc.stdout), name)
                # A .param listing, never the configuration.
                self.assertNotIn("Configuration file", proc.stdout, name)
                self.assertTrue(all(line.startswith("#") for line in
                                    proc.stdout.splitlines()), name)

    def test_keys_and_long_options_make_the_same_simulation(self):
        def systems(*args):
            out = self.path("s%d.fits" % len(os.listdir(self.work)))
            run_octarc("simulate", "lenses", *args, out, "--threads", 1)
            with fits.open(out) as f:
                return f["LDAC_OBJECTS"].data.tobytes(), f["ARCS"].data.tobytes()

        options = systems("-n", 3, "--seed", 5, "--sampling", "plain", "--quiet", "-o")
        keys = systems("-COUNT", 3, "-SEED", 5, "-SAMPLING", "plain", "-QUIET", "Y",
                       "-OUTPUT")
        self.assertEqual(keys, options)
        # A key's value that starts with '-' is still its value, and the range check names it.
        proc = run_octarc("simulate", "field", "-OUTPUT", self.path("f.fits"), "-LENSES", -1,
                          check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertIn("--lenses", proc.stderr)
        # The last value of a key wins, as in SExtractor.
        proc = run_octarc("demo", "-SIZE", 0, "--size", 16, "-SIZE", -3, "-QUIET", "Y",
                          "--out", self.path("d"), check=False)
        self.assertEqual(proc.returncode, 1)
        self.assertIn("-3", proc.stderr)

    def test_unknown_keys_and_missing_c_files_of_the_simulations_are_refused(self):
        for command in (("simulate", "lenses"), ("simulate", "field"), ("demo",)):
            proc = run_octarc(*command, "-SIZ", 3, check=False)
            self.assertEqual(proc.returncode, 1)
            self.assertEqual(len(proc.stderr.strip().splitlines()), 1, proc.stderr)
            self.assertIn("-SIZ", proc.stderr)
            proc = run_octarc(*command, "-c", self.path("x.sex"), check=False)
            self.assertEqual(proc.returncode, 1)
            self.assertIn(self.path("x.sex"), proc.stderr)

    def test_a_dd_template_of_a_simulation_loads_back(self):
        # -dd > file, a key changed in it, -c file: the same tables as the long options give;
        # a key on the command line wins over the file's.
        def systems(*args):
            out = self.path("s%d.fits" % len(os.listdir(self.work)))
            run_octarc("simulate", "lenses", *args, "-o", out, "--threads", 1)
            with fits.open(out) as f:
                return f["LDAC_OBJECTS"].data.tobytes(), f["ARCS"].data.tobytes()

        template = run_octarc("simulate", "lenses", "-dd").stdout
        template = re.sub(r"(?m)^SAMPLING +importance", "SAMPLING plain", template)
        template = re.sub(r"(?m)^SEED +1 ", "SEED 7 ", template)
        path = self.path("lenses.sex")
        with open(path, "w") as f:
            f.write(template)
        self.assertIn("SAMPLING plain", template)
        expected = systems("-n", 3, "--seed", 5, "--sampling", "plain", "--quiet")
        self.assertEqual(systems("-c", path, "-n", 3, "--seed", 5, "--quiet"), expected)
        self.assertNotEqual(systems("-c", path, "-n", 3, "--quiet"), expected)  # SEED 7


class ConfigurationDumps(WorkDirTest):
    """-d and -dd: every key of the schema (SExtractor's keys, in SExtractor's order, and the
    README's octarc keys), and a dump loads back as a .sex file giving the same run."""

    def test_dd_lists_every_key(self):
        require_program("source-extractor")
        sex = [k for k, _ in dump_keys(subprocess.run(["source-extractor", "-dd"],
                                                      capture_output=True, text=True).stdout)]
        for command in ("measure", "detect"):
            ours = [k for k, _ in dump_keys(run_octarc(command, "-dd").stdout)]
            self.assertEqual(len(ours), len(set(ours)), "%s -dd repeats a key" % command)
            self.assertEqual(set(ours), set(sex) | readme_keys())
            self.assertEqual([k for k in ours if k in sex], sex, "SExtractor's order")

    def test_d_is_the_short_list_with_the_same_values(self):
        for command in ("measure", "detect"):
            full = dict(dump_keys(run_octarc(command, "-dd").stdout))
            short = dump_keys(run_octarc(command, "-d").stdout)
            self.assertGreater(len(short), 20)
            self.assertLess(len(short), len(full))
            for key, value in short:
                self.assertEqual(full.get(key), value, key)

    def run_detect(self, cwd, *config):
        param = write_param(os.path.join(cwd, "p.param"),
                            ["NUMBER", "THRESH_LEVEL", "X_IMAGE", "FLUX_ISO", "ARCNESS"])
        out = os.path.join(cwd, "out%d.ldac" % len(os.listdir(cwd)))
        proc = octarc_in(cwd, "detect", IMAGE, *config, "-PARAMETERS_NAME", param,
                         "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out)
        # No warning but SExtractor's own about a missing ./default.sex.
        self.assertNotIn("WARNING", proc.stderr.replace(
            "WARNING: default.sex not found, using internal defaults", ""))
        return out

    def test_dumps_load_back_to_the_defaults(self):
        # In a directory without default.sex, so that "no -c" means the built-in defaults.
        cwd = self.path("run")
        os.mkdir(cwd)
        reference = self.run_detect(cwd)
        for flag in ("-d", "-dd"):
            for command in ("measure", "detect"):
                dump = os.path.join(cwd, "dump%s_%s.sex" % (flag, command))
                with open(dump, "w") as f:
                    f.write(run_octarc(command, flag).stdout)
                out = self.run_detect(cwd, "-c", dump)
                self.assertEqual(objects_bytes(out), objects_bytes(reference), dump)
                self.assertEqual(imhead_cards(out), imhead_cards(reference), dump)


class ColumnList(WorkDirTest):
    """-dp: every column the README names, with SExtractor's description and unit for the
    SExtractor-named ones, and as a .param file (one "NAME # description [unit]" per line) it
    gives a catalog of exactly those columns with those units and descriptions."""

    def test_dp_lists_the_readme_columns(self):
        for command in ("measure", "detect"):
            listed = column_listing(run_octarc(command, "-dp").stdout)
            self.assertEqual(set(listed), readme_columns(), command)

    def test_sextractor_named_columns_carry_sextractors_description_and_unit(self):
        require_program("source-extractor")
        theirs = column_listing(subprocess.run(["source-extractor", "-dp"], capture_output=True,
                                               text=True).stdout)
        ours = column_listing(run_octarc("detect", "-dp").stdout)
        shared = [n for n in ours if n in theirs]
        self.assertGreater(len(shared), 35)
        for name in shared:
            self.assertEqual(ours[name], theirs[name], name)

    def test_the_listing_is_a_param_file_octarc_accepts(self):
        listed = column_listing(run_octarc("detect", "-dp").stdout)
        param = self.path("all.param")
        with open(param, "w") as f:
            for name, (description, unit) in listed.items():
                request = name + "(2)" if name == "VECTOR_ASSOC" else name
                f.write("%-24s # %s%s\n" % (request, description, " [%s]" % unit if unit else ""))
        assoc = self.path("assoc.txt")
        with open(assoc, "w") as f:
            f.write("1 101.3 100.6 17.5\n2 50.0 50.0 21.0\n")
        out = self.path("all.ldac")
        proc = run_octarc("detect", IMAGE, "-PARAMETERS_NAME", param, "-CATALOG_TYPE",
                          "FITS_LDAC", "-CATALOG_NAME", out, "-ASSOC_NAME", assoc,
                          "-ASSOC_PARAMS", "2,3", "-ASSOC_DATA", "1,4", "-ASSOC_RADIUS", "3")
        self.assertNotIn("unknown", proc.stderr)
        # No warning but SExtractor's own about a missing ./default.sex.
        self.assertNotIn("WARNING", proc.stderr.replace(
            "WARNING: default.sex not found, using internal defaults", ""))
        own = readme_columns() - set(column_listing(subprocess.run(
            ["source-extractor", "-dp"], capture_output=True, text=True).stdout)) \
            if shutil.which("source-extractor") else set()
        with fits.open(out) as f:
            table = f["LDAC_OBJECTS"]
            self.assertEqual(table.columns.names, list(listed))
            for i, name in enumerate(table.columns.names, start=1):
                # The TTYPE comment is the description, cut at column 80 as SExtractor cuts it;
                # octarc's own descriptions fit whole.
                comment = table.header.comments["TTYPE%d" % i]
                self.assertTrue(comment and listed[name][0].startswith(comment), name)
                if name in own:
                    self.assertEqual(comment, listed[name][0], name)
                self.assertEqual(table.header.get("TUNIT%d" % i, ""), listed[name][1], name)
            if own:
                self.assertIn("ARCNESS", own)
            self.assertTrue(table.columns["VECTOR_ASSOC"].format.startswith("2"))


class DefaultConfigFile(WorkDirTest):
    """Without -c, ./default.sex is read when it exists (as SExtractor does); -KEY value still
    wins over it, and with -c it is not read at all."""

    def setUp(self):
        super().setUp()
        self.cwd = self.path("run")
        os.mkdir(self.cwd)
        write_param(os.path.join(self.cwd, "p.param"), ["NUMBER", "THRESH_LEVEL"])
        with open(os.path.join(self.cwd, "default.sex"), "w") as f:
            f.write("CATALOG_NAME  from-default.ldac\nCATALOG_TYPE  FITS_LDAC\n"
                    "PARAMETERS_NAME p.param\nTHRESH_TYPE RELATIVE\nDETECT_LEVELS 3,7.5\n"
                    "FILTER N\n")

    def test_default_sex_is_read(self):
        octarc_in(self.cwd, "detect", IMAGE)
        out = os.path.join(self.cwd, "from-default.ldac")
        head = ldac_imhead(out)
        self.assertEqual(head["OCTNLEV"], 2)
        # The cards print 13 significant digits.
        self.assertAlmostEqual(head["OCTTH2"] / head["OCTTH1"], 2.5, delta=1e-11)
        self.assertAlmostEqual(head["OCTTH1"], 3.0 * head["SEXBKDEV"], delta=1e-11 * head["OCTTH1"])
        self.assertEqual(sorted(set(ldac_objects(out)[0]["THRESH_LEVEL"])), [1, 2])

    def test_command_line_wins_over_default_sex(self):
        octarc_in(self.cwd, "detect", IMAGE, "-DETECT_LEVELS", "4")
        head = ldac_imhead(os.path.join(self.cwd, "from-default.ldac"))
        self.assertEqual(head["OCTNLEV"], 1)
        self.assertAlmostEqual(head["OCTTH1"], 4.0 * head["SEXBKDEV"], delta=1e-11 * head["OCTTH1"])

    def test_c_replaces_default_sex(self):
        other = os.path.join(self.cwd, "other.sex")
        with open(other, "w") as f:
            f.write("CATALOG_NAME other.ldac\nCATALOG_TYPE FITS_LDAC\nPARAMETERS_NAME p.param\n")
        octarc_in(self.cwd, "detect", IMAGE, "-c", other)
        self.assertFalse(os.path.exists(os.path.join(self.cwd, "from-default.ldac")))
        head = ldac_imhead(os.path.join(self.cwd, "other.ldac"))
        defaults = dict(dump_keys(run_octarc("detect", "-dd").stdout))
        self.assertEqual(head["OCTNLEV"], int(defaults["DETECT_NLEVELS"]))


class FilterLookup(WorkDirTest):
    """A FILTER_NAME without a directory that is not in the working directory is looked up in
    params/ and then in /usr/share/source-extractor/; one with a directory is taken as it is."""

    def filtered(self, cwd, name, tag):
        path = os.path.join(cwd, "%s.filtered.fits" % tag)
        octarc_in(cwd, "detect", IMAGE, "-PARAMETERS_NAME",
                  write_param(os.path.join(cwd, "p.param"), ["NUMBER"]), "-CATALOG_TYPE",
                  "FITS_LDAC", "-CATALOG_NAME", os.path.join(cwd, "%s.ldac" % tag), "-FILTER", "Y",
                  "-FILTER_NAME", name, "-DETECT_NLEVELS", "1", "-CHECKIMAGE_TYPE",
                  "FILTERED,-BACKGROUND", "-CHECKIMAGE_NAME",
                  "%s,%s" % (path, os.path.join(cwd, "%s.sub.fits" % tag)))
        return fits.getdata(path), fits.getdata(os.path.join(cwd, "%s.sub.fits" % tag))

    def test_lookup_order(self):
        empty = self.path("empty")
        os.mkdir(empty)
        # Only in /usr/share/source-extractor: found there.
        by_name, _ = self.filtered(empty, "gauss_2.0_5x5.conv", "a")
        by_path, _ = self.filtered(empty, os.path.join(SEX_SHARE, "gauss_2.0_5x5.conv"), "b")
        np.testing.assert_array_equal(by_name, by_path)
        # default.conv from a directory without one: params/default.conv.
        by_name, _ = self.filtered(empty, "default.conv", "c")
        by_path, sub = self.filtered(empty, os.path.join(SOURCE_DIR, "params", "default.conv"),
                                     "d")
        np.testing.assert_array_equal(by_name, by_path)
        self.assertFalse(np.array_equal(by_name, sub))
        # A default.conv in the working directory comes first: here the identity mask.
        own = self.path("own")
        os.mkdir(own)
        with open(os.path.join(own, "default.conv"), "w") as f:
            f.write("CONV NORM\n0 0 0\n0 1 0\n0 0 0\n")
        filtered, sub = self.filtered(own, "default.conv", "e")
        np.testing.assert_array_equal(filtered, sub)

    def test_missing_filter_and_directory_names_are_not_looked_up(self):
        for name in ("no-such-mask.conv", os.path.join("sub", "gauss_2.0_5x5.conv")):
            out = self.path("x.ldac")
            proc = run_octarc("detect", IMAGE, "-FILTER", "Y", "-FILTER_NAME", name,
                              "-PARAMETERS_NAME", write_param(self.path("p.param"), ["NUMBER"]),
                              "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
                              "-VERBOSE_TYPE", "QUIET", check=False, cwd=self.work)
            self.assertNotEqual(proc.returncode, 0, name)
            lines = [l for l in proc.stderr.splitlines() if l.strip()]
            self.assertEqual(len(lines), 1, proc.stderr)
            self.assertIn(name, lines[0])
            self.assertFalse(os.path.exists(out))


PARAM = SEX_COLUMNS


def detect_one_level(work, image, tag, *extra):
    """`octarc detect` at one level, 3 sigma, FILTER N, with SEGMENTATION (one level: one
    image, as SExtractor's), BACKGROUND and -BACKGROUND check-images."""
    out = os.path.join(work, "%s.ldac" % tag)
    checks = {t: os.path.join(work, "%s.%s.fits" % (tag, n))
              for t, n in (("SEGMENTATION", "seg"), ("BACKGROUND", "bkg"), ("-BACKGROUND", "sub"))}
    run_octarc("detect", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
               "-PARAMETERS_NAME", write_param(os.path.join(work, "%s.param" % tag), PARAM),
               "-FILTER", "N", "-DETECT_NLEVELS", 1, "-DETECT_THRESH", 3, "-DETECT_MINAREA", 5,
               "-THRESH_TYPE", "RELATIVE", "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
               "-CHECKIMAGE_TYPE", ",".join(checks), "-CHECKIMAGE_NAME", ",".join(checks.values()),
               "-VERBOSE_TYPE", "QUIET", *extra)
    return out, checks


def sextractor_one_level(work, image, tag, *extra):
    param = write_param(os.path.join(work, "%s.sex.param" % tag), PARAM)
    return run_sextractor(image, work, tag, param, 3, ["-FILTER", "N", "-DETECT_MINAREA", "5",
                                                        "-THRESH_TYPE", "RELATIVE"] + list(extra),
                          ["SEGMENTATION"])


def plain_copy(work):
    """The example image without gzip (source-extractor reads no compressed file)."""
    path = os.path.join(work, "image.fits")
    with fits.open(IMAGE) as f:
        fits.PrimaryHDU(f[0].data.astype(np.float32), f[0].header).writeto(path)
    return path


class BackgroundTypes(WorkDirTest):
    """BACK_TYPE MANUAL and GLOBAL through `octarc detect`."""

    def setUp(self):
        super().setUp()
        self.image = plain_copy(self.work)

    def test_manual_background_is_sextractors(self):
        # MANUAL: the level is BACK_VALUE; the noise is still the median of the mesh RMS, as in
        # SExtractor, so the whole run is source-extractor's.
        extra = ["-BACK_TYPE", "MANUAL", "-BACK_VALUE", "97.5"]
        out, checks = detect_one_level(self.work, self.image, "octarc", *extra)
        cat, sex = sextractor_one_level(self.work, self.image, "sex", *extra)
        ours, theirs = ldac_imhead(out), ldac_imhead(cat)
        for key in ("SEXBKGND", "SEXBKDEV"):
            self.assertEqual(card_text(ours, key), card_text(theirs, key), key)
        # SExtractor forms its threshold in single precision (see test_detect_vs_sextractor).
        threshold = np.float32(theirs["SEXTHLD"])
        self.assertLessEqual(abs(np.float32(ours["SEXTHLD"]) - threshold), np.spacing(threshold))
        self.assertEqual(ours["OCTBKSRC"], "MANUAL")
        self.assertEqual(ours["OCTSGSRC"], "MESH_MEDIAN")
        image = fits.getdata(IMAGE).astype(np.float32)
        np.testing.assert_array_equal(fits.getdata(checks["-BACKGROUND"]),
                                      image - np.float32(97.5))
        mapping = label_correspondence(self, fits.getdata(checks["SEGMENTATION"]),
                                       fits.getdata(sex["SEGMENTATION"]), "MANUAL")
        rows, _ = ldac_objects(out)
        assert_rows_agree(self, rows, ldac_objects(cat)[0], mapping, "MANUAL")

    def test_global_background_is_the_clipped_level_and_rms(self):
        out, checks = detect_one_level(self.work, self.image, "octarc", "-BACK_TYPE", "GLOBAL")
        head = ldac_imhead(out)
        self.assertEqual(head["OCTBKSRC"], "GLOBAL")
        self.assertEqual(head["OCTSGSRC"], "CLIPPED_RMS")
        image = fits.getdata(IMAGE).astype(np.float32)
        # 3-sigma clipping about the median, population standard deviation, to convergence; the
        # level is SExtractor's mode estimate 2.5 median - 1.5 mean unless the two differ by
        # 0.3 sigma or more (then the median).
        mean, median, std = sigma_clipped_stats(image[np.isfinite(image)].astype(float),
                                                sigma=3, maxiters=100, cenfunc="median",
                                                stdfunc="std")
        level = 2.5 * median - 1.5 * mean if abs(mean - median) < 0.3 * std else median
        # Sums in another order than numpy's: a few ulps, so 13 printed digits may differ in
        # the last one.
        self.assertAlmostEqual(head["SEXBKGND"], level, delta=1e-12 * level)
        self.assertAlmostEqual(head["SEXBKDEV"], std, delta=1e-12 * std)
        self.assertAlmostEqual(head["OCTTH1"], 3.0 * std, delta=1e-12 * std)
        np.testing.assert_array_equal(fits.getdata(checks["-BACKGROUND"]),
                                      image - np.float32(head["SEXBKGND"]))
        np.testing.assert_array_equal(fits.getdata(checks["BACKGROUND"]),
                                      np.full(image.shape, np.float32(head["SEXBKGND"])))


class GainAndOrigins(WorkDirTest):
    """The gain: the input catalog's SEXGAIN, else the header keyword GAIN_KEY names, else
    GAIN; and the cards naming where the background (OCTBKSRC) and the noise (OCTSGSRC) came
    from, for each origin, with the values taken from there."""

    def setUp(self):
        super().setUp()
        self.image = plain_copy(self.work)
        fits.setval(self.image, "MYGAIN", value=2.5, comment="another gain keyword")  # GAIN is 4

    def test_header_keyword_then_gain_as_source_extractor(self):
        require_program("source-extractor")
        for tag, args, gain in (("default", ["-GAIN", "9"], 4.0),
                                ("mygain", ["-GAIN_KEY", "MYGAIN", "-GAIN", "9"], 2.5),
                                ("absent", ["-GAIN_KEY", "NO_SUCH_KEY", "-GAIN", "9"], 9.0)):
            out, checks = detect_one_level(self.work, self.image, tag, *args)
            cat, sex = sextractor_one_level(self.work, self.image, "sex" + tag, *args)
            self.assertEqual(ldac_imhead(out)["SEXGAIN"], gain, tag)
            self.assertEqual(ldac_imhead(cat)["SEXGAIN"], gain, tag)
            # FLUXERR_ISO = sqrt(A sigma^2 + F / gain): the gain used is SExtractor's.
            mapping = label_correspondence(self, fits.getdata(checks["SEGMENTATION"]),
                                           fits.getdata(sex["SEGMENTATION"]), tag)
            assert_rows_agree(self, ldac_objects(out)[0], ldac_objects(cat)[0], mapping, tag)

    def test_input_catalog_gain_wins(self):
        # A SExtractor run whose gain (6) is neither the header's GAIN nor MYGAIN.
        extra = ["-GAIN_KEY", "NO_SUCH_KEY", "-GAIN", "6"]
        cat, sex = run_sextractor(self.image, self.work, "sex",
                                  write_param(self.path("sex.param"), PARAM), 3,
                                  ["-FILTER", "N", "-DETECT_MINAREA", "5"] + extra,
                                  ["SEGMENTATION", "BACKGROUND"])
        self.assertEqual(ldac_imhead(cat)["SEXGAIN"], 6.0)
        out = self.path("measure.ldac")
        run_octarc("measure", self.image, "-PARAMETERS_NAME", write_param(self.path("o.param"),
                                                                          PARAM),
                   "-SEGMENTATION_NAME", sex["SEGMENTATION"], "-INPUT_CATALOG", cat,
                   "-BACKGROUND_NAME", sex["BACKGROUND"], "-APPEND_COLUMNS", "N",
                   "-GAIN_KEY", "MYGAIN", "-GAIN", "9", "-FILTER", "N",
                   "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out, "-VERBOSE_TYPE", "QUIET")
        head = ldac_imhead(out)
        self.assertEqual(head["SEXGAIN"], 6.0)
        ours, theirs = ldac_objects(out)[0], ldac_objects(cat)[0]
        np.testing.assert_array_equal(ours["NUMBER"], theirs["NUMBER"])
        assert_float_columns_agree(ours, theirs, "FLUXERR_ISO with the catalog's gain")

    def measure(self, tag, *args):
        out = self.path("%s.ldac" % tag)
        run_octarc("measure", self.image, "-PARAMETERS_NAME",
                   write_param(self.path("m.param"), ["NUMBER", "FLUX_ISO"]),
                   "-SEGMENTATION_NAME", self.sex_checks["SEGMENTATION"], "-FILTER", "N",
                   "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out, "-VERBOSE_TYPE", "QUIET",
                   *args)
        return ldac_imhead(out)

    def test_every_origin_of_background_and_noise(self):
        param = write_param(self.path("sex.param"), ["NUMBER"])
        cat, self.sex_checks = run_sextractor(self.image, self.work, "sex", param, 3,
                                              ["-FILTER", "N", "-BACK_SIZE", "64"],
                                              ["SEGMENTATION", "BACKGROUND", "BACKGROUND_RMS"])
        sex_head = ldac_imhead(cat)

        def sorted_median(path):
            # The median of a map: the middle value of its finite pixels, the upper one of the
            # two for an even count.
            values = np.sort(fits.getdata(path)[np.isfinite(fits.getdata(path))].ravel())
            return float(values[len(values) // 2])

        cases = {
            # tag: (arguments, OCTBKSRC, OCTSGSRC, SEXBKGND, SEXBKDEV); None = source-extractor's
            # card, compared as printed.
            "auto": ([], "AUTO", "MESH_MEDIAN", None, None),
            "manual": (["-BACK_TYPE", "MANUAL", "-BACK_VALUE", "101.25"], "MANUAL",
                       "MESH_MEDIAN", 101.25, None),
            "map": (["-BACKGROUND_NAME", self.sex_checks["BACKGROUND"]], "CHECKIMAGE",
                    "MESH_MEDIAN", sorted_median(self.sex_checks["BACKGROUND"]), None),
            "rms map": (["-BACKGROUND_RMS_NAME", self.sex_checks["BACKGROUND_RMS"]], "AUTO",
                        "CHECKIMAGE", None, sorted_median(self.sex_checks["BACKGROUND_RMS"])),
            "catalog": (["-INPUT_CATALOG", cat, "-APPEND_COLUMNS", "N", "-BACK_TYPE", "MANUAL",
                         "-BACK_VALUE", "55", "-BACKGROUND_RMS_NAME",
                         self.sex_checks["BACKGROUND_RMS"]], "CATALOG", "CATALOG", None, None),
        }
        for tag, (args, bksrc, sgsrc, level, sigma) in cases.items():
            head = self.measure(tag.replace(" ", "_"), *args)
            self.assertEqual(head["OCTBKSRC"], bksrc, tag)
            self.assertEqual(head["OCTSGSRC"], sgsrc, tag)
            if level is None:
                self.assertEqual(card_text(head, "SEXBKGND"), card_text(sex_head, "SEXBKGND"),
                                 tag)
            else:
                self.assertEqual(card_text(head, "SEXBKGND"), "%.12E" % level, tag)
            if sigma is None:
                self.assertEqual(card_text(head, "SEXBKDEV"), card_text(sex_head, "SEXBKDEV"),
                                 tag)
            else:
                self.assertEqual(card_text(head, "SEXBKDEV"), "%.12E" % sigma, tag)
            self.assertEqual(head["SEXGAIN"], 4.0, tag)   # the header's GAIN


if __name__ == "__main__":
    unittest.main()


class ExpressionKeys(WorkDirTest):
    """Expression keys reach muparser as written, '=' included, from the command line and from
    a .sex file; the search refuses them before it reads the grid, so a missing grid tells an
    accepted expression from a refused one."""

    def search_error(self, *args):
        proc = run_octarc("search", IMAGE, "-GRID_NAME", self.path("no.grid.fits"), *args,
                          check=False, cwd=self.work)
        self.assertNotEqual(proc.returncode, 0)
        return proc.stderr

    def test_comparisons_with_equals_are_kept(self):
        for cut in ("ARCNESS >= 0.1", "ARCNESS <= 0.15", "FLAGS == 0", "FLAGS != 4"):
            err = self.search_error("-SEARCH_SPACE", "X: " + cut)
            self.assertNotIn("cannot parse", err)
            self.assertIn("no.grid.fits", err)  # got past the expressions
            # The text muparser is given, shown by its own error message.
            err = self.search_error("-SEARCH_SPACE", "X: %s &&" % cut)
            self.assertIn("cannot parse \"%s &&\"" % cut, err)
        sex = os.path.join(self.work, "x.sex")
        with open(sex, "w") as f:
            f.write("SEARCH_SPACE A: ARCNESS >= 0.1 &&   # a comment\n")
        self.assertIn("cannot parse \"ARCNESS >= 0.1 &&\"", self.search_error("-c", sex))

    def test_plus_equals_and_assignment_are_parse_errors(self):
        err = self.search_error("-SEARCH_SPACE", "X: E_IMAGE += 1")
        self.assertIn("SEARCH_SPACE search space 'X': cannot parse \"E_IMAGE += 1\"", err)
        err = self.search_error("-SEARCH_SPACE", "X: FLAGS = 0")
        self.assertIn("'=' assigns a value; compare with '=='", err)

    def test_colour_cut_of_a_lone_comma_is_refused(self):
        err = self.search_error("-COLOUR_CUT", " ,")
        self.assertIn("COLOUR_CUT: a comma but no band and no MAX", err)


class CommandLineHints(WorkDirTest):
    def test_unknown_key_suggests_the_nearest(self):
        proc = run_octarc("detect", IMAGE, "-DETECT_TRESH", "3", check=False, cwd=self.work)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("'-DETECT_TRESH': unknown keyword (did you mean -DETECT_THRESH?)",
                      proc.stderr)

    def test_two_dashes_are_refused(self):
        proc = run_octarc("detect", IMAGE, "--DETECT_THRESH", "3", check=False, cwd=self.work)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("'--DETECT_THRESH': keys take one dash, as in SExtractor (-DETECT_THRESH)",
                      proc.stderr)

    def test_full_verbosity_times_to_the_hundredth(self):
        proc = run_octarc("detect", IMAGE, "-VERBOSE_TYPE", "FULL", "-CATALOG_NAME",
                          self.path("t.cat"), cwd=self.work)
        times = re.findall(r"^> Time: .* (\S+) s$", proc.stderr, re.M)
        self.assertTrue(times, proc.stderr)
        for t in times:
            self.assertRegex(t, r"^\d+\.\d\d$")
