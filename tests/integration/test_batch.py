"""`octarc batch` end to end on eight overlapping tiles cut from one simulated field: the survey
catalog is the same on 1, 2 and 4 MPI ranks and as a job array; its duplicates and its area are
worked out again here (astropy) from the tiles' own catalogs and the whole field's search; a
rank killed with SIGKILL, then the same command again, gives the uninterrupted run's outputs;
a corrupt tile fails alone; bad manifests are refused naming the line. `simulate lenses` gives
the same data on 1 and 4 ranks."""
import fcntl
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import numpy as np
from astropy.coordinates import SkyCoord
from astropy.io import fits
from astropy.table import Table
from astropy.wcs import WCS
import astropy.units as u

from octarc_testlib import (OCTARC, SOURCE_DIR, WorkDirTest, fitsverify_errors, ldac_imhead,
                            mpi_env, require_program, run_octarc)

# scripts/mpi_ranks.py, on octarc_testlib's path
from mpi_ranks import journal, rank_process, temporaries  # noqa: E402

SEX = os.path.join(SOURCE_DIR, "params", "octarc.sex")
GRID = os.path.join(SOURCE_DIR, "params", "demo.grid.fits")
FIELD_SIZE = 2400
# Four columns and two rows of tiles, 700 x 1300 pixels, overlapping by 133 to 200 pixels.
TILE_X0 = (0, 567, 1133, 1700)
TILE_Y0 = (0, 1100)
TILE_W, TILE_H = 700, 1300


def mpi_command(ranks, *args):
    return ["mpirun", "--oversubscribe", "-np", str(ranks), OCTARC] + [str(a) for a in args]


def run_mpi(ranks, *args, check=True, cwd=None):
    require_program("mpirun")
    proc = subprocess.run(mpi_command(ranks, *args), capture_output=True, text=True, cwd=cwd,
                          env=mpi_env())
    if check and proc.returncode != 0:
        raise AssertionError("mpirun -np %d octarc %s failed (%d):\n%s\n%s"
                             % (ranks, " ".join(map(str, args)), proc.returncode, proc.stdout,
                                proc.stderr))
    return proc


def table_data(path, hdu="LDAC_OBJECTS"):
    with fits.open(path) as f:
        return {c.name: np.array(f[hdu].data[c.name]) for c in f[hdu].columns}, f[hdu].header.copy()


def assert_same_tables(test, a, b):
    da, ha = table_data(a)
    db, hb = table_data(b)
    test.assertEqual(list(da), list(db))
    for name in da:
        x, y = da[name], db[name]
        if x.dtype.kind == "f":
            test.assertTrue(np.array_equal(x, y, equal_nan=True), name)
        else:
            test.assertTrue(np.array_equal(x, y), name)
    for key in ("NCANDID", "NTILECND", "NDUPLIC", "SRCHAREA"):
        if key in ha:
            test.assertEqual(ha[key], hb[key], key)


def read_text(path):
    with open(path) as f:
        return f.read()


def make_tiles(directory):
    """The field, its eight tiles (image and weight, WCS shifted) and their manifest."""
    field = os.path.join(directory, "field.fits")
    run_octarc("simulate", "field", "-o", field, "--size", FIELD_SIZE, "--lenses", "40",
               "--min-einstein-radius", "1.5", "--seed", "21", "--quiet")
    with fits.open(field) as f, fits.open(os.path.join(directory, "field.weight.fits")) as g:
        write_tiles(directory, f[0], g[0])
    return field


def write_tiles(directory, image, weight):
    lines = ["image,weight"]
    k = 0
    for y0 in TILE_Y0:
        for x0 in TILE_X0:
            k += 1
            for hdu, suffix in ((image, ""), (weight, ".weight")):
                header = hdu.header.copy()
                header["CRPIX1"] -= x0
                header["CRPIX2"] -= y0
                data = hdu.data[y0:y0 + TILE_H, x0:x0 + TILE_W]
                fits.PrimaryHDU(data, header).writeto(
                    os.path.join(directory, "tile%d%s.fits" % (k, suffix)))
            lines.append("tile%d.fits,tile%d.weight.fits" % (k, k))
    with open(os.path.join(directory, "survey.csv"), "w") as f:
        f.write("\n".join(lines) + "\n")


def make_fixture(d):
    """The data the batch cases share, in directory d: the field, its tiles and manifest, and
    the uninterrupted one-process run of them (with its standard output). ctest makes it once
    for BatchRanks and BatchResume (the fixture of tests/integration/CMakeLists.txt, in
    OCTARC_FIXTURE_DIR); run alone, a case makes its own."""
    make_tiles(d)
    proc = run_octarc("batch", os.path.join(d, "survey.csv"),
                      *BatchFixture.config(os.path.join(d, "reference")))
    with open(os.path.join(d, "reference.stdout.txt"), "w") as f:
        f.write(proc.stdout)


class BatchFixture(WorkDirTest):
    """The tiles and the uninterrupted one-process run of them, made once (make_fixture)."""

    @classmethod
    def setUpClass(cls):
        require_program("mpirun")
        cls.own_data = not os.environ.get("OCTARC_FIXTURE_DIR")
        if cls.own_data:
            cls.data = tempfile.mkdtemp(prefix="octarc-batch-")
            make_fixture(cls.data)
        else:
            cls.data = os.environ["OCTARC_FIXTURE_DIR"]
        cls.field = os.path.join(cls.data, "field.fits")
        cls.manifest = os.path.join(cls.data, "survey.csv")
        cls.reference = os.path.join(cls.data, "reference")
        cls.reference_stdout = read_text(os.path.join(cls.data, "reference.stdout.txt"))

    @classmethod
    def tearDownClass(cls):
        if cls.own_data:
            shutil.rmtree(cls.data, ignore_errors=True)

    @staticmethod
    def config(out, *more):
        return ["-c", SEX, "-GRID_NAME", GRID, "-WEIGHT_TYPE", "MAP_WEIGHT", "-OUTPUT_DIR", out,
                *more]


