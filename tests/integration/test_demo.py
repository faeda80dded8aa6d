"""`octarc demo`: a small field end to end (simulate, detect with ASSOC, report); the report's
arc count recomputed from the catalog and the truth list; bad input (issue 4, acceptance 4, 5)."""
import os
import re
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (SOURCE_DIR, WorkDirTest, fitsverify_errors, ldac_objects,
                            require_shared, run_octarc)

PIXEL_SCALE = 0.257


def recovered_arcs(rows, truth, scale=PIXEL_SCALE):
    """The report's arc rules applied here to the catalog and the truth list: a row is an arc of
    a system when it is resolved (sqrt(2) SIZE > 1"), >= 1" from the system's lens and within 2"
    of one of its lensed images; "other objects" are resolved rows farther than theta_E + 4" from
    every lens. Returns {system: best arcness}, the arcs' arcness and the others' arcness."""
    lenses = truth[truth[:, 5] == 1]
    resolved = np.sqrt(2) * rows["SIZE_IMAGE"] * scale > 1.0
    finite = np.isfinite(rows["ARCNESS"])
    arc_of = np.zeros(len(rows), int)
    near_system = np.zeros(len(rows), bool)
    for lens in lenses:
        system = int(lens[8])
        from_lens = np.hypot(rows["X_IMAGE"] - lens[1], rows["Y_IMAGE"] - lens[2]) * scale
        near_system |= from_lens < lens[7] + 4.0
        images = truth[(truth[:, 5] == 2) & (truth[:, 8] == system)]
        near = np.zeros(len(rows), bool)
        for im in images:
            near |= np.hypot(rows["X_IMAGE"] - im[1], rows["Y_IMAGE"] - im[2]) * scale < 2.0
        arc_of[near & resolved & (from_lens >= 1.0)] = system
    arcs = (arc_of > 0) & finite
    found = {int(system): float(rows["ARCNESS"][arcs & (arc_of == system)].max())
             for system in set(arc_of[arcs])}
    others = ~arcs & ~near_system & resolved & finite
    return found, rows["ARCNESS"][arcs], rows["ARCNESS"][others]


