#!/usr/bin/python3
"""Regenerates testdata/: a small synthetic survey field with a lensed arc, and the outputs of
three SExtractor runs on it (one per threshold, pure thresholding, no deblending).

Usage: /usr/bin/python3 scripts/make-testdata.py [OUTDIR]   (default: testdata/)
Needs python3-numpy, python3-astropy and source-extractor (Debian packages).
"""
import os
import subprocess
import sys

import numpy as np
from astropy.io import fits

SIZE = 200                  # pixels per side
SKY_ADU = 100.0             # flat sky level
NOISE_ADU = 5.0             # per-pixel noise sigma
GAIN = 4.0                  # e-/ADU, written to the header
PIXEL_SCALE_DEG = 0.257 / 3600.0   # DLS-like 0.257"/px
THRESHOLDS_SIGMA = (3.0, 6.0, 12.0)
SEED = 20080101


def sersic(x, y, x0, y0, flux, r_eff, q, theta_deg, n):
    """Elliptical Sersic profile (pixel-centre sampled) normalised to `flux`."""
    t = np.radians(theta_deg)
    dx, dy = x - x0, y - y0
    u = dx * np.cos(t) + dy * np.sin(t)
    v = -dx * np.sin(t) + dy * np.cos(t)
    r = np.sqrt(u * u + (v / q) ** 2)
    b = 2.0 * n - 1.0 / 3.0 + 0.009876 / n
    img = np.exp(-b * ((r / r_eff) ** (1.0 / n) - 1.0))
    return flux * img / img.sum()


def arc(x, y, x0, y0, radius, half_open_deg, centre_deg, width, flux):
    """A tangential arc: a Gaussian ring of `radius` around (x0, y0), cut to an opening."""
    dx, dy = x - x0, y - y0
    r = np.hypot(dx, dy)
    phi = np.degrees(np.arctan2(dy, dx)) - centre_deg
    phi = (phi + 180.0) % 360.0 - 180.0
    taper = np.exp(-0.5 * (phi / (0.6 * half_open_deg)) ** 4)
    img = np.exp(-0.5 * ((r - radius) / width) ** 2) * taper
    return flux * img / img.sum()


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "testdata"
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(SEED)
    y, x = np.mgrid[0:SIZE, 0:SIZE].astype(float)
    scene = np.zeros((SIZE, SIZE))
    # The lens: a bright elliptical at the centre, and its arc 16 px (4.1") away.
    scene += sersic(x, y, 100.3, 99.6, 60000.0, 6.0, 0.8, 20.0, 4.0)
    scene += arc(x, y, 100.3, 99.6, 16.0, 50.0, 60.0, 1.3, 12000.0)
    # Field galaxies and a star.
    for (x0, y0, f, re, q, th, n) in [(40, 50, 15000, 4.0, 0.5, -30, 1.0),
                                      (150, 40, 8000, 3.0, 0.7, 70, 1.0),
                                      (30, 160, 20000, 5.0, 0.9, 10, 4.0),
                                      (170, 170, 5000, 2.5, 0.4, 45, 1.0)]:
        scene += sersic(x, y, x0, y0, f, re, q, th, n)
    scene += sersic(x, y, 160.2, 110.7, 25000.0, 1.0, 1.0, 0.0, 0.5)
    electrons = rng.poisson((scene + SKY_ADU) * GAIN)
    image = (electrons / GAIN + rng.normal(0.0, np.sqrt(max(NOISE_ADU**2 - SKY_ADU / GAIN, 0.0)),
                                           scene.shape)).astype(np.float32)

    hdr = fits.Header()
    hdr["OBJECT"] = ("octarc example field", "synthetic: lens + arc + field galaxies")
    hdr["GAIN"] = (GAIN, "e-/ADU")
    hdr["SATURATE"] = (60000.0, "ADU")
    hdr["CTYPE1"], hdr["CTYPE2"] = "RA---TAN", "DEC--TAN"
    hdr["CRPIX1"], hdr["CRPIX2"] = 100.5, 100.5
    hdr["CRVAL1"], hdr["CRVAL2"] = 139.5, 30.0
    hdr["CD1_1"], hdr["CD1_2"] = -PIXEL_SCALE_DEG, 0.0
    hdr["CD2_1"], hdr["CD2_2"] = 0.0, PIXEL_SCALE_DEG
    hdr["EQUINOX"], hdr["RADESYS"] = 2000.0, "ICRS"
    hdr["COMMENT"] = "Made by scripts/make-testdata.py (octarc); seed %d" % SEED
    image_path = os.path.join(out, "example.fits")
    fits.PrimaryHDU(image, hdr).writeto(image_path, overwrite=True)

    param_path = os.path.join(out, "sextractor.param")
    with open(param_path, "w") as f:
        f.write("NUMBER\nX_IMAGE\nY_IMAGE\nX2_IMAGE\nY2_IMAGE\nXY_IMAGE\nA_IMAGE\nB_IMAGE\n"
                "THETA_IMAGE\nISOAREA_IMAGE\nFLUX_ISO\nFLUXERR_ISO\nMAG_ISO\nFLAGS\n")
    for k, t in enumerate(THRESHOLDS_SIGMA, start=1):
        subprocess.run(
            ["source-extractor", image_path,
             "-c", "/dev/null",
             "-PARAMETERS_NAME", param_path,
             "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", os.path.join(out, "example.cat%d.ldac" % k),
             "-DETECT_THRESH", str(t), "-ANALYSIS_THRESH", str(t), "-THRESH_TYPE", "RELATIVE",
             "-DETECT_MINAREA", "5", "-FILTER", "N", "-DEBLEND_NTHRESH", "1", "-CLEAN", "N",
             "-BACK_TYPE", "AUTO", "-BACK_SIZE", "64", "-BACK_FILTERSIZE", "3",
             "-MAG_ZEROPOINT", "30.0", "-SATUR_LEVEL", "60000",
             "-CHECKIMAGE_TYPE", "SEGMENTATION,BACKGROUND",
             "-CHECKIMAGE_NAME", "%s,%s" % (os.path.join(out, "example.seg%d.fits" % k),
                                             os.path.join(out, "example.bkg.fits")),
             "-VERBOSE_TYPE", "QUIET", "-WRITE_XML", "N"],
            check=True)
    # Integer maps compress well; cfitsio reads .fits.gz transparently.
    for name in ["example.fits", "example.bkg.fits"] + ["example.seg%d.fits" % k for k in (1, 2, 3)]:
        subprocess.run(["gzip", "-9nf", os.path.join(out, name)], check=True)


if __name__ == "__main__":
    main()
