"""octarc's own columns, value by value: SIZE_IMAGE, E1/E2/E_IMAGE, I_AAB/I_ABB/I_AAA/I_BBB_IMAGE,
ARCNESS, ANTIARCNESS, SKEW_MAJOR, SKEW_MINOR and ARC_SIDE of every object at every level of an
`octarc detect` run, recomputed from the SEGMENTATION check-image (one HDU per level, labels =
NUMBER) and the background-subtracted pixels, in two independent ways:

- numpy: centroid, centred second moments, theta = 0.5 atan2(2 Ixy, Ixx - Iyy) in (-90, 90] deg,
  then every pixel's offsets rotated into the major/minor-axis frame (da, db) and the third
  moments summed there (core/Conventions.h, METHOD.md section 1);
- photutils: SourceCatalog.moments_central of the same segmentation and pixels (sums of
  w dx^p dy^q about photutils' own centroid), the major axis taken as the eigenvector of the
  second-moment matrix with the larger eigenvalue, and the third-moment tensor rotated into that
  frame with numpy.einsum.

With FILTER N every footprint pixel is above a positive threshold on the measured image itself,
so photutils (which drops negative pixels from its moments) sees the same pixels as octarc.

Images: the real NTT/EMMI image (AUTO background; the -BACKGROUND check-image must be the image
minus the BACKGROUND check-image, bit for bit) and a synthetic field made here with a flat sky of
exactly 200 ADU (BACK_TYPE MANUAL, so the background-subtracted pixels are computed here without
any octarc output), holding galaxies and rasterised circular arcs whose centres of curvature are
known: there ARC_SIDE is also checked against the geometry (the centre lies on the +b side of the
centroid for ARC_SIDE +1).

Tolerances, set by what each column stores and by what was reached (largest differences over
every object of both images, both references):
- float64 columns (I_*_IMAGE): 1e-12 s^3, s = SIZE_IMAGE. octarc and the references all sum in
  double, in different orders and about different origins; the differences reached are below
  5e-15 s^3. A term 1e-14 s^3 / E_IMAGE is added for the rounding of the major-axis angle of
  nearly round objects (its error grows as 1/e).
- float32 columns: one float32 ulp of the reference value (the catalog value is the double
  result rounded once; reached: half an ulp), plus the float64 allowance above made
  dimensionless (1e-12, and 1e-12 s for SIZE_IMAGE), for values that cancel to near zero where
  an ulp is tiny.
- ARC_SIDE: exactly the sign of the reference I_aab wherever that is larger than its tolerance.
Swapping any two of these columns (or the values filling them) fails the test.
"""
import math
import os
import unittest

import numpy as np
from astropy import log as astropy_log
from astropy.io import fits
from photutils.segmentation import SegmentationImage, SourceCatalog

from octarc_testlib import (SEX_SHARE, WorkDirTest, ldac_objects, require_shared, run_octarc,
                            write_param)

astropy_log.setLevel("ERROR")  # the ESO-LOG cards of the real image are not FITS keywords

COLUMNS = ["NUMBER", "THRESH_LEVEL", "SIZE_IMAGE", "E1_IMAGE", "E2_IMAGE", "E_IMAGE",
           "I_AAB_IMAGE", "I_ABB_IMAGE", "I_AAA_IMAGE", "I_BBB_IMAGE", "ARCNESS", "ANTIARCNESS",
           "SKEW_MAJOR", "SKEW_MINOR", "ARC_SIDE", "OCT_FLAGS"]
THIRD = {"I_AAB_IMAGE": (2, 1), "I_ABB_IMAGE": (1, 2), "I_AAA_IMAGE": (3, 0),
         "I_BBB_IMAGE": (0, 3)}   # powers of (da, db)
NORMALISED = {"ARCNESS": "I_AAB_IMAGE", "ANTIARCNESS": "I_ABB_IMAGE", "SKEW_MAJOR": "I_AAA_IMAGE",
              "SKEW_MINOR": "I_BBB_IMAGE"}