class SmallDemo(WorkDirTest):

    def test_small_demo_runs_and_reports(self):
        # Seeded, so the outcome is fixed: with this seed 3 of the 6 arcs are found.
        out = self.path("demo")
        proc = run_octarc("demo", "--size", 1024, "--lenses", 6, "--seed", 1, "--out", out,
                          "--quiet")
        self.assertEqual(proc.stderr, "")
        text = proc.stdout
        for needle in ("Field: ", "1024 x 1024 px of 0.257\"", "sky noise",
                       "level  threshold [ADU]  objects",
                       "Injected arcs detected:", "median best ARCNESS",
                       "system  theta_E[\"]  best ARCNESS  level     S/N", "injected arcs",
                       "other objects", "Outputs:"):
            self.assertIn(needle, text)
        names = ("field.fits", "field.weight.fits", "field.truth.txt", "field.ldac",
                 "injection-systems.txt", "injection-candidates.txt")
        for name in names:
            self.assertTrue(os.path.isfile(os.path.join(out, name)), name)
            self.assertIn(os.path.join(out, name), text)
        code, msg = fitsverify_errors(os.path.join(out, "field.ldac"))
        self.assertEqual(code, 0, msg)

        rows, _ = ldac_objects(os.path.join(out, "field.ldac"))
        # Objects per level as printed = rows per THRESH_LEVEL of the catalog; 15 levels
        # log-spaced from 2.5 to 20 sigma (params/octarc.sex), so the last is 8 times the first.
        table = text.split("level  threshold [ADU]  objects")[1].split("Injected")[0]
        printed = {int(a): (float(b), int(c)) for a, b, c in
                   re.findall(r"^\s+(\d+)\s+([\d.]+)\s+(\d+)\s*$", table, re.M)}
        self.assertEqual(sorted(printed), list(range(1, 16)))
        for level, (threshold, count) in printed.items():
            self.assertEqual(count, int(np.sum(rows["THRESH_LEVEL"] == level)))
            self.assertAlmostEqual(
                threshold, rows["THRESHOLD"][rows["THRESH_LEVEL"] == level][0], places=3)
        # Ratios of printed (rounded) thresholds: within what the rounding of the first allows.
        decimals = len(re.search(r"^\s+1\s+\d+\.(\d+)", table, re.M).group(1))
        slack = 0.5 * 10.0 ** -decimals / printed[1][0]
        self.assertAlmostEqual(printed[15][0] / printed[1][0], 8.0, delta=10 * slack + 1e-3)
        self.assertAlmostEqual(printed[2][0] / printed[1][0], 8.0 ** (1 / 14),
                               delta=2 * slack + 1e-3)
        # The catalog carries the truth through ASSOC: VECTOR_ASSOC(5) = id, kind, mag, theta_E,
        # system, and every injected lens galaxy's entry is matched by some object.
        self.assertEqual(rows["VECTOR_ASSOC"].shape[1], 5)
        truth = np.loadtxt(os.path.join(out, "field.truth.txt"), ndmin=2)
        kinds = set(rows["VECTOR_ASSOC"][rows["NUMBER_ASSOC"] > 0, 1].astype(int))
        self.assertIn(1, kinds)
        self.assertTrue(kinds <= {1, 2, 3, 4})

        # The arc count recomputed here with the report's rules: an object >= 1" from its lens,
        # sqrt(2) SIZE > 1", within 2" of one of the system's lensed images, at any level.
        found, _, _ = recovered_arcs(rows, truth)
        lenses = truth[truth[:, 5] == 1]
        m = re.search(r"Injected arcs detected: (\d+) of (\d+) systems", text)
        self.assertEqual(int(m.group(2)), 6)
        self.assertEqual(int(m.group(1)), len(found))
        self.assertGreaterEqual(len(found), 1)
        # Each found system's best arcness is printed in its table row.
        for system, best in found.items():
            row = re.search(r"^\s+%d\s+([\d.]+)\s+([\d.]+)\s+(\d+)\s+([\d.]+)$" % system, text,
                            re.M)
            self.assertIsNotNone(row, "system %d" % system)
            self.assertAlmostEqual(float(row.group(2)), best, places=3)
        # The demo injects lenses whose arcs can separate from the lens: theta_E >= 1.5".
        self.assertTrue(np.all(lenses[:, 7] >= 1.5))

        # The search: its candidates, and which injected lenses they are.
        cand = fits.getdata(os.path.join(out, "candidates", "candidates.fits"), "LDAC_OBJECTS")
        self.assertIn("Search: octarc search -SELECTION_METHOD TREES -MODEL_NAME", text)
        self.assertIn("LENS_SCORE >= 0.01)", text)
        self.assertIn("%d candidate(s)," % len(cand), text)
        self.assertTrue(np.all(cand["LENS_SCORE"] >= 0.01))
        self.assertTrue(os.path.isfile(os.path.join(out, "candidates", "index.html")))
        systems = np.loadtxt(os.path.join(out, "injection-systems.txt"), ndmin=2)
        per_candidate = np.loadtxt(os.path.join(out, "injection-candidates.txt"), ndmin=2)
        self.assertEqual(len(systems), 6)
        self.assertEqual(len(per_candidate), len(cand))
        arcs = int(np.sum(per_candidate[:, 1] > 0))
        # Seeded: some injected lens comes back as a candidate.
        self.assertGreaterEqual(int(np.sum(systems[:, 3] > 0)), 1)
        self.assertIn("%d candidate(s) are arcs of injected lenses, %d are other objects"
                      % (arcs, len(cand) - arcs), text)
        for system, theta_e, _, number, spaces, lens_right, estimate in systems:
            if number == 0:
                continue
            row = cand[int(number) - 1]
            self.assertEqual(per_candidate[int(number) - 1, 1], system)
            self.assertEqual(row["SPACES"], spaces)
            # The lens is right when the candidate's lens lies within 1" of the injected one.
            lens = lenses[lenses[:, 8] == system][0]
            d = np.hypot(row["LENS_X"] - lens[1], row["LENS_Y"] - lens[2]) * PIXEL_SCALE
            self.assertEqual(bool(lens_right), bool(row["LENS_NUMBER"] > 0 and d <= 1.0))
            if row["LENS_NUMBER"] > 0:  # 0 for no estimate (the arc on its lens)
                self.assertAlmostEqual(np.nan_to_num(row["THETA_E"]), estimate, delta=1e-3)


