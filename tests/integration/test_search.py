"""`octarc search` end to end on a simulated field: the candidates against the selection worked
out again here with numpy from the catalog `octarc detect` writes for the same image and the
grid file; the outputs in their real readers (fitsverify, astropy, STILTS, astropy regions,
SAOImage DS9, Chromium); and bad input."""
import csv
import io
import os
import re
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
from astropy.io import fits
from astropy.table import Table
from astropy.wcs import WCS

from octarc_testlib import (SOURCE_DIR, WorkDirTest, fitsverify_errors, have_program,
                            require_program, run_octarc, run_page_in_chromium)

SEX = os.path.join(SOURCE_DIR, "params", "octarc.sex")
GRID_ARGS = ["-GRID_AXES", "ARCNESS,E_IMAGE", "-GRID_LEVEL", "0.9", "-CHECKPLOT_TYPE", "NONE"]
# A low floor, so that a small field gives a few tens of candidates to compare.
SNR_MIN = "8"


def in_ci():
    return os.environ.get("CI") == "true"


def make_fixture(d):
    """The data the search cases share, in directory d: a 1024^2 field with injected lenses, its
    weight map, and a 1-D grid of known contents with the survey setup of a small lens
    simulation's calibrated grid. ctest makes it once for every case (the fixture of
    tests/integration/CMakeLists.txt, in OCTARC_FIXTURE_DIR); run alone, a case makes its own."""
    run_octarc("simulate", "field", "-o", os.path.join(d, "field.fits"), "--size", "1024",
               "--lenses", "6", "--min-einstein-radius", "1.5", "--seed", "3", "--quiet")
    run_octarc("simulate", "lenses", "-n", "3000", "--seed", "5", "-o",
               os.path.join(d, "sim.fits"), "--quiet")
    calibrated = os.path.join(d, "calibrated.grid.fits")
    run_octarc("calibrate", os.path.join(d, "sim.fits"), "-CALIBRATION_NAME",
               os.path.join(d, "cal.fits"), "-GRID_NAME", calibrated, *GRID_ARGS,
               "-NOISE_STUDY", "N", cwd=d)
    # A few thousand systems give only some arcs: the test's grid keeps the calibrated
    # grid's survey setup but holds a known selection, 0.10 <= ARCNESS < 0.30.
    known_grid(calibrated, os.path.join(d, "grid.fits"))


class SearchFixture(WorkDirTest):
    """A 1024^2 field with injected lenses and a 2-D grid of a small lens simulation, made once
    (make_fixture)."""

    @classmethod
    def setUpClass(cls):
        cls.data = tempfile.mkdtemp(prefix="octarc-search-")
        shared = os.environ.get("OCTARC_FIXTURE_DIR")
        if not shared:
            make_fixture(cls.data)
        cls.image = os.path.join(shared or cls.data, "field.fits")
        cls.weight = os.path.join(shared or cls.data, "field.weight.fits")
        cls.grid = os.path.join(shared or cls.data, "grid.fits")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.data, ignore_errors=True)

    def search(self, *args, out="out", check=True, image=None):
        return run_octarc("search", image or self.image, "-c", SEX, "-GRID_NAME", self.grid,
                          "-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE", self.weight,
                          "-SNR_MIN", SNR_MIN, "-OUTPUT_DIR", self.path(out), "-NTHREADS", "2",
                          *args, check=check, cwd=self.work)

    def candidates(self, out="out"):
        return fits.getdata(self.path(os.path.join(out, "candidates.fits")), "LDAC_OBJECTS")