REL64 = 1e-12        # float64 columns, in units of s^3
THETA_ROUNDING = 1e-14
SKY_ADU = 200.0      # the synthetic field's sky


def statistics(ixx, iyy, ixy, third, theta):
    """The catalog columns from second moments, the four rotated third moments (dict keyed by
    column name) and the major-axis angle, all per object."""
    trace = ixx + iyy
    size = np.sqrt(trace)
    out = {"SIZE_IMAGE": size, "E1_IMAGE": (ixx - iyy) / trace, "E2_IMAGE": 2.0 * ixy / trace,
           "THETA": theta}
    out["E_IMAGE"] = np.hypot(out["E1_IMAGE"], out["E2_IMAGE"])
    out.update(third)
    for name, moment in NORMALISED.items():
        out[name] = third[moment] / size ** 3
    out["ARCNESS"] = np.abs(out["ARCNESS"])
    return out


def numpy_reference(labels, pixels, numbers):
    """Moments of the objects `numbers` of one segmentation level, summed per label with
    numpy.bincount over the pixels (x along NAXIS1, 0-based)."""
    flat = labels.ravel()
    inside = flat > 0
    label = flat[inside]
    yy, xx = np.indices(labels.shape)
    x = xx.ravel()[inside].astype(float)
    y = yy.ravel()[inside].astype(float)
    w = pixels.ravel()[inside].astype(float)
    n = int(label.max()) + 1 if label.size else 1

    def mean(values):
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.bincount(label, w * values, n) / np.bincount(label, w, n)

    # Centroid, then the offsets re-centred once more about their own weighted mean.
    dx = x - mean(x)[label]
    dy = y - mean(y)[label]
    dx -= mean(dx)[label]
    dy -= mean(dy)[label]
    ixx, iyy, ixy = mean(dx * dx), mean(dy * dy), mean(dx * dy)
    theta = 0.5 * np.arctan2(2.0 * ixy, ixx - iyy)
    theta = np.where(theta <= -0.5 * math.pi, theta + math.pi, theta)
    c, s = np.cos(theta)[label], np.sin(theta)[label]
    da = c * dx + s * dy
    db = -s * dx + c * dy
    third = {name: mean(da ** p * db ** q)[numbers] for name, (p, q) in THIRD.items()}
    out = statistics(ixx[numbers], iyy[numbers], ixy[numbers], third, theta[numbers])
    out["X"], out["Y"] = mean(x)[numbers], mean(y)[numbers]
    return out


def photutils_reference(labels, pixels, numbers):
    """The same from photutils' central moments, rotated as tensors into the frame of the
    major axis (eigenvector of the second-moment matrix)."""
    catalog = SourceCatalog(pixels.astype(float), SegmentationImage(labels))
    index = np.searchsorted(catalog.labels, numbers)
    np.testing.assert_array_equal(catalog.labels[index], numbers)
    mc = np.asarray(catalog.moments_central)[index]   # [k, q, p] = sum w dy^q dx^p
    m00 = mc[:, 0, 0]
    second = np.empty((len(numbers), 2, 2))
    second[:, 0, 0] = mc[:, 0, 2] / m00
    second[:, 1, 1] = mc[:, 2, 0] / m00
    second[:, 0, 1] = second[:, 1, 0] = mc[:, 1, 1] / m00
    tensor = np.empty((len(numbers), 2, 2, 2))   # axis 0 = x, 1 = y
    for i in range(2):
        for j in range(2):
            for k in range(2):
                q = i + j + k   # number of y indices
                tensor[:, i, j, k] = mc[:, q, 3 - q] / m00
    _, vectors = np.linalg.eigh(second)
    major = vectors[:, :, 1]   # eigenvalues ascending: the last is the major axis
    theta = np.arctan2(major[:, 1], major[:, 0])
    theta = np.where(theta > 0.5 * math.pi, theta - math.pi, theta)
    theta = np.where(theta <= -0.5 * math.pi, theta + math.pi, theta)
    c, s = np.cos(theta), np.sin(theta)
    rotation = np.stack([np.stack([c, s], axis=-1), np.stack([-s, c], axis=-1)], axis=1)
    rotated = np.einsum("nai,nbj,nck,nijk->nabc", rotation, rotation, rotation, tensor)
    third = {"I_AAB_IMAGE": rotated[:, 0, 0, 1], "I_ABB_IMAGE": rotated[:, 0, 1, 1],
             "I_AAA_IMAGE": rotated[:, 0, 0, 0], "I_BBB_IMAGE": rotated[:, 1, 1, 1]}
    return statistics(second[:, 0, 0], second[:, 1, 1], second[:, 0, 1], third, theta)


