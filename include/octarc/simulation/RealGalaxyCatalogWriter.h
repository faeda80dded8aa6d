// Writer for GalSim's RealGalaxyCatalog format, the counterpart of RealGalaxyCatalog.h: a FITS
// table with one row per galaxy plus a FITS file of galaxy stamps (and optionally one PSF image),
// laid out like the public COSMOS/AEGIS samples so that GalSim and octarc read it alike.
//
// Files, all in the catalog's directory, for a catalog "<dir>/<stem>.fits":
//   <stem>.fits         primary HDU empty, HDU 1 the binary table (columns below);
//   <stem>_images.fits  the stamps: a single stamp is the primary image, several are image
//                       extensions 1..n after an empty primary (GAL_HDU says which);
//   <stem>_psf.fits     only when a PSF is given: the PSF image as the primary HDU (PSF_HDU 0).
// GAL_FILENAME / PSF_FILENAME hold the bare file names, which readers resolve relative to the
// catalog's directory; PSF_FILENAME is "" when no PSF is written.
//
// Table columns, with the types of the public samples: IDENT (K), RA, DEC (D, degrees), MAG (D),
// BAND (A), WEIGHT (D), GAL_FILENAME, PSF_FILENAME (A), GAL_HDU, PSF_HDU (K), PIXEL_SCALE (D,
// arcsec), NOISE_MEAN, NOISE_VARIANCE (D), NOISE_FILENAME (A), stamp_flux (D, sum of the stamp),
// and three columns tracing each galaxy back to the image it was cut from: X_IMAGE, Y_IMAGE (D,
// 1-based flux centroid) and ISOAREA_IMAGE (K, footprint pixels).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/Image.h"

namespace octarc::simulation {

struct RealGalaxyRecord {
  std::int64_t ident = 0;
  double raDeg = std::numeric_limits<double>::quiet_NaN();  // NaN when the image has no WCS
  double decDeg = std::numeric_limits<double>::quiet_NaN();
  double mag = 0.0;
  double weight = 1.0;
  ImageF stamp;  // flux per pixel; its centre pixel is the galaxy's reference point
  double noiseMean = 0.0;
  double noiseVariance = 0.0;
  double xImage = 0.0;  // 1-based FITS coordinates of the centroid in the parent image
  double yImage = 0.0;
  std::int64_t isoAreaPixels = 0;
};

struct RealGalaxyCatalogInfo {
  std::string band;               // BAND of every row, e.g. "F606W"
  double pixelScaleArcsec = 0.0;  // PIXEL_SCALE of every row
  std::string noiseFilename;      // NOISE_FILENAME of every row ("" for none)
  // Written as <stem>_psf.fits when present (normalised to unit sum first); PSF_FILENAME is ""
  // otherwise.
  std::optional<ImageD> psf;
  // Extra primary-header cards of the catalog (80-character cards, e.g. HISTORY of the build).
  std::vector<std::string> extraCards;
};

struct RealGalaxyCatalogPaths {
  std::string catalog;
  std::string galaxyImages;
  std::string psfImage;  // "" when no PSF file is written
};

// The file names that writeRealGalaxyCatalog uses for `catalogPath`.
RealGalaxyCatalogPaths realGalaxyCatalogPaths(const std::string& catalogPath, bool withPsf);

// Writes the catalog and its image files. Every file is first written under a temporary name and
// renamed only when all of them are complete (catalog last), so a failure leaves no new file.
// Throws ConfigError if `records` is empty, a stamp is empty, or pixelScaleArcsec <= 0; IoError
// naming the file if a file cannot be written.
RealGalaxyCatalogPaths writeRealGalaxyCatalog(const std::string& catalogPath,
                                              const std::vector<RealGalaxyRecord>& records,
                                              const RealGalaxyCatalogInfo& info);

}  // namespace octarc::simulation
