"""Writes python3-sep's background and rms maps of a FITS image, for comparison in the tests.

usage: sep_background.py IMAGE OUT_BACK OUT_RMS BW BH FW FH
The global level and rms go into the SEPBKG / SEPRMS header cards of OUT_BACK.
"""
import sys

import numpy as np
import sep
from astropy.io import fits


def main():
    image, out_back, out_rms = sys.argv[1:4]
    bw, bh, fw, fh = (int(v) for v in sys.argv[4:8])
    data = np.ascontiguousarray(fits.getdata(image), dtype=np.float32)  # native byte order
    bkg = sep.Background(data, bw=bw, bh=bh, fw=fw, fh=fh)
    header = fits.Header()
    header["SEPBKG"] = (float(bkg.globalback), "sep global background")
    header["SEPRMS"] = (float(bkg.globalrms), "sep global rms")
    fits.writeto(out_back, bkg.back().astype(np.float32), header, overwrite=True)
    fits.writeto(out_rms, bkg.rms().astype(np.float32), overwrite=True)


if __name__ == "__main__":
    main()