class BatchRanks(BatchFixture):
    def test_one_two_and_four_ranks_give_the_same_survey_catalog(self):
        ref = os.path.join(self.reference, "candidates.fits")
        self.assertEqual(fitsverify_errors(ref)[0], 0)
        for ranks in (1, 2, 4):
            out = self.path("ranks%d" % ranks)
            proc = run_mpi(ranks, "batch", self.manifest, *self.config(out, "-NTHREADS", "1"))
            self.assertIn("(%d rank(s), whole manifest): 8 done, 0 failed" % ranks, proc.stdout)
            assert_same_tables(self, ref, os.path.join(out, "candidates.fits"))
            events = journal(out)
            ranks_seen = {int(d.split("rank ")[1]) for _, _, e, _, d in events if e == "done"}
            self.assertEqual(len([e for e in events if e[2] == "done"]), 8)
            self.assertEqual(len(ranks_seen), ranks)  # every rank took tiles
            self.assertEqual(temporaries(out), [])

    def test_duplicates_and_area_worked_out_again(self):
        # The tiles' own catalogs, matched here with astropy: copies of two tiles closer than 1"
        # are one object, kept from the tile whose centre is nearest.
        copies = []  # (tile index, tile name, NUMBER, ra, dec, distance to its tile's centre)
        for k in range(1, 9):
            name = "tile%d" % k
            data, _ = table_data(os.path.join(self.reference, "tiles", name, "candidates.fits"))
            w = WCS(fits.getheader(os.path.join(self.data, name + ".fits")))
            centre = w.pixel_to_world((TILE_W - 1) / 2, (TILE_H - 1) / 2)
            sky = SkyCoord(data["ALPHA_J2000"] * u.deg, data["DELTA_J2000"] * u.deg)
            for number, c, d in zip(data["NUMBER"], sky, sky.separation(centre).deg):
                copies.append((k, name, int(number), c.ra.deg, c.dec.deg, d))
        sky = SkyCoord([c[3] for c in copies] * u.deg, [c[4] for c in copies] * u.deg)
        i, j, _, _ = sky.search_around_sky(sky, 1.0 * u.arcsec)
        near = {}
        for a, b in zip(i, j):
            if copies[a][0] != copies[b][0]:
                near.setdefault(int(a), []).append(int(b))
        # Best first; a copy near a kept copy of another tile is that object again, unless the
        # kept copy already stands for a copy of this tile.
        held = {}
        best = []
        for n in sorted(range(len(copies)), key=lambda n: (copies[n][5], copies[n][0],
                                                           copies[n][2])):
            match = [k for k in near.get(n, []) if k in held and copies[n][0] not in held[k]]
            if match:
                held[match[0]].add(copies[n][0])
            else:
                held[n] = {copies[n][0]}
                best.append(n)
        expected = sorted((copies[n][1], copies[n][2]) for n in best)
        data, header = table_data(os.path.join(self.reference, "candidates.fits"))
        got = sorted(zip(data["TILE"], data["TILE_NUMBER"].tolist()))
        self.assertEqual(got, expected)
        self.assertEqual(header["NTILECND"], len(copies))
        self.assertEqual(header["NDUPLIC"], len(copies) - len(best))
        self.assertGreater(header["NDUPLIC"], 0)  # the overlaps hold objects seen twice
        self.assertTrue(np.all(np.diff(data["LENS_SCORE"]) <= 0))  # ranked by LENS_SCORE
        self.assertEqual(list(data["LENS_RANK"]), list(data["NUMBER"]))

        # The union of the tiles' searched areas is the whole field's, as its own search has it.
        run_octarc("search", self.field, "-c", SEX, "-GRID_NAME", GRID, "-WEIGHT_TYPE",
                   "MAP_WEIGHT", "-WEIGHT_IMAGE", os.path.join(self.data, "field.weight.fits"),
                   "-OUTPUT_DIR", self.path("whole"), "-STAMPS", "N")
        whole = fits.getheader(self.path("whole/candidates.fits"), "LDAC_OBJECTS")["SRCHAREA"]
        self.assertAlmostEqual(header["SRCHAREA"] / whole, 1.0, delta=1e-4)
        summary = read_text(os.path.join(self.reference, "summary.txt"))
        self.assertIn("8 done, 0 failed, 0 skipped", summary)
        self.assertIn("%d duplicate(s) in overlaps removed" % header["NDUPLIC"], summary)

    def test_survey_index_links_every_tile(self):
        html = read_text(os.path.join(self.reference, "index.html"))
        for k in range(1, 9):
            self.assertIn('href="tiles/tile%d/index.html"' % k, html)
            self.assertTrue(os.path.exists(
                os.path.join(self.reference, "tiles", "tile%d" % k, "candidates.reg")))

    def test_survey_vetting_page_regions_and_ascii_catalog(self):
        import json
        import regions
        from astropy.io import ascii
        data = Table.read(os.path.join(self.reference, "candidates.fits"), hdu="LDAC_OBJECTS")
        self.assertGreater(len(data), 5)
        html = read_text(os.path.join(self.reference, "candidates.html"))
        embedded = re.search(r'<script type="application/json" id="candidates">(.*?)</script>',
                             html, re.S).group(1)
        rows = json.loads(embedded)["rows"]
        # One card per survey candidate (the duplicates gone), each with the stamp its tile
        # made, linked relative to the page.
        self.assertEqual([r["n"] for r in rows], list(data["NUMBER"]))
        for r, row in zip(rows, data):
            self.assertEqual((r["tile"], r["tn"]), (row["TILE"], row["TILE_NUMBER"]))
            self.assertEqual(r["stamp"], "tiles/%s/stamps/%04d.png" % (row["TILE"],
                                                                         row["TILE_NUMBER"]))
            self.assertTrue(os.path.isfile(os.path.join(self.reference, r["stamp"])), r["stamp"])
            self.assertEqual(r["cutout"], r["stamp"][:-4] + ".fits")
            self.assertTrue(os.path.isfile(os.path.join(self.reference, r["cutout"])), r["cutout"])
        self.assertNotIn(self.data, html)
        self.assertIn('href="candidates.html"',
                      read_text(os.path.join(self.reference, "index.html")))
        # candidates.reg: a circle at each candidate's RA, Dec (fk5), labelled with NUMBER.
        shapes = regions.Regions.read(os.path.join(self.reference, "candidates.reg"),
                                      format="ds9")
        self.assertEqual(len(shapes), len(data))
        for shape, row in zip(shapes, data):
            self.assertEqual(str(shape.meta["text"]), str(row["NUMBER"]))
            self.assertAlmostEqual(shape.center.ra.deg, row["ALPHA_J2000"], delta=1e-6)
            self.assertAlmostEqual(shape.center.dec.deg, row["DELTA_J2000"], delta=1e-6)
        # candidates.cat: the same rows as ASCII_HEAD.
        cat = ascii.read(os.path.join(self.reference, "candidates.cat"), format="sextractor")
        self.assertEqual(list(cat["NUMBER"]), list(data["NUMBER"]))
        self.assertEqual(list(cat["TILE"]), [str(t) for t in data["TILE"]])
        np.testing.assert_allclose(cat["LENS_SCORE"], data["LENS_SCORE"], rtol=1e-5)

    def test_catalog_type_applies_to_the_survey_catalog_not_the_tiles(self):
        out = self.path("votable")
        run_octarc("batch", self.manifest, *self.config(out, "-CATALOG_TYPE", "ASCII_VOTABLE",
                                                        "-STAMPS", "N"))
        ref = Table.read(os.path.join(self.reference, "candidates.fits"), hdu="LDAC_OBJECTS")
        t = Table.read(os.path.join(out, "candidates.fits"), format="votable")
        self.assertGreater(len(ref), 5)
        self.assertEqual(t.colnames, ref.colnames)
        self.assertEqual(len(t), len(ref))
        for name in ref.colnames:
            want = np.asarray(ref[name])
            got = np.asarray(np.ma.filled(t[name], np.nan) if want.dtype.kind == "f" else t[name])
            if want.dtype.kind == "S":  # FITS text, read as bytes
                want, got = want.astype(str), got.astype(str)
            np.testing.assert_array_equal(got, want, err_msg=name)
        self.assertEqual(t["TILE"].meta["ucd"], "meta.id;obs.field")
        self.assertEqual(t["LEVELS"].meta["ucd"], "meta.id.part")
        self.assertEqual(t["LEVELS"].shape, (len(t), 15))
        # The tiles stay FITS-LDAC: the merge reads them back.
        for k in range(1, 9):
            with fits.open(os.path.join(out, "tiles", "tile%d" % k, "candidates.fits")) as f:
                self.assertEqual([h.name for h in f[1:]], ["LDAC_IMHEAD", "LDAC_OBJECTS"])

    def test_job_array_tasks_share_one_journal(self):
        out = self.path("array")
        for task, left in ((0, 5), (1, 2)):
            proc = run_octarc("batch", self.manifest,
                              *self.config(out, "-ARRAY_TASK", "%d/3" % task))
            self.assertIn("The survey outputs wait for %d tile(s) (0 that another run was "
                          "searching, %d left to other array tasks or to a rerun)" % (left, left),
                          proc.stdout)
            self.assertFalse(os.path.exists(os.path.join(out, "candidates.fits")))
        # The last task, as Slurm would start it (--array=5-7: task ids 5, 6, 7).
        env = dict(os.environ, SLURM_ARRAY_TASK_ID="7", SLURM_ARRAY_TASK_MIN="5",
                   SLURM_ARRAY_TASK_COUNT="3")
        proc = subprocess.run([OCTARC, "batch", self.manifest, *self.config(out)],
                              capture_output=True, text=True, env=env)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("array task 2/3", proc.stdout)
        assert_same_tables(self, os.path.join(self.reference, "candidates.fits"),
                           os.path.join(out, "candidates.fits"))
        done = [e[3] for e in journal(out) if e[2] == "done"]
        self.assertEqual(sorted(done), sorted("tile%d" % k for k in range(1, 9)))


