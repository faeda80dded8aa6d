#!/usr/bin/python3
"""Writes the seed corpus of the fuzz targets (fuzz/): one folder per target under OUTDIR,
holding files from testdata/ and params/ and small files made here, so that every reader starts
from valid input of each kind it accepts (every BITPIX, scaling, blank values, WCS, several
extensions, tile compression, LDAC and FITS_1.0 catalogs, RealGalaxyCatalogs, text formats).

Usage: /usr/bin/python3 scripts/make-fuzz-corpus.py OUTDIR
Needs python3-numpy and python3-astropy (Debian packages). Never reads ../shared.
"""
import gzip
import os
import shutil
import sys
import warnings

import numpy as np
from astropy.io import fits
from astropy.utils.exceptions import AstropyWarning

warnings.simplefilter("ignore", AstropyWarning)

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TESTDATA = os.path.join(ROOT, "testdata")
PARAMS = os.path.join(ROOT, "params")

TAN_WCS = [("CTYPE1", "RA---TAN"), ("CTYPE2", "DEC--TAN"), ("CRPIX1", 4.5), ("CRPIX2", 3.5),
           ("CRVAL1", 139.5), ("CRVAL2", 30.0), ("CD1_1", -7.1388888888888e-05),
           ("CD1_2", 0.0), ("CD2_1", 0.0), ("CD2_2", 7.13888888888888e-05),
           ("EQUINOX", 2000.0), ("RADESYS", "ICRS")]


def header(cards=()):
    h = fits.Header()
    for key, value in cards:
        h[key] = value
    return h


def write(hdus, path):
    fits.HDUList(hdus).writeto(path, overwrite=True, output_verify="silentfix")


def copy(name, folder, source_dir=TESTDATA, target_name=None):
    shutil.copy(os.path.join(source_dir, name), os.path.join(folder, target_name or name))


def text(folder, name, content):
    with open(os.path.join(folder, name), "wb") as f:
        f.write(content if isinstance(content, bytes) else content.encode())


def images(folder):
    rng = np.random.default_rng(1)
    values = rng.normal(100.0, 5.0, (6, 8))
    write([fits.PrimaryHDU(values.astype(np.float32), header(TAN_WCS + [("GAIN", 4.0),
                                                                       ("SATURATE", 6e4)]))],
          os.path.join(folder, "float32-wcs.fits"))
    write([fits.PrimaryHDU(values.astype(np.float64))], os.path.join(folder, "float64.fits"))
    nan = values.astype(np.float32)
    nan[2, 3] = np.nan
    write([fits.PrimaryHDU(nan, header([("BSCALE", 2.0), ("BZERO", 1.0)]))],
          os.path.join(folder, "float32-scaled-nan.fits"))
    for dtype, name in ((np.uint8, "uint8"), (np.int16, "int16"), (np.int32, "int32"),
                        (np.int64, "int64")):
        hdu = fits.PrimaryHDU(values.astype(dtype))
        write([hdu], os.path.join(folder, name + ".fits"))
    scaled = fits.PrimaryHDU((values * 10).astype(np.int16),
                             header([("BSCALE", 0.1), ("BZERO", 32768.0), ("BLANK", -32768)]))
    write([scaled], os.path.join(folder, "int16-bscale-blank.fits"))
    unsigned = fits.PrimaryHDU(values.astype(np.uint16))  # astropy writes BZERO 32768
    write([unsigned], os.path.join(folder, "uint16.fits"))
    cube = fits.PrimaryHDU(values.astype(np.float32).reshape(1, 6, 8))
    write([cube], os.path.join(folder, "cube-one-plane.fits"))
    mef = [fits.PrimaryHDU(header=header([("EXTEND", True)])),
           fits.ImageHDU(values.astype(np.float32), header(TAN_WCS), name="SCI"),
           fits.ImageHDU(values.astype(np.int16), name="DQ"),
           fits.BinTableHDU.from_columns([fits.Column("NUMBER", "J", array=[1, 2])],
                                         name="CAT")]
    write(mef, os.path.join(folder, "mef.fits"))
    sip = TAN_WCS[:]
    sip[0] = ("CTYPE1", "RA---TAN-SIP")
    sip[1] = ("CTYPE2", "DEC--TAN-SIP")
    sip += [("A_ORDER", 2), ("A_2_0", 1e-6), ("B_ORDER", 2), ("B_0_2", -1e-6)]
    write([fits.PrimaryHDU(values.astype(np.float32), header(sip))],
          os.path.join(folder, "float32-sip.fits"))
    for compression in ("RICE_1", "GZIP_1", "HCOMPRESS_1"):
        data = values.astype(np.float32 if compression == "GZIP_1" else np.int32)
        comp = fits.CompImageHDU(data, compression_type=compression, tile_shape=(2, 8))
        write([fits.PrimaryHDU(), comp], os.path.join(folder, "tiles-%s.fits" % compression))
    with open(os.path.join(folder, "float32-wcs.fits"), "rb") as f:
        raw = f.read()
    with open(os.path.join(folder, "float32-wcs.fits.gz"), "wb") as f:
        f.write(gzip.compress(raw))


