"""`octarc simulate database` on the Hubble eXtreme Deep Field image, checked against SEP.

The XDF image of the shared data is a display-stretched luminance picture (its header says so):
its fluxes are not linear, so the database it gives is good for morphology only. That is what
the lens simulations take from a source galaxy; they rescale its flux to a drawn magnitude.

With the defaults (4 sigma, DETECT_MINAREA 5, --min-size 25 pixels) the image gives 1784
objects, of which 401 are kept: 16 touch the border and 1367 have fewer than 25 pixels. SEP,
run with the same rules (SExtractor's background, no filter, no deblending, no cleaning), finds
the same objects with the same fluxes.
"""
import os
import subprocess
import unittest

import numpy as np
from astropy.io import fits

from octarc_testlib import WorkDirTest, require_shared, run_octarc

XDF = ("xdf", "xdf_luminance.fits")


def sep_reference(image_path, threshold_sigma=4.0, min_area=5, min_size=25):
    """The galaxies SEP keeps under the builder's rules: (flux, area) sorted by flux."""
    import sep
    data = fits.getdata(image_path).astype(np.float32)
    bkg = sep.Background(data.copy())
    sub = data - bkg.back()
    sep.set_extract_pixstack(10 ** 7)
    objects, seg = sep.extract(sub, threshold_sigma, err=bkg.globalrms, minarea=min_area,
                               filter_kernel=None, deblend_cont=1.0, clean=False,
                               segmentation_map=True)
    height, width = data.shape
    kept = []
    for i in range(len(objects)):
        ys, xs = np.nonzero(seg == i + 1)
        if xs.min() == 0 or ys.min() == 0 or xs.max() == width - 1 or ys.max() == height - 1:
            continue
        if len(xs) < min_size:
            continue
        kept.append((float(sub[ys, xs].astype(np.float64).sum()), len(xs)))
    return len(objects), bkg.globalrms, sorted(kept)


class XdfDatabase(WorkDirTest):
    def test_builds_the_database_sep_finds(self):
        image = require_shared(self, *XDF)
        cat = self.path("xdf.fits")
        proc = run_octarc("simulate", "database", image, "-o", cat, "--zeropoint", "30",
                          "--psf-fwhm", "0.1")
        self.assertIn("401 galaxies from 1784 objects", proc.stdout)
        self.assertEqual(sorted(os.listdir(self.work)),
                         ["xdf.fits", "xdf_images.fits", "xdf_psf.fits"])

        n_objects, sigma, reference = sep_reference(image)
        self.assertEqual(n_objects, 1784)
        with fits.open(cat) as hdul:
            table = hdul[1].data
            for name in ("IDENT", "RA", "DEC", "MAG", "BAND", "WEIGHT", "GAL_FILENAME",
                         "PSF_FILENAME", "GAL_HDU", "PSF_HDU", "PIXEL_SCALE", "NOISE_MEAN",
                         "NOISE_VARIANCE", "NOISE_FILENAME", "stamp_flux"):
                self.assertIn(name, table.columns.names)
            self.assertEqual(len(table), 401)
            self.assertEqual(len(table), len(reference))
            # Same galaxies, same fluxes (the two backgrounds agree to float rounding).
            np.testing.assert_allclose(np.sort(table["stamp_flux"]),
                                       [f for f, _ in reference], rtol=1e-5)
            np.testing.assert_allclose(table["PIXEL_SCALE"], 0.138)  # header PIXSCALE
            np.testing.assert_allclose(table["NOISE_VARIANCE"], sigma ** 2, rtol=1e-5)
            np.testing.assert_allclose(table["MAG"], 30 - 2.5 * np.log10(table["stamp_flux"]),
                                       rtol=0, atol=1e-9)
            self.assertTrue(np.all(table["GAL_FILENAME"] == "xdf_images.fits"))
            self.assertTrue(np.all(table["PSF_FILENAME"] == "xdf_psf.fits"))
            threshold = 4.0 * np.sqrt(table["NOISE_VARIANCE"][0])

        with fits.open(self.path("xdf_images.fits")) as stamps:
            self.assertEqual(len(stamps), 402)  # empty primary + one HDU per galaxy
            for row in table:
                stamp = stamps[row["GAL_HDU"]].data.astype(np.float64)
                self.assertEqual(stamps[row["GAL_HDU"]].header["IDENT"], row["IDENT"])
                h, w = stamp.shape
                self.assertEqual((h % 2, w % 2), (1, 1))
                self.assertAlmostEqual(stamp.sum(), row["stamp_flux"],
                                       delta=1e-9 * row["stamp_flux"])
                # Noise-free and clean: only the footprint, every pixel of it above 4 sigma.
                nonzero = stamp[stamp != 0]
                self.assertEqual(len(nonzero), row["ISOAREA_IMAGE"])
                self.assertTrue(np.all(nonzero > threshold * (1 - 1e-6)))
                # Centred: with the centre pixel at the rounded centroid, the stamp gives X_IMAGE.
                x0 = round(row["X_IMAGE"] - 1) - (w - 1) // 2
                y0 = round(row["Y_IMAGE"] - 1) - (h - 1) // 2
                ys, xs = np.nonzero(stamp)
                cx = (stamp[ys, xs] * (xs + x0)).sum() / stamp[ys, xs].sum() + 1
                self.assertAlmostEqual(cx, row["X_IMAGE"], delta=1e-4)
        with fits.open(self.path("xdf_psf.fits")) as psf:
            self.assertAlmostEqual(float(psf[0].data.astype(np.float64).sum()), 1.0, places=5)

    def test_the_lens_simulator_uses_it(self):
        image = require_shared(self, *XDF)
        cat = self.path("xdf.fits")
        run_octarc("simulate", "database", image, "-o", cat, "--quiet")
        out = self.path("lenses.fits")
        run_octarc("simulate", "lenses", "-n", "20", "--seed", "7", "--database", cat,
                   "-o", out, "--threads", "1", "--quiet", "--sampling", "plain")
        with fits.open(out) as hdul:
            systems = hdul["LDAC_OBJECTS"].data
            head = fits.Header.fromstring("".join(c.ljust(80) for c in
                                                  hdul["LDAC_IMHEAD"].data[0][0]), sep="")
            self.assertEqual(head["OCTNSYS"], 20)
            # Every system's source is a row of the 401-galaxy database, lensed and detected.
            self.assertTrue(np.all((systems["SOURCE_INDEX"] >= 0) &
                                   (systems["SOURCE_INDEX"] < 401)))
            self.assertGreater(len(set(systems["SOURCE_INDEX"])), 10)
            # Systems below the skip limit on theta_E are counted but not rendered (no row).
            self.assertGreater(len(systems), 0)
            self.assertEqual(len(systems) + head["OCTNSKIP"], 20)
            self.assertTrue(np.all(systems["MAGNIFICATION"] > 1.0))
            self.assertTrue(np.all(systems["N_OBJECTS"] >= 1))


