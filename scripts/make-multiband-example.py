#!/usr/bin/python3
"""Makes the two-band example of testdata/: an r-band image (the measurement band) and a g-band
image of the same 300 x 300 field on one pixel grid, with three systems of known colours, and
the table of what was injected where.

  (a) a red early-type lens with a blue tangential arc;
  (b) a dark-lens pair: a primary arc and its counter-image of the same colour on the opposite
      side of an invisible lens, at a smaller separation;
  (c) a red lens with an arc of its own (red) colour, which a colour cut removes;
plus two field galaxies and a star.

Usage: /usr/bin/python3 scripts/make-multiband-example.py [OUTDIR]   (default: testdata/)
Writes multiband.r.fits.gz, multiband.g.fits.gz and multiband.truth.txt. Needs python3-numpy
and python3-astropy (Debian packages); the output depends only on SEED.
"""
import os
import subprocess
import sys

import numpy as np
from astropy.io import fits

SIZE = 300
PIXEL_SCALE_DEG = 0.257 / 3600.0
SEEING_FWHM_PIX = 0.9 / 0.257
GAIN = 4.0  # e-/ADU, both bands
SEED = 20080102
# Per band: sky level and total noise sigma (ADU), zero-point (mag of 1 ADU).
BANDS = {"r": (100.0, 5.0, 30.0), "g": (60.0, 4.0, 29.5)}

# What is injected: (name, kind, parameters, r mag, g - r). Positions are 0-based numpy pixels
# (add 1 for FITS); the truth table gives them 1-based.
LENSES = [
    # name, x, y, r_eff (px), axis ratio, angle (deg), r mag, g - r
    ("a.lens", 80.3, 90.6, 3.5, 0.8, 20.0, 19.5, 1.3),
    ("c.lens", 150.4, 215.3, 3.5, 0.75, -40.0, 19.5, 1.3),
]
ARCS = [
    # name, centre x, y, radius (px), half-opening (deg), direction (deg), width (px), r mag,
    # g - r
    ("a.arc", 80.3, 90.6, 18.0, 50.0, 60.0, 1.3, 20.5, 0.2),
    # (b): theta_E = 11 px, source 3 px off axis: images at 14 and 8 px, on opposite sides.
    ("b.arc", 215.2, 85.4, 14.0, 45.0, 200.0, 1.2, 20.6, 0.6),
    ("b.counter", 215.2, 85.4, 8.0, 20.0, 20.0, 1.2, 21.8, 0.6),
    ("c.arc", 150.4, 215.3, 17.0, 50.0, -120.0, 1.3, 20.5, 1.3),
]
FIELD = [
    # name, x, y, r_eff, axis ratio, angle, Sersic n, r mag, g - r
    ("field.disk", 40.0, 240.0, 4.0, 0.5, -30.0, 1.0, 20.0, 0.4),
    ("field.red", 262.0, 252.0, 3.0, 0.7, 60.0, 4.0, 20.5, 1.2),
    ("field.star", 250.2, 160.7, 0.3, 1.0, 0.0, 0.5, 19.0, 0.8),
]


def sersic(x, y, x0, y0, r_eff, q, theta_deg, n):
    """Elliptical Sersic profile (pixel-centre sampled), unit total."""
    t = np.radians(theta_deg)
    dx, dy = x - x0, y - y0
    u = dx * np.cos(t) + dy * np.sin(t)
    v = -dx * np.sin(t) + dy * np.cos(t)
    r = np.sqrt(u * u + (v / q) ** 2)
    b = 2.0 * n - 1.0 / 3.0 + 0.009876 / n
    img = np.exp(-b * ((r / r_eff) ** (1.0 / n) - 1.0))
    return img / img.sum()


def arc(x, y, x0, y0, radius, half_open_deg, centre_deg, width):
    """A tangential arc: a Gaussian ring of `radius` about (x0, y0) cut to an opening; unit total."""
    dx, dy = x - x0, y - y0
    r = np.hypot(dx, dy)
    phi = np.degrees(np.arctan2(dy, dx)) - centre_deg
    phi = (phi + 180.0) % 360.0 - 180.0
    img = np.exp(-0.5 * ((r - radius) / width) ** 2) * np.exp(-0.5 * (phi / (0.6 * half_open_deg)) ** 4)
    return img / img.sum()


