"""`octarc batch -TASK MEASURE` end to end: three tiles cut from the two-band example's r image
(testdata/), each run through source-extractor for its SEGMENTATION check-image and FITS-LDAC
catalog; the batch's catalog of each tile equals, column by column and card by card, what
`octarc measure` writes for the same tile (appended and new); the appended catalog keeps every
column of source-extractor's as it was; a run killed after its first tile, then the same command
again, redoes only the tiles the journal does not hold; bad manifest rows are refused naming
the manifest's line, with nothing written."""
import fcntl
import os
import shutil
import subprocess
import tempfile
import time
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (OCTARC, SEX_SHARE, SOURCE_DIR, WorkDirTest, mpi_env,
                            require_program, run_octarc, run_sextractor, write_param)
from mpi_ranks import journal  # noqa: E402  (scripts/, on octarc_testlib's path)

IMAGE = os.path.join(SOURCE_DIR, "testdata", "multiband.r.fits.gz")
# Three 160 x 160 tiles overlapping by 20 pixels: (x0, y0) of each, 0-based.
TILE_ORIGINS = [(0, 0), (140, 0), (70, 140)]
TILE_SIDE = 160
SEX_COLUMNS = ["NUMBER", "X_IMAGE", "Y_IMAGE", "A_IMAGE", "B_IMAGE", "ISOAREA_IMAGE",
               "FLUX_APER(2)", "FLAGS", "X_WORLD", "Y_WORLD"]
OCTARC_COLUMNS = ["NUMBER", "X_IMAGE", "X2_IMAGE", "Y2_IMAGE", "FLUX_ISO", "ARCNESS", "ARC_SIDE",
                  "OCT_FLAGS", "THRESH_LEVEL"]
PURE = ["-FILTER", "N", "-DETECT_MINAREA", "5", "-BACK_TYPE", "AUTO", "-PHOT_APERTURES", "5,10"]
# The LDAC_IMHEAD cards of a new catalog that differ from run to run.
RUN_OWN_CARDS = ("SEXELAPS", "SEXDATE", "SEXTIME")
# The same configuration for `octarc measure` and the batch.
CONFIG = ["-c", os.path.join(SEX_SHARE, "default.sex"), "-FILTER", "N", "-NTHREADS", "1"]


def cut_tiles(directory):
    """The tiles as FITS files, their WCS moved with them. Returns their paths."""
    with fits.open(IMAGE) as f:
        data, header = f[0].data, f[0].header
        paths = []
        for k, (x0, y0) in enumerate(TILE_ORIGINS):
            h = header.copy()
            h["CRPIX1"] -= x0
            h["CRPIX2"] -= y0
            path = os.path.join(directory, "tile%d.fits" % (k + 1))
            fits.PrimaryHDU(data[y0:y0 + TILE_SIDE, x0:x0 + TILE_SIDE], h).writeto(path)
            paths.append(path)
    return paths


def hdus(path):
    """Every HDU of a FITS file: (header cards but the checksums, {column: values} or None)."""
    out = []
    with fits.open(path) as f:
        for hdu in f:
            cards = [c.image for c in hdu.header.cards if c.keyword not in ("CHECKSUM", "DATASUM")]
            columns = None
            if isinstance(hdu, fits.BinTableHDU):
                columns = {c.name: np.array(hdu.data[c.name]) for c in hdu.columns}
                if "Field Header Card" in columns:
                    # The time a run took and its date are its own.
                    columns["Field Header Card"] = np.array(
                        [[str(c) for c in np.ravel(row) if not str(c).startswith(RUN_OWN_CARDS)]
                         for row in hdu.data["Field Header Card"]])
            out.append((cards, columns))
    return out