def known_grid(template, path):
    """A 1-D ARCNESS grid of six bins on [0, 0.3): counts 1, 2, 2, 2, 2, 2; at P = 0.9 the
    contour holds bins 1 to 5 (10/11 of the probability), i.e. 0.05 <= ARCNESS < 0.30."""
    with fits.open(template) as f:
        h = f["OCC_GRID"].header.copy()
    for key in list(h.keys()):
        if key.startswith("TTYPE") or key.startswith("TFORM") or key.startswith("TDISP"):
            del h[key]
        elif re.fullmatch(r"AX(EXPR|LO|HI|BINS)\d+", key):
            del h[key]
    h["GRIDDIM"] = 1
    h["AXEXPR1"], h["AXLO1"], h["AXHI1"], h["AXBINS1"] = "ARCNESS", 0.0, 0.3, 6
    h["PLEVEL"], h["PSELECT"], h["NSELECT"] = 0.9, 10 / 11, 5
    h["NBINNED"], h["NOUTSIDE"], h["NUNDEF"], h["NOCCUP"] = 11, 0, 0, 6
    h["WBINNED"], h["NDROPAX"] = 11.0, 0  # unit weights
    counts = np.array([2, 2, 2, 2, 2, 1])
    cols = [fits.Column("BIN", "1J", array=[1, 2, 3, 4, 5, 0]),
            fits.Column("COUNT", "1K", array=counts),
            fits.Column("WEIGHT", "1D", array=counts.astype(float)),
            fits.Column("PROB", "1D", array=counts / 11),
            fits.Column("CUMPROB", "1D", array=np.cumsum(counts) / 11),
            fits.Column("SELECTED", "1I", array=[1, 1, 1, 1, 1, 0])]
    table = fits.BinTableHDU.from_columns(cols, name="OCC_GRID")
    for card in h.cards:
        if card.keyword not in table.header and card.keyword not in (
                "XTENSION", "BITPIX", "NAXIS", "NAXIS1", "NAXIS2", "PCOUNT", "GCOUNT",
                "TFIELDS"):
            table.header.append(card)
    fits.HDUList([fits.PrimaryHDU(), table]).writeto(path)


def grid_selected_bins(grid_path):
    """The selected bins of a grid file as a set of index tuples, and its axes."""
    with fits.open(grid_path) as f:
        h, d = f["OCC_GRID"].header, f["OCC_GRID"].data
        axes = [(h["AXEXPR%d" % (k + 1)], h["AXLO%d" % (k + 1)], h["AXHI%d" % (k + 1)],
                 h["AXBINS%d" % (k + 1)]) for k in range(h["GRIDDIM"])]
        bins = d["BIN"].reshape(len(d), -1)
        selected = {tuple(int(v) for v in b) for b, s in zip(bins, d["SELECTED"]) if s == 1}
    return axes, selected