def float32_ulp(values):
    return np.spacing(np.abs(values).astype(np.float32)).astype(float)


def assert_columns_match(test, rows, ref, what):
    """Every octopole column of `rows` (one level, in catalog order) against one reference."""
    size = ref["SIZE_IMAGE"]
    with np.errstate(divide="ignore"):
        angle = THETA_ROUNDING / ref["E_IMAGE"]
    tol3 = (REL64 + angle) * size ** 3      # third moments
    # Near theta = +-90 deg the two sides of the cut are the same axis in opposite directions:
    # the odd statistics of such an object may come out with either sign.
    odd_either = np.abs(np.abs(ref["THETA"]) - 0.5 * math.pi) < 1e-9
    for name in THIRD:
        ours = rows[name].astype(float)
        theirs = np.where(odd_either & (np.sign(ours) != np.sign(ref[name])), -ref[name],
                          ref[name])
        bad = np.abs(ours - theirs) > tol3
        test.assertFalse(np.any(bad), "%s %s: %s" % (what, name, first_bad(rows, ours, theirs,
                                                                             bad)))
    for name in list(NORMALISED) + ["E1_IMAGE", "E2_IMAGE", "E_IMAGE", "SIZE_IMAGE"]:
        ours = rows[name].astype(float)
        theirs = ref[name]
        if name in ("ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR"):
            theirs = np.where(odd_either & (np.sign(ours) != np.sign(theirs)), -theirs, theirs)
        if name == "SIZE_IMAGE":
            slack = REL64 * size
        elif name in NORMALISED:
            slack = REL64 + angle
        else:
            slack = np.full(len(size), REL64)
        bad = np.abs(ours - theirs) > float32_ulp(theirs) + slack
        test.assertFalse(np.any(bad), "%s %s: %s" % (what, name, first_bad(rows, ours, theirs,
                                                                             bad)))
    defined = (np.abs(ref["I_AAB_IMAGE"]) > tol3) & ~odd_either
    np.testing.assert_array_equal(rows["ARC_SIDE"][defined],
                                  np.sign(ref["I_AAB_IMAGE"][defined]).astype(int),
                                  err_msg="%s ARC_SIDE" % what)
    # Where I_aab is within rounding of 0 (a footprint symmetric about its minor axis), octarc
    # may give 0, -1 or +1.
    test.assertTrue(np.all(np.isin(rows["ARC_SIDE"], (-1, 0, 1))), what)


def first_bad(rows, ours, theirs, bad):
    i = int(np.argmax(bad))
    return "NUMBER %d: octarc %r, reference %r (%d objects differ)" % (
        rows["NUMBER"][i], ours[i], theirs[i], int(bad.sum()))


def detect(test, image, work, extra, levels):
    """`octarc detect` at `levels` sigma (FILTER N) with the SEGMENTATION, -BACKGROUND and
    BACKGROUND check-images; returns the catalog rows and the check-image paths."""
    param = write_param(os.path.join(work, "octopole.param"), COLUMNS)
    out = os.path.join(work, "octopole.ldac")
    checks = {t: os.path.join(work, "check%d.fits" % i)
              for i, t in enumerate(("SEGMENTATION", "-BACKGROUND", "BACKGROUND"))}
    run_octarc("detect", image, "-c", os.path.join(SEX_SHARE, "default.sex"),
               "-PARAMETERS_NAME", param, "-FILTER", "N", "-THRESH_TYPE", "RELATIVE",
               "-DETECT_LEVELS", ",".join("%.6g" % t for t in levels), "-DETECT_MINAREA", 5,
               "-CATALOG_TYPE", "FITS_LDAC", "-CATALOG_NAME", out,
               "-CHECKIMAGE_TYPE", ",".join(checks), "-CHECKIMAGE_NAME", ",".join(checks.values()),
               "-VERBOSE_TYPE", "QUIET", *extra)
    rows, _ = ldac_objects(out)
    return rows, checks


