"""Prints astropy's sigma-clipped mean, median and standard deviation of a FITS image.

usage: astropy_sigma_clip.py IMAGE KAPPA
Clipping about the median with the population standard deviation, iterated to convergence,
non-finite pixels ignored (the statistics octarc's estimateGlobalBackground reproduces).
"""
import sys

import numpy as np
from astropy.io import fits
from astropy.stats import sigma_clipped_stats


def main():
    data = fits.getdata(sys.argv[1]).astype(np.float64)
    kappa = float(sys.argv[2])
    finite = data[np.isfinite(data)]
    mean, median, std = sigma_clipped_stats(finite, sigma=kappa, maxiters=None,
                                            cenfunc="median", stdfunc="std")
    print(f"{mean:.17g} {median:.17g} {std:.17g}")


if __name__ == "__main__":
    main()
