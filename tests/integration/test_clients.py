"""The astromatic tools downstream of SExtractor on octarc's catalogs: PSFEx and SCAMP give the
same results on a SExtractor catalog and on that catalog after `octarc measure` appended its
columns (.psf and .head files compared byte for byte); `octarc detect` catalogs lack the columns
they need, and they say so."""
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import (OCTARC, SEX_SHARE, WorkDirTest, have_program, run_octarc,
                            run_sextractor, write_param)

SHIPPED = os.path.normpath(os.path.join(os.path.dirname(OCTARC), "..", "share", "octarc"))
# The columns of a SExtractor run made for PSFEx and SCAMP.
SEX_COLUMNS = ["NUMBER", "X_IMAGE", "Y_IMAGE", "XWIN_IMAGE", "YWIN_IMAGE", "ERRAWIN_IMAGE",
               "ERRBWIN_IMAGE", "ERRTHETAWIN_IMAGE", "X_WORLD", "Y_WORLD", "ERRA_WORLD",
               "ERRB_WORLD", "ERRTHETA_WORLD", "FLUX_AUTO", "FLUXERR_AUTO", "MAG_AUTO",
               "MAGERR_AUTO", "FLUX_APER(1)", "FLUXERR_APER(1)", "FLUX_RADIUS", "ELONGATION",
               "SNR_WIN", "FLAGS", "VIGNET(35,35)"]


def run_tool(cmd, cwd):
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)


def psfex(catalog, cwd):
    config = os.path.join(cwd, "default.psfex")
    with open(config, "w") as f:
        subprocess.run(["psfex", "-dd"], stdout=f, check=True)
    return run_tool(["psfex", catalog, "-c", config, "-CHECKPLOT_TYPE", "NONE",
                     "-CHECKIMAGE_TYPE", "NONE", "-WRITE_XML", "N", "-PSF_DIR", cwd,
                     "-VERBOSE_TYPE", "QUIET"], cwd)


def scamp(catalog, reference, cwd):
    config = os.path.join(cwd, "default.scamp")
    with open(config, "w") as f:
        subprocess.run(["scamp", "-dd"], stdout=f, check=True)
    return run_tool(["scamp", catalog, "-c", config, "-ASTREF_CATALOG", "FILE",
                     "-ASTREFCAT_NAME", reference, "-CHECKPLOT_DEV", "NULL", "-WRITE_XML", "N",
                     "-VERBOSE_TYPE", "QUIET"], cwd)


@unittest.skipUnless(have_program("psfex") and have_program("scamp"),
                     "psfex and scamp not installed")
class PsfexAndScamp(WorkDirTest):
    """A simulated 1024^2 field with a TAN WCS; its truth list is SCAMP's reference catalog.
    The field and its two catalogs are made once for the class; each test works in its own
    directory."""

    @classmethod
    def setUpClass(cls):
        cls.data = tempfile.mkdtemp(prefix="octarc-clients-")
        cls.addClassCleanup(shutil.rmtree, cls.data, ignore_errors=True)  # also when setup fails
        cls.image = os.path.join(cls.data, "field.fits")
        run_octarc("simulate", "field", "-o", cls.image, "--size", 1024, "--seed", 5, "--quiet")
        param = write_param(os.path.join(cls.data, "sex.param"), SEX_COLUMNS)
        cls.catalog, checks = run_sextractor(
            cls.image, cls.data, "field", param, 3.0,
            ["-FILTER", "N", "-DETECT_MINAREA", "5", "-PHOT_APERTURES", "10"], ["SEGMENTATION"])
        cls.segmentation = checks["SEGMENTATION"]
        cls.appended = os.path.join(cls.data, "field+octarc.ldac")
        # The shipped column list, as a user would append it.
        run_octarc("measure", cls.image, "-c", os.path.join(SEX_SHARE, "default.sex"),
                   "-PARAMETERS_NAME", os.path.join(SHIPPED, "octarc.param"),
                   "-SEGMENTATION_NAME", cls.segmentation, "-INPUT_CATALOG", cls.catalog,
                   "-CATALOG_NAME", cls.appended, "-FILTER", "N", "-VERBOSE_TYPE", "QUIET")

    def test_measure_appends_the_shipped_columns(self):
        with fits.open(self.catalog) as a, fits.open(self.appended) as b:
            self.assertGreater(len(b[2].columns), len(a[2].columns))

    def twice(self, tool, name, *extra):
        """Runs `tool` on the original and on the appended catalog, each copied as cat.ldac
        into a directory of its own; returns the two output files' bytes."""
        outputs = []
        for tag, catalog in (("original", self.catalog), ("appended", self.appended)):
            d = self.path(tag)
            os.mkdir(d)
            shutil.copy(catalog, os.path.join(d, "cat.ldac"))
            proc = tool("cat.ldac", *extra, d)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            with open(os.path.join(d, name), "rb") as f:
                outputs.append(f.read())
        return outputs

    def test_psfex_makes_the_same_psf(self):
        original, appended = self.twice(psfex, "cat.psf")
        self.assertEqual(original, appended)
        with fits.open(os.path.join(self.path("original"), "cat.psf")) as f:
            self.assertGreater(f["PSF_DATA"].header["ACCEPTED"], 10)

    def test_scamp_finds_the_same_solution(self):
        # Reference catalog: the true positions and magnitudes of the brighter objects.
        truth = np.loadtxt(self.image.replace(".fits", ".truth.txt"), ndmin=2)
        truth = truth[truth[:, 6] < 24]  # id x y ra dec kind mag theta_E system
        n = len(truth)
        reference = self.path("reference.ldac")
        fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU.from_columns([
            fits.Column(name="X_WORLD", format="1D", unit="deg", array=truth[:, 3]),
            fits.Column(name="Y_WORLD", format="1D", unit="deg", array=truth[:, 4]),
            fits.Column(name="ERRA_WORLD", format="1E", unit="deg", array=np.full(n, 2e-5)),
            fits.Column(name="ERRB_WORLD", format="1E", unit="deg", array=np.full(n, 2e-5)),
            fits.Column(name="ERRTHETA_WORLD", format="1E", unit="deg", array=np.zeros(n)),
            fits.Column(name="MAG", format="1E", unit="mag", array=truth[:, 6]),
            fits.Column(name="MAGERR", format="1E", unit="mag", array=np.full(n, 0.02))],
            name="LDAC_OBJECTS")]).writeto(reference)
        original, appended = self.twice(scamp, "cat.head", reference)
        self.assertEqual(original, appended)
        # SCAMP's .head is text, one card a line, its COMMENT lines in UTF-8.
        head = {}
        for line in original.decode("utf-8").splitlines():
            if line[8:10] == "= ":
                card = fits.Card.fromstring(line)
                head[card.keyword] = card.value
        self.assertEqual(head["CTYPE1"], "RA---TAN")
        # Matched to the reference to better than 0.1".
        self.assertGreater(head["ASTRRMS1"], 0.0)
        self.assertLess(head["ASTRRMS1"], 0.1 / 3600)

    def test_detect_catalogs_lack_the_columns_they_need(self):
        detected = self.path("detect.ldac")
        run_octarc("detect", self.image, "-c", os.path.join(SHIPPED, "octarc.sex"),
                   "-CATALOG_NAME", detected, "-VERBOSE_TYPE", "QUIET")
        proc = psfex(detected, self.work)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("not found in catalog", proc.stderr)  # FLUX_RADIUS (spelt FLUS_RADIUS)
        proc = scamp(detected, detected, self.work)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("XWIN_IMAGE parameter not found in catalog", proc.stderr)


if __name__ == "__main__":
    unittest.main()