def seeing(image):
    """Convolution with a circular Gaussian of SEEING_FWHM_PIX (FFT; the edges wrap, far from any
    source)."""
    sigma = SEEING_FWHM_PIX / 2.3548
    f = np.fft.fftfreq(SIZE)
    kernel = np.exp(-2.0 * (np.pi * sigma) ** 2 * (f[:, None] ** 2 + f[None, :] ** 2))
    return np.real(np.fft.ifft2(np.fft.fft2(image) * kernel))


def flux_adu(mag, zeropoint):
    return 10.0 ** (-0.4 * (mag - zeropoint))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "testdata"
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(SEED)
    y, x = np.mgrid[0:SIZE, 0:SIZE].astype(float)
    # Unit-flux shapes, then each band's scene from the magnitudes.
    shapes = []
    for name, x0, y0, r_eff, q, th, r_mag, gr in LENSES:
        shapes.append((name, x0, y0, sersic(x, y, x0, y0, r_eff, q, th, 4.0), r_mag, gr))
    for name, x0, y0, radius, half, direction, width, r_mag, gr in ARCS:
        t = np.radians(direction)
        # The arc's position in the truth table: the middle of its ridge.
        xs, ys = x0 + radius * np.cos(t), y0 + radius * np.sin(t)
        shapes.append((name, xs, ys, arc(x, y, x0, y0, radius, half, direction, width), r_mag, gr))
    for name, x0, y0, r_eff, q, th, n, r_mag, gr in FIELD:
        shapes.append((name, x0, y0, sersic(x, y, x0, y0, r_eff, q, th, n), r_mag, gr))

    header = fits.Header()
    header["CTYPE1"], header["CTYPE2"] = "RA---TAN", "DEC--TAN"
    header["CRPIX1"], header["CRPIX2"] = 150.5, 150.5
    header["CRVAL1"], header["CRVAL2"] = 150.1, 2.2
    header["CD1_1"], header["CD1_2"] = -PIXEL_SCALE_DEG, 0.0
    header["CD2_1"], header["CD2_2"] = 0.0, PIXEL_SCALE_DEG
    header["EQUINOX"], header["RADESYS"] = 2000.0, "ICRS"
    header["GAIN"] = (GAIN, "e-/ADU")
    header["SATURATE"] = (30000.0, "ADU")
    for band, (sky, noise, zeropoint) in BANDS.items():
        scene = np.zeros((SIZE, SIZE))
        for _, _, _, shape, r_mag, gr in shapes:
            scene += flux_adu(r_mag + (gr if band == "g" else 0.0), zeropoint) * shape
        scene = seeing(scene)
        electrons = rng.poisson(np.clip(scene + sky, 0.0, None) * GAIN)
        read = rng.normal(0.0, np.sqrt(max(noise ** 2 - sky / GAIN, 0.0)), scene.shape)
        # Whole ADU (the noise is 4-5 ADU): 16-bit integers keep the files small.
        image = np.round(electrons / GAIN + read).astype(np.int16)
        h = header.copy()
        h["FILTER"] = (band, "band")
        h["MAGZERO"] = (zeropoint, "magnitude of 1 ADU")
        h["OBJECT"] = "octarc two-band example"
        h["COMMENT"] = "Made by scripts/make-multiband-example.py (octarc); seed %d" % SEED
        path = os.path.join(out, "multiband.%s.fits" % band)
        fits.PrimaryHDU(image, h).writeto(path, overwrite=True)
        subprocess.run(["gzip", "-9nf", path], check=True)

    with open(os.path.join(out, "multiband.truth.txt"), "w") as f:
        f.write("# What scripts/make-multiband-example.py injected (seed %d): position (1-based "
                "pixels; an arc's is the middle of its ridge), r magnitude, g - r.\n" % SEED)
        f.write("# name x y r_mag g_r\n")
        for name, xs, ys, _, r_mag, gr in shapes:
            f.write("%-10s %7.2f %7.2f %6.2f %5.2f\n" % (name, xs + 1, ys + 1, r_mag, gr))


if __name__ == "__main__":
    main()
