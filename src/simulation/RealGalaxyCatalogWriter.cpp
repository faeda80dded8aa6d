// The table is written with cfitsio directly (as RealGalaxyCatalog.cpp reads it); the stamp and
// PSF files go through octarc::writeImageFile.
#include "octarc/simulation/RealGalaxyCatalogWriter.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/detail/Cfitsio.h"
#include "octarc/simulation/Psf.h"

namespace octarc::simulation {

namespace {

using detail::throwIfFitsError;

// One table column as cfitsio wants it (TTYPE, TFORM, TUNIT).
struct ColumnSpec {
  std::string name;
  std::string form;
  std::string unit;
};

void writeStrings(fitsfile* f, const std::string& file, int col,
                  const std::vector<std::string>& values) {
  std::vector<char*> pointers;
  for (const std::string& v : values) pointers.push_back(const_cast<char*>(v.c_str()));
  int status = 0;
  fits_write_col_str(f, col, 1, 1, static_cast<LONGLONG>(values.size()), pointers.data(), &status);
  throwIfFitsError(status, file, "cannot write table column " + std::to_string(col));
}

void writeDoubles(fitsfile* f, const std::string& file, int col, std::vector<double> values) {
  int status = 0;
  fits_write_col(f, TDOUBLE, col, 1, 1, static_cast<LONGLONG>(values.size()), values.data(),
                 &status);
  throwIfFitsError(status, file, "cannot write table column " + std::to_string(col));
}

void writeIntegers(fitsfile* f, const std::string& file, int col, std::vector<LONGLONG> values) {
  int status = 0;
  fits_write_col(f, TLONGLONG, col, 1, 1, static_cast<LONGLONG>(values.size()), values.data(),
                 &status);
  throwIfFitsError(status, file, "cannot write table column " + std::to_string(col));
}

// Width of a fixed-length string column holding `values` (FITS wants at least 1).
std::string stringForm(const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const std::string& v : values) width = std::max(width, v.size());
  return std::to_string(width) + "A";
}

void writeTable(const std::string& path, const std::string& finalName,
                const std::vector<RealGalaxyRecord>& records, const RealGalaxyCatalogInfo& info,
                const RealGalaxyCatalogPaths& paths) {
  const std::size_t n = records.size();
  const std::string galName = std::filesystem::path(paths.galaxyImages).filename().string();
  const std::string psfName =
      paths.psfImage.empty() ? "" : std::filesystem::path(paths.psfImage).filename().string();
  // A single stamp is the primary image; several follow an empty primary.
  auto galHdu = [n](std::size_t k) { return n == 1 ? LONGLONG(0) : LONGLONG(k + 1); };

  std::vector<std::string> band(n, info.band), galFile(n, galName), psfFile(n, psfName),
      noiseFile(n, info.noiseFilename);
  const std::vector<ColumnSpec> columns = {
      {"IDENT", "1K", ""},
      {"RA", "1D", "deg"},
      {"DEC", "1D", "deg"},
      {"MAG", "1D", "mag"},
      {"BAND", stringForm(band), ""},
      {"WEIGHT", "1D", ""},
      {"GAL_FILENAME", stringForm(galFile), ""},
      {"PSF_FILENAME", stringForm(psfFile), ""},
      {"GAL_HDU", "1K", ""},
      {"PSF_HDU", "1K", ""},
      {"PIXEL_SCALE", "1D", "arcsec"},
      {"NOISE_MEAN", "1D", ""},
      {"NOISE_VARIANCE", "1D", ""},
      {"NOISE_FILENAME", stringForm(noiseFile), ""},
      {"stamp_flux", "1D", ""},
      {"X_IMAGE", "1D", "pixel"},
      {"Y_IMAGE", "1D", "pixel"},
      {"ISOAREA_IMAGE", "1K", "pixel**2"},
  };

  detail::FitsPtr file = detail::createFits(path);
  fitsfile* f = file.get();
  int status = 0;
  fits_create_img(f, BYTE_IMG, 0, nullptr, &status);
  for (const std::string& card : info.extraCards) {
    fits_write_record(f, card.c_str(), &status);
  }
  throwIfFitsError(status, finalName, "cannot write the primary header");

  std::vector<char*> ttype, tform, tunit;
  for (const ColumnSpec& c : columns) {
    ttype.push_back(const_cast<char*>(c.name.c_str()));
    tform.push_back(const_cast<char*>(c.form.c_str()));
    tunit.push_back(const_cast<char*>(c.unit.c_str()));
  }
  fits_create_tbl(f, BINARY_TBL, static_cast<LONGLONG>(n), static_cast<int>(columns.size()),
                  ttype.data(), tform.data(), tunit.data(), "OBJECTS", &status);
  throwIfFitsError(status, finalName, "cannot create the catalog table");

  auto doubles = [&](auto get) {
    std::vector<double> v;
    for (const RealGalaxyRecord& r : records) v.push_back(get(r));
    return v;
  };
  auto integers = [&](auto get) {
    std::vector<LONGLONG> v;
    for (std::size_t k = 0; k < n; ++k) v.push_back(get(k));
    return v;
  };
  writeIntegers(f, finalName, 1, integers([&](std::size_t k) { return records[k].ident; }));
  writeDoubles(f, finalName, 2, doubles([](const RealGalaxyRecord& r) { return r.raDeg; }));
  writeDoubles(f, finalName, 3, doubles([](const RealGalaxyRecord& r) { return r.decDeg; }));
  writeDoubles(f, finalName, 4, doubles([](const RealGalaxyRecord& r) { return r.mag; }));
  writeStrings(f, finalName, 5, band);
  writeDoubles(f, finalName, 6, doubles([](const RealGalaxyRecord& r) { return r.weight; }));
  writeStrings(f, finalName, 7, galFile);
  writeStrings(f, finalName, 8, psfFile);
  writeIntegers(f, finalName, 9, integers(galHdu));
  writeIntegers(f, finalName, 10, integers([](std::size_t) { return LONGLONG(0); }));
  writeDoubles(f, finalName, 11,
               doubles([&](const RealGalaxyRecord&) { return info.pixelScaleArcsec; }));
  writeDoubles(f, finalName, 12, doubles([](const RealGalaxyRecord& r) { return r.noiseMean; }));
  writeDoubles(f, finalName, 13,
               doubles([](const RealGalaxyRecord& r) { return r.noiseVariance; }));
  writeStrings(f, finalName, 14, noiseFile);
  writeDoubles(f, finalName, 15, doubles([](const RealGalaxyRecord& r) {
                 double sum = 0.0;  // float pixels summed in double, as a reader would
                 for (float v : r.stamp.pixels()) sum += v;
                 return sum;
               }));
  writeDoubles(f, finalName, 16, doubles([](const RealGalaxyRecord& r) { return r.xImage; }));
  writeDoubles(f, finalName, 17, doubles([](const RealGalaxyRecord& r) { return r.yImage; }));
  writeIntegers(f, finalName, 18,
                integers([&](std::size_t k) { return LONGLONG(records[k].isoAreaPixels); }));

  fitsfile* raw = file.release();
  fits_close_file(raw, &status);
  throwIfFitsError(status, finalName, "cannot finish writing the catalog");
}

}  // namespace