class BatchResume(BatchFixture):
    def test_killed_rank_then_rerun_gives_the_uninterrupted_outputs(self):
        out = self.path("killed")
        args = ["batch", self.manifest, *self.config(out, "-NTHREADS", "1")]
        require_program("mpirun")
        proc = subprocess.Popen(mpi_command(2, *args), stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, env=mpi_env())
        killed = None
        ranks = {}
        deadline = time.time() + 120
        while time.time() < deadline and proc.poll() is None and killed is None:
            # Both ranks are found as they start, long before a tile is done, so that the kill
            # follows the first "done" at once.
            for rank in (0, 1):
                pid = ranks.get(rank) or rank_process(OCTARC, out, rank)
                if pid:
                    ranks[rank] = pid
            done = [e for e in journal(out) if e[2] == "done"]
            if done and len(ranks) == 2:
                # Rank 0 is held still while rank 1 dies, so that it cannot finish the survey
                # before mpirun's signal reaches it (the tiles take milliseconds); it acts on
                # that signal once it goes on.
                os.kill(ranks[0], signal.SIGSTOP)
                os.kill(ranks[1], signal.SIGKILL)
                killed = ranks[1]
                time.sleep(0.5)
                os.kill(ranks[0], signal.SIGCONT)
            time.sleep(0.002)
        proc.communicate(timeout=120)
        self.assertIsNotNone(killed, "rank 1 was not found running")
        self.assertNotEqual(proc.returncode, 0)  # the job ends with its rank
        first = {e[3] for e in journal(out) if e[2] == "done"}
        self.assertLess(len(first), 8, "every tile was done before the kill: tiles too fast")
        self.assertFalse(os.path.exists(os.path.join(out, "candidates.fits")))

        rerun = run_mpi(2, *args)
        self.assertIn("%d done, 0 failed, %d skipped" % (8 - len(first), len(first)),
                      rerun.stdout)
        events = journal(out)
        second = {e[3] for e in events if e[2] == "done" and e[0] == "2"}
        self.assertEqual(second, {"tile%d" % k for k in range(1, 9)} - first)  # only the rest
        self.assertEqual(len([e for e in events if e[2] == "done"]), 8)
        self.assertEqual(temporaries(out), [])
        assert_same_tables(self, os.path.join(self.reference, "candidates.fits"),
                           os.path.join(out, "candidates.fits"))
        for k in range(1, 9):
            tile = os.path.join("tiles", "tile%d" % k, "candidates.fits")
            assert_same_tables(self, os.path.join(self.reference, tile), os.path.join(out, tile))

    def test_interrupted_batch_leaves_no_temporary_and_resumes(self):
        out = self.path("interrupted")
        args = [OCTARC, "batch", self.manifest, *self.config(out, "-NTHREADS", "1")]
        with subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE) as proc:
            deadline = time.time() + 120
            while time.time() < deadline and proc.poll() is None:
                if os.path.exists(os.path.join(out, "journal.txt")) and any(
                        e[2] == "done" for e in journal(out)):
                    proc.send_signal(signal.SIGINT)
                    break
                time.sleep(0.01)
            _, err = proc.communicate(timeout=120)
        self.assertEqual(proc.returncode, 128 + signal.SIGINT, err)
        self.assertEqual(temporaries(out), [])
        first = {e[3] for e in journal(out) if e[2] == "done"}
        self.assertLess(len(first), 8)
        # The last line says what is on disk: the journal's tiles, each folder complete, and no
        # survey output.
        self.assertEqual(
            err.decode().strip().splitlines()[-1],
            "octarc batch: interrupted by SIGINT; this run searched and journaled %d tile(s), "
            "kept in %s/tiles (run the same command again to resume from them); it wrote no "
            "survey output (candidates.fits, summary.txt, index.html, candidates.html, "
            "candidates.reg, candidates.cat); nothing half-written is left" % (len(first), out))
        for name in first:
            self.assertTrue(os.path.exists(os.path.join(out, "tiles", name, "area.fits")), name)
        for name in ("candidates.fits", "summary.txt", "index.html", "candidates.html",
                     "candidates.reg", "candidates.cat"):
            self.assertFalse(os.path.exists(os.path.join(out, name)), name)
        proc = run_octarc("batch", self.manifest, *self.config(out))
        self.assertIn("%d done, 0 failed, %d skipped" % (8 - len(first), len(first)), proc.stdout)
        assert_same_tables(self, os.path.join(self.reference, "candidates.fits"),
                           os.path.join(out, "candidates.fits"))

    def test_every_rank_signalled_says_what_is_kept(self):
        # SIGTERM to each rank, as scancel sends it: the first rank counts the journal's tiles,
        # the other points to them.
        out = self.path("terminated")
        args = ["batch", self.manifest, *self.config(out, "-NTHREADS", "1")]
        require_program("mpirun")
        proc = subprocess.Popen(mpi_command(2, *args), stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, env=mpi_env(), text=True)
        ranks = []
        deadline = time.time() + 120
        while time.time() < deadline and proc.poll() is None and not ranks:
            if os.path.exists(os.path.join(out, "journal.txt")) and any(
                    e[2] == "done" for e in journal(out)):
                ranks = [rank_process(OCTARC, out, 0), rank_process(OCTARC, out, 1)]
                self.assertNotIn(None, ranks)
                for pid in ranks:
                    os.kill(pid, signal.SIGTERM)
            time.sleep(0.01)
        _, err = proc.communicate(timeout=120)
        self.assertTrue(ranks, "the ranks were not found running")
        done = len([e for e in journal(out) if e[2] == "done"])
        self.assertLess(done, 8)
        self.assertIn("octarc batch: interrupted by SIGTERM; this run searched and journaled %d "
                      "tile(s), kept in %s/tiles (run the same command again to resume from "
                      "them); it wrote no survey output (candidates.fits, summary.txt, "
                      "index.html, candidates.html, candidates.reg, candidates.cat); nothing "
                      "half-written is left\n" % (done, out), err)
        self.assertIn("octarc batch: interrupted by SIGTERM (rank 1): its tile in progress is "
                      "left to a rerun; the tiles with a `done` line in %s/journal.txt are kept "
                      "(run the same command again to resume from them)\n" % out, err)
        self.assertFalse(os.path.exists(os.path.join(out, "candidates.fits")))
        self.assertEqual(temporaries(out), [])

    def test_searched_area_cards_out_of_their_range_are_refused(self):
        # A finished batch run again merges its tiles' searched areas from their area.fits:
        # a card no search writes stops the merge, naming the file and the card.
        cases = (("IMWIDTH", 0, "IMWIDTH = 0 is not an integer from 1 to 2147483647"),
                 ("IMHEIGHT", 2 ** 31, "IMHEIGHT = 2147483648 is not an integer from 1 to "
                  "2147483647"),
                 ("BLOCKPIX", 32, "BLOCKPIX = 32 is not an integer from 64 to 64"),
                 ("PIXSCALE", -0.25, "PIXSCALE = -0.25 is not a finite number > 0"),
                 ("NPIX", 64 * 64 + 1, "NPIX = 4097 in row 1 is not an integer from 1 to 4096"))
        for key, value, expected in cases:
            out = self.path("area-" + key)
            shutil.copytree(self.reference, out)
            area = os.path.join(out, "tiles", "tile2", "area.fits")
            with fits.open(area, mode="update") as f:
                if key == "NPIX":
                    f["SEARCHED_AREA"].data["NPIX"][0] = value
                else:
                    f["SEARCHED_AREA"].header[key] = value
            proc = run_octarc("batch", self.manifest, *self.config(out), check=False)
            self.assertNotEqual(proc.returncode, 0, proc.stdout)
            self.assertIn(area + "[SEARCHED_AREA]: " + expected, proc.stderr)
            shutil.rmtree(out)

    def test_corrupt_tile_is_reported_and_the_others_complete(self):
        d = self.path("bad")
        os.mkdir(d)
        lines = read_text(self.manifest).splitlines()
        for k in range(1, 9):
            for suffix in ("", ".weight"):
                os.symlink(os.path.join(self.data, "tile%d%s.fits" % (k, suffix)),
                           os.path.join(d, "tile%d%s.fits" % (k, suffix)))
        os.remove(os.path.join(d, "tile3.fits"))
        with open(os.path.join(self.data, "tile3.fits"), "rb") as f:
            head = f.read(2880 * 3)
        with open(os.path.join(d, "tile3.fits"), "wb") as f:
            f.write(head)  # the header and a part of the data
        with open(os.path.join(d, "survey.csv"), "w") as f:
            f.write("\n".join(lines) + "\n")
        out = self.path("bad-out")
        for attempt in (1, 2):
            proc = run_octarc("batch", os.path.join(d, "survey.csv"), *self.config(out),
                              check=False)
            self.assertEqual(proc.returncode, 1, proc.stderr)
            self.assertIn("failed: tile3 (line 4): ", proc.stdout)
            self.assertIn("tile3.fits", proc.stdout)
            if attempt == 1:
                self.assertIn("7 done, 1 failed, 0 skipped", proc.stdout)
            else:
                self.assertIn("0 done, 1 failed, 7 skipped", proc.stdout)
            self.assertIn("1 tile(s) failed", proc.stderr)
            self.assertEqual(fitsverify_errors(os.path.join(out, "candidates.fits"))[0], 0)
            data, _ = table_data(os.path.join(out, "candidates.fits"))
            self.assertNotIn("tile3", set(data["TILE"]))
            self.assertGreater(len(data["TILE"]), 0)
            # The vetting page says a tile failed, without the error quoting its path.
            page = read_text(os.path.join(out, "candidates.html"))
            self.assertIn(" 1 failed, ", page)
            self.assertNotIn(d, page)
            self.assertIn(d, read_text(os.path.join(out, "summary.txt")))
        failed = [e for e in journal(out) if e[2] == "failed"]
        self.assertEqual([e[3] for e in failed], ["tile3", "tile3"])