class SearchSelection(SearchFixture):

    def test_candidates_are_the_selection_worked_out_from_the_catalog(self):
        self.search()
        # The same image through `octarc detect`, with the same configuration.
        catalog = self.path("all.ldac")
        run_octarc("detect", self.image, "-c", SEX, "-WEIGHT_TYPE", "MAP_WEIGHT",
                   "-WEIGHT_IMAGE", self.weight, "-CATALOG_NAME", catalog, "-NTHREADS", "2",
                   cwd=self.work)
        rows = fits.getdata(catalog, "LDAC_OBJECTS")
        scale = np.sqrt(abs(np.linalg.det(WCS(fits.getheader(self.image)).pixel_scale_matrix)))
        scale *= 3600
        axes, selected = grid_selected_bins(self.grid)
        index = []
        for name, lo, hi, n in axes:
            v = rows[name].astype(float)
            k = np.floor((v - lo) / ((hi - lo) / n))
            k[(v < lo) | (v >= hi) | ~np.isfinite(v)] = -1
            index.append(k.astype(int))
        in_grid = np.array([tuple(ix) in selected for ix in zip(*index)])
        weight = fits.getdata(self.weight)
        xi = np.floor(rows["X_IMAGE"] - 0.5).astype(int)
        yi = np.floor(rows["Y_IMAGE"] - 0.5).astype(int)
        good = weight[yi, xi] > 0
        passed = (good & (rows["SNR_ISO"] > float(SNR_MIN)) &
                  (np.sqrt(2) * rows["SIZE_IMAGE"] * scale > 1.0) & in_grid)
        # Merge through the parent links: each passing row joins its nearest passing ancestor.
        key = {(int(l), int(n)): i for i, (l, n) in
               enumerate(zip(rows["THRESH_LEVEL"], rows["NUMBER"]))}
        root = {}

        def top(i):
            j, found = i, i
            while rows["THRESH_LEVEL"][j] > 1:
                up = key.get((int(rows["THRESH_LEVEL"][j]) - 1, int(rows["PARENT_NUMBER"][j])))
                if up is None:
                    break
                j = up
                if passed[j]:
                    found = j
            return found

        for i in np.nonzero(passed)[0]:
            t = i
            while top(t) != t:
                t = top(t)
            root.setdefault(t, []).append(i)
        cand = self.candidates()
        self.assertGreaterEqual(len(root), 5)
        self.assertEqual(len(cand), len(root))
        # Each candidate is one merged object: its levels are those of the object's rows.
        expected = sorted(sorted({int(rows["THRESH_LEVEL"][i]) for i in members})
                          for members in root.values())
        # LEVELS: a vector of octarc.sex's 15 levels, the passed ones first, then 0.
        self.assertEqual(cand["LEVELS"].shape, (len(cand), 15))
        got = sorted([int(v) for v in row if v != 0] for row in cand["LEVELS"])
        self.assertEqual(got, expected)
        for row in cand["LEVELS"]:
            n = np.count_nonzero(row)
            self.assertTrue(np.all(row[n:] == 0))
        # Ranked by LENS_SCORE, each candidate's the highest of its rows': the arcs' probability
        # of the row's bin over the bin's share of the rows scored (searched, above the floor,
        # resolved; one row added to each of the grid's occupied bins), times the prior odds of
        # LENS_DENSITY (1 per deg2) over those rows.
        self.assertTrue(np.all(np.diff(cand["LENS_SCORE"]) <= 0))
        self.assertEqual(list(cand["LENS_RANK"]), list(range(1, len(cand) + 1)))
        scored = good & (rows["SNR_ISO"] > float(SNR_MIN)) & (
            np.sqrt(2) * rows["SIZE_IMAGE"] * scale > 1.0)
        with fits.open(self.grid) as f:
            bins, prob = f["OCC_GRID"].data["BIN"].reshape(-1), f["OCC_GRID"].data["PROB"]
        in_bin = {int(b): 1 + int(np.sum(scored & (index[0] == b))) for b in bins}
        total = scored.sum() + len(bins)
        area = fits.getheader(self.path("out/candidates.fits"), "LDAC_OBJECTS")["SRCHAREA"]
        prior = area / scored.sum()
        odds = np.zeros(len(rows))
        for b, p in zip(bins, prob):
            odds[index[0] == b] = p / (in_bin[int(b)] / total) * prior / (1 - prior)
        score = odds / (1 + odds)
        expected = sorted(max(score[i] for i in members) for members in root.values())
        np.testing.assert_allclose(sorted(cand["LENS_SCORE"]), expected, rtol=1e-9)
        # ARCNESS and positions are those of a passing row.
        passing = {(round(float(x), 2), round(float(y), 2)) for x, y in
                   zip(rows["X_IMAGE"][passed], rows["Y_IMAGE"][passed])}
        for x, y in zip(cand["X_IMAGE"], cand["Y_IMAGE"]):
            self.assertIn((round(float(x), 2), round(float(y), 2)), passing)
        # The summary in the header.
        h = fits.getheader(self.path("out/candidates.fits"), "LDAC_OBJECTS")
        self.assertEqual(h["NCANDID"], len(cand))
        self.assertEqual(h["NROWSEL"], int(passed.sum()))
        self.assertEqual(h["NROWSRCH"], int(good.sum()))
        self.assertAlmostEqual(h["SRCHAREA"], h["SRCHPIX"] * (scale / 3600) ** 2,
                               delta=1e-3 * h["SRCHAREA"])
        for k in range(h["NSPACES"]):
            n = k + 1
            self.assertEqual(h["SPCAND%d" % n], int(np.sum((cand["SPACES"] >> k) & 1)))

    def test_positions_names_and_lenses(self):
        self.search()
        cand = self.candidates()
        w = WCS(fits.getheader(self.image))
        ra, dec = w.all_pix2world(cand["X_IMAGE"], cand["Y_IMAGE"], 1)
        np.testing.assert_allclose(cand["ALPHA_J2000"], ra, atol=1e-7)
        np.testing.assert_allclose(cand["DELTA_J2000"], dec, atol=1e-7)
        from astropy.coordinates import Angle
        for row in cand:
            self.assertAlmostEqual(Angle(row["RA_SEX"], unit="hourangle").deg,
                                   row["ALPHA_J2000"], delta=0.01 / 3600 * 15)
            self.assertAlmostEqual(Angle(row["DEC_SEX"], unit="deg").deg, row["DELTA_J2000"],
                                   delta=0.1 / 3600)
            self.assertTrue(re.fullmatch(r"OCTARC J\d{6}\.\d{2}[+-]\d{6}\.\d", row["NAME"]))
            has_lens = row["LENS_NUMBER"] > 0
            self.assertEqual(bool(row["CAND_FLAGS"] & 1), not has_lens)
            if not has_lens:
                self.assertEqual(row["THETA_E_METHOD"], 0)
                self.assertTrue(np.isnan(row["THETA_E"]) and np.isnan(row["LENS_DIST"]))
                continue
            scale = np.sqrt(abs(np.linalg.det(w.pixel_scale_matrix))) * 3600
            if not row["CAND_FLAGS"] & 64:  # the arc is the candidate's centroid
                d = np.hypot(row["LENS_X"] - row["X_IMAGE"], row["LENS_Y"] - row["Y_IMAGE"])
                self.assertAlmostEqual(row["LENS_DIST"], d * scale, delta=1e-3 * row["LENS_DIST"])
                self.assertLessEqual(row["LENS_DIST"], 6.0 + 1e-6)
            method, theta_e, dist = row["THETA_E_METHOD"], row["THETA_E"], row["LENS_DIST"]
            if method == 1:  # the mean of the arc's and a nearer counter-image's distances
                self.assertTrue(0.5 * dist <= theta_e <= dist * (1 + 1e-6))
            elif method == 2:  # the circle's radius
                self.assertAlmostEqual(theta_e, row["CURV_RADIUS"] * scale, delta=1e-3 * theta_e)
            else:
                self.assertEqual(method, 3)
                self.assertAlmostEqual(theta_e, dist / (1 + 0.5 ** 0.5), delta=1e-3 * theta_e)