class ReadmeFigures(WorkDirTest):
    """The figures the README quotes from `octarc demo` (default options) against values computed
    here from the demo's output files (image, catalog, truth list, candidates) and from the
    arithmetic of the quoted lines themselves: the README's numbers, not octarc's printout, are
    what is checked, so a stale README or a report that prints a wrong figure fails."""

    def quoted_lines(self):
        with open(os.path.join(SOURCE_DIR, "README.md")) as f:
            text = f.read()
        block = text.split("`octarc demo` simulates", 1)[1].split("```\n", 2)[1]
        return [line for line in block.splitlines() if line.strip() != "..."]

    def quoted(self, pattern):
        """The groups of the one quoted line that matches `pattern`."""
        matches = [m for m in (re.search(pattern, line) for line in self.lines) if m]
        self.assertEqual(len(matches), 1, "README lines matching %r" % pattern)
        return matches[0].groups()

    def assertRounded(self, quoted, value, what):
        """`quoted` (text) is `value` rounded to the decimals it is written with."""
        decimals = len(quoted.split(".")[1]) if "." in quoted else 0
        self.assertLessEqual(abs(float(quoted) - value), 0.5 * 10.0 ** -decimals + 1e-9,
                             "%s: README %s, computed %r" % (what, quoted, value))

    def test_readme_figures_are_the_default_demos(self):
        self.lines = self.quoted_lines()
        out = self.path("demo")
        run_octarc("demo", "--out", out, "--quiet")
        image = fits.getdata(os.path.join(out, "field.fits"))
        truth = np.loadtxt(os.path.join(out, "field.truth.txt"), ndmin=2)
        rows, _ = ldac_objects(os.path.join(out, "field.ldac"))
        with fits.open(os.path.join(out, "candidates", "candidates.fits")) as f:
            cand = f["LDAC_OBJECTS"].data.copy()
            cand_header = f["LDAC_OBJECTS"].header.copy()
        per_candidate = np.loadtxt(os.path.join(out, "injection-candidates.txt"), ndmin=2)

        # The field: its systems, its size in pixels and arcminutes.
        (lens_count,) = self.quoted(r"^octarc demo: a simulated survey field with (\d+) injected")
        systems = set(truth[truth[:, 8] > 0, 8].astype(int))
        self.assertEqual(int(lens_count), len(systems))
        width, height, scale, width_arcmin, height_arcmin = self.quoted(
            r"^  (\d+) x (\d+) px of ([\d.]+)\" \(([\d.]+)' x ([\d.]+)'\)")
        self.assertEqual((int(height), int(width)), image.shape)
        self.assertEqual(float(scale), PIXEL_SCALE)
        self.assertRounded(width_arcmin, int(width) * PIXEL_SCALE / 60, "width [']")
        self.assertRounded(height_arcmin, int(height) * PIXEL_SCALE / 60, "height [']")

        # Injected arcs detected, and their arcness, from the catalog and the truth list.
        found, arc_arcness, other_arcness = recovered_arcs(rows, truth)
        detected, of = self.quoted(r"^Injected arcs detected: (\d+) of (\d+) systems")
        self.assertEqual(int(of), len(systems))
        self.assertEqual(int(detected), len(found))
        (median_best,) = self.quoted(r"^  median best ARCNESS ([\d.]+)$")
        self.assertRounded(median_best, np.median(list(found.values())), "median best ARCNESS")
        for label, values in (("injected arcs", arc_arcness), ("other objects", other_arcness)):
            n, median, percent = self.quoted(
                r"^  %s +(\d+) rows: median ([\d.]+), ([\d.]+)%% above 0.1$" % label)
            self.assertEqual(int(n), len(values), label)
            self.assertRounded(median, np.median(values), label + " median")
            self.assertRounded(percent, 100.0 * np.mean(values > 0.1), label + " % above 0.1")

        # The search: rows and level-1 objects of the catalog (the whole field is searched),
        # the rejected percentage from the quoted counts.
        objects, searched, selected, rejected = self.quoted(
            r"^  (\d+) objects \((\d+) rows at all levels\) searched; (\d+) rows selected "
            r"\(([\d.]+)% rejected\)$")
        self.assertEqual(int(objects), int(np.sum(rows["THRESH_LEVEL"] == 1)))
        self.assertEqual(int(searched), len(rows))
        self.assertEqual(int(selected), cand_header["NROWSEL"])
        self.assertGreaterEqual(int(selected), len(cand))
        self.assertRounded(rejected, 100.0 * (1.0 - int(selected) / int(searched)), "% rejected")

        # The candidates: their count, per deg2 of the field, and those without a lens.
        count, per_deg2, dark = self.quoted(
            r"^  (\d+) candidate\(s\), ([\d.]+) per deg2; (\d+) without a visible lens$")
        self.assertEqual(int(count), len(cand))
        area_deg2 = int(width) * int(height) * (PIXEL_SCALE / 3600.0) ** 2
        self.assertRounded(per_deg2, int(count) / area_deg2, "candidates per deg2")
        self.assertEqual(int(dark), int(np.sum((cand["CAND_FLAGS"] & 1) != 0)))
        self.assertEqual(int(dark), int(np.sum(cand["LENS_NUMBER"] == 0)))

        # Which candidates are injected arcs: the candidates' own rows against the truth list
        # (a candidate also counts when a row of it at another level matches, which its best
        # row alone cannot show, so the arcs found from best rows are a subset).
        arcs, others = self.quoted(
            r"^  (\d+) candidate\(s\) are arcs of injected lenses, (\d+) are other objects$")
        self.assertEqual(int(arcs) + int(others), len(cand))
        self.assertEqual(int(arcs), int(np.sum(per_candidate[:, 1] > 0)))
        lenses = truth[truth[:, 5] == 1]
        for i, row in enumerate(cand):
            for lens in lenses:
                images = truth[(truth[:, 5] == 2) & (truth[:, 8] == lens[8])]
                from_lens = np.hypot(row["X_IMAGE"] - lens[1], row["Y_IMAGE"] - lens[2])
                from_images = np.hypot(row["X_IMAGE"] - images[:, 1], row["Y_IMAGE"] - images[:, 2])
                if from_lens * PIXEL_SCALE >= 1.0 and np.any(from_images * PIXEL_SCALE <= 2.0):
                    self.assertGreater(per_candidate[i, 1], 0, "candidate %d" % (i + 1))

        # The candidates in LENS_SCORE order, and the injected lenses the README lists with
        # their candidate's rank, against the run's per-system outcomes.
        self.assertTrue(np.all(np.diff(cand["LENS_SCORE"]) <= 0))
        self.assertEqual(list(cand["LENS_RANK"]), list(range(1, len(cand) + 1)))
        outcomes = np.loadtxt(os.path.join(out, "injection-systems.txt"), ndmin=2)
        listed = [m.groups() for m in (re.match(
            r'^ +(\d+) +([\d.]+)" +([\d.]+) +#(\d+) +(yes|no) +([\d.]+)"$', line)
            for line in self.lines) if m]
        self.assertEqual(len(listed), int(np.sum(outcomes[:, 3] > 0)))
        for system, theta_e, mag, number, right, estimate in listed:
            row = outcomes[outcomes[:, 0] == int(system)][0]
            self.assertRounded(theta_e, row[1], "theta_E of system " + system)
            self.assertRounded(mag, row[2], "arc mag of system " + system)
            self.assertEqual(int(number), int(row[3]))
            self.assertEqual(int(cand["LENS_RANK"][int(number) - 1]), int(number))
            self.assertEqual(right == "yes", row[5] == 1)
            self.assertRounded(estimate, row[6], "theta_E estimate of system " + system)