# Six small tiles (200 x 300 pixels, side by side) for the runs that share one OUTPUT_DIR: what
# is tested is who searches which tile, not the search.
SMALL_TILE_X0 = (0, 200, 400)
SMALL_TILE_Y0 = (0, 300)


def not_in_slurm():
    """This environment without Slurm's variables (a CI runner may run inside a job)."""
    return {k: v for k, v in os.environ.items() if not k.startswith("SLURM_")}


def array_env(task_id, first, last, step, count):
    """A task's environment as slurmctld makes it: MIN and MAX the lowest and highest id, STEP
    the number after ':' in --array (1 without), COUNT the number of ids."""
    return dict(not_in_slurm(), SLURM_ARRAY_TASK_ID=str(task_id), SLURM_ARRAY_TASK_MIN=str(first),
                SLURM_ARRAY_TASK_MAX=str(last), SLURM_ARRAY_TASK_STEP=str(step),
                SLURM_ARRAY_TASK_COUNT=str(count))


def flock_waiters(path):
    """How many processes wait for the flock of the file `path` (Linux's /proc/locks)."""
    st = os.stat(path)
    inode = ":%d " % st.st_ino
    with open("/proc/locks") as f:
        return sum(1 for line in f if " -> FLOCK " in line and inode in line)


class BatchSharing(WorkDirTest):
    """Runs that share one OUTPUT_DIR at the same time (batches started at once, the tasks of a
    job array) search each tile once: a tile is searched only under its claim."""

    @classmethod
    def setUpClass(cls):
        cls.data = tempfile.mkdtemp(prefix="octarc-sharing-")
        field = os.path.join(cls.data, "field.fits")
        run_octarc("simulate", "field", "-o", field, "--size", 600, "--lenses", "6",
                   "--min-einstein-radius", "1.5", "--seed", "5", "--quiet")
        cls.tiles = []
        with fits.open(field) as f:
            for y0 in SMALL_TILE_Y0:
                for x0 in SMALL_TILE_X0:
                    name = "small%d" % (len(cls.tiles) + 1)
                    header = f[0].header.copy()
                    header["CRPIX1"] -= x0
                    header["CRPIX2"] -= y0
                    fits.PrimaryHDU(f[0].data[y0:y0 + 300, x0:x0 + 200], header).writeto(
                        os.path.join(cls.data, name + ".fits"))
                    cls.tiles.append(name)
        cls.manifest = os.path.join(cls.data, "small.txt")
        with open(cls.manifest, "w") as f:
            f.write("".join(name + ".fits\n" for name in cls.tiles))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.data, ignore_errors=True)

    def command(self, out, *more):
        return [OCTARC, "batch", self.manifest, "-c", SEX, "-GRID_NAME", GRID, "-STAMPS", "N",
                "-NTHREADS", "1", "-OUTPUT_DIR", out, *more]

    def run_task(self, out, env):
        proc = subprocess.run(self.command(out), capture_output=True, text=True, env=env)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        return proc

    def start_together(self, out, envs):
        """One `octarc batch` per environment, all held at their first journal line (the journal's
        lock, taken here) until every one has read the journal: each then plans every tile not
        done, and they race for the same tiles. Returns the finished processes."""
        # A run that searches nothing makes OUTPUT_DIR and its journal.
        subprocess.run(self.command(out, "-ARRAY_TASK", "99/100"), check=True,
                       capture_output=True, env=not_in_slurm())
        path = os.path.join(out, "journal.txt")
        with open(path, "a") as gate:
            fcntl.flock(gate, fcntl.LOCK_EX)
            procs = [subprocess.Popen(self.command(out), stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True, env=env)
                     for env in envs]
            deadline = time.time() + 120
            while flock_waiters(path) < len(procs):
                self.assertTrue(time.time() < deadline and all(p.poll() is None for p in procs),
                                "the runs did not all come to the journal's lock")
                time.sleep(0.01)
            fcntl.flock(gate, fcntl.LOCK_UN)
        for p in procs:
            p.stdout_text, p.stderr_text = p.communicate(timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr_text)
        return procs

    def done_lines(self, out):
        """Tile -> the runs whose `done` line names it."""
        done = {}
        for run, _, event, tile, _ in journal(out):
            if event == "done":
                done.setdefault(tile, []).append(run)
        return done

    def assert_each_tile_searched_once(self, out):
        done = self.done_lines(out)
        self.assertEqual(sorted(done), sorted(self.tiles))
        for tile, runs in done.items():
            self.assertEqual(len(runs), 1, "%s searched by runs %s" % (tile, runs))
        # The tiles' folders are complete, and nothing is left half written.
        for tile in self.tiles:
            self.assertTrue(os.path.exists(os.path.join(out, "tiles", tile, "area.fits")), tile)
        self.assertEqual(temporaries(out), [])
        return done

    def assert_survey_merged(self, out):
        _, header = table_data(os.path.join(out, "candidates.fits"))
        self.assertEqual(header["NTILES"], len(self.tiles))
        # The survey counts every tile's candidates once: the journal's done lines say how many.
        in_tiles = sum(int(d.split(" candidates")[0]) for _, _, e, _, d in journal(out)
                       if e == "done")
        self.assertEqual(header["NTILECND"], in_tiles)
        self.assertIn("%d tiles" % len(self.tiles), read_text(os.path.join(out, "summary.txt")))

    def assert_merged_or_left_to_another(self, procs):
        """Each run wrote the survey outputs, or ended saying it left them to a run that was
        still searching a tile; at least one wrote them."""
        merged = 0
        for p in procs:
            if "Open " in p.stdout_text:
                merged += 1
            else:
                last = p.stdout_text.strip().splitlines()[-1]
                self.assertRegex(last, r"^The survey outputs wait for \d+ tile\(s\) \([1-9]\d* "
                                 r"that another run was searching, 0 left to other array tasks "
                                 r"or to a rerun\)")
        self.assertGreaterEqual(merged, 1)

    def test_a_rerun_with_another_configuration_is_refused_until_restart(self):
        out = self.path("config")
        self.run_task(out, not_in_slurm())
        grid_copy = self.path("copy.grid.fits")
        shutil.copyfile(GRID, grid_copy)
        changed_grid = self.path("changed.grid.fits")
        with open(GRID, "rb") as f, open(changed_grid, "wb") as g:
            g.write(f.read() + b"x")

        def refused(*more):
            before = read_text(os.path.join(out, "journal.txt"))
            proc = subprocess.run(self.command(out, *more), capture_output=True, text=True,
                                  env=not_in_slurm())
            self.assertNotEqual(proc.returncode, 0)
            lines = proc.stderr.strip().splitlines()
            self.assertEqual(len(lines), 1, proc.stderr)
            self.assertEqual(read_text(os.path.join(out, "journal.txt")), before)
            return lines[0]

        # octarc.sex has DETECT_THRESH 2.5, SNR_MIN is unset there.
        line = refused("-DETECT_THRESH", "3.0", "-SNR_MIN", "7")
        self.assertIn("OUTPUT_DIR %s was made with DETECT_THRESH 2.5, this run has 3.0; SNR_MIN "
                      % out, line)
        self.assertIn(", this run has 7: its tiles would mix two searches; give -RESTART Y to "
                      "set them aside (into %s/earlier-N) and start over" % out, line)
        self.assertIn("GRID_NAME %s (content " % GRID, refused("-GRID_NAME", changed_grid))
        # Keys that do not change a tile's search, and a copy of the grid: the tiles are kept.
        for more in (("-NTHREADS", "2", "-MATCH_RADIUS", "2", "-VERBOSE_TYPE", "NORMAL",
                      "-CATALOG_TYPE", "FITS_1.0", "-CATALOG_NAME", "other.ldac"),
                     ("-GRID_NAME", grid_copy)):
            proc = subprocess.run(self.command(out, *more), capture_output=True, text=True,
                                  env=not_in_slurm())
            self.assertEqual(proc.returncode, 0, proc.stderr)
            self.assertIn("0 done, 0 failed, 6 skipped", proc.stdout)

        # A configuration recorded before some keys existed (here SNR_MIN and LENS_LIGHT_BAND
        # taken out of it): a run that leaves them at their default resumes; one that sets one
        # differs from it.
        config_path = os.path.join(out, "configuration.txt")
        recorded = read_text(config_path)
        with open(config_path, "w") as f:
            f.write("".join(line for line in recorded.splitlines(keepends=True)
                            if line.split("\t")[0] not in ("SNR_MIN", "LENS_LIGHT_BAND")))
        self.assertNotIn("SNR_MIN", read_text(config_path))
        proc = subprocess.run(self.command(out), capture_output=True, text=True,
                              env=not_in_slurm())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("0 done, 0 failed, 6 skipped", proc.stdout)
        self.assertIn("SNR_MIN none, this run has 7", refused("-SNR_MIN", "7"))
        with open(config_path, "w") as f:
            f.write(recorded)

        # A directory of an octarc that kept no configuration takes this run's, with a warning.
        os.remove(os.path.join(out, "configuration.txt"))
        proc = self.run_task(out, not_in_slurm())
        self.assertIn("WARNING: octarc batch: OUTPUT_DIR %s holds 6 tile(s) done by runs that "
                      "recorded no configuration" % out, proc.stderr)
        self.assertIn("DETECT_THRESH\t2.5\t2.5\n",
                      read_text(os.path.join(out, "configuration.txt")))

        # RESTART Y: the earlier runs' files set aside, the user's own left, a new journal.
        with open(os.path.join(out, "notes.txt"), "w") as f:
            f.write("mine")
        earlier_journal = read_text(os.path.join(out, "journal.txt"))
        proc = subprocess.run(self.command(out, "-DETECT_THRESH", "3.0", "-RESTART", "Y"),
                              capture_output=True, text=True, env=not_in_slurm())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("6 done, 0 failed, 0 skipped", proc.stdout)
        aside = os.path.join(out, "earlier-1")
        self.assertEqual(sorted(os.listdir(aside)),
                         ["candidates.cat", "candidates.fits", "candidates.html", "candidates.reg",
                          "configuration.txt", "index.html", "journal.txt", "summary.txt",
                          "tiles"])
        self.assertEqual(read_text(os.path.join(aside, "journal.txt")), earlier_journal)
        self.assertEqual(sorted(os.listdir(os.path.join(aside, "tiles"))), sorted(self.tiles))
        self.assertIn("DETECT_THRESH\t2.5\t2.5\n",
                      read_text(os.path.join(aside, "configuration.txt")))
        self.assertIn("DETECT_THRESH\t3.0\t3.0\n",
                      read_text(os.path.join(out, "configuration.txt")))
        self.assertEqual(read_text(os.path.join(out, "notes.txt")), "mine")
        self.assertEqual({e[0] for e in journal(out)}, {"1"})
        self.assert_each_tile_searched_once(out)
        # The same configuration with RESTART Y resumes.
        proc = subprocess.run(self.command(out, "-DETECT_THRESH", "3.0", "-RESTART", "Y"),
                              capture_output=True, text=True, env=not_in_slurm())
        self.assertIn("0 done, 0 failed, 6 skipped", proc.stdout)
        self.assertFalse(os.path.exists(os.path.join(out, "earlier-2")))

    def test_two_batches_started_at_once_search_each_tile_once(self):
        out = self.path("two")
        procs = self.start_together(out, [not_in_slurm(), not_in_slurm()])
        events = journal(out)
        starts = [i for i, e in enumerate(events) if e[2] == "start" and e[0] != "1"]
        first_done = min(i for i, e in enumerate(events) if e[2] == "done")
        self.assertEqual(len(starts), 2)
        self.assertLess(max(starts), first_done)  # both planned every tile before any was done
        done = self.assert_each_tile_searched_once(out)
        # What each run says it did is what the journal says.
        for p in procs:
            run = re.search(r"^Run (\d+) \(1 rank\(s\), whole manifest\): (\d+) done, 0 failed",
                            p.stdout_text, re.M)
            self.assertIsNotNone(run, p.stdout_text)
            self.assertEqual(int(run.group(2)),
                             sum(1 for runs in done.values() if runs == [run.group(1)]))
        self.assert_merged_or_left_to_another(procs)
        self.assert_survey_merged(out)

    def test_a_tile_another_run_holds_is_left_to_it(self):
        out = self.path("held")
        subprocess.run(self.command(out, "-ARRAY_TASK", "99/100"), check=True,
                       capture_output=True, env=not_in_slurm())
        with open(os.path.join(out, "claims", "small4"), "a") as claim:
            fcntl.flock(claim, fcntl.LOCK_EX)
            proc = self.run_task(out, not_in_slurm())
        self.assertIn("5 done, 0 failed, 0 skipped (done earlier or by other runs), 1 left to "
                      "other runs or tasks", proc.stdout)
        self.assertEqual(proc.stdout.strip().splitlines()[-1],
                         "The survey outputs wait for 1 tile(s) (1 that another run was "
                         "searching, 0 left to other array tasks or to a rerun): the run that "
                         "journals the last of them writes them")
        self.assertNotIn("small4", self.done_lines(out))
        self.assertFalse(os.path.exists(os.path.join(out, "candidates.fits")))
        # Let go (as when its run ends or is killed): the next run searches it alone. That run
        # is one of two tasks that srun started without joining them in MPI: it says so.
        proc = self.run_task(out, dict(not_in_slurm(), SLURM_STEP_ID="0",
                                       SLURM_STEP_NUM_TASKS="2", SLURM_NTASKS="2"))
        self.assertEqual(proc.stderr.splitlines()[:2], [
            "> Batch run 3: 6 tiles, 1 to search (whole manifest) on 1 rank(s) of 1 thread(s)",
            "WARNING: octarc batch: Slurm started 2 tasks but MPI sees 1 rank: launch with srun "
            "--mpi=pmix (or mpirun); each task now runs alone"])
        self.assertIn("1 done, 0 failed, 5 skipped", proc.stdout)
        self.assertIn("Open ", proc.stdout)
        self.assert_each_tile_searched_once(out)
        self.assert_survey_merged(out)

    def test_stepped_array_tasks_take_the_share_of_their_position(self):
        # --array=10-14:2: ids 10, 12 and 14, the shares 0/3, 1/3 and 2/3; run one after another,
        # the last to finish writes the survey.
        out = self.path("stepped")
        for task_id, position in ((12, 1), (14, 2), (10, 0)):
            proc = self.run_task(out, array_env(task_id, 10, 14, 2, 3))
            self.assertIn("(1 rank(s), array task %d/3)" % position, proc.stdout)
            self.assertIn("> Slurm array task %d (--array=10-14:2 of 3 tasks): share %d/3"
                          % (task_id, position), proc.stderr)
            mine = {t for t, runs in self.done_lines(out).items()
                    if runs == [journal(out)[-1][0]]}
            self.assertEqual(mine, {t for k, t in enumerate(self.tiles) if k % 3 == position})
            self.assertEqual("Open " in proc.stdout, position == 0, proc.stdout)
        self.assert_each_tile_searched_once(out)
        self.assert_survey_merged(out)

    def test_failed_tasks_sent_again_as_a_list_share_what_is_left(self):
        # --array=0-3 where tasks 1 and 3 failed: 0 and 2 searched the tiles k % 4 of 0 and 2.
        out = self.path("resent")
        for task_id in (0, 2):
            proc = self.run_task(out, array_env(task_id, 0, 3, 1, 4))
            self.assertIn("array task %d/4" % task_id, proc.stdout)
        self.assertEqual(sorted(self.done_lines(out)), [self.tiles[k] for k in (0, 2, 4)])
        # Sent again, --array=1,3: ids that are no range, so each takes what no other has, and
        # both start at once.
        procs = self.start_together(out, [array_env(1, 1, 3, 1, 2), array_env(3, 1, 3, 1, 2)])
        for p, task_id in zip(procs, (1, 3)):
            self.assertIn("> Slurm array task %d, one of 2 ids from 1 to 3 that are not a range "
                          "with step 1: the whole manifest, shared with the other tasks through "
                          "the tiles' claims" % task_id, p.stderr_text)
            self.assertIn("(1 rank(s), whole manifest)", p.stdout_text)
        self.assert_each_tile_searched_once(out)
        self.assert_merged_or_left_to_another(procs)
        self.assert_survey_merged(out)


