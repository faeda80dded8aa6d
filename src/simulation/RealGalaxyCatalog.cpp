// Reads the catalog table with cfitsio directly (the io stage reads images only); the stamps
// themselves go through octarc::readImage.
#include "octarc/simulation/RealGalaxyCatalog.h"

#include <climits>
#include <cmath>
#include <filesystem>
#include <set>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/detail/Cfitsio.h"
#include "octarc/simulation/Psf.h"

namespace octarc::simulation {

namespace {

using detail::throwIfFitsError;

// File names from the catalog are shown in messages up to this length.
constexpr std::size_t kPathChars = 200;

int columnNumber(fitsfile* f, const std::string& file, const char* name, bool required) {
  int status = 0;
  int col = 0;
  fits_get_colnum(f, CASEINSEN, const_cast<char*>(name), &col, &status);
  if (status == 0) return col;
  fits_clear_errmsg();
  if (required)
    throw IoError(file + ": RealGalaxyCatalog table has no column " + std::string(name));
  return 0;
}

std::vector<double> readDoubles(fitsfile* f, const std::string& file, int col, long rows) {
  std::vector<double> v(static_cast<std::size_t>(rows));
  int status = 0;
  int anyNull = 0;
  if (rows > 0) fits_read_col(f, TDOUBLE, col, 1, 1, rows, nullptr, v.data(), &anyNull, &status);
  throwIfFitsError(status, file, "cannot read table column " + std::to_string(col));
  return v;
}

std::vector<long long> readIntegers(fitsfile* f, const std::string& file, int col, long rows) {
  std::vector<long long> v(static_cast<std::size_t>(rows));
  int status = 0;
  int anyNull = 0;
  if (rows > 0) fits_read_col(f, TLONGLONG, col, 1, 1, rows, nullptr, v.data(), &anyNull, &status);
  throwIfFitsError(status, file, "cannot read table column " + std::to_string(col));
  return v;
}

std::vector<std::string> readStrings(fitsfile* f, const std::string& file, int col, long rows) {
  int status = 0;
  int typecode = 0;
  long repeat = 0;
  long width = 0;
  fits_get_eqcoltype(f, col, &typecode, &repeat, &width, &status);
  throwIfFitsError(status, file, "cannot read table column " + std::to_string(col));
  if (typecode != TSTRING)
    throw IoError(file + ": table column " + std::to_string(col) + " is not a string column");
  std::vector<std::string> out;
  std::vector<char> buffer(static_cast<std::size_t>(repeat) + 1);
  for (long r = 1; r <= rows; ++r) {
    char* ptr = buffer.data();
    int anyNull = 0;
    fits_read_col_str(f, col, r, 1, 1, const_cast<char*>(""), &ptr, &anyNull, &status);
    throwIfFitsError(status, file, "cannot read string in row " + std::to_string(r));
    std::string s(ptr);
    while (!s.empty() && s.back() == ' ') s.pop_back();
    out.push_back(s);
  }
  return out;
}

std::string resolve(const std::filesystem::path& dir, const std::string& name) {
  const std::filesystem::path p(name);
  return (p.is_absolute() ? p : dir / p).string();
}

}  // namespace

RealGalaxyCatalog RealGalaxyCatalog::load(const std::string& catalogPath, bool checkGalaxyFiles) {
  if (!std::filesystem::exists(catalogPath))
    throw IoError(catalogPath + ": RealGalaxyCatalog file does not exist");
  detail::FitsPtr file = detail::openFits(catalogPath);
  fitsfile* f = file.get();
  int status = 0;
  int hduType = 0;
  fits_movabs_hdu(f, 2, &hduType, &status);
  if (status != 0 || hduType != BINARY_TBL) {
    fits_clear_errmsg();
    throw IoError(catalogPath + ": not a RealGalaxyCatalog (no binary table in HDU 1)");
  }
  // The row count sizes every column buffer: the table must fit in the file first.
  detail::requireSoundHdu(f, catalogPath);
  long rows = 0;
  fits_get_num_rows(f, &rows, &status);
  throwIfFitsError(status, catalogPath, "cannot read the number of rows");

  const auto ident =
      readIntegers(f, catalogPath, columnNumber(f, catalogPath, "IDENT", true), rows);
  const auto mag = readDoubles(f, catalogPath, columnNumber(f, catalogPath, "MAG", true), rows);
  const auto band = readStrings(f, catalogPath, columnNumber(f, catalogPath, "BAND", true), rows);
  const auto scale =
      readDoubles(f, catalogPath, columnNumber(f, catalogPath, "PIXEL_SCALE", true), rows);
  const auto galFile =
      readStrings(f, catalogPath, columnNumber(f, catalogPath, "GAL_FILENAME", true), rows);
  const auto galHdu =
      readIntegers(f, catalogPath, columnNumber(f, catalogPath, "GAL_HDU", true), rows);
  const int psfFileCol = columnNumber(f, catalogPath, "PSF_FILENAME", false);
  const int psfHduCol = columnNumber(f, catalogPath, "PSF_HDU", false);
  std::vector<std::string> psfFile;
  std::vector<long long> psfHdu;
  if (psfFileCol > 0 && psfHduCol > 0) {
    psfFile = readStrings(f, catalogPath, psfFileCol, rows);
    psfHdu = readIntegers(f, catalogPath, psfHduCol, rows);
  }

  RealGalaxyCatalog catalog;
  catalog.path_ = catalogPath;
  const std::filesystem::path dir = std::filesystem::path(catalogPath).parent_path();
  std::set<std::string> checked;
  for (long r = 0; r < rows; ++r) {
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
    const auto badHdu = [](long long hdu) { return hdu < 0 || hdu > INT_MAX; };
    if (badHdu(galHdu[r]) || (!psfHdu.empty() && badHdu(psfHdu[r])))
      throw IoError(where + ": HDU number out of range");
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
  stamp.type = GalaxyType::Spiral;
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