def segmentations(folder):
    for k in (1, 2, 3):
        copy("example.seg%d.fits.gz" % k, folder)
    labels = np.zeros((7, 9), np.int32)
    labels[1:3, 1:4] = 1
    labels[4:6, 5:8] = 2
    labels[5, 1] = 7
    write([fits.PrimaryHDU(labels)], os.path.join(folder, "labels-int32.fits"))
    write([fits.PrimaryHDU(labels.astype(np.int16))], os.path.join(folder, "labels-int16.fits"))
    write([fits.PrimaryHDU(labels.astype(np.uint8))], os.path.join(folder, "labels-uint8.fits"))
    comp = fits.CompImageHDU(labels, compression_type="RICE_1")
    write([fits.PrimaryHDU(), comp], os.path.join(folder, "labels-rice.fits"))


def catalogs(folder):
    for k in (1, 2, 3):
        copy("example.cat%d.ldac" % k, folder)
    with fits.open(os.path.join(TESTDATA, "example.cat1.ldac")) as cat:
        primary, imhead, objects = (h.copy() for h in cat)
        # A catalog of a two-extension image: one LDAC_IMHEAD + LDAC_OBJECTS pair per extension.
        write([primary, imhead, objects, imhead.copy(), objects.copy()],
              os.path.join(folder, "two-parts.ldac"))
        small = objects.copy()
        small.data = small.data[:2]
        write([primary, imhead, small], os.path.join(folder, "two-rows.ldac"))
    number = fits.Column("NUMBER", "J", array=[1, 2, 3])
    flux = fits.Column("FLUX_ISO", "E", array=[10.0, 20.5, -1.0])
    fits10 = fits.BinTableHDU.from_columns([number, flux], name="OBJECTS")
    write([fits.PrimaryHDU(), fits10], os.path.join(folder, "fits10.fits"))


def real_galaxy_catalogs(folder):
    rng = np.random.default_rng(2)
    galaxy = rng.normal(0.0, 1.0, (8, 8)).astype(np.float32)
    psf = np.outer([1, 2, 1], [1, 2, 1]).astype(np.float32)
    columns = [fits.Column("IDENT", "J", array=[101, 102]),
               fits.Column("MAG", "D", array=[23.5, 24.0]),
               fits.Column("BAND", "5A", array=["F814W", "F814W"]),
               fits.Column("PIXEL_SCALE", "D", array=[0.03, 0.03]),
               fits.Column("GAL_FILENAME", "12A", array=["catalog.fits", "catalog.fits"]),
               fits.Column("GAL_HDU", "K", array=[2, 3]),
               fits.Column("PSF_FILENAME", "12A", array=["catalog.fits", ""]),
               fits.Column("PSF_HDU", "K", array=[4, 0])]
    table = fits.BinTableHDU.from_columns(columns)
    write([fits.PrimaryHDU(), table, fits.ImageHDU(galaxy), fits.ImageHDU(galaxy[:5, :6]),
           fits.ImageHDU(psf)], os.path.join(folder, "catalog-with-stamps.fits"))
    write([fits.PrimaryHDU(), fits.BinTableHDU.from_columns(columns[:6])],
          os.path.join(folder, "catalog-no-psf.fits"))


