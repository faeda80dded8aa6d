// The table is written through io/FitsTable (as RealGalaxyCatalog.cpp reads it), the stamp and
// PSF files through octarc::writeImageFile.
#include "octarc/simulation/RealGalaxyCatalogWriter.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/FitsTable.h"
#include "octarc/simulation/Psf.h"

namespace octarc::simulation {

namespace {

// A table column named `name` (unit `unit`) holding one value per row. Its TTYPEn comment is the
// one cfitsio gives a new column, which the files written so far carry.
FitsColumn column(std::string name, std::string unit, FitsColumnValues values) {
  FitsColumn c;
  c.name = std::move(name);
  c.unit = std::move(unit);
  c.values = std::move(values);
  if (c.type() == FitsColumnType::String) c.repeat = 0;  // as wide as the longest value
  return c;
}

void numberColumnComments(std::vector<FitsColumn>& columns) {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    char text[32];
    std::snprintf(text, sizeof text, "label for field %3d", static_cast<int>(i + 1));
    columns[i].comment = text;
  }
}

void writeTable(const std::string& path, const std::string& finalName,
                const std::vector<RealGalaxyRecord>& records, const RealGalaxyCatalogInfo& info,
                const RealGalaxyCatalogPaths& paths) {
  const std::size_t n = records.size();
  const std::string galName = std::filesystem::path(paths.galaxyImages).filename().string();
  const std::string psfName =
      paths.psfImage.empty() ? "" : std::filesystem::path(paths.psfImage).filename().string();

  auto doubles = [&](auto get) {
    std::vector<double> v;
    v.reserve(n);
    for (const RealGalaxyRecord& r : records) v.push_back(get(r));
    return v;
  };
  auto integers = [&](auto get) {
    std::vector<std::int64_t> v;
    v.reserve(n);
    for (std::size_t k = 0; k < n; ++k) v.push_back(get(k));
    return v;
  };
  // A single stamp is the primary image; several follow an empty primary.
  auto galHdu = [n](std::size_t k) { return n == 1 ? std::int64_t(0) : std::int64_t(k + 1); };
  const std::vector<std::string> band(n, info.band), galFile(n, galName), psfFile(n, psfName),
      noiseFile(n, info.noiseFilename);

  FitsTable table;
  table.name = "OBJECTS";
  table.columns = {
      column("IDENT", "", integers([&](std::size_t k) { return records[k].ident; })),
      column("RA", "deg", doubles([](const RealGalaxyRecord& r) { return r.raDeg; })),
      column("DEC", "deg", doubles([](const RealGalaxyRecord& r) { return r.decDeg; })),
      column("MAG", "mag", doubles([](const RealGalaxyRecord& r) { return r.mag; })),
      column("BAND", "", band),
      column("WEIGHT", "", doubles([](const RealGalaxyRecord& r) { return r.weight; })),
      column("GAL_FILENAME", "", galFile),
      column("PSF_FILENAME", "", psfFile),
      column("GAL_HDU", "", integers(galHdu)),
      column("PSF_HDU", "", integers([](std::size_t) { return std::int64_t(0); })),
      column("PIXEL_SCALE", "arcsec",
             doubles([&](const RealGalaxyRecord&) { return info.pixelScaleArcsec; })),
      column("NOISE_MEAN", "", doubles([](const RealGalaxyRecord& r) { return r.noiseMean; })),
      column("NOISE_VARIANCE", "",
             doubles([](const RealGalaxyRecord& r) { return r.noiseVariance; })),
      column("NOISE_FILENAME", "", noiseFile),
      column("stamp_flux", "", doubles([](const RealGalaxyRecord& r) {
               double sum = 0.0;  // float pixels summed in double, as a reader would
               for (float v : r.stamp.pixels()) sum += v;
               return sum;
             })),
      column("X_IMAGE", "pixel", doubles([](const RealGalaxyRecord& r) { return r.xImage; })),
      column("Y_IMAGE", "pixel", doubles([](const RealGalaxyRecord& r) { return r.yImage; })),
      column("ISOAREA_IMAGE", "pixel**2",
             integers([&](std::size_t k) { return std::int64_t(records[k].isoAreaPixels); })),
  };
  numberColumnComments(table.columns);
  try {
    writeFitsTables(path, {table}, info.extraCards);
  } catch (const IoError& e) {
    // Messages name the catalog, not the temporary file it is written to.
    std::string what = e.what();
    if (what.compare(0, path.size(), path) == 0) what.replace(0, path.size(), finalName);
    throw IoError(what);
  }
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