def check_every_level(test, rows, seg_path, pixels, what, levels):
    """Both references at every level; returns the numpy references by level."""
    references = {}
    with fits.open(seg_path) as seg:
        test.assertEqual(len(seg), len(levels) + 1)
        for k in range(1, len(levels) + 1):
            labels = seg[k].data.astype(np.int64)
            mine = rows[rows["THRESH_LEVEL"] == k]
            numbers = mine["NUMBER"].astype(np.int64)
            # One row per label, NUMBER = label.
            np.testing.assert_array_equal(np.sort(numbers), np.unique(labels[labels > 0]))
            test.assertGreater(len(mine), 0, "%s level %d" % (what, k))
            # No bad pixel, no non-positive flux, no degenerate second moments (bits 1, 2, 4).
            test.assertTrue(np.all(mine["OCT_FLAGS"] & 7 == 0), "%s level %d" % (what, k))
            ref = numpy_reference(labels, pixels, numbers)
            assert_columns_match(test, mine, ref, "%s level %d, numpy" % (what, k))
            assert_columns_match(test, mine, photutils_reference(labels, pixels, numbers),
                                 "%s level %d, photutils" % (what, k))
            references[k] = (mine, ref)
    return references


def thin_arc(image, xc, yc, radius, phi0, half_opening, flux, psf_sigma):
    """Adds a uniform circular arc (centre (xc, yc), 0-based pixels; radius in pixels; centred on
    direction phi0, half-opening in radians) seen through a Gaussian PSF, by summing the PSF over
    points spaced 0.1 px along the arc."""
    count = max(2, int(2 * half_opening * radius / 0.1))
    angles = phi0 + np.linspace(-half_opening, half_opening, count)
    xs, ys = xc + radius * np.cos(angles), yc + radius * np.sin(angles)
    r = int(radius + 5 * psf_sigma) + 2
    x0, y0 = int(xc) - r, int(yc) - r
    yy, xx = np.mgrid[y0:y0 + 2 * r + 1, x0:x0 + 2 * r + 1]
    stamp = np.zeros(xx.shape)
    for px, py in zip(xs, ys):
        stamp += np.exp(-0.5 * ((xx - px) ** 2 + (yy - py) ** 2) / psf_sigma ** 2)
    image[y0:y0 + 2 * r + 1, x0:x0 + 2 * r + 1] += flux * stamp / stamp.sum()


