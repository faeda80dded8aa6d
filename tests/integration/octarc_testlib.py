"""Helpers of the end-to-end tests: run octarc and source-extractor, read catalogs with astropy.

The tests are run by ctest (through run_testcase.py) with OCTARC_BIN set to the octarc
executable (<build>/bin/octarc). The shared reference data (real survey images) is looked up in
$OCTARC_SHARED_DIR/data/real or ../shared/data/real; tests that need it, or a program that is not
installed, are skipped with a message that starts with MISSING_DATA or MISSING_PROGRAM (on the
CI machine run_testcase.py turns those skips into failures).
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest
import warnings
from unittest import mock

import numpy as np
from astropy.io import fits
from astropy.utils.exceptions import AstropyWarning

warnings.simplefilter("ignore", AstropyWarning)

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
# The scripts' shared module of MPI batch runs (its environment, journal, ranks).
sys.path.insert(0, os.path.join(SOURCE_DIR, "scripts"))
import mpi_ranks  # noqa: E402  (scripts/mpi_ranks.py)
OCTARC = os.environ.get("OCTARC_BIN", os.path.join(SOURCE_DIR, "build", "release", "bin", "octarc"))
SEX_SHARE = "/usr/share/source-extractor"

# Prefixes of the skip reasons for an absent dependency (run_testcase.py looks for them).
MISSING_DATA = "shared reference data not found"
MISSING_PROGRAM = "program not installed:"


def shared_data_dir():
    candidates = []
    if os.environ.get("OCTARC_SHARED_DIR"):
        candidates.append(os.path.join(os.environ["OCTARC_SHARED_DIR"], "data", "real"))
    candidates.append(os.path.join(os.path.dirname(SOURCE_DIR), "shared", "data", "real"))
    for c in candidates:
        if os.path.isdir(c):
            return c
    return None


def require_shared(test, *parts):
    base = shared_data_dir()
    if base is None or not os.path.exists(os.path.join(base, *parts)):
        test.skipTest("%s (../shared/data/real/%s); set OCTARC_SHARED_DIR to run this test"
                      % (MISSING_DATA, "/".join(parts)))
    return os.path.join(base, *parts)


def have_program(name):
    return shutil.which(name) is not None


def require_program(name):
    """Skips the running test (raises unittest.SkipTest) when `name` is not on PATH."""
    if not have_program(name):
        raise unittest.SkipTest("%s %s" % (MISSING_PROGRAM, name))


class WorkDirTest(unittest.TestCase):
    """A test case with a fresh scratch directory."""

    def setUp(self):
        self.work = tempfile.mkdtemp(prefix="octarc-test-")

    def tearDown(self):
        shutil.rmtree(self.work, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.work, name)


def run_octarc(*args, check=True, cwd=None):
    proc = subprocess.run([OCTARC] + [str(a) for a in args], capture_output=True, text=True,
                          cwd=cwd)
    if check and proc.returncode != 0:
        raise AssertionError("octarc %s failed (%d):\n%s" % (" ".join(map(str, args)),
                                                            proc.returncode, proc.stderr))
    return proc


def full_allocation_stacks_env(env):
    """`env` (a dict of environment variables) with full allocation stacks for the sanitizers
    (fast_unwind_on_malloc=0; no effect on a release build), for runs whose expected leaks are a
    third-party library's own and are named in tests/lsan.supp by a function or library that only
    a full stack shows: Open MPI's, and cfitsio's on a corrupt tile. scripts/test.sh unwinds fast
    elsewhere: the full unwind doubles the CPU time of every short octarc run."""
    options = env.get("ASAN_OPTIONS", "")
    env["ASAN_OPTIONS"] = (options + ":" if options else "") + "fast_unwind_on_malloc=0"
    return env


def full_allocation_stacks():
    """A context in which octarc runs with full_allocation_stacks_env."""
    return mock.patch.dict(os.environ, full_allocation_stacks_env(dict(os.environ)))


def mpi_env():
    """The environment of an octarc run under mpirun (scripts/mpi_ranks.py's)."""
    env = mpi_ranks.mpi_env()
    # Open MPI keeps what MPI_Init allocates; tests/lsan.supp names its libraries, which only a
    # full allocation stack shows.
    return full_allocation_stacks_env(env)


def param_names(path):
    """The column names of a .param file, in order (comments and vector sizes left out)."""
    names = []
    with open(path) as f:
        lines = f.read().splitlines()
    for line in lines:
        line = line.split("#")[0].strip()
        if line:
            names.append(re.split(r"[\s(]", line)[0])
    return names


def write_param(path, names):
    with open(path, "w") as f:
        f.write("\n".join(names) + "\n")
    return path


PURE_THRESHOLDING = ["-DEBLEND_NTHRESH", "1", "-DEBLEND_MINCONT", "1.0", "-CLEAN", "N",
                     "-MASK_TYPE", "NONE", "-MEMORY_OBJSTACK", "30000",
                     "-MEMORY_BUFSIZE", "4096", "-VERBOSE_TYPE", "QUIET", "-WRITE_XML", "N"]


# source-extractor allocates and clears its whole pixel stack (MEMORY_PIXSTACK) at every run: on
# the 1024^2 NTT image a run took 203 ms of CPU with a stack the size of the image and 122 ms
# with 100 000 pixels. The stack holds the pixels of the objects still open in the scan, far
# fewer; 100 000 is enough for most test images.
SEXTRACTOR_SMALL_PIXSTACK = 100000


def sextractor_pixstack(images, workdir):
    """A MEMORY_PIXSTACK that cannot overflow: the pixel count of the largest image HDU of
    `images` (one path, or two for dual-image mode, "a,b"; relative to workdir) plus 2
    (SExtractor stops at its last free slot), at least the default 300 000: the stack holds
    pixels above the threshold, each once."""
    pixels = 0
    for image in images.split(","):
        with fits.open(os.path.join(workdir, image.split("[")[0])) as f:
            for hdu in f:
                shape = getattr(hdu, "shape", None) or ()
                if len(shape) >= 2:
                    pixels = max(pixels, int(np.prod(shape)))
    return max(300000, pixels + 2)


def run_sextractor(image, workdir, tag, param, threshold, extra=(), checkimages=()):
    """One source-extractor run in the pure-thresholding configuration. Returns the paths of the
    catalog and of the requested check-images (dict type -> path). The run starts with a small
    pixel stack; when source-extractor reports that it overflowed (a warning it prints whatever
    VERBOSE_TYPE, after which it truncates the largest open object), it runs again with a stack
    that cannot overflow."""
    require_program("source-extractor")
    cat = os.path.join(workdir, "%s.ldac" % tag)
    checks = {t: os.path.join(workdir, "%s.%s.fits" % (tag, t.lower().replace("-", "m")))
              for t in checkimages}

    def command(pixstack):
        cmd = ["source-extractor", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
               "-PARAMETERS_NAME", param, "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", cat,
               "-DETECT_THRESH", str(threshold), "-ANALYSIS_THRESH", str(threshold),
               "-FILTER_NAME", os.path.join(SEX_SHARE, "default.conv"),
               "-STARNNW_NAME", os.path.join(SEX_SHARE, "default.nnw"),
               "-MEMORY_PIXSTACK", str(pixstack)] + PURE_THRESHOLDING + list(extra)
        if checks:
            cmd += ["-CHECKIMAGE_TYPE", ",".join(checks),
                    "-CHECKIMAGE_NAME", ",".join(checks.values())]
        return cmd

    proc = subprocess.run(command(SEXTRACTOR_SMALL_PIXSTACK), check=True, capture_output=True,
                          cwd=workdir, text=True, errors="replace")
    if "Pixel stack overflow" in proc.stderr:
        proc = subprocess.run(command(sextractor_pixstack(image, workdir)), check=True,
                              capture_output=True, cwd=workdir, text=True, errors="replace")
        assert "Pixel stack overflow" not in proc.stderr, proc.stderr
    return cat, checks


def ldac_objects(path, hdu=2):
    with fits.open(path) as f:
        return f[hdu].data.copy(), f[hdu].header.copy()


def ldac_imhead(path, hdu=1):
    """The LDAC_IMHEAD cards of a catalog as an astropy Header."""
    with fits.open(path) as f:
        cards = f[hdu].data[0][0]
    text = "".join(c.ljust(80) for c in cards)
    return fits.Header.fromstring(text)


def card_text(header, key):
    """The value field of a card as written (columns 11-30), for comparing printed values digit
    for digit."""
    return header.cards[key].image[10:30].strip()


def fitsverify_errors(path):
    """The number of errors fitsverify reports on one file, read from its summary line
    ("verification OK: FILE" or "verification FAILED: FILE, N errors"; -1 when there is no such
    line), and its report."""
    require_program("fitsverify")
    proc = subprocess.run(["fitsverify", "-q", "-e", path], capture_output=True, text=True)
    text = proc.stdout + proc.stderr
    if re.search(r"^verification OK: ", text, re.M):
        return 0, text
    m = re.search(r"^verification FAILED: .*, (\d+) errors?\s*$", text, re.M)
    return (int(m.group(1)) if m else -1), text


def run_page_in_chromium(page, driver_js, work, budget_ms=20000):
    """Opens the HTML file `page` in headless Chromium with `driver_js` run after the page's own
    scripts, and returns (the JSON value the driver passed to report(value), wall-clock seconds).

    The page is copied into `work` with a <base> pointing at its folder (its relative links and
    stamps still resolve; the output folder is not touched), and the driver appended. The
    driver calls report(value) when done; report writes JSON into <pre id="test-report">, read
    back from --dump-dom. A fresh profile per call: localStorage starts empty."""
    import json
    import time
    with open(page, encoding="utf-8") as f:
        html = f.read()
    # The page's own script errors are collected from the start, and reported instead of a
    # value when the driver fails.
    base = ('<base href="file://%s/"><script>window.pageErrors = []; addEventListener("error",'
            ' e => pageErrors.push(e.message + " (line " + e.lineno + ")"));</script>'
            % os.path.dirname(os.path.abspath(page)))
    html = html.replace("<head>", "<head>" + base, 1)
    report = ("function report(value) { const p = document.createElement('pre');"
              " p.id = 'test-report'; p.textContent = JSON.stringify(value);"
              " document.body.appendChild(p); }\n")
    driver = ("try {\n" + driver_js + "\n} catch (e) {"
              " report({driverError: String(e), pageErrors}); }")
    html = html.replace("</body>", "<script>\n" + report + driver + "\n</script>\n</body>")
    copy = os.path.join(work, "driven-" + os.path.basename(page))
    with open(copy, "w", encoding="utf-8") as f:
        f.write(html)
    profile = tempfile.mkdtemp(prefix="chromium-", dir=work)
    start = time.monotonic()
    r = subprocess.run(["chromium", "--headless=new", "--no-sandbox", "--disable-gpu",
                        "--allow-file-access-from-files", "--user-data-dir=" + profile,
                        "--virtual-time-budget=%d" % budget_ms, "--window-size=1400,1000",
                        "--dump-dom", "file://" + copy],
                       capture_output=True, text=True, timeout=300)
    seconds = time.monotonic() - start
    m = re.search(r'<pre id="test-report">(.*?)</pre>', r.stdout, re.S)
    if m is None:
        raise AssertionError("the page reported nothing; chromium said:\n" + r.stderr[-3000:])
    text = m.group(1).replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", '"')
    value = json.loads(text.replace("&amp;", "&"))
    if isinstance(value, dict) and "driverError" in value:
        raise AssertionError("the page's script failed: %s; page errors: %s"
                             % (value["driverError"], value["pageErrors"]))
    return value, seconds


def interrupted_python(test, setup, call, after, delay_sec):
    """Runs the Python code `setup`, then the statement `call`, in a fresh Python (this one's
    executable, with this environment), sends it SIGINT `delay_sec` after `call` starts, and
    returns what it printed: "interrupted in NAME: LINE" (the innermost Python frame the
    KeyboardInterrupt came out of) or "finished", then the value of the expression `after`,
    which shows that the module still works. The process must end with status 0."""
    script = (setup + "\nimport traceback\nprint('ready', flush=True)\ntry:\n    " + call +
              "\n    print('finished')\nexcept KeyboardInterrupt as e:\n"
              "    frame = traceback.extract_tb(e.__traceback__)[-1]\n"
              "    print('interrupted in %s: %s' % (frame.name, frame.line))\n"
              "print(" + after + ")\n")
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    test.assertEqual(proc.stdout.readline().strip(), "ready")
    time.sleep(delay_sec)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    test.assertEqual(proc.returncode, 0, err)
    return out


def assert_one_line_error(test, kind, pattern, call, *args, **kwargs):
    """`call(*args, **kwargs)` raises `kind` with a one-line message matching `pattern`."""
    with test.assertRaises(kind) as caught:
        call(*args, **kwargs)
    message = str(caught.exception)
    test.assertNotIn("\n", message)
    test.assertRegex(message, pattern)