class BatchBadInput(WorkDirTest):
    def batch(self, manifest, *more):
        return run_octarc("batch", manifest, "-c", SEX, "-GRID_NAME", GRID, "-OUTPUT_DIR",
                          self.path("out"), *more, check=False, cwd=self.work)

    def write(self, name, text):
        with open(self.path(name), "w") as f:
            f.write(text)
        return self.path(name)

    def assert_refused(self, proc, *fragments):
        self.assertNotEqual(proc.returncode, 0)
        lines = proc.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, proc.stderr)
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(self.path("out")))

    def test_bad_manifest_lines_are_named(self):
        for name in ("a.fits", "b.fits"):
            fits.PrimaryHDU(np.zeros((20, 20), np.float32)).writeto(self.path(name))
        m = self.write("m.txt", "a.fits\n# comment\nmissing.fits\n")
        self.assert_refused(self.batch(m), "m.txt:3:", "missing.fits", "no such file")
        m = self.write("m.txt", "a.fits\nb.fits\n./a.fits\n")
        self.assert_refused(self.batch(m), "m.txt:3:", "duplicate tile", "line 1")
        self.write("bad.reg", "image\ncircle(10,10\n")
        m = self.write("m.txt", "a.fits,-,bad.reg\n")
        self.assert_refused(self.batch(m), "m.txt:1:", "mask", "bad.reg:2")
        os.mkdir(self.path("folder.reg"))
        m = self.write("m.txt", "b.fits,-,folder.reg\n")
        self.assert_refused(self.batch(m), "m.txt:1:", "mask", "cannot be read")
        m = self.write("m.txt", "a.fits,b.fits\n")
        self.assert_refused(self.batch(m), "m.txt:1:", "WEIGHT_TYPE is NONE")
        m = self.write("m.txt", "a.fits\n")
        self.assert_refused(self.batch(m, "-WEIGHT_TYPE", "MAP_WEIGHT"), "m.txt:1:",
                            "no weight map")

    def test_zero_tiles_and_other_refusals(self):
        self.assert_refused(self.batch(self.write("m.txt", "# no tile yet\n")), "m.txt",
                            "lists no tile")
        self.assert_refused(self.batch(self.path("none-*.fits")), "no file matches")
        fits.PrimaryHDU(np.zeros((20, 20), np.float32)).writeto(self.path("a.fits"))
        m = self.write("m.txt", "a.fits\n")
        self.assert_refused(self.batch(m, "-MASK_NAME", "x.reg"), "MASK_NAME", "manifest")
        self.assert_refused(self.batch(m, "-COLOUR_IMAGE", "a.fits", "-COLOUR_BAND", "g"),
                            "COLOUR_IMAGE", "manifest")
        self.assert_refused(self.batch(m, "-LENS_LIGHT", "LOCAL", "-LENS_LIGHT_BAND", "i"),
                            "LENS_LIGHT_BAND", "manifest")
        self.assert_refused(self.batch(m, "-ARRAY_TASK", "3/3"), "ARRAY_TASK")
        os.mkdir(self.path("out"))
        self.write("out/notes.txt", "mine")
        proc = self.batch(m)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("is not the output of an octarc batch", proc.stderr)
        self.assertEqual(os.listdir(self.path("out")), ["notes.txt"])