class SearchOutputs(SearchFixture):

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.out = os.path.join(cls.data, "shared-out")
        run_octarc("search", cls.image, "-c", SEX, "-GRID_NAME", cls.grid, "-WEIGHT_TYPE",
                   "MAP_WEIGHT", "-WEIGHT_IMAGE", cls.weight, "-SNR_MIN", SNR_MIN,
                   "-OUTPUT_DIR", cls.out, "-NTHREADS", "2", cwd=cls.data)
        cls.cand = fits.getdata(os.path.join(cls.out, "candidates.fits"), "LDAC_OBJECTS")

    def test_catalog_passes_fitsverify_and_reads_in_stilts(self):
        path = os.path.join(self.out, "candidates.fits")
        self.assertEqual(fitsverify_errors(path)[0], 0)
        require_program("stilts")
        for name, fmt in (("candidates.fits", "fits"), ("candidates.cat", "ascii")):
            hdu = "#2" if fmt == "fits" else ""
            r = subprocess.run(["stilts", "tpipe", "in=" + os.path.join(self.out, name) + hdu,
                                "ifmt=" + fmt, "omode=stats"], capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("Total Rows: %d" % len(self.cand), r.stdout)
            if fmt == "fits":
                self.assertIn("ARCNESS", r.stdout)
        r = subprocess.run(["stilts", "tpipe", "in=" + os.path.join(self.out, "candidates.cat"),
                            "ifmt=ascii", "omode=count"], capture_output=True, text=True)
        self.assertIn("rows: %d" % len(self.cand), r.stdout)

    def test_ascii_catalog_equals_the_fits_one(self):
        from astropy.io import ascii
        t = ascii.read(os.path.join(self.out, "candidates.cat"), format="sextractor")
        self.assertEqual(len(t), len(self.cand))
        self.assertEqual(list(t["NAME"]), [str(n).replace(" ", "_") for n in self.cand["NAME"]])
        np.testing.assert_allclose(t["ARCNESS"], self.cand["ARCNESS"], atol=1e-4)
        np.testing.assert_allclose(t["X_IMAGE"], self.cand["X_IMAGE"], atol=1e-3)

    def test_regions_sit_on_the_candidates(self):
        import regions
        header = fits.getheader(self.image)
        w = WCS(header)
        shapes = regions.Regions.read(os.path.join(self.out, "candidates.reg"), format="ds9")
        arcs = [s for s in shapes if s.visual.get("color", s.meta.get("color")) == "green"
                or "text" in s.meta]
        self.assertEqual(len(arcs), len(self.cand))
        for s, row in zip(arcs, self.cand):
            p = s.to_pixel(w)
            # astropy's pixels are 0-based; octarc's catalog 1-based. astropy applies the
            # FK5 -> ICRS frame bias (about 0.02", 0.09 px here): octarc writes fk5 for J2000.
            self.assertAlmostEqual(p.center.x + 1, row["X_IMAGE"], delta=0.12)
            self.assertAlmostEqual(p.center.y + 1, row["Y_IMAGE"], delta=0.12)
            self.assertAlmostEqual(p.width / 2, 3 * row["A_IMAGE"], delta=0.01 * row["A_IMAGE"])
            # The ellipse's angle back on the pixels is THETA_IMAGE (modulo 180 degrees).
            d = (p.angle.to("deg").value - row["THETA_IMAGE"] + 90) % 180 - 90
            self.assertAlmostEqual(d, 0.0, delta=0.2)

    def test_stamps_one_per_candidate(self):
        stamps = sorted(os.listdir(os.path.join(self.out, "stamps")))
        numbers = range(1, len(self.cand) + 1)
        self.assertEqual(stamps, sorted(["%04d.png" % n for n in numbers] +
                                        ["%04d.fits" % n for n in numbers]))
        for name in stamps:
            if name.endswith(".png"):
                with open(os.path.join(self.out, "stamps", name), "rb") as f:
                    self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_fits_cutouts_carry_the_image_wcs(self):
        image = fits.getdata(self.image)
        side = None
        for row in self.cand:
            path = os.path.join(self.out, "stamps", "%04d.fits" % row["NUMBER"])
            with fits.open(path) as f:
                cut, header = f[0].data, f[0].header
            side = side or cut.shape[0]
            self.assertEqual(cut.shape, (side, side))
            # The candidate's RA, Dec (from the image's WCS) fall on its pixel of the cut-out,
            # whose pixel 1 is the image's pixel 1 - LTV.
            x, y = WCS(header).all_world2pix(row["ALPHA_J2000"], row["DELTA_J2000"], 1)
            self.assertAlmostEqual(float(x), row["X_IMAGE"] + header["LTV1"], delta=0.01)
            self.assertAlmostEqual(float(y), row["Y_IMAGE"] + header["LTV2"], delta=0.01)
            # The pixels are the image's there, less a smooth background.
            x0, y0 = int(-header["LTV1"]), int(-header["LTV2"])
            inside = x0 + side <= image.shape[1] and y0 + side <= image.shape[0]
            if x0 >= 0 and y0 >= 0 and inside:
                raw = image[y0:y0 + side, x0:x0 + side]
                self.assertGreater(np.corrcoef(raw.ravel(), cut.ravel())[0, 1], 0.99)
        if have_program("fitsverify") or in_ci():
            self.assertEqual(fitsverify_errors(path)[0], 0)
        # The vetting page links each card to its cut-out.
        with open(os.path.join(self.out, "index.html")) as f:
            html = f.read()
        self.assertEqual(re.findall(r'"cutout":"([^"]*)"', html),
                         ["stamps/%04d.fits" % n for n in self.cand["NUMBER"]])

    def test_ds9_places_every_region_where_octarc_wrote_it(self):
        if not have_program("ds9") and not in_ci():
            self.skipTest("program not installed: ds9 (saods9)")
        require_program("xvfb-run")
        work = self.work
        tcl = os.path.join(work, "ds9headless.tcl")
        with open(tcl, "w") as f:
            f.write("package require img::window\npackage require img::png\n"
                    "source /usr/share/saods9/library/ds9.tcl\n")
        listed = os.path.join(work, "listed.reg")
        r = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "wish", "-f", tcl,
                            self.image, "-regions", os.path.join(self.out, "candidates.reg"),
                            "-regions", "system", "image", "-regions", "save", listed,
                            "-exit"], capture_output=True, text=True, timeout=300)
        self.assertTrue(os.path.exists(listed), r.stderr)
        with open(listed) as f:
            text = f.read()
        ellipses = re.findall(r"ellipse\(([-\d.e+]+),([-\d.e+]+),", text)
        self.assertEqual(len(ellipses), len(self.cand))
        # DS9 converts the fk5 positions back through the image's WCS (ICRS here: 0.02").
        for (x, y), row in zip(ellipses, self.cand):
            self.assertAlmostEqual(float(x), row["X_IMAGE"], delta=0.1)
            self.assertAlmostEqual(float(y), row["Y_IMAGE"], delta=0.1)

    def test_vetting_page_opens_in_chromium(self):
        if not have_program("chromium") and not in_ci():
            self.skipTest("program not installed: chromium")
        page = os.path.join(self.out, "index.html")
        # The driver loads every card's stamp (the page loads them lazily) and reads the cards.
        driver = """
        document.getElementById('sort').value = 'arcness';
        document.getElementById('sort').dispatchEvent(new Event('change'));
        document.getElementById('ascending').checked = true;
        document.getElementById('ascending').dispatchEvent(new Event('change'));
        const cards = Array.from(document.querySelectorAll('#grid .card'));
        Promise.all(cards.map(c => new Promise(done => {
          const i = new Image();
          i.onload = () => done(i.naturalWidth > 0);
          i.onerror = () => done(false);
          i.src = c.querySelector('img').src; }))).then(loaded => report({
            order: cards.map(c => Number(c.dataset.number)),
            loaded: loaded.filter(x => x).length,
            text: document.body.innerText}));
        """
        result, _ = run_page_in_chromium(page, driver, self.work)
        n = len(self.cand)
        self.assertGreaterEqual(n, 5)
        self.assertEqual(result["loaded"], n)
        arcness = self.cand["ARCNESS"]
        self.assertEqual(result["order"], [int(i) + 1 for i in np.argsort(arcness, kind="stable")])
        # What a reader sees names no absolute path and holds no test status line.
        self.assertNotIn(self.data, result["text"])
        self.assertNotIn(self.image, result["text"])
        self.assertNotIn(self.grid, result["text"])
        self.assertNotIn("loaded", result["text"])
        self.assertIn("%d of %d candidates shown" % (n, n), result["text"])
        shot = os.path.join(self.work, "sheet.png")
        subprocess.run(["chromium", "--headless=new", "--no-sandbox", "--disable-gpu",
                        "--allow-file-access-from-files", "--virtual-time-budget=5000",
                        "--screenshot=" + shot, "--window-size=1400,1000", "file://" + page],
                       capture_output=True, timeout=300)
        from PIL import Image
        pixels = np.asarray(Image.open(shot).convert("L"), dtype=float)
        self.assertGreater(pixels.std(), 5.0)