class BadInput(WorkDirTest):
    def expect_failure(self, *args):
        out = os.path.join(self.work, "out")
        os.makedirs(out, exist_ok=True)
        proc = run_octarc("simulate", "database", *args, "-o", os.path.join(out, "db.fits"),
                          check=False)
        self.assertEqual(proc.returncode, 1, proc.stderr)
        lines = proc.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, proc.stderr)
        self.assertEqual(os.listdir(out), [])
        return lines[0]

    def image(self, header=None):
        y, x = np.mgrid[0:128, 0:128]
        rng = np.random.default_rng(5)
        data = 100 + 300 * np.exp(-((x - 64) ** 2 + (y - 64) ** 2) / 18.0) + \
            rng.normal(0, 2, (128, 128))
        path = self.path("image.fits")
        fits.PrimaryHDU(data.astype(np.float32), header=header).writeto(path)
        return path

    def test_not_an_image(self):
        text = self.path("notes.fits")
        with open(text, "w") as f:
            f.write("not FITS\n")
        self.assertIn("notes.fits", self.expect_failure(text))

    def test_a_table(self):
        table = self.path("table.fits")
        fits.HDUList([fits.PrimaryHDU(),
                      fits.BinTableHDU.from_columns([fits.Column("A", "D", array=[1.0])])]
                     ).writeto(table)
        self.assertIn("table.fits", self.expect_failure(table))

    def test_no_pixel_scale(self):
        msg = self.expect_failure(self.image())
        self.assertIn("--pixel-scale", msg)
        self.assertIn("image.fits", msg)

    def test_header_cards_out_of_their_range(self):
        # A pixel scale or zero point card that is there but not a number in its range is an
        # error naming the image and the card, not a missing one.
        for key, value, expected in (("PIXSCALE", -0.2, "PIXSCALE = -0.2 is not a finite number "
                                      "> 0 (arcsec)"),
                                     ("PIXSCALE", "0.2", "PIXSCALE = 0.2 is not a finite number "
                                      "> 0 (arcsec)"),
                                     ("MAGZERO", "abc", "MAGZERO = abc is not a finite number "
                                      "(mag)")):
            with self.subTest(key=key, value=value):
                header = fits.Header()
                if key != "PIXSCALE":
                    header["PIXSCALE"] = 0.2
                header[key] = value  # a string is a quoted card: FITS types a value as written
                path = self.image(header)
                msg = self.expect_failure(path)
                self.assertIn(path + ": " + expected, msg)
                os.remove(path)

    def test_threshold_not_positive(self):
        header = fits.Header()
        header["PIXSCALE"] = 0.05
        image = self.image(header)
        for value in ("0", "-2"):
            self.assertIn("--threshold", self.expect_failure(image, "--threshold", value))
        # The same image builds with a sensible threshold.
        run_octarc("simulate", "database", image, "-o", self.path("ok.fits"), "--quiet")
        self.assertEqual(len(fits.getdata(self.path("ok.fits"), 1)), 1)


if __name__ == "__main__":
    unittest.main()
