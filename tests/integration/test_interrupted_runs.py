"""Interrupted and failing runs leave the complete outputs of the run or none of them.

SIGINT, SIGTERM and SIGKILL are sent at several points of an `octarc detect` with check-images,
of an `octarc measure` in append mode and of an `octarc simulate lenses` run (the points are
found from the progress lines each command prints, or from the time a whole run takes). After
each: either every output exists and is complete (fitsverify: 0 errors; the catalog and the
check-images are from the same run) or none exists; after SIGINT/SIGTERM no temporary file is
left; the inputs are unchanged. After SIGKILL the next run removes the dead run's temporaries.
A run that fails half-way (its check-image exceeds the file-size limit) leaves no catalog.
"""
import hashlib
import os
import re
import resource
import shutil
import signal
import subprocess
import time
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (OCTARC, SEX_SHARE, SOURCE_DIR, WorkDirTest, fitsverify_errors,
                            ldac_imhead, run_sextractor, write_param)

OCTARC_SEX = os.path.join(SOURCE_DIR, "params", "octarc.sex")
SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGKILL)


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def write_field(path, size, seed):
    """A float32 field: sky 100 ADU, noise 5 ADU and Gaussian sources."""
    rng = np.random.default_rng(seed)
    image = rng.normal(100.0, 5.0, (size, size)).astype(np.float32)
    yy, xx = np.mgrid[-12:13, -12:13]
    for _ in range(size * size // 4000):
        x, y = rng.integers(12, size - 12, 2)
        s = rng.uniform(1.0, 3.0)
        image[y - 12:y + 13, x - 12:x + 13] += (rng.uniform(50, 3000) *
                                                np.exp(-(xx ** 2 + yy ** 2) / (2 * s * s)))
    fits.PrimaryHDU(image).writeto(path)


def catches_interrupt(pid):
    """Whether process pid has its own SIGINT handler yet (the SigCgt mask of /proc/PID/status):
    octarc installs it first thing in main(), after the dynamic loader's 80 ms or so."""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("SigCgt:"):
                    return (int(line.split()[1], 16) >> (signal.SIGINT - 1)) & 1 == 1
    except (FileNotFoundError, ProcessLookupError):
        pass
    return False


def run_until(cmd, trigger, sig, cwd, delay=0.0):
    """Starts cmd; when a stderr line matches `trigger` (or, when trigger is None, `delay`
    seconds after octarc has installed its signal handler: a signal before main() ends the
    process by its default action, which this test is not about) sends `sig`. Returns
    (returncode, stderr, whether the signal was sent)."""
    proc = subprocess.Popen(cmd, cwd=cwd, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                            text=True)
    seen = []
    sent = False
    if trigger is None:
        while proc.poll() is None and not catches_interrupt(proc.pid):
            time.sleep(0.001)
        time.sleep(delay)
        if proc.poll() is None:
            proc.send_signal(sig)
            sent = True
    else:
        for line in proc.stderr:
            seen.append(line)
            if re.search(trigger, line):
                if proc.poll() is None:
                    proc.send_signal(sig)
                    sent = True
                break
    rest = proc.stderr.read()
    proc.wait(timeout=120)
    return proc.returncode, "".join(seen) + rest, sent


class Outcome:
    """Checks on the directory a run left."""

    def __init__(self, test, workdir, outputs, inputs):
        self.test, self.workdir, self.outputs, self.inputs = test, workdir, outputs, inputs
        self.interrupted = 0  # runs that the signal ended before they were complete
        self.runs = 0

    def check(self, returncode, stderr, sig, complete_check, fresh=True):
        """`fresh`: no outputs existed before the run (an interrupted run then leaves none);
        otherwise an older run's complete set did (and stays, unless the run completed)."""
        t = self.test
        names = os.listdir(self.workdir)
        present = [o for o in self.outputs if os.path.basename(o) in names]
        temporaries = [n for n in names if ".tmp." in n]
        for path, before in self.inputs.items():
            t.assertEqual(digest(path), before, "input changed: " + path)
        self.runs += 1
        if returncode != 0 and "they are complete" not in stderr:
            self.interrupted += 1
        t.assertIn(len(present), (0, len(self.outputs)),
                   "a partial set of outputs %s after %s (exit %s):\n%s" %
                   (present, sig.name, returncode, stderr))
        if sig != signal.SIGKILL:
            t.assertEqual(temporaries, [], "temporaries after %s:\n%s" % (sig.name, stderr))
            if returncode != 0:
                t.assertEqual(returncode, 128 + sig, stderr)
                t.assertIn("interrupted by " + sig.name, stderr)
                if "they are complete" in stderr:
                    # The signal came while or after the outputs were renamed into place.
                    t.assertEqual(len(present), len(self.outputs), stderr)
                else:
                    t.assertEqual(len(present), 0 if fresh else len(self.outputs), stderr)
        if present:
            for o in self.outputs:
                status, text = fitsverify_errors(o)
                t.assertIn("verification OK", text, o)
            complete_check()
        return bool(present)

    def clear(self):
        for o in self.outputs:
            if os.path.exists(o):
                os.remove(o)


class InterruptedDetect(WorkDirTest):

    @classmethod
    def setUpClass(cls):
        cls.shared = os.path.join(os.path.dirname(__file__), "..", "..", "build")
        cls.fixture = __import__("tempfile").mkdtemp(prefix="octarc-kill-")
        cls.image = os.path.join(cls.fixture, "field.fits")
        write_field(cls.image, 2500, 11)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.fixture, ignore_errors=True)

    def setUp(self):
        super().setUp()
        self.param = write_param(self.path("cols.param"),
                                 ["NUMBER", "THRESH_LEVEL", "X_IMAGE", "Y_IMAGE", "FLUX_ISO",
                                  "ARCNESS"])
        self.catalog = self.path("cat.ldac")
        self.seg = self.path("seg.fits")
        self.bkg = self.path("bkg.fits")

    def command(self, thresh="2.5"):
        return [OCTARC, "detect", self.image, "-c", OCTARC_SEX, "-PARAMETERS_NAME", self.param,
                "-DETECT_THRESH", thresh, "-CATALOG_NAME", self.catalog, "-CHECKIMAGE_TYPE",
                "SEGMENTATION,BACKGROUND", "-CHECKIMAGE_NAME", self.seg + "," + self.bkg,
                "-NTHREADS", "2"]

    def same_run(self):
        """The catalog and the segmentation image come from one run: the same thresholds."""
        imhead = ldac_imhead(self.catalog)
        with fits.open(self.seg) as seg:
            self.assertEqual(len(seg), 16)
            for k in range(1, 16):
                self.assertAlmostEqual(float(seg[k].header["THRESHLD"]),
                                       float(imhead["OCTTH%d" % k]), places=3)

    def test_signals_at_every_stage(self):
        outcome = Outcome(self, self.work, [self.catalog, self.seg, self.bkg],
                          {self.image: digest(self.image), self.param: digest(self.param)})
        triggers = [r"^> Reading", r"^> Level 1 ", r"^> Wrote .*cat\.ldac",
                    r"^> Wrote check-image .*seg\.fits"]
        for sig in SIGNALS:
            for trigger in triggers:
                with self.subTest(signal=sig.name, at=trigger):
                    rc, err, _ = run_until(self.command(), trigger, sig, self.work)
                    outcome.check(rc, err, sig, self.same_run)
                    outcome.clear()
                    for n in os.listdir(self.work):
                        if ".tmp." in n:
                            os.remove(self.path(n))
        # Every trigger point lies before the end of the run.
        self.assertEqual(outcome.interrupted, outcome.runs)

    def test_interrupted_rerun_keeps_the_older_complete_set(self):
        # A complete run, then a second one with another threshold killed part way: the files
        # on disk are always one run's complete set (never a new catalog beside an old image).
        subprocess.run(self.command("2.5"), check=True, capture_output=True)
        outcome = Outcome(self, self.work, [self.catalog, self.seg, self.bkg],
                          {self.image: digest(self.image)})
        for sig in SIGNALS:
            for trigger in [r"^> Level 1 ", r"^> Wrote .*cat\.ldac",
                            r"^> Wrote check-image .*seg\.fits"]:
                with self.subTest(signal=sig.name, at=trigger):
                    rc, err, _ = run_until(self.command("3.0"), trigger, sig, self.work)
                    self.assertTrue(outcome.check(rc, err, sig, self.same_run, fresh=False))
        self.assertEqual(outcome.interrupted, outcome.runs)

    def test_rerun_after_sigkill_removes_the_dead_runs_temporaries(self):
        rc, err, sent = run_until(self.command(), r"^> Wrote .*cat\.ldac", signal.SIGKILL,
                                  self.work)
        self.assertTrue(sent)
        self.assertTrue([n for n in os.listdir(self.work) if ".tmp." in n],
                        "SIGKILL during the check-images leaves their temporaries")
        subprocess.run(self.command(), check=True, capture_output=True)
        self.assertEqual([n for n in os.listdir(self.work) if ".tmp." in n], [])

    def test_failure_part_way_leaves_no_output(self):
        # The check-images exceed a 20 MB file-size limit (the catalog does not): the run fails
        # naming the check-image, and leaves neither it nor the catalog.
        def limit():
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (20_000_000, 20_000_000))
        proc = subprocess.run(self.command(), capture_output=True, text=True, preexec_fn=limit)
        self.assertEqual(proc.returncode, 1, proc.stderr)
        self.assertIn("seg.fits", proc.stderr.splitlines()[-1])
        self.assertEqual(sorted(os.listdir(self.work)), ["cols.param"], proc.stderr)


