"""octarc run in an empty directory, as SExtractor users run it: without -c and without
./default.sex, SExtractor's warning and the built-in defaults; without PARAMETERS_NAME and
./default.param, the shipped column list with a warning; a PARAMETERS_NAME that names a missing
file is an error naming it."""
import os
import shutil
import subprocess
import unittest

from astropy.io import fits

from octarc_testlib import (OCTARC, SEX_SHARE, SOURCE_DIR, WorkDirTest, param_names, run_octarc,
                            write_param)

IMAGE = os.path.join(SOURCE_DIR, "testdata", "example.fits.gz")
SHIPPED_PARAM = os.path.normpath(os.path.join(os.path.dirname(OCTARC), "..", "share", "octarc",
                                              "octarc.param"))


def ascii_head_names(path):
    with open(path) as f:
        return [line.split()[2] for line in f if line.startswith("#")]


class EmptyDirectory(WorkDirTest):

    def warnings_of(self, stderr):
        return [line for line in stderr.splitlines() if line.startswith("WARNING")]

    def test_without_default_sex_and_default_param(self):
        # SExtractor's own warning, from source-extractor run in an empty directory.
        sex_dir = self.path("sex")
        os.mkdir(sex_dir)
        proc = subprocess.run(["source-extractor", IMAGE], cwd=sex_dir, capture_output=True,
                              text=True)
        theirs = [line.lstrip("> ").strip() for line in proc.stderr.splitlines()
                  if "default.sex" in line]
        self.assertEqual(theirs, ["WARNING: default.sex not found, using internal defaults"])

        run_dir = self.path("run")
        os.mkdir(run_dir)
        proc = run_octarc("detect", IMAGE, cwd=run_dir)
        self.assertEqual(self.warnings_of(proc.stderr),
                         theirs + ["WARNING: default.param not found, using the shipped column "
                                   "list " + SHIPPED_PARAM])
        # The built-in defaults (SExtractor's CATALOG_NAME test.cat, CATALOG_TYPE ASCII_HEAD)
        # with the shipped columns.
        self.assertEqual(os.listdir(run_dir), ["test.cat"])
        self.assertEqual(ascii_head_names(os.path.join(run_dir, "test.cat")),
                         param_names(SHIPPED_PARAM))
        # The same for measure.
        seg = os.path.join(SOURCE_DIR, "testdata", "example.seg1.fits.gz")
        proc = run_octarc("measure", IMAGE, "-SEGMENTATION_NAME", seg, "-CATALOG_NAME", "m.cat",
                          cwd=run_dir)
        self.assertEqual(len(self.warnings_of(proc.stderr)), 2, proc.stderr)
        self.assertEqual(ascii_head_names(os.path.join(run_dir, "m.cat")),
                         param_names(SHIPPED_PARAM))

    def test_quiet_runs_do_not_warn(self):
        proc = run_octarc("detect", IMAGE, "-VERBOSE_TYPE", "QUIET", cwd=self.work)
        self.assertEqual(proc.stderr, "")

    def test_files_of_the_working_directory_are_used_without_warning(self):
        shutil.copy(os.path.join(SEX_SHARE, "default.sex"), self.path("default.sex"))
        write_param(self.path("default.param"), ["NUMBER", "X_IMAGE", "ARCNESS"])
        proc = run_octarc("detect", IMAGE, "-CATALOG_NAME", "own.cat", cwd=self.work)
        self.assertEqual(self.warnings_of(proc.stderr), [])
        self.assertEqual(ascii_head_names(self.path("own.cat")), ["NUMBER", "X_IMAGE", "ARCNESS"])

    def test_missing_parameters_name_given_is_an_error(self):
        for args in (["-PARAMETERS_NAME", "nothere.param"],
                     ["-PARAMETERS_NAME", os.path.join(self.work, "sub", "nothere.param")]):
            proc = run_octarc("detect", IMAGE, *args, "-CATALOG_NAME", "x.cat", cwd=self.work,
                              check=False)
            self.assertNotEqual(proc.returncode, 0)
            lines = [line for line in proc.stderr.splitlines() if line.strip()]
            self.assertEqual(len(lines), 1, proc.stderr)
            self.assertIn("nothere.param", lines[0])
            self.assertIn("PARAMETERS_NAME", lines[0])
            self.assertEqual(os.listdir(self.work), [])

    def test_parameters_name_in_a_config_file_is_found_among_the_shipped_files(self):
        # octarc.sex names PARAMETERS_NAME octarc.param without a directory: run from anywhere,
        # it is the shipped file, as FILTER_NAME is.
        sex = os.path.join(os.path.dirname(SHIPPED_PARAM), "octarc.sex")
        proc = run_octarc("detect", IMAGE, "-c", sex, "-CATALOG_NAME", "s.ldac", cwd=self.work)
        self.assertEqual(self.warnings_of(proc.stderr), [])
        self.assertEqual(fits.getdata(self.path("s.ldac"), 2).columns.names,
                         param_names(SHIPPED_PARAM))


if __name__ == "__main__":
    unittest.main()