def configurations(folder):
    copy("example.sex", folder)
    copy("octarc.sex", folder, PARAMS)
    text(folder, "weights.sex", "WEIGHT_TYPE MAP_WEIGHT,MAP_RMS\nWEIGHT_IMAGE w.fits\n"
                                "WEIGHT_THRESH 0.5\nRESCALE_WEIGHTS N\nBACK_SIZE 32,48\n"
                                "BACK_TYPE MANUAL,AUTO\nBACK_VALUE 100,-5.5\n")
    text(folder, "assoc.sex", "ASSOC_NAME sky.list\nASSOC_PARAMS 2,3,4\nASSOC_DATA 0\n"
                              "ASSOC_TYPE MAG_MEAN\nASSOCSELEC_TYPE -MATCHED\n"
                              "CATALOG_NAME ${HOME}/out.cat\nCHECKIMAGE_TYPE SEGMENTATION,"
                              "-BACKGROUND\nCHECKIMAGE_NAME a.fits b.fits\n")
    text(folder, "command-line.args", "-DETECT_THRESH\n3\n-THRESH_TYPE\nABSOLUTE\n-c\nx.sex\n"
                                      "-DETECT_LEVELS\n2,4,8\nimage.fits\n-dd\n")


def params(folder):
    copy("example.param", folder)
    copy("sextractor.param", folder)
    copy("octarc.param", folder, PARAMS)
    text(folder, "vectors.param", "NUMBER\nVECTOR_ASSOC(3)\nNUMBER_ASSOC\nFLUX_APER(2)\n"
                                  "VIGNET(5,5)\n#X_IMAGE\nX_WORLD Y_WORLD\n")


def convs(folder):
    copy("default.conv", folder, PARAMS)
    text(folder, "gauss5.conv", "CONV NORM\n# 5x5 Gaussian\n0.0625 0.25 0.375 0.25 0.0625\n"
                                "0.25 1 1.5 1 0.25\n0.375 1.5 2.25 1.5 0.375\n"
                                "0.25 1 1.5 1 0.25\n0.0625 0.25 0.375 0.25 0.0625\n")
    text(folder, "nonorm.conv", "CONV NONORM\n-1 -1 -1\n-1 8 -1\n-1 -1 -1\n")


def assoc_lists(folder):
    # The first byte chooses the settings (fuzz_assoc.cpp), the rest is the list.
    body = b"# x y mag id\n10.5 10.5 21.3 1\n 50 50.2 19.0 2\n\t# skipped\n99.6 99.6 99 3\n"
    for choice in (0, 1, 2, 3, 5, 22, 63, 255):
        text(folder, "list-%d" % choice, bytes([choice]) + body)


def populations(folder):
    copy("population.txt", folder, os.path.join(PARAMS, "simulation"))


MAKERS = {
    "fuzz_fits_image": images,
    "fuzz_segmentation": segmentations,
    "fuzz_input_catalog": catalogs,
    "fuzz_sex_config": configurations,
    "fuzz_param": params,
    "fuzz_conv": convs,
    "fuzz_assoc": assoc_lists,
    "fuzz_population": populations,
    "fuzz_real_galaxy_catalog": real_galaxy_catalogs,
}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    for target, make in MAKERS.items():
        folder = os.path.join(out, target)
        shutil.rmtree(folder, ignore_errors=True)
        os.makedirs(folder)
        make(folder)
    # The image readers also start from every other FITS seed.
    for target in ("fuzz_segmentation", "fuzz_input_catalog", "fuzz_real_galaxy_catalog"):
        for name in os.listdir(os.path.join(out, target)):
            shutil.copy(os.path.join(out, target, name),
                        os.path.join(out, "fuzz_fits_image", target + "-" + name))


if __name__ == "__main__":
    main()