class MeasureTiles(WorkDirTest):
    """The tiles, their source-extractor outputs and `octarc measure`'s catalogs of each, made
    once for the test case in its own folder."""

    @classmethod
    def setUpClass(cls):
        require_program("source-extractor")
        cls.data = tempfile.mkdtemp(prefix="octarc-test-tiles-")
        cls.param = write_param(os.path.join(cls.data, "octarc.param"), OCTARC_COLUMNS)
        sex_param = write_param(os.path.join(cls.data, "sex.param"), SEX_COLUMNS)
        cls.tiles = []
        for image in cut_tiles(cls.data):
            tag = os.path.basename(image)[:-5]
            cat, checks = run_sextractor(image, cls.data, tag, sex_param, 3.0, PURE,
                                         ("SEGMENTATION",))
            cls.tiles.append((tag, image, checks["SEGMENTATION"], cat))
        cls.manifest = os.path.join(cls.data, "tiles.csv")
        with open(cls.manifest, "w") as f:
            f.write("image,segmentation,catalog\n")
            for _, image, seg, cat in cls.tiles:
                f.write("%s, %s, %s\n" % tuple(os.path.basename(p) for p in (image, seg, cat)))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.data, ignore_errors=True)

    def measure(self, tile, append):
        """`octarc measure`'s catalog of a tile (APPEND_COLUMNS Y or N)."""
        tag, image, seg, cat = tile
        output = self.path("%s.%s.ldac" % (tag, append))
        run_octarc("measure", image, *CONFIG, "-PARAMETERS_NAME", self.param,
                   "-SEGMENTATION_NAME", seg, "-INPUT_CATALOG", cat, "-CATALOG_NAME", output,
                   "-APPEND_COLUMNS", append, "-CATALOG_TYPE", "FITS_LDAC",
                   "-VERBOSE_TYPE", "QUIET")
        return output

    def batch_args(self, out, *more):
        return ["batch", self.manifest, "-TASK", "MEASURE", *CONFIG, "-PARAMETERS_NAME",
                self.param, "-OUTPUT_DIR", out, *more]

    def batch(self, out, *more, check=True):
        return run_octarc(*self.batch_args(out, *more), check=check)

    def assert_same_file(self, expected, got):
        a, b = hdus(expected), hdus(got)
        self.assertEqual(len(a), len(b), got)
        for (cards_a, cols_a), (cards_b, cols_b) in zip(a, b):
            self.assertEqual(cards_a, cards_b, got)
            self.assertEqual(cols_a is None, cols_b is None, got)
            if cols_a is None:
                continue
            self.assertEqual(list(cols_a), list(cols_b), got)
            for name in cols_a:
                x, y = cols_a[name], cols_b[name]
                same = (np.array_equal(x, y, equal_nan=True) if x.dtype.kind == "f"
                        else np.array_equal(x, y))
                self.assertTrue(same, "%s: column %s" % (got, name))


class BatchMeasure(MeasureTiles):
    def test_appended_catalogs_are_those_of_octarc_measure(self):
        out = self.path("survey")
        proc = self.batch(out)
        self.assertIn("3 done, 0 failed, 0 skipped", proc.stdout)
        summary = open(os.path.join(out, "summary.txt")).read()
        for tile in self.tiles:
            tag, image, seg, cat = tile
            got = os.path.join(out, "tiles", tag, os.path.basename(cat))
            self.assert_same_file(self.measure(tile, "Y"), got)
            # source-extractor's columns, every value as it wrote them.
            with fits.open(cat) as a, fits.open(got) as b:
                for c in a["LDAC_OBJECTS"].columns:
                    x, y = a["LDAC_OBJECTS"].data[c.name], b["LDAC_OBJECTS"].data[c.name]
                    self.assertTrue(np.array_equal(x, y), c.name)
                rows = len(a["LDAC_OBJECTS"].data)
            self.assertGreater(rows, 0, tag)
            # The summary: the rows of each tile (those of source-extractor's catalog).
            self.assertRegex(summary, r"\n  %s: %d rows, [0-9.]+ s \(run 1, rank 0\), "
                             r"tiles/%s/%s\n" % (tag, rows, tag, os.path.basename(cat)))
        self.assertEqual(sorted(os.listdir(out)),
                         [".octarc-batch", "claims", "configuration.txt", "journal.txt",
                          "summary.txt", "tiles"])
        # Run again: nothing to do, the same catalogs.
        proc = self.batch(out)
        self.assertIn("0 done, 0 failed, 3 skipped", proc.stdout)