class SearchCatalogTypes(SearchFixture):
    """CATALOG_TYPE applies to candidates.fits (whose name is kept): FITS_1.0, ASCII_HEAD and
    ASCII_VOTABLE hold the rows of the FITS-LDAC catalog of the same search, as astropy and STILTS
    read them."""

    TYPES = ("FITS_LDAC", "FITS_1.0", "ASCII_HEAD", "ASCII_VOTABLE")

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.outs = {}
        for kind in cls.TYPES:
            out = os.path.join(cls.data, "out-" + kind)
            run_octarc("search", cls.image, "-c", SEX, "-GRID_NAME", cls.grid, "-WEIGHT_TYPE",
                       "MAP_WEIGHT", "-WEIGHT_IMAGE", cls.weight, "-SNR_MIN", SNR_MIN,
                       "-OUTPUT_DIR", out, "-NTHREADS", "2", "-STAMPS", "N",
                       "-CATALOG_TYPE", kind, cwd=cls.data)
            cls.outs[kind] = os.path.join(out, "candidates.fits")
        cls.ldac = Table.read(cls.outs["FITS_LDAC"], hdu="LDAC_OBJECTS")

    def assert_same_rows(self, table, skip=()):
        self.assertGreaterEqual(len(self.ldac), 5)
        self.assertEqual(len(table), len(self.ldac))
        for name in self.ldac.colnames:
            if name in skip:
                continue
            want = np.asarray(self.ldac[name])
            got = np.asarray(np.ma.filled(table[name], np.nan) if want.dtype.kind == "f"
                             else table[name])
            if want.dtype.kind == "S":  # FITS text, read as bytes
                want, got = want.astype(str), got.astype(str)
            np.testing.assert_array_equal(got, want, err_msg=name)

    def test_fits_1_0_reads_without_naming_the_hdu(self):
        t = Table.read(self.outs["FITS_1.0"])
        self.assertEqual(t.colnames, self.ldac.colnames)
        self.assert_same_rows(t)
        self.assertEqual(t.meta["NCANDID"], len(self.ldac))
        self.assertEqual(fitsverify_errors(self.outs["FITS_1.0"])[0], 0)

    def test_votable_has_the_values_units_and_ucds(self):
        t = Table.read(self.outs["ASCII_VOTABLE"], format="votable")
        self.assertEqual(t.colnames, self.ldac.colnames)
        self.assert_same_rows(t)
        self.assertEqual(t["LEVELS"].shape, (len(t), 15))
        self.assertEqual(str(t["ALPHA_J2000"].unit), "deg")
        self.assertEqual(t["ALPHA_J2000"].meta["ucd"], "pos.eq.ra;pos.barycenter;meta.main")
        self.assertEqual(t["X_IMAGE"].meta["ucd"],
                         "pos.cartesian.x;pos.barycenter;instr.det;meta.main")
        self.assertEqual(t["LEVELS"].meta["ucd"], "meta.id.part")
        self.assertEqual(str(t["THETA_E"].unit), "arcsec")
        from astropy.io.votable import parse_single_table
        params = {p.name: p.value for p in parse_single_table(self.outs["ASCII_VOTABLE"]).params}
        self.assertEqual(params["NCANDID"], len(self.ldac))
        self.assertEqual(params["SELMETH"], "GRID")
        require_program("stilts")
        r = subprocess.run(["stilts", "tpipe", "in=" + self.outs["ASCII_VOTABLE"],
                            "ifmt=votable", "cmd=meta", "ofmt=csv"],
                           capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = {row["Name"]: row for row in csv.DictReader(io.StringIO(r.stdout))}
        self.assertEqual(sorted(rows), sorted(self.ldac.colnames))
        self.assertEqual(rows["LEVELS"]["UCD"], "meta.id.part")
        self.assertEqual(rows["LENS_SCORE"]["UCD"], "stat.probability")
        self.assertEqual(rows["LEVELS"]["Class"], "short[]")
        self.assertTrue(all(row["UCD"] for row in rows.values()))

    def test_ascii_head_is_sextractors_layout(self):
        from astropy.io import ascii
        t = ascii.read(self.outs["ASCII_HEAD"], format="sextractor")
        self.assertEqual(len(t), len(self.ldac))
        self.assertEqual(list(t["NAME"]), [str(n).replace(" ", "_") for n in self.ldac["NAME"]])
        np.testing.assert_allclose(t["ARCNESS"], self.ldac["ARCNESS"], atol=1e-4)
        # The 15 elements of LEVELS are 15 numbered columns.
        with open(self.outs["ASCII_HEAD"]) as f:
            numbers = {l.split()[2]: int(l.split()[1]) for l in f if l.startswith("#")}
        self.assertEqual(numbers["NLEVELS"] - numbers["LEVELS"], 15)
        words = np.loadtxt(self.outs["ASCII_HEAD"], dtype=str, ndmin=2)
        first = numbers["LEVELS"] - 1
        np.testing.assert_array_equal(words[:, first:first + 15].astype(int), self.ldac["LEVELS"])

    def test_none_and_unsupported_types_are_one_line_errors(self):
        for kind in ("NONE", "ASCII_SKYCAT", "FITS_TPX"):
            p = self.search("-CATALOG_TYPE", kind, out="refused", check=False)
            self.assertNotEqual(p.returncode, 0)
            lines = [l for l in p.stderr.splitlines() if l.strip()]
            self.assertEqual(len(lines), 1, p.stderr)
            self.assertIn("CATALOG_TYPE " + kind, lines[0])
            self.assertFalse(os.path.exists(self.path("refused")))


class SearchInterrupted(SearchFixture):
    """SIGINT or SIGTERM at several points of a search: OUTPUT_DIR complete or absent, and no
    temporary directory left."""

    def test_interrupted_search_leaves_all_or_nothing(self):
        import signal
        cmd = [os.environ.get("OCTARC_BIN", "octarc"), "search", self.image, "-c", SEX,
               "-GRID_NAME", self.grid, "-WEIGHT_TYPE", "MAP_WEIGHT", "-WEIGHT_IMAGE",
               self.weight, "-SNR_MIN", SNR_MIN, "-OUTPUT_DIR", self.path("out"),
               "-NTHREADS", "2"]
        interrupted = 0
        for trigger in (r"> Level 3 ", r"> Level 15 ", r"> Selecting candidates"):
            for sig in (signal.SIGINT, signal.SIGTERM):
                shutil.rmtree(self.path("out"), ignore_errors=True)
                with subprocess.Popen(cmd, cwd=self.work, stderr=subprocess.PIPE,
                                      stdout=subprocess.DEVNULL, text=True) as proc:
                    for line in proc.stderr:
                        if re.search(trigger, line):
                            proc.send_signal(sig)
                            break
                    err = proc.stderr.read()
                    proc.wait(timeout=120)
                names = os.listdir(self.work)
                self.assertEqual([n for n in names if ".tmp." in n], [], err)
                if proc.returncode == 0:
                    self.assertTrue(os.path.exists(self.path("out/.octarc-search")))
                else:
                    interrupted += 1
                    self.assertEqual(proc.returncode, 128 + sig, err)
                    self.assertFalse(os.path.exists(self.path("out")), err)
        self.assertGreater(interrupted, 0)


class SearchBadInput(SearchFixture):

    def test_malformed_region_line_names_file_and_line(self):
        reg = self.path("mask.reg")
        with open(reg, "w") as f:
            f.write("# Region file format: DS9 version 4.1\nimage\ncircle(100,100,50)\n"
                    "box(10,10,5)\n")
        r = self.search("-MASK_NAME", reg, "-VERBOSE_TYPE", "QUIET", check=False)
        self.assertNotEqual(r.returncode, 0)
        # One line, before any pixel is read.
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("mask.reg:4", r.stderr)
        self.assertFalse(os.path.exists(self.path("out")))
        self.assertEqual([n for n in os.listdir(self.work) if n.startswith(".")], [])

    def test_mask_excludes_its_area(self):
        reg = self.path("mask.reg")
        with open(reg, "w") as f:
            f.write("image\nbox(512.5,512.5,1024,1024)\n-box(256.5,512.5,512,1024)\n")
        self.search("-MASK_NAME", reg)
        cand = self.candidates()
        self.assertTrue(np.all(cand["X_IMAGE"] >= 512.5))
        h = fits.getheader(self.path("out/candidates.fits"), "LDAC_OBJECTS")
        self.assertEqual(h["SRCHPIX"], 512 * 1024 - int(
            np.sum(fits.getdata(self.weight)[:, 512:] <= 0)))

    def test_image_without_wcs_searches_in_pixels(self):
        with fits.open(self.image) as f:
            h = f[0].header
            for k in list(h.keys()):
                if k[:5] in ("CTYPE", "CRVAL", "CRPIX", "CUNIT", "CDELT", "RADES", "EQUIN") or \
                        k[:2] in ("CD", "PC"):
                    del h[k]
            f.writeto(self.path("nowcs.fits"))
        r = self.search("-PIXEL_SCALE", "0.257", image=self.path("nowcs.fits"))
        self.assertIn("no celestial WCS", r.stderr)
        cand = self.candidates()
        # The area from the pixel scale: every pixel of good weight, 0.257" square.
        h = fits.getheader(self.path("out/candidates.fits"), "LDAC_OBJECTS")
        good = int(np.sum(fits.getdata(self.weight) > 0))
        self.assertEqual(h["SRCHPIX"], good)
        self.assertAlmostEqual(h["SRCHAREA"], good * (0.257 / 3600) ** 2, delta=1e-12)
        self.assertGreater(len(cand), 0)
        self.assertTrue(np.all(np.isnan(cand["ALPHA_J2000"])))
        self.assertTrue(np.all(cand["CAND_FLAGS"] & 4))
        with open(self.path("out/candidates.reg")) as f:
            self.assertIn("\nimage\n", f.read())
        r = self.search("-PIXEL_SCALE", "0", image=self.path("nowcs.fits"), out="out2",
                        check=False)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("PIXEL_SCALE", r.stderr)
        self.assertFalse(os.path.exists(self.path("out2")))

    def test_empty_result_is_a_valid_empty_catalog_and_sheet(self):
        self.search("-SNR_MIN", "1e12")
        cand = self.candidates()
        self.assertEqual(len(cand), 0)
        self.assertEqual(fitsverify_errors(self.path("out/candidates.fits"))[0], 0)
        with open(self.path("out/index.html")) as f:
            self.assertIn('"rows":[]}', f.read())
        self.assertEqual(os.listdir(self.path("out/stamps")), [])

    def test_grid_of_another_setup_is_warned(self):
        r = self.search("-SEEING_FWHM", "1.5")
        self.assertIn("made for another setup: seeing FWHM", r.stderr)

    def test_output_dir_that_is_not_a_search_output_is_refused(self):
        os.makedirs(self.path("mine"))
        with open(self.path("mine/notes.txt"), "w") as f:
            f.write("keep me\n")
        r = self.search(out="mine", check=False)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("not an earlier output", r.stderr)
        self.assertEqual(os.listdir(self.path("mine")), ["notes.txt"])
        # A directory that merely holds a candidates.fits is no search output either.
        with open(self.path("mine/candidates.fits"), "w") as f:
            f.write("not ours\n")
        r = self.search(out="mine", check=False)
        self.assertNotEqual(r.returncode, 0)
        self.assertEqual(sorted(os.listdir(self.path("mine"))), ["candidates.fits", "notes.txt"])
        # An earlier search output is replaced whole: many candidates, then none.
        self.search()
        self.assertGreater(len(os.listdir(self.path("out/stamps"))), 0)
        self.search("-SNR_MIN", "1e12")
        self.assertEqual(len(self.candidates()), 0)
        self.assertEqual(os.listdir(self.path("out/stamps")), [])
        self.assertEqual([n for n in os.listdir(self.work) if n.startswith(".")], [])

    def test_inputs_inside_output_dir_are_refused_before_the_run(self):
        self.search()
        shutil.copy(SEX, self.path("out/my.sex"))
        r = run_octarc("search", self.image, "-c", self.path("out/my.sex"), "-GRID_NAME",
                       self.grid, "-OUTPUT_DIR", self.path("out"), "-VERBOSE_TYPE", "QUIET",
                       check=False, cwd=self.work)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("holds", r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertTrue(os.path.exists(self.path("out/my.sex")))


if __name__ == "__main__":
    unittest.main()
