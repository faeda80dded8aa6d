"""The vetting page and `octarc grades` on synthetic candidate catalogs made here with astropy
(independent of octarc's search): the GRADE column merged from a CSV, the errors that name the
CSV's line, and the page of 10 000 candidates driven in headless Chromium: a filter leaves the
cards counted here, a key grades the current card, the export holds the grade, and octarc grades
puts it into the catalog."""

import csv
import hashlib
import io
import os
import unittest
from urllib.parse import unquote

import numpy as np
from astropy.io import fits
from astropy.table import Table

from octarc_testlib import (WorkDirTest, fitsverify_errors, have_program, run_octarc,
                            run_page_in_chromium)


def in_ci():
    return os.environ.get("CI", "").lower() == "true"


def write_catalog(path, count, tiles=None, seed=3, ldac=True):
    """A survey-style candidate catalog of `count` rows: NUMBER by descending LENS_SCORE, NAME,
    RA/Dec, ARCNESS, CAND_FLAGS (1: no visible lens, 32: a dark-lens pair), and TILE /
    TILE_NUMBER when `tiles` names them. Returns its columns as numpy arrays."""
    rng = np.random.default_rng(seed)
    score = np.sort(rng.uniform(0, 1, count))[::-1]
    cols = {
        "NUMBER": np.arange(1, count + 1, dtype=np.int32),
        "LENS_SCORE": score,
        "NAME": np.array(["OCTARC J%06d" % k for k in range(1, count + 1)]),
        "ALPHA_J2000": rng.uniform(149, 151, count),
        "DELTA_J2000": rng.uniform(1, 3, count),
        "ARCNESS": rng.uniform(0, 0.5, count).astype(np.float32),
        "SNR_ISO": rng.uniform(5, 100, count).astype(np.float32),
        "CAND_FLAGS": rng.choice(np.array([0, 1, 8, 33], dtype=np.int16), count),
    }
    if tiles:
        cols["TILE"] = np.array([tiles[k % len(tiles)] for k in range(count)])
        cols["TILE_NUMBER"] = np.array([k // len(tiles) + 1 for k in range(count)], np.int32)
    columns = []
    for name, v in cols.items():
        if v.dtype.kind == "U":
            form = "%dA" % max(len(s) for s in v)
        elif v.dtype.kind == "i":
            form = "J" if v.dtype == np.int32 else "I"
        else:
            form = "D" if v.dtype == np.float64 else "E"
        columns.append(fits.Column(name=name, format=form, array=v))
    objects = fits.BinTableHDU.from_columns(columns, name="LDAC_OBJECTS" if ldac else "OBJECTS")
    hdus = [fits.PrimaryHDU()]
    if ldac:
        cards = np.array([["SIMPLE  =                    T".ljust(80), "END".ljust(80)]])
        hdus.append(fits.BinTableHDU.from_columns(
            [fits.Column(name="Field Header Card", format="160A", dim="(80, 2)",
                         array=cards)], name="LDAC_IMHEAD"))
    hdus.append(objects)
    fits.HDUList(hdus).writeto(path)
    return cols


def sha(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


class GradesCommand(WorkDirTest):
    def test_grades_become_a_column_of_a_copy(self):
        cat = self.path("candidates.fits")
        cols = write_catalog(cat, 40)
        before = sha(cat)
        with open(self.path("grades.csv"), "w") as f:
            f.write("NUMBER,NAME,ALPHA_J2000,DELTA_J2000,GRADE\n"
                    "7,OCTARC J000007,150.1,2.1,lens\n3,\"OCTARC J000003\",,,maybe\n"
                    "12,OCTARC J000012,,,no\n")
        run_octarc("grades", cat, self.path("grades.csv"), "-o", self.path("graded.fits"))
        self.assertEqual(sha(cat), before)  # the input is never written
        t = Table.read(self.path("graded.fits"), hdu="LDAC_OBJECTS")
        want = {7: "lens", 3: "maybe", 12: "no"}
        self.assertEqual([str(g).strip() for g in t["GRADE"]],
                         [want.get(n, "") for n in cols["NUMBER"]])
        self.assertEqual(list(t["NAME"]), list(cols["NAME"]))
        with fits.open(self.path("graded.fits")) as f:
            self.assertEqual([h.name for h in f], ["PRIMARY", "LDAC_IMHEAD", "LDAC_OBJECTS"])
        if have_program("fitsverify") or in_ci():
            self.assertEqual(fitsverify_errors(self.path("graded.fits"))[0], 0)
        # FITS_1.0 stays FITS_1.0.
        write_catalog(self.path("fits10.fits"), 20, ldac=False)
        run_octarc("grades", self.path("fits10.fits"), self.path("grades.csv"), "-o",
                   self.path("graded10.fits"))
        with fits.open(self.path("graded10.fits")) as f:
            self.assertEqual([h.name for h in f], ["PRIMARY", "OBJECTS"])
            self.assertEqual(f["OBJECTS"].data["GRADE"][6].strip(), "lens")

    def test_an_unknown_number_is_one_line_naming_the_csv_line(self):
        cat = self.path("candidates.fits")
        write_catalog(cat, 10)
        grades = self.path("grades.csv")
        with open(grades, "w") as f:
            f.write("NUMBER,GRADE\n2,lens\n11,no\n")
        r = run_octarc("grades", cat, grades, "-o", self.path("graded.fits"), check=False)
        self.assertEqual(r.returncode, 1)
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertIn(grades + ":3: NUMBER 11 is not in", lines[0])
        self.assertFalse(os.path.exists(self.path("graded.fits")))
        # Writing over the catalog itself is refused.
        with open(grades, "w") as f:
            f.write("NUMBER,GRADE\n2,lens\n")
        r = run_octarc("grades", cat, grades, "-o", cat, check=False)
        self.assertEqual(r.returncode, 1)
        self.assertIn(cat, r.stderr)


class VettingPageChromium(WorkDirTest):
    COUNT = 10000
    TILES = ["north", "south", "east", "west"]

    def test_ten_thousand_candidates_filter_grade_export(self):
        if not have_program("chromium") and not in_ci():
            self.skipTest("program not installed: chromium")
        from PIL import Image
        survey = self.path("survey")
        os.makedirs(survey)
        cat = os.path.join(survey, "candidates.fits")
        cols = write_catalog(cat, self.COUNT, tiles=self.TILES)
        # Tiny stamps, one file linked under every name the page asks for.
        stamp = self.path("stamp.png")
        Image.new("RGB", (8, 8), (90, 90, 90)).save(stamp)
        for tile in self.TILES:
            os.makedirs(os.path.join(survey, "tiles", tile, "stamps"))
        for tile, number in zip(cols["TILE"], cols["TILE_NUMBER"]):
            os.symlink(stamp, os.path.join(survey, "tiles", tile, "stamps", "%04d.png" % number))
        page = os.path.join(survey, "candidates.html")
        run_octarc("grades", cat, "--page", page, "--quiet")

        # The filter the driver sets, and what it must leave, worked out here.
        min_score, min_arcness = 0.5, 0.25
        keep = ((cols["LENS_SCORE"] >= min_score) & (cols["ARCNESS"] >= min_arcness)
                & ((cols["CAND_FLAGS"] & 1) != 0) & (cols["TILE"] == "south"))
        kept = cols["NUMBER"][keep]  # by descending LENS_SCORE already
        self.assertGreater(len(kept), 10)
        driver = """
        const readyMs = performance.now();
        const $ = id => document.getElementById(id);
        const count = () => ({matching: Number($('count').dataset.matching),
          page: Number($('count').dataset.page),
          cards: Array.from(document.querySelectorAll('#grid .card'))
                      .map(c => Number(c.dataset.number))});
        const before = count();
        $('next').click();
        const second = count();
        const set = (id, value) => {
          $(id).value = value;
          $(id).dispatchEvent(new Event('change'));
        };
        set('min-score', '%g');
        set('min-arcness', '%g');
        set('lens', 'dark');
        set('tile', 'south');
        const filtered = count();
        const key = k => document.body.dispatchEvent(
          new KeyboardEvent('keydown', {key: k, bubbles: true}));
        key('j'); key('2'); key('j'); key('1');
        const graded = Array.from(document.querySelectorAll('#grid .card[data-grade]'))
          .map(c => [Number(c.dataset.number), c.dataset.grade]);
        const link = $('export');
        link.addEventListener('click', e => e.preventDefault());  // no download, keep the CSV
        link.click();
        const stored = Object.keys(localStorage).filter(k => k.startsWith('octarc-grades:'))
          .map(k => JSON.parse(localStorage.getItem(k)));
        report({readyMs, before, second, filtered, graded, stored, href: link.href,
                text: document.body.innerText.slice(0, 4000)});
        """ % (min_score, min_arcness)
        result, seconds = run_page_in_chromium(page, driver, self.work)
        print("\n10 000-candidate page: page ready %.0f ms after navigation; the whole "
              "headless Chromium run %.1f s (page %.1f MB)"
              % (result["readyMs"], seconds, os.path.getsize(page) / 1e6))

        per_page = 200
        self.assertEqual(result["before"]["matching"], self.COUNT)
        self.assertEqual(result["before"]["cards"], list(range(1, per_page + 1)))
        self.assertEqual(result["second"]["page"], 2)
        self.assertEqual(result["second"]["cards"], list(range(per_page + 1, 2 * per_page + 1)))
        self.assertEqual(result["filtered"]["matching"], len(kept))
        self.assertEqual(result["filtered"]["cards"], list(kept[:per_page]))
        # j moved to the second card, 2 graded it maybe; j, 1: the third is a lens.
        want = {int(kept[1]): "maybe", int(kept[2]): "lens"}
        self.assertEqual(dict((n, g) for n, g in result["graded"]), want)
        self.assertEqual(result["stored"], [{str(k): v for k, v in want.items()}])
        self.assertNotIn(self.work, result["text"])

        prefix = "data:text/csv;charset=utf-8,"
        self.assertTrue(result["href"].startswith(prefix), result["href"][:80])
        text = unquote(result["href"][len(prefix):])
        rows = list(csv.DictReader(io.StringIO(text)))
        self.assertEqual(list(rows[0].keys()), ["NUMBER", "TILE", "TILE_NUMBER", "NAME",
                                                "ALPHA_J2000", "DELTA_J2000", "GRADE"])
        self.assertEqual({int(r["NUMBER"]): r["GRADE"] for r in rows}, want)
        for r in rows:
            i = int(r["NUMBER"]) - 1
            self.assertEqual((r["TILE"], int(r["TILE_NUMBER"]), r["NAME"]),
                             (cols["TILE"][i], cols["TILE_NUMBER"][i], cols["NAME"][i]))
            self.assertAlmostEqual(float(r["ALPHA_J2000"]), cols["ALPHA_J2000"][i], delta=1e-9)
        # The exported CSV read back into the catalog by octarc grades.
        with open(self.path("grades.csv"), "w") as f:
            f.write(text)
        run_octarc("grades", cat, self.path("grades.csv"), "-o", self.path("graded.fits"))
        t = Table.read(self.path("graded.fits"), hdu="LDAC_OBJECTS")
        got = {int(n): str(g).strip() for n, g in zip(t["NUMBER"], t["GRADE"]) if str(g).strip()}
        self.assertEqual(got, want)


if __name__ == "__main__":
    unittest.main()
