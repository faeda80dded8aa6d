// Reader for GalSim's RealGalaxyCatalog format: a FITS binary table (first extension) with one
// row per galaxy and at least the columns IDENT, MAG, BAND, PIXEL_SCALE, GAL_FILENAME, GAL_HDU
// (PSF_FILENAME, PSF_HDU optional). Stamps live in other FITS files named relative to the
// catalog's directory; *_HDU counts from 0 = primary HDU. An optional string column MORPH_TYPE
// ("elliptical", "spiral" or "irregular", any case) gives each galaxy's morphological type;
// without it the type is measured on the stamp (simulation/Morphology.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/simulation/SourceStamp.h"

namespace octarc::simulation {

struct RealGalaxyEntry {
  std::int64_t ident = 0;
  double mag = 0.0;
  std::string band;
  double pixelScaleArcsec = 0.0;
  std::string galaxyPath;  // resolved file path (no HDU suffix)
  int galaxyHdu = 0;
  std::string psfPath;  // resolved file path, "" if no PSF column or an empty PSF_FILENAME
  int psfHdu = 0;
  std::optional<GalaxyType> type;  // from MORPH_TYPE, if the catalog has the column
};

class RealGalaxyCatalog {
 public:
  // Reads the table. Throws IoError naming the catalog file if it is unreadable, lacks a required
  // column, has a non-positive PIXEL_SCALE, a negative HDU or an unknown MORPH_TYPE, or
  // (checkGalaxyFiles) names a galaxy
  // image file that does not exist. PSF files are not checked here: they are needed only when a
  // PSF is asked for.
  static RealGalaxyCatalog load(const std::string& catalogPath, bool checkGalaxyFiles = true);

  const std::string& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }
  const RealGalaxyEntry& entry(std::size_t i) const { return entries_.at(i); }

  // The galaxy stamp of row i (pixel values as stored), typed by MORPH_TYPE or, without that
  // column, by classifyMorphology of its light. Throws IoError naming the missing/unreadable
  // file.
  SourceStamp loadGalaxy(std::size_t i) const;
  // The PSF image of row i, normalised to unit sum. Throws IoError naming the file if it is
  // missing or the catalog has no PSF column.
  ImageD loadPsf(std::size_t i) const;

 private:
  std::string path_;
  std::vector<RealGalaxyEntry> entries_;
};

}  // namespace octarc::simulation
