// The catalog table is read through io/FitsTable, the stamps through octarc::readImage.
#include "octarc/simulation/RealGalaxyCatalog.h"

#include <climits>
#include <cmath>
#include <filesystem>
#include <set>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/FitsTable.h"
#include "octarc/simulation/Morphology.h"
#include "octarc/simulation/Psf.h"

namespace octarc::simulation {

namespace {

// File names from the catalog are shown in messages up to this length.
constexpr std::size_t kPathChars = 200;

// The columns read, in the order their absence is reported; the PSF ones may be missing.
const std::vector<std::string> kRequiredColumns = {"IDENT",       "MAG",          "BAND",
                                                   "PIXEL_SCALE", "GAL_FILENAME", "GAL_HDU"};
const std::vector<std::string> kPsfColumns = {"PSF_FILENAME", "PSF_HDU"};
const char* const kTypeColumn = "MORPH_TYPE";

std::string resolve(const std::filesystem::path& dir, const std::string& name) {
  const std::filesystem::path p(name);
  return (p.is_absolute() ? p : dir / p).string();
}

}  // namespace

RealGalaxyCatalog RealGalaxyCatalog::load(const std::string& catalogPath, bool checkGalaxyFiles) {
  if (!std::filesystem::exists(catalogPath))
    throw IoError(catalogPath + ": RealGalaxyCatalog file does not exist");
  if (!hasFitsTableAt(catalogPath, 1))
    throw IoError(catalogPath + ": not a RealGalaxyCatalog (no binary table in HDU 1)");
  std::vector<std::string> columns = kRequiredColumns;
  columns.insert(columns.end(), kPsfColumns.begin(), kPsfColumns.end());
  columns.push_back(kTypeColumn);
  const FitsTable table = readFitsTableAt(catalogPath, 1, {}, columns);
  for (const std::string& name : kRequiredColumns) {
    if (table.findColumn(name) == nullptr)
      throw IoError(catalogPath + ": RealGalaxyCatalog table has no column " + name);
  }
  const std::int64_t rows = table.rows();
  const std::vector<std::int64_t> ident = table.integers("IDENT");
  const std::vector<double> mag = table.doubles("MAG");
  const std::vector<std::string> band = table.strings("BAND");
  const std::vector<double> scale = table.doubles("PIXEL_SCALE");
  const std::vector<std::string> galFile = table.strings("GAL_FILENAME");
  const std::vector<std::int64_t> galHdu = table.integers("GAL_HDU");
  std::vector<std::string> psfFile;
  std::vector<std::int64_t> psfHdu;
  if (table.findColumn("PSF_FILENAME") != nullptr && table.findColumn("PSF_HDU") != nullptr) {
    psfFile = table.strings("PSF_FILENAME");
    psfHdu = table.integers("PSF_HDU");
  }
  std::vector<std::string> morphType;
  if (table.findColumn(kTypeColumn) != nullptr) morphType = table.strings(kTypeColumn);

  RealGalaxyCatalog catalog;
  catalog.path_ = catalogPath;
  const std::filesystem::path dir = std::filesystem::path(catalogPath).parent_path();
  std::set<std::string> checked;
  for (std::int64_t r = 0; r < rows; ++r) {
    RealGalaxyEntry e;
    e.ident = ident[r];
    e.mag = mag[r];
    e.band = band[r];
    e.pixelScaleArcsec = scale[r];
    e.galaxyPath = resolve(dir, galFile[r]);
    e.galaxyHdu = static_cast<int>(galHdu[r]);
    // An empty PSF_FILENAME means the row has no PSF (as the catalog writer leaves it).
    if (!psfFile.empty() && !psfFile[r].empty()) {
      e.psfPath = resolve(dir, psfFile[r]);
      e.psfHdu = static_cast<int>(psfHdu[r]);
    }
    const std::string where =
        catalogPath + ": row " + std::to_string(r + 1) + " (IDENT " + std::to_string(e.ident) + ")";
    if (!(e.pixelScaleArcsec > 0.0) || !std::isfinite(e.pixelScaleArcsec))
      throw IoError(where + ": PIXEL_SCALE must be a finite number > 0, got " +
                    std::to_string(e.pixelScaleArcsec));
    if (!std::isfinite(e.mag)) throw IoError(where + ": MAG must be a finite number");
    const auto badHdu = [](std::int64_t hdu) { return hdu < 0 || hdu > INT_MAX; };
    if (badHdu(galHdu[r]) || (!psfHdu.empty() && badHdu(psfHdu[r])))
      throw IoError(where + ": HDU number out of range");
    if (!morphType.empty()) {
      GalaxyType type = GalaxyType::Spiral;
      if (!parseGalaxyType(morphType[r], &type))
        throw IoError(where + ": " + kTypeColumn + " " + quoteForMessage(morphType[r]) +
                      " is not elliptical, spiral or irregular");
      e.type = type;
    }
    if (checkGalaxyFiles && checked.insert(e.galaxyPath).second &&
        !std::filesystem::exists(e.galaxyPath))
      throw IoError(where + ": galaxy image file " + quoteForMessage(e.galaxyPath, kPathChars) +
                    " does not exist");
    catalog.entries_.push_back(std::move(e));
  }
  return catalog;
}

SourceStamp RealGalaxyCatalog::loadGalaxy(std::size_t i) const {
  const RealGalaxyEntry& e = entry(i);
  if (!std::filesystem::exists(e.galaxyPath))
    throw IoError(path_ + ": IDENT " + std::to_string(e.ident) + ": galaxy image file " +
                  quoteForMessage(e.galaxyPath, kPathChars) + " does not exist");
  const ImageHdu hdu = readImage(e.galaxyPath + "[" + std::to_string(e.galaxyHdu) + "]");
  SourceStamp stamp;
  stamp.fluxPerPixel = ImageD(hdu.pixels.width(), hdu.pixels.height());
  for (std::int64_t k = 0; k < hdu.pixels.size(); ++k) {
    const float v = hdu.pixels[k];
    stamp.fluxPerPixel[k] = std::isfinite(v) ? v : 0.0;  // blank pixels carry no flux
  }
  stamp.pixelScaleArcsec = e.pixelScaleArcsec;
  // GalSim's format carries no morphology: measure it when the catalog does not say.
  stamp.type = e.type ? *e.type : classifyMorphology(measureMorphology(stamp));
  stamp.name =
      std::filesystem::path(path_).filename().string() + " IDENT " + std::to_string(e.ident);
  return stamp;
}

ImageD RealGalaxyCatalog::loadPsf(std::size_t i) const {
  const RealGalaxyEntry& e = entry(i);
  if (e.psfPath.empty())
    throw IoError(path_ + ": no PSF_FILENAME/PSF_HDU columns, but a PSF was asked for");
  if (!std::filesystem::exists(e.psfPath))
    throw IoError(path_ + ": IDENT " + std::to_string(e.ident) + ": PSF image file " +
                  quoteForMessage(e.psfPath, kPathChars) + " does not exist");
  const std::string hduPath = e.psfPath + "[" + std::to_string(e.psfHdu) + "]";
  const ImageHdu hdu = readImage(hduPath);
  ImageD psf(hdu.pixels.width(), hdu.pixels.height());
  for (std::int64_t k = 0; k < psf.size(); ++k) psf[k] = hdu.pixels[k];
  try {
    return normalisedPsf(psf, hduPath.c_str());
  } catch (const ConfigError& err) {
    throw IoError(err.what());
  }
}

}  // namespace octarc::simulation