class IntoRealImage(WorkDirTest):
    """--into: lenses injected into the real NTT/EMMI frame, whose pixels are otherwise kept."""

    def test_injected_light_sits_on_the_truth_list(self):
        real = require_shared(self, "ntt-emmi", "galaxies.fits")
        out = self.path("demo")
        proc = run_octarc("demo", "--into", real, "--pixel-scale", 0.35, "--seeing", 1.2,
                          "--gain", 1.7, "--mag-zero", 34.2, "--lenses", 3, "--seed", 4,
                          "--out", out, "--quiet")
        self.assertIn("3 galaxy-galaxy lenses injected into", proc.stdout)
        self.assertIn("has no celestial WCS", proc.stdout)
        # LENS_SCORE's prior: the 3 lenses over the frame's own area (1024^2 pixels of 0.35"),
        # not over a simulated field of --size.
        header = fits.getheader(os.path.join(out, "candidates", "candidates.fits"), "LDAC_OBJECTS")
        self.assertAlmostEqual(header["LENSDENS"], 3 / (1024 * 1024 * (0.35 / 3600) ** 2),
                               places=6)
        added = (fits.getdata(os.path.join(out, "field.fits")).astype(float)
                 - fits.getdata(real).astype(float))
        truth = np.loadtxt(os.path.join(out, "field.truth.txt"), ndmin=2)
        # Only lens systems: a lens galaxy and its images per system.
        self.assertEqual(set(truth[:, 5].astype(int)), {1, 2})
        self.assertEqual(sorted(set(truth[:, 8].astype(int))), [1, 2, 3])
        yy, xx = np.mgrid[1:added.shape[0] + 1, 1:added.shape[1] + 1]
        near = np.zeros(added.shape, bool)
        for lens in truth[truth[:, 5] == 1]:
            near |= np.hypot(xx - lens[1], yy - lens[2]) < 40
        # The injected light (with its photon noise) lies around the lenses; elsewhere the
        # pixels are the frame's own, up to the float32 rounding of its scaled 16-bit values
        # (astropy and cfitsio round a few of them differently).
        self.assertLess(np.abs(added[~near]).max(), 0.01)
        self.assertGreater(added[near].sum(), 0)
        # The lens galaxy's magnitude, at the zero point given: its flux is most of the light.
        lens_flux = np.sum(10 ** (-0.4 * (truth[truth[:, 5] == 1][:, 6] - 34.2)))
        self.assertGreater(added[near].sum(), 0.8 * lens_flux)

        # The injected image itself as --into with the same --out: refused, nothing touched.
        field = os.path.join(out, "field.fits")
        before = fits.getdata(field).copy()
        r = run_octarc("demo", "--into", field, "--pixel-scale", 0.35, "--seeing", 1.2,
                       "--gain", 1.7, "--mag-zero", 34.2, "--out", out, "--quiet", check=False)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("octarc never writes over its inputs", r.stderr)
        np.testing.assert_array_equal(fits.getdata(field), before)
        # A real image's instrument is never assumed.
        r = run_octarc("demo", "--into", real, "--pixel-scale", 0.35, "--seeing", 1.2,
                       "--mag-zero", 34.2, "--out", self.path("x"), "--quiet", check=False)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--gain", r.stderr)
        self.assertFalse(os.path.exists(self.path("x")))


class BadInput(WorkDirTest):

    def check_error(self, words, *args):
        proc = run_octarc("demo", "--quiet", *args, check=False)
        self.assertNotEqual(proc.returncode, 0, proc.stderr)
        lines = proc.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, proc.stderr)
        for w in words:
            self.assertIn(w, lines[0])

    def test_nonsense_ranges_write_nothing(self):
        out = self.path("demo")
        self.check_error(["--size", "0"], "--size", 0, "--out", out)
        self.check_error(["--lenses", "-1"], "--lenses", -1, "--out", out)
        self.check_error(["--lenses", "do not fit"], "--size", 128, "--lenses", 40, "--out", out)
        self.assertEqual(os.listdir(self.work), [])

    def test_output_directory_that_cannot_be_made(self):
        with open(self.path("file.txt"), "w") as f:
            f.write("x")
        self.check_error(["file.txt"], "--size", 128, "--lenses", 1, "--out",
                         self.path("file.txt/demo"))
        self.assertEqual(os.listdir(self.work), ["file.txt"])


if __name__ == "__main__":
    unittest.main()