def synthetic_field(path, seed=20261201):
    """A 700 x 700 float32 field: sky exactly SKY_ADU + Gaussian noise of 5 ADU, 40 elliptical
    Gaussian and exponential galaxies, and 9 isolated arcs; returns the arcs as
    (xc, yc, radius, phi0, half-opening) with the centres of curvature in 0-based pixels."""
    rng = np.random.default_rng(seed)
    size = 700
    image = rng.normal(0.0, 5.0, (size, size))
    yy, xx = np.mgrid[0:size, 0:size]
    for _ in range(40):
        x0, y0 = rng.uniform(30, size - 30, 2)
        q, theta = rng.uniform(0.3, 1.0), rng.uniform(0, math.pi)
        u = (xx - x0) * math.cos(theta) + (yy - y0) * math.sin(theta)
        v = (-(xx - x0) * math.sin(theta) + (yy - y0) * math.cos(theta)) / q
        r2 = u * u + v * v
        scale = rng.uniform(1.0, 4.0)
        profile = np.exp(-0.5 * r2 / scale ** 2) if rng.uniform() < 0.5 else \
            np.exp(-np.sqrt(r2) / scale)
        image += 10 ** rng.uniform(3.0, 4.5) * profile / profile.sum()
    arcs = []
    for i in range(9):   # a 3 x 3 grid of cells far from each other
        xc, yc = 120 + 230 * (i % 3) + rng.uniform(-10, 10), 120 + 230 * (i // 3) + \
            rng.uniform(-10, 10)
        radius, phi0 = rng.uniform(12, 30), rng.uniform(-math.pi, math.pi)
        half = math.radians(rng.uniform(20, 80))
        thin_arc(image, xc, yc, radius, phi0, half, rng.uniform(4e3, 2e4), 1.2)
        arcs.append((xc, yc, radius, phi0, half))
    fits.PrimaryHDU((image + SKY_ADU).astype(np.float32)).writeto(path)
    return arcs


class OctopoleColumns(WorkDirTest):

    def test_real_image_every_level(self):
        image = require_shared(self, "ntt-emmi", "galaxies.fits")
        levels = [2.5 * 8.0 ** (k / 14) for k in range(15)]
        rows, checks = detect(self, image, self.work, ["-BACK_TYPE", "AUTO"], levels)
        pixels = np.asarray(fits.getdata(image), dtype=np.float32)  # scaled as SExtractor does
        background = fits.getdata(checks["BACKGROUND"])
        subtracted = fits.getdata(checks["-BACKGROUND"])
        np.testing.assert_array_equal(subtracted, pixels - background)
        refs = check_every_level(self, rows, checks["SEGMENTATION"], subtracted, "galaxies.fits",
                                 levels)
        self.assertGreater(sum(len(m) for m, _ in refs.values()), 4000)

    def test_synthetic_field_with_known_background_and_arcs(self):
        path = self.path("field.fits")
        arcs = synthetic_field(path)
        levels = [3.0, 6.0, 12.0, 24.0]
        rows, checks = detect(self, path, self.work,
                              ["-BACK_TYPE", "MANUAL", "-BACK_VALUE", SKY_ADU], levels)
        pixels = fits.getdata(path) - np.float32(SKY_ADU)   # float32, as octarc subtracts
        refs = check_every_level(self, rows, checks["SEGMENTATION"], pixels, "synthetic field",
                                 levels)
        # The arcs: wherever the object holding an arc's mid-point is the arc alone (its
        # footprint stays inside the arc's annulus), the centre of curvature lies on the side of
        # the centroid that ARC_SIDE names, along the minor axis b = (-sin theta, cos theta).
        checked = 0
        with fits.open(checks["SEGMENTATION"]) as seg:
            for k, (mine, ref) in refs.items():
                labels = seg[k].data
                yy, xx = np.indices(labels.shape)
                for xc, yc, radius, phi0, half in arcs:
                    xm, ym = xc + radius * math.cos(phi0), yc + radius * math.sin(phi0)
                    number = labels[int(round(ym)), int(round(xm))]
                    if number == 0:
                        continue
                    mask = labels == number
                    distance = np.hypot(xx[mask] - xc, yy[mask] - yc)
                    if distance.min() < 0.5 * radius or distance.max() > 1.5 * radius + 6:
                        continue   # merged with something else
                    i = int(np.flatnonzero(mine["NUMBER"] == number)[0])
                    row = mine[i]
                    # Centroid and major axis of the numpy reference, 0-based like (xc, yc).
                    theta = ref["THETA"][i]
                    to_centre = (xc - ref["X"][i], yc - ref["Y"][i])
                    along_b = -math.sin(theta) * to_centre[0] + math.cos(theta) * to_centre[1]
                    self.assertEqual(row["ARC_SIDE"], 1 if along_b > 0 else -1,
                                     "level %d arc at (%.1f, %.1f)" % (k, xc, yc))
                    self.assertGreater(row["ARCNESS"], 0.01)
                    checked += 1
        self.assertGreaterEqual(checked, 20)


if __name__ == "__main__":
    unittest.main()