class LensRuns(WorkDirTest):
    """`simulate lenses` on one process or on MPI ranks, and the comparison of two outputs."""

    def lenses(self, ranks, n, out, *more):
        args = ["simulate", "lenses", "-n", n, "--seed", "17", "-o", self.path(out), "--quiet",
                *more]
        if ranks == 1:
            return run_octarc(*args)
        return run_mpi(ranks, *args, "--threads", "1")

    def assert_same_data(self, a, b):
        with fits.open(self.path(a)) as fa, fits.open(self.path(b)) as fb:
            self.assertEqual(len(fa), len(fb))
            for ha, hb in zip(fa, fb):
                if ha.data is None:
                    continue
                if isinstance(ha, fits.BinTableHDU):
                    self.assertEqual(ha.data.tobytes(), hb.data.tobytes(), ha.name)
                else:
                    self.assertTrue(np.array_equal(ha.data, hb.data), ha.name)



class ClusterLenses(LensRuns):
    def test_two_thousand_systems_on_one_and_four_ranks(self):
        # The dls preset: importance sampling renders some hundred of the 2 000 drawn systems,
        # whose weights the ranks must sum as one process does.
        self.lenses(1, 2000, "one.fits", "--preset", "dls")
        self.lenses(4, 2000, "four.fits", "--preset", "dls")
        self.assert_same_data("one.fits", "four.fits")
        head = ldac_imhead(self.path("one.fits"))
        self.assertEqual(head["OCTNSYS"], 2000)
        with fits.open(self.path("one.fits")) as f:
            self.assertEqual(len(f["LDAC_OBJECTS"].data), head["OCTNREND"])
            self.assertGreater(head["OCTNREND"], 50)
            self.assertGreater(len(f["ARCS"].data), 0)

class ClusterLensStamps(LensRuns):
    """A small run, also for the sanitizer pass (MPI under ASan)."""

    def test_stamps_beyond_the_first_rank_share(self):
        # 40 systems on 4 ranks: the first rank makes 10; stamps of 25 are asked for.
        self.lenses(1, 40, "one.fits", "--stamps", self.path("one.stamps.fits"),
                    "--stamp-count", "25")
        self.lenses(4, 40, "four.fits", "--stamps", self.path("four.stamps.fits"),
                    "--stamp-count", "25")
        self.assert_same_data("one.fits", "four.fits")
        self.assert_same_data("one.stamps.fits", "four.stamps.fits")
        self.assertEqual(fits.getdata(self.path("four.stamps.fits")).shape[0], 25)


if __name__ == "__main__":
    unittest.main()