RealGalaxyCatalogPaths realGalaxyCatalogPaths(const std::string& catalogPath, bool withPsf) {
  const std::filesystem::path p(catalogPath);
  std::string stem = p.filename().string();
  for (const char* ext : {".fits", ".fit", ".fts"}) {
    const std::string e(ext);
    if (stem.size() > e.size() && stem.compare(stem.size() - e.size(), e.size(), e) == 0) {
      stem.resize(stem.size() - e.size());
      break;
    }
  }
  RealGalaxyCatalogPaths paths;
  paths.catalog = catalogPath;
  paths.galaxyImages = (p.parent_path() / (stem + "_images.fits")).string();
  if (withPsf) paths.psfImage = (p.parent_path() / (stem + "_psf.fits")).string();
  return paths;
}

RealGalaxyCatalogPaths writeRealGalaxyCatalog(const std::string& catalogPath,
                                              const std::vector<RealGalaxyRecord>& records,
                                              const RealGalaxyCatalogInfo& info) {
  if (records.empty())
    throw ConfigError(catalogPath + ": no galaxies to write in the RealGalaxyCatalog");
  if (!(info.pixelScaleArcsec > 0.0) || !std::isfinite(info.pixelScaleArcsec))
    throw ConfigError(catalogPath + ": PIXEL_SCALE must be positive, got " +
                      std::to_string(info.pixelScaleArcsec));
  for (const RealGalaxyRecord& r : records) {
    if (r.stamp.empty())
      throw ConfigError(catalogPath + ": galaxy IDENT " + std::to_string(r.ident) +
                        " has an empty stamp");
  }
  const RealGalaxyCatalogPaths paths = realGalaxyCatalogPaths(catalogPath, info.psf.has_value());
  const std::filesystem::path dir = std::filesystem::path(catalogPath).parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir))
    throw IoError(catalogPath + ": cannot write: directory " + dir.string() + " does not exist");

  // The catalog is the main output: it appears last, so that it never names a file that is not
  // there yet.
  OutputFiles outputs;
  outputs.add(paths.catalog);
  outputs.add(paths.galaxyImages);
  if (info.psf) outputs.add(paths.psfImage);
  // Stamps: one HDU each, with the galaxy's identity and where it came from.
  outputs.write(1, [&](const std::string& path) {
    std::vector<OutputImageHdu> hdus(records.size());
    for (std::size_t k = 0; k < records.size(); ++k) {
      const RealGalaxyRecord& r = records[k];
      FitsHeader& h = hdus[k].header;
      h.set("IDENT", std::to_string(r.ident), "galaxy identifier (catalog IDENT)");
      h.set("PIXSCALE", formatNumber(info.pixelScaleArcsec, "%.10G"), "pixel size, arcsec");
      h.set("XIMAGE", formatNumber(r.xImage, "%.10G"), "centroid x in the parent image (1-based)");
      h.set("YIMAGE", formatNumber(r.yImage, "%.10G"), "centroid y in the parent image (1-based)");
      hdus[k].floatPixels = &r.stamp;
    }
    writeImageFile(path, hdus);
  });
  if (info.psf) {
    ImageD normalised;
    try {
      normalised = normalisedPsf(*info.psf, "RealGalaxyCatalog PSF image");
    } catch (const ConfigError& e) {
      throw ConfigError(paths.psfImage + ": " + e.what());
    }
    ImageF pixels(normalised.width(), normalised.height());
    for (std::int64_t k = 0; k < pixels.size(); ++k) pixels[k] = static_cast<float>(normalised[k]);
    OutputImageHdu hdu;
    hdu.header.set("PIXSCALE", formatNumber(info.pixelScaleArcsec, "%.10G"), "pixel size, arcsec");
    hdu.floatPixels = &pixels;
    outputs.write(2, [&](const std::string& path) { writeImageFile(path, {hdu}); });
  }
  outputs.write(
      0, [&](const std::string& path) { writeTable(path, paths.catalog, records, info, paths); });
  outputs.commit();
  return paths;
}

}  // namespace octarc::simulation
