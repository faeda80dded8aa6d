"""Reads or writes FITS binary tables with astropy, for the FitsTable tests.

    dump PATH    prints every binary table of PATH as astropy sees it, one item per line:
                   TABLE <extname> <rows>
                   COLUMN <name>|<TFORM>|<TUNIT>|<TDISP>|<TTYPE comment>|<values, row by row>
                   KEY <name>|<value>|<comment>     (every keyword but the structural ones)
                 values are comma-separated: integers in decimal, reals as Python's repr
                 (the shortest text that reads back to the same double), nan, T/F, UNDEFINED.
    write PATH   writes the table FitsTable_test.cpp reads (every value is listed there too).
"""
import math
import re
import sys

import numpy as np
from astropy.io import fits

STRUCTURAL = re.compile(r"^(XTENSION|BITPIX|NAXIS\d*|PCOUNT|GCOUNT|TFIELDS|EXTNAME|LONGSTRN|"
                        r"COMMENT|HISTORY|(TTYPE|TFORM|TUNIT|TDISP|TNULL|TSCAL|TZERO|TDIM)\d+)$")


def text(value):
    if isinstance(value, (bool, np.bool_)):
        return "T" if value else "F"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return "nan" if math.isnan(value) else repr(float(value))
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, str):
        return value
    return "UNDEFINED"


def dump(path):
    with fits.open(path) as hdus:
        for hdu in hdus:
            if not isinstance(hdu, fits.BinTableHDU):
                continue
            print(f"TABLE {hdu.name} {hdu.header['NAXIS2']}")
            for i, column in enumerate(hdu.columns, start=1):
                values = []
                for row in (hdu.data[column.name] if hdu.header["NAXIS2"] else []):
                    values.extend(np.atleast_1d(row).tolist() if not isinstance(row, str)
                                  else [row])
                print(f"COLUMN {column.name}|{column.format}|{column.unit or ''}|"
                      f"{column.disp or ''}|{hdu.header.comments[f'TTYPE{i}']}|"
                      + ",".join(text(v) for v in values))
            for key in hdu.header:
                if STRUCTURAL.match(key) or key == "":
                    continue
                print(f"KEY {key}|{text(hdu.header[key])}|{hdu.header.comments[key]}")


def write(path):
    columns = [
        fits.Column(name="U16", format="I", bzero=32768,
                    array=np.array([0, 40000, 65535], dtype=np.uint16)),
        fits.Column(name="FLAG", format="L", array=np.array([True, False, True])),
        fits.Column(name="BYTE", format="B", array=np.array([0, 200, 255], dtype=np.uint8)),
        fits.Column(name="NAME", format="3A", array=np.array(["a", "bc", "def"])),
        fits.Column(name="VEC", format="2E", unit="arcsec",
                    array=np.array([[1.5, -2.25], [0.0, 4.0], [8.0, -0.5]], dtype=np.float32)),
    ]
    hdu = fits.BinTableHDU.from_columns(columns, name="ASTROPY")
    hdu.header["SURVEY"] = ("DLS", "survey name")
    hdu.header["PIXSCALE"] = (0.257, "arcsec per pixel")
    hdu.header["NSYS"] = (90000, "systems")
    hdu.header["DEEP"] = (True, "a logical")
    hdu.header["EXPR"] = ("ARCNESS > 0.15 && " * 6 + "SNR_ISO > 40", "a long string")
    fits.HDUList([fits.PrimaryHDU(), hdu]).writeto(path, overwrite=True)


if __name__ == "__main__":
    {"dump": dump, "write": write}[sys.argv[1]](sys.argv[2])