class InterruptedMeasureAppend(WorkDirTest):
    """`octarc measure` appending to three SExtractor catalogs of a 2500^2 field."""

    @classmethod
    def setUpClass(cls):
        cls.fixture = __import__("tempfile").mkdtemp(prefix="octarc-kill-")
        cls.image = os.path.join(cls.fixture, "field.fits")
        write_field(cls.image, 2500, 12)
        param = write_param(os.path.join(cls.fixture, "sex.param"),
                            ["NUMBER", "X_IMAGE", "Y_IMAGE", "FLUX_ISO", "VIGNET(15,15)"])
        cls.runs = []
        for k, t in enumerate((3.0, 6.0, 12.0)):
            cat, checks = run_sextractor(cls.image, cls.fixture, "t%d" % k, param, t,
                                         extra=["-FILTER", "N"],
                                         checkimages=("SEGMENTATION",))
            cls.runs.append((cat, checks["SEGMENTATION"]))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.fixture, ignore_errors=True)

    def command(self):
        self.outputs = [self.path("out%d.ldac" % k) for k in range(3)]
        return [OCTARC, "measure", self.image, "-c", OCTARC_SEX, "-PARAMETERS_NAME",
                os.path.join(SOURCE_DIR, "params", "octarc.param"),
                "-SEGMENTATION_NAME", ",".join(seg for _, seg in self.runs),
                "-INPUT_CATALOG", ",".join(cat for cat, _ in self.runs),
                "-CATALOG_NAME", ",".join(self.outputs)]

    def test_signals_at_every_stage(self):
        cmd = self.command()
        start = time.monotonic()
        subprocess.run(cmd, check=True, capture_output=True)
        whole = time.monotonic() - start
        for o in self.outputs:
            os.remove(o)
        inputs = {p: digest(p) for run in self.runs for p in run}
        inputs[self.image] = digest(self.image)
        outcome = Outcome(self, self.work, self.outputs, inputs)

        def appended():
            for (cat, _), out in zip(self.runs, self.outputs):
                with fits.open(cat) as a, fits.open(out) as b:
                    self.assertEqual(len(a[2].data), len(b[2].data))
                    self.assertIn("ARCNESS", b[2].columns.names)

        points = [(r"^> Reading", 0), (r"^> Measuring", 0), (None, 0.6 * whole),
                  (None, 0.9 * whole)]
        for sig in SIGNALS:
            for trigger, delay in points:
                with self.subTest(signal=sig.name, at=trigger or "%.2f s" % delay):
                    rc, err, _ = run_until(cmd, trigger, sig, self.work, delay)
                    outcome.check(rc, err, sig, appended)
                    outcome.clear()
                    for n in os.listdir(self.work):
                        if ".tmp." in n:
                            os.remove(self.path(n))
        print("measure: %d of %d runs interrupted" % (outcome.interrupted, outcome.runs))
        self.assertGreaterEqual(outcome.interrupted, outcome.runs // 2)


class InterruptedSimulation(WorkDirTest):

    def test_signals_part_way(self):
        out, stamps = self.path("sims.fits"), self.path("stamps.fits")
        # Plain sampling renders every system: a run long enough to be interrupted part way.
        cmd = [OCTARC, "simulate", "lenses", "-n", "400", "--seed", "5", "--sampling", "plain",
               "-o", out, "--stamps",
               stamps, "--stamp-count", "50", "--threads", "2"]
        start = time.monotonic()
        subprocess.run(cmd, check=True, capture_output=True)
        whole = time.monotonic() - start
        with fits.open(out) as f:
            reference = f["LDAC_OBJECTS"].data.copy()
        outcome = Outcome(self, self.work, [out, stamps], {})
        outcome.clear()

        def complete():
            with fits.open(out) as f:
                np.testing.assert_array_equal(f["LDAC_OBJECTS"].data["SYSTEM"],
                                              reference["SYSTEM"])
            with fits.open(stamps) as f:
                self.assertEqual(f[0].data.shape[0], 50)

        for sig in SIGNALS:
            for fraction in (0.1, 0.5, 0.95):
                with self.subTest(signal=sig.name, at=fraction):
                    rc, err, _ = run_until(cmd, None, sig, self.work, fraction * whole)
                    outcome.check(rc, err, sig, complete)
                    outcome.clear()
                    for n in os.listdir(self.work):
                        if ".tmp." in n:
                            os.remove(self.path(n))
        print("simulate: %d of %d runs interrupted" % (outcome.interrupted, outcome.runs))
        self.assertGreaterEqual(outcome.interrupted, outcome.runs // 2)

    def test_demo_interrupted_between_its_steps_leaves_nothing(self):
        # The demo writes the field, then searches it: interrupted during the search, its
        # directory (which it made) goes, with the field files already written.
        out = self.path("demo")
        for sig in (signal.SIGINT, signal.SIGTERM):
            with self.subTest(signal=sig.name):
                rc, err, sent = run_until([OCTARC, "demo", "--size", "1024", "--lenses", "2",
                                           "--out", out], r"^> Searching", sig, self.work)
                self.assertTrue(sent, err)
                self.assertEqual(rc, 128 + sig, err)
                self.assertEqual(os.listdir(self.work), [], err)


if __name__ == "__main__":
    unittest.main()