class BatchMeasureRanks(MeasureTiles):
    def test_new_catalogs_on_two_ranks_are_those_of_octarc_measure(self):
        require_program("mpirun")
        out = self.path("survey")
        subprocess.run(["mpirun", "--oversubscribe", "-np", "2", OCTARC,
                        *self.batch_args(out, "-APPEND_COLUMNS", "N", "-CATALOG_TYPE",
                                         "FITS_LDAC")],
                       check=True, capture_output=True, env=mpi_env())
        for tile in self.tiles:
            self.assert_same_file(self.measure(tile, "N"),
                                  os.path.join(out, "tiles", tile[0], tile[0] + ".cat"))
        self.assertEqual({e[3] for e in journal(out) if e[2] == "done"},
                         {t[0] for t in self.tiles})


class BatchMeasureResume(MeasureTiles):
    def killed_run(self, out):
        """A batch killed once it has journaled a tile: as soon as the journal has a `done`
        line, the test takes the journal's lock, so the run cannot journal another, and kills
        it. Returns the tiles it journaled; None when it journaled every tile first."""
        proc = subprocess.Popen([OCTARC, *self.batch_args(out)], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        path = os.path.join(out, "journal.txt")
        lock = None
        deadline = time.time() + 60
        while time.time() < deadline and proc.poll() is None:
            if os.path.exists(path) and any(e[2] == "done" for e in journal(out)):
                lock = open(path, "a")
                fcntl.flock(lock, fcntl.LOCK_EX)
                break
            time.sleep(0.0002)
        proc.kill()
        proc.wait()
        if lock:
            lock.close()
        done = {e[3] for e in journal(out) if e[2] == "done"}
        return done if len(done) < len(self.tiles) else None

    def test_killed_run_then_rerun_redoes_only_the_unfinished_tiles(self):
        # The tiles take milliseconds each: a run that journals all three before the lock is
        # taken is tried again in a new OUTPUT_DIR.
        for attempt in range(20):
            out = self.path("survey%d" % attempt)
            first = self.killed_run(out)
            if first is not None:
                break
        self.assertIsNotNone(first, "every run journaled all its tiles before it was killed")
        self.assertGreater(len(first), 0)
        self.assertFalse(os.path.exists(os.path.join(out, "summary.txt")))

        rerun = self.batch(out)
        self.assertIn("%d done, 0 failed, %d skipped" % (3 - len(first), len(first)),
                      rerun.stdout)
        events = journal(out)
        second = {e[3] for e in events if e[2] == "done" and e[0] == "2"}
        self.assertEqual(second, {t[0] for t in self.tiles} - first)
        for tile in self.tiles:
            self.assert_same_file(self.measure(tile, "Y"),
                                  os.path.join(out, "tiles", tile[0], os.path.basename(tile[3])))
        leftovers = [n for _, dirs, files in os.walk(out) for n in dirs + files if ".tmp." in n]
        self.assertEqual(leftovers, [])


class BatchMeasureBadInput(MeasureTiles):
    def assert_refused(self, proc, *fragments):
        """One line of error (after the configuration's warnings), naming `fragments`; no
        OUTPUT_DIR."""
        self.assertNotEqual(proc.returncode, 0)
        lines = [l for l in proc.stderr.strip().splitlines() if not l.startswith("WARNING: ")]
        self.assertEqual(len(lines), 1, proc.stderr)
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(self.path("out")))

    def write_manifest(self, text):
        """A manifest beside the tiles (their paths relative to it)."""
        with open(self.manifest_path, "w") as f:
            f.write(text)

    def setUp(self):
        super().setUp()
        self.manifest_path = os.path.join(self.data, "bad.csv")

    def batch(self, out, *more, check=True):
        return run_octarc("batch", self.manifest_path, "-TASK", "MEASURE", *CONFIG,
                          "-PARAMETERS_NAME", self.param, "-OUTPUT_DIR", out, *more, check=check)

    def test_bad_rows_are_named_and_nothing_is_written(self):
        tag, image, seg, cat = (os.path.basename(p) for p in self.tiles[0])
        good = "%s,%s,%s\n" % (image, seg, cat)
        out = self.path("out")
        self.write_manifest(good + "%s,%s\n" % (image, seg))
        self.assert_refused(self.batch(out, check=False), "bad.csv:2:", "2 field(s)",
                            "IMAGE SEGMENTATION CATALOG [WEIGHT]")
        self.write_manifest(good + "%s %s %s - x\n" % (image, seg, cat))
        self.assert_refused(self.batch(out, check=False), "bad.csv:2:", "5 field(s)")
        self.write_manifest("# tiles\n" + good + "tile2.fits, missing.seg.fits, %s\n" % cat)
        self.assert_refused(self.batch(out, check=False), "bad.csv:3:",
                            "segmentation image", "missing.seg.fits", "no such file")
        self.write_manifest(good + "tile2.fits, %s, nothing.ldac\n" % seg)
        self.assert_refused(self.batch(out, check=False), "bad.csv:2:", "catalog",
                            "nothing.ldac", "no such file")
        self.write_manifest(good)
        self.assert_refused(self.batch(out, "-SEGMENTATION_NAME", seg, check=False),
                            "SEGMENTATION_NAME", "manifest")
        self.assert_refused(
            run_octarc("batch", os.path.join(self.data, "tile*.fits"), "-TASK", "MEASURE",
                       "-OUTPUT_DIR", out, check=False), "not a glob")

    def test_check_images_of_the_sextractor_configuration_warn(self):
        # The .sex file of the runs that made the segmentation images asks for them: said once,
        # the tiles measured; on the command line the key is refused.
        tag, image, seg, cat = (os.path.basename(p) for p in self.tiles[0])
        self.write_manifest("%s,%s,%s\n" % (image, seg, cat))
        sex = self.path("survey.sex")
        with open(os.path.join(SEX_SHARE, "default.sex")) as f:
            text = f.read()
        with open(sex, "w") as f:
            f.write(text + "\nCHECKIMAGE_TYPE SEGMENTATION\nCHECKIMAGE_NAME check.fits\n")
        out = self.path("survey")
        proc = run_octarc("batch", self.manifest_path, "-TASK", "MEASURE", "-c", sex,
                          "-FILTER", "N", "-PARAMETERS_NAME", self.param, "-OUTPUT_DIR", out)
        self.assertRegex(proc.stderr, r"WARNING: .*survey\.sex:\d+: CHECKIMAGE_TYPE is not "
                         r"used by a batch, which writes no check-images")
        self.assertEqual([e[3] for e in journal(out) if e[2] == "done"], [tag])
        self.assert_refused(self.batch(self.path("other"), "-CHECKIMAGE_TYPE", "SEGMENTATION",
                                       check=False),
                            "CHECKIMAGE_TYPE: a batch writes no check-images")
        self.assertFalse(os.path.exists(self.path("other")))

    def test_keys_of_the_search_warn_and_a_search_directory_is_refused(self):
        tag, image, seg, cat = (os.path.basename(p) for p in self.tiles[0])
        self.write_manifest("%s,%s,%s\n" % (image, seg, cat))
        proc = self.batch(self.path("survey"), "-MATCH_RADIUS", "2", "-STAMPS", "N")
        for key in ("MATCH_RADIUS", "STAMPS"):
            self.assertIn("WARNING: command line: -%s is not used with TASK MEASURE (a key of "
                          "TASK SEARCH; setting it has no effect)" % key, proc.stderr)
        # A measuring batch's OUTPUT_DIR is no search's.
        images = os.path.join(self.data, "images.txt")
        with open(images, "w") as f:
            f.write(image + "\n")
        proc = run_octarc("batch", images, "-c", os.path.join(SOURCE_DIR, "params", "octarc.sex"),
                          "-GRID_NAME", os.path.join(SOURCE_DIR, "params", "demo.grid.fits"),
                          "-OUTPUT_DIR", self.path("survey"), check=False)
        self.assertNotEqual(proc.returncode, 0)
        self.assertEqual(proc.stderr.strip().splitlines()[-1],
                         "octarc batch: error: OUTPUT_DIR %s was made with TASK MEASURE, this run "
                         "has SEARCH: its tiles would mix two tasks; give -RESTART Y to set them "
                         "aside (into %s/earlier-N) and start over, or another OUTPUT_DIR"
                         % (self.path("survey"), self.path("survey")))


if __name__ == "__main__":
    unittest.main()
