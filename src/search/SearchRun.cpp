#include "octarc/search/SearchRun.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>

#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/TableCatalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Segment.h"
#include "octarc/io/Ds9Region.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/FitsTable.h"
#include "octarc/measure/Colour.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/run/RunKeys.h"
#include "octarc/search/CandidateTable.h"
#include "octarc/search/LensLightSearch.h"
#include "octarc/search/VettingPage.h"
#include "octarc/selection/ColumnExpression.h"
#include "octarc/selection/SurveySetup.h"

namespace octarc {

namespace fs = std::filesystem;

namespace {

// Pixel scale at the image centre from the WCS (the mean of the two axes' steps), 0 if none.
double wcsPixelScaleArcsec(const Wcs& wcs, std::int64_t width, std::int64_t height) {
  const double xc = 0.5 * double(width + 1), yc = 0.5 * double(height + 1);
  const auto c = wcs.pixelToWorld(xc, yc);
  const auto dx = wcs.pixelToWorld(xc + 1, yc);
  const auto dy = wcs.pixelToWorld(xc, yc + 1);
  auto separationArcsec = [](const std::array<double, 2>& a, const std::array<double, 2>& b) {
    const double k = std::numbers::pi / 180.0;
    const double s = std::sin(0.5 * (b[1] - a[1]) * k), t = std::sin(0.5 * (b[0] - a[0]) * k);
    const double h = s * s + std::cos(a[1] * k) * std::cos(b[1] * k) * t * t;
    return 2.0 * std::asin(std::sqrt(std::min(1.0, h))) / k * 3600.0;
  };
  const double scale = 0.5 * (separationArcsec(c, dx) + separationArcsec(c, dy));
  return std::isfinite(scale) ? scale : 0.0;
}

// Points of a mask as circles of MASK_POINT_RADIUS: the radius in pixels, through PIXEL_SCALE
// or the WCS of the image's header (0 when points are refused).
double maskPointRadiusPix(const SearchRunSettings& s, const ImageHdu& image,
                          const std::string& imagePath) {
  if (!(s.maskPointRadiusArcsec > 0)) return 0.0;
  double scale = s.run.pixelScaleArcsec;
  if (!(scale > 0)) {
    const std::optional<Wcs> wcs = Wcs::fromHeader(image.header, imagePath);
    scale = wcs ? wcsPixelScaleArcsec(*wcs, image.widthPix, image.heightPix) : 0.0;
  }
  if (!(scale > 0)) {
    throw ConfigError("MASK_POINT_RADIUS: " + imagePath +
                      " has no WCS to take the pixel scale from; set PIXEL_SCALE");
  }
  return s.maskPointRadiusArcsec / scale;
}

// The searched image's name in messages: its file, or what an in-memory image was called.
std::string searchedImageName(const SearchRun& run, const RunSettings& rs) {
  return rs.imagePaths.empty() ? run.image.hdu.path : rs.measurementImagePath();
}

// PIXEL_SCALE, else the WCS's at the image centre; ConfigError when neither gives one.
double runPixelScaleArcsec(const SearchRun& run, const RunSettings& rs) {
  if (rs.pixelScaleArcsec > 0) return rs.pixelScaleArcsec;
  const double scale = run.image.wcs
                           ? wcsPixelScaleArcsec(*run.image.wcs, run.image.hdu.pixels.width(),
                                                 run.image.hdu.pixels.height())
                           : 0.0;
  if (!(scale > 0)) {
    throw ConfigError(searchedImageName(run, rs) +
                      ": no WCS to take the pixel scale from; set PIXEL_SCALE");
  }
  return scale;
}

void requireColumns(const Table& catalog, const std::vector<std::string>& names,
                    const std::string& source) {
  std::string missing;
  for (const std::string& n : names) {
    if (catalog.findColumn(n) < 0) missing += (missing.empty() ? "" : ", ") + n;
  }
  if (!missing.empty()) {
    throw ConfigError(source + ": lacks the column(s) the search needs: " + missing);
  }
}

// Every file the search reads, for the check that none lies inside OUTPUT_DIR.
std::vector<NamedInput> searchInputs(const SearchRunSettings& s) {
  std::vector<NamedInput> inputs = runInputs(s.run, s.assoc ? s.assoc->listPath : std::string());
  if (s.search.method == SelectionMethod::Trees) {
    inputs.push_back({"MODEL_NAME", s.modelPath});
  } else {
    inputs.push_back({"GRID_NAME", s.gridPath});
  }
  if (!s.maskPath.empty()) inputs.push_back({"MASK_NAME", s.maskPath});
  if (!s.inputCatalogPath.empty()) inputs.push_back({"INPUT_CATALOG", s.inputCatalogPath});
  for (const std::string& path : s.colourImagePaths) inputs.push_back({"COLOUR_IMAGE", path});
  return inputs;
}

// Each COLOUR_IMAGE on the measurement image's pixel grid, from the headers alone.
void checkColourImageGrids(const SearchRunSettings& s) {
  if (s.colourImagePaths.empty()) return;
  const std::string& measured = s.run.measurementImagePath();
  auto grid = [](const std::string& path) {
    const ImageHdu hdu = readImageHeader(path);
    return std::make_tuple(hdu.widthPix, hdu.heightPix, Wcs::fromHeader(hdu.header, path));
  };
  const auto [width, height, wcs] = grid(measured);
  for (const std::string& path : s.colourImagePaths) {
    const auto [w, h, bandWcs] = grid(path);
    const std::string difference = pixelGridDifference(width, height, wcs, w, h, bandWcs);
    if (!difference.empty()) {
      throw ConfigError("COLOUR_IMAGE " + path + " and the measurement image " + measured +
                        " must share one pixel grid (" + difference + ")");
    }
  }
}

// A colour band's image, background-subtracted with the measurement image's BACK_TYPE and mesh
// settings (its own background; no BACKGROUND_NAME maps, no weight map, no filter).
PreparedImage prepareColourImage(const SearchRunSettings& s, const std::string& path,
                                 const RunLog& log) {
  RunSettings band = measurementImageSettings(s.run);
  band.weightType = WeightType::None;
  band.weightImagePath.clear();
  band.filter = false;
  // The measurement image's background maps are not another band's: each band's own is
  // estimated (or is 0, readColourSettings).
  band.backgroundMapPath.clear();
  band.backgroundRmsMapPath.clear();
  if (log) log("> Reading " + path);
  return prepareImage(path, band, {}, false);
}

// Every colour band's image (prepareColourImage).
std::vector<PreparedImage> prepareColourImages(const SearchRunSettings& s, const RunLog& log) {
  std::vector<PreparedImage> images;
  for (const std::string& path : s.colourImagePaths) {
    images.push_back(prepareColourImage(s, path, log));
  }
  return images;
}

// OUTPUT_DIR is replaced whole: it must be new or an earlier search output, and hold no input.
void checkOutputDirectory(const SearchRunSettings& s) {
  if (s.outputDir.empty()) throw ConfigError("OUTPUT_DIR: empty");
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(s.outputDir, ec);
  for (const NamedInput& in : searchInputs(s)) {
    if (in.path.empty()) continue;
    const std::size_t bracket = in.path.find('[');  // cfitsio syntax: file[HDU]
    const fs::path file = fs::weakly_canonical(
        bracket == std::string::npos ? in.path : in.path.substr(0, bracket), ec);
    if (!ec && std::mismatch(out.begin(), out.end(), file.begin(), file.end()).first == out.end()) {
      throw ConfigError("OUTPUT_DIR " + s.outputDir + " holds " + in.key + " " + in.path +
                        ", and is replaced whole by the search; choose another OUTPUT_DIR");
    }
  }
  // The test AtomicDirectory makes again when the outputs are written, before any work.
  AtomicDirectory::checkReplaceable(s.outputDir, kSearchMarkerFile, kSearchMarkerText);
}

}  // namespace

std::vector<RegionShape> readSearchMask(const SearchRunSettings& settings,
                                        const std::string& maskPath, const std::string& imagePath) {
  const ImageHdu image = readImageHeader(imagePath);
  return readDs9Regions(maskPath, image.header, imagePath,
                        maskPointRadiusPix(settings, image, imagePath));
}

namespace {

// The rows detected and measured in memory, as octarc detect makes them (and, with LENS_LIGHT,
// those of the residual).
void detectRows(const SearchRunSettings& settings, SearchRun& run, const RunLog& log) {
  const RunSettings& rs = settings.run;
  const int levelCount = int(detectionLevels(rs, 1.0).size());
  const ColumnPlan columns = planColumns(rs, true, levelCount);
  if (settings.lensLight.mode != lenslight::SubtractionMode::Off) {
    lenslight::checkLensSelectColumns(Table(columns.outputColumns),
                                      settings.lensLight.selectExpression);
  }
  DetectionRunResult detected = runDetection(rs, columns, settings.assoc, log, true);
  DetectedExtension& ext = detected.extensions.front();
  run.catalog = std::move(ext.table);
  run.catalogOrder = std::move(ext.order);
  run.levels = ext.levels;
  run.runCards = ext.cards;
  run.image = std::move(*detected.checkImage);
  run.footprints = std::move(detected.segmentation);
  requireColumns(run.catalog, searchRequiredColumns(), "PARAMETERS_NAME " + rs.parametersPath);
  if (settings.lensLight.mode != lenslight::SubtractionMode::Off) {
    run.pixelScaleArcsec = runPixelScaleArcsec(run, rs);
    // LENS_LIGHT_BAND: that band's image, needed only for the fits (read again for the colours).
    std::optional<PreparedImage> fitBand;
    if (settings.lensLightBand >= 0) {
      fitBand = prepareColourImage(
          settings, settings.colourImagePaths[std::size_t(settings.lensLightBand)], log);
    }
    applyLensLight(run, settings, columns, log, fitBand ? &*fitBand : nullptr);
  }
}

// The rows of an earlier run (INPUT_CATALOG), and the levels as the catalog holds them.
void readEarlierRows(const SearchRunSettings& settings, SearchRun& run, const RunLog& log) {
  const RunSettings& rs = settings.run;
  if (log) log("> Reading " + settings.inputCatalogPath);
  run.catalog = tableFromFits(readFitsTable(settings.inputCatalogPath, "LDAC_OBJECTS"));
  requireColumns(run.catalog, searchRequiredColumns(), settings.inputCatalogPath);
  if (log) log("> Reading " + rs.imagePaths[0]);
  run.image = prepareImage(rs.imagePaths[0], rs, {}, false);
  for (const std::string& w : run.image.warnings) run.warnings.push_back(w);
  // The levels as the catalog holds them (THRESHOLD per THRESH_LEVEL).
  const int level = run.catalog.findColumn("THRESH_LEVEL");
  const int threshold = run.catalog.findColumn("THRESHOLD");
  for (std::int64_t r = 0; r < run.catalog.rows(); ++r) {
    // A value from the user's file: checked before it becomes an index.
    const double levelValue = run.catalog.value(r, level);
    if (!(levelValue >= 1 && levelValue <= kMaxThresholdLevels)) continue;
    const int k = int(levelValue);
    if (int(run.levels.size()) < k) run.levels.resize(std::size_t(k));
    ThresholdLevel& t = run.levels[std::size_t(k - 1)];
    t.level = k;
    t.thresholdAdu = threshold >= 0 ? run.catalog.value(r, threshold) : std::nan("");
    t.thresholdSigma = t.thresholdAdu / run.image.sigmaAdu;
  }
  if (std::any_of(run.levels.begin(), run.levels.end(),
                  [](const ThresholdLevel& t) { return t.level == 0; })) {
    throw ConfigError(settings.inputCatalogPath +
                      ": THRESH_LEVEL skips a level (a filtered catalog?); the search needs "
                      "every level of the run");
  }
}

// The rows of an image prepared in memory (run.image), detected and measured as detectRows
// does a file's: the PARAMETERS_NAME columns, ASSOC, and with LENS_LIGHT those of the residual.
void detectPreparedRows(const SearchRunSettings& settings, SearchRun& run,
                        const std::function<void()>& checkpoint, const RunLog& log) {
  const RunSettings& rs = settings.run;
  run.levels = detectionLevels(rs, run.image.detectionSigma());
  const ColumnPlan columns = planColumns(rs, true, int(run.levels.size()));
  if (settings.lensLight.mode != lenslight::SubtractionMode::Off) {
    lenslight::checkLensSelectColumns(Table(columns.outputColumns),
                                      settings.lensLight.selectExpression);
  }
  MeasureContext context = run.image.context(rs);
  context.levels = run.levels;
  DetectionRequest request = configuredRequest(rs, run.levels);
  request.keepSegmentation = true;  // the footprints: arcs' curvature, colours, lens light
  request.checkpoint = checkpoint;
  ImageRunResult detected = detectAndMeasure(run.image, columns.plan, context, request, &rs);
  Table full = std::move(detected.rows);
  if (settings.assoc) {
    // ASSOC removes rows: put them in catalog order first (as a file's run does).
    full = rowsInOrder(full, detected.catalogOrder);
    detected.catalogOrder.clear();
    applyAssoc(*settings.assoc, columns.assocVectorSize, run.image, full, true);
  }
  run.catalog = outputTable(columns, std::move(full));
  run.catalogOrder = std::move(detected.catalogOrder);
  run.footprints = std::move(detected.segmentation);
  requireColumns(run.catalog, searchRequiredColumns(), "PARAMETERS_NAME " + rs.parametersPath);
  if (settings.lensLight.mode != lenslight::SubtractionMode::Off) {
    run.pixelScaleArcsec = runPixelScaleArcsec(run, rs);
    applyLensLight(run, settings, columns, log, nullptr, checkpoint);
  }
}

// Warnings when the model or grid was made for another setup than this image's.
void compareWithSelectionSetup(const SearchRunSettings& settings, SearchRun& run) {
  const RunSettings& rs = settings.run;
  const bool trees = settings.search.method == SelectionMethod::Trees;
  SurveySetup here;
  here.pixelScaleArcsec = run.pixelScaleArcsec;
  here.seeingFwhmArcsec = rs.seeingFwhmArcsec;
  here.gainElectronsPerAdu = run.image.gain > 0 ? run.image.gain : std::nan("");
  here.skySigmaAdu = run.image.sigmaAdu;
  for (const ThresholdLevel& t : run.levels) here.thresholdsSigma.push_back(t.thresholdSigma);
  here.minAreaPix = rs.minAreaPix;
  const std::string selector =
      trees ? "the model " + settings.modelPath : "the grid " + settings.gridPath;
  for (const std::string& d :
       compareSetups(trees ? run.model->setup : run.grid->provenance.setup, here)) {
    run.warnings.push_back(selector + " was made for another setup: " + d);
  }
  if (trees && (settings.search.snrMin < run.model->training.snrMin ||
                settings.search.resolvedMinArcsec < run.model->training.resolvedMinArcsec)) {
    run.warnings.push_back(selector + " was trained on rows with S/N > " +
                           formatNumber(run.model->training.snrMin, "%g") + " and resolved > " +
                           formatNumber(run.model->training.resolvedMinArcsec, "%g") +
                           "\"; rows below are scored by extrapolation");
  }
}

// The searched area, the search's inputs (lens-light marks, colour bands) and the candidates.
SearchResult selectCandidates(const SearchRunSettings& settings, SearchRun& run,
                              SearchMaskSettings maskSettings, const RunLog& log) {
  const RunSettings& rs = settings.run;
  const Wcs* wcs = run.image.wcs ? &*run.image.wcs : nullptr;
  if (!run.image.variance.empty()) maskSettings.varianceAdu2 = &run.image.variance;
  maskSettings.borderPix = settings.borderPix;
  const SearchMask mask(run.image.hdu.pixels.width(), run.image.hdu.pixels.height(), maskSettings);
  run.searchedBlocks = mask.blockCounts();

  SearchSettings search = settings.search;
  search.pixelScaleArcsec = run.pixelScaleArcsec;
  search.threads = resolveThreads(settings.run.threads);
  SearchInput input;
  input.catalog = &run.catalog;
  input.grid = run.grid ? &*run.grid : nullptr;
  input.model = run.model ? &*run.model : nullptr;
  input.mask = &mask;
  input.wcs = wcs;
  input.footprints = run.footprints ? &*run.footprints : nullptr;
  input.pixels = &run.image.hdu.pixels;
  std::map<std::size_t, std::pair<double, double>> fittedCentres;
  if (run.lensLight) {
    for (const lenslight::FittedGalaxy& g : run.lensLight->galaxies) {
      if (g.subtracted()) fittedCentres[g.row] = {g.fittedXPix(), g.fittedYPix()};
    }
    input.fittedCentres = &fittedCentres;
    input.lensLightOf = &run.lensLightOf;
    input.residualPixels = &run.lensLight->residual;
    input.residualRowsAreExtra = settings.lensLight.mode == lenslight::SubtractionMode::Local;
    // IMAGE: every row was measured on the residual, and its arcs are fitted there.
    if (!input.residualRowsAreExtra) input.pixels = &run.lensLight->residual;
  }
  // The colour bands' images are needed only here and for the colour stamps: freed when the
  // candidates are made unless stamps are written.
  std::vector<PreparedImage> colourImages = prepareColourImages(settings, log);
  const auto bandOf = [](const PreparedImage& image, double magZeropoint) {
    BandImage band;
    band.pixels = &image.hdu.pixels;
    band.variance = image.variance.empty() ? nullptr : &image.variance;
    band.sigmaAdu = image.sigmaAdu;
    band.gain = image.gain;
    band.magZeropoint = magZeropoint;
    return band;
  };
  const BandImage measurementBand = bandOf(run.image, rs.magZeropoint);
  std::vector<BandImage> bands;
  for (std::size_t k = 0; k < colourImages.size(); ++k) {
    for (const std::string& w : colourImages[k].warnings) run.warnings.push_back(w);
    bands.push_back(bandOf(colourImages[k], settings.colourZeropoints[k]));
  }
  input.measurementBand = &measurementBand;
  input.bands = &bands;
  if (log) log("> Selecting candidates");
  SearchResult result = searchCandidates(input, search);
  if (settings.writeStamps) run.colourImages = std::move(colourImages);
  return result;
}

// What every search does once its rows are in `run`: the pixel scale, the grid's or model's
// setup compared with the image's, the selection in the searched area.
void selectFromRows(const SearchRunSettings& settings, SearchRun& run,
                    SearchMaskSettings maskSettings, const RunLog& log) {
  const RunSettings& rs = settings.run;
  run.pixelScaleArcsec = runPixelScaleArcsec(run, rs);
  if (!run.image.wcs) {
    run.warnings.push_back(searchedImageName(run, rs) +
                           " has no celestial WCS: candidates get pixel positions only (no RA, "
                           "Dec or name), the searched area comes from PIXEL_SCALE");
  }
  compareWithSelectionSetup(settings, run);
  run.result = selectCandidates(settings, run, std::move(maskSettings), log);
  if (log) {
    for (const std::string& w : run.warnings) log("WARNING: " + w);
  }
}

// The settings the candidate tables are written with: the run's pixel scale and levels.
SearchSettings outputSearchSettings(const SearchRun& run, const SearchRunSettings& settings) {
  SearchSettings search = settings.search;
  search.pixelScaleArcsec = run.pixelScaleArcsec;
  search.threads = resolveThreads(settings.run.threads);
  // LEVELS as long as the run's levels, also when an input catalog has no object at the top
  // ones: a batch's tiles then have one LEVELS length, which the survey merge requires.
  search.levelCount =
      std::max(int(run.levels.size()), int(detectionLevels(settings.run, 1.0).size()));
  return search;
}

}  // namespace

FitsTable searchCandidateTable(const SearchRun& run, const SearchRunSettings& settings) {
  return candidateObjectsTable(run.catalog, run.result, outputSearchSettings(run, settings));
}

SearchRun searchImage(const SearchRunSettings& settings, const RunLog& log) {
  const RunSettings& rs = settings.run;
  if (rs.imagePaths.empty() || rs.imagePaths.size() > 2) {
    throw ConfigError("search: give one image, or a detection and a measurement image (see -h)");
  }
  if (rs.dualImage() && !settings.inputCatalogPath.empty()) {
    throw ConfigError("search: INPUT_CATALOG " + settings.inputCatalogPath +
                      " already holds the measurements; give its one image, not two");
  }
  SearchRun run;
  // Everything that can be checked is checked before any pixel is read.
  checkOutputDirectory(settings);
  checkColourImageGrids(settings);
  // A GRID_NAME or MODEL_NAME without a directory may be a shipped one (-GRID_NAME
  // demo.grid.fits).
  const bool trees = settings.search.method == SelectionMethod::Trees;
  if (trees) {
    run.model = loadLensModel(existingUserOrDataFile(settings.modelPath, "MODEL_NAME file"));
  } else {
    run.grid = loadGrid(existingUserOrDataFile(settings.gridPath, "GRID_NAME file"));
  }
  SearchMaskSettings maskSettings;
  if (!settings.maskPath.empty()) {
    maskSettings.regions = readSearchMask(settings, settings.maskPath, rs.imagePaths[0]);
  }
  if (settings.inputCatalogPath.empty()) {
    detectRows(settings, run, log);
  } else {
    readEarlierRows(settings, run, log);
  }
  selectFromRows(settings, run, std::move(maskSettings), log);
  return run;
}

SearchRun searchPreparedImage(const SearchRunSettings& settings, PreparedImage image,
                              std::optional<SavedGrid> grid, std::optional<SavedLensModel> model,
                              const std::function<void()>& checkpoint, const RunLog& log) {
  // Keys that name files, which an image in memory has no place for.
  const std::pair<const char*, bool> fileKeys[] = {
      {"COLOUR_IMAGE", !settings.colourImagePaths.empty()},
      {"MASK_NAME", !settings.maskPath.empty()},
      {"INPUT_CATALOG", !settings.inputCatalogPath.empty()}};
  for (const auto& [key, given] : fileKeys) {
    if (given) {
      throw ConfigError(std::string(key) +
                        ": not available for an image in memory; use octarc search on a file");
    }
  }
  const bool trees = settings.search.method == SelectionMethod::Trees;
  if (trees && !model) throw ConfigError("SELECTION_METHOD TREES: no lens model given");
  if (!trees && !grid) throw ConfigError("SELECTION_METHOD GRID: no grid given");
  SearchRun run;
  if (trees) {
    run.model = std::move(model);
  } else {
    run.grid = std::move(grid);
  }
  run.image = std::move(image);
  detectPreparedRows(settings, run, checkpoint, log);
  selectFromRows(settings, run, {}, log);
  return run;
}

std::string reportSpaceLine(const std::string& name, const std::string& expression,
                            std::int64_t candidates, double areaDeg2) {
  std::string line =
      "  " + name + " (" + expression + "): " + std::to_string(candidates) + " candidate(s)";
  if (areaDeg2 > 0)
    line += ", " + formatNumber(double(candidates) / areaDeg2, "%.1f") + " per deg2";
  return line;
}

std::vector<std::string> searchSummaryLines(const SearchRun& run,
                                            const SearchRunSettings& settings) {
  const SearchSummary& s = run.result.summary;
  std::vector<std::string> lines;
  const RunSettings& rs = settings.run;
  lines.push_back((rs.dualImage() ? "Images " + rs.detectionImagePath() + " (detection), " +
                                        rs.measurementImagePath() + " (measurement)"
                                  : "Image " + searchedImageName(run, rs)) +
                  (run.model ? ", model " + settings.modelPath : ", grid " + settings.gridPath));
  std::string area = std::to_string(s.searchedPixels) + " pixels searched";
  area += " (" + formatNumber(s.searchedAreaDeg2, "%.5f") + " deg2" +
          (run.image.wcs ? std::string(")") : std::string(", from PIXEL_SCALE: no WCS)"));
  lines.push_back(area);
  lines.push_back(std::to_string(s.objectsSearched) + " objects (" +
                  std::to_string(s.rowsSearched) + " rows at all levels) searched; " +
                  std::to_string(s.rowsSelected) + " rows selected (" +
                  formatNumber(100.0 * s.rejectedFraction(), "%.3f", true) + "% rejected)");
  std::string cands = std::to_string(s.candidates) + " candidate(s)";
  if (s.searchedAreaDeg2 > 0) {
    cands += ", " + formatNumber(s.candidatesPerDeg2(), "%.1f") + " per deg2";
  }
  std::int64_t dark = 0;
  for (const Candidate& c : run.result.candidates) dark += (c.flags & kCandidateDarkLens) != 0;
  cands += "; " + std::to_string(dark) + " without a visible lens";
  lines.push_back(cands);
  const SearchSettings& search = settings.search;
  if (!search.colourBands.empty()) {
    std::string bands;
    for (const std::string& b : search.colourBands) bands += (bands.empty() ? "" : ", ") + b;
    std::int64_t pairs = 0;
    for (const Candidate& c : run.result.candidates) {
      pairs += (c.flags & kCandidateDarkLensPair) != 0;
    }
    lines.push_back("Colour band(s) " + bands + ": " + std::to_string(pairs) +
                    " dark-lens pair(s) (a same-colour counter-image, no lens)");
  }
  if (search.colourCut) {
    const std::string max = formatNumber(search.colourCut->maxArcMinusLensMag, "%g");
    lines.push_back("Colour cut COLOUR_CUT " + search.colourCut->band + "," + max + ": " +
                    std::to_string(s.candidates + s.removedByColourCut) +
                    " candidate(s) before the cut, " + std::to_string(s.removedByColourCut) +
                    " removed (arc minus lens colour in " + search.colourCut->band + " above " +
                    max + " mag), " + std::to_string(s.candidates) +
                    " after it; every other count is after the cut");
  }
  for (const SpaceCount& space : s.spaces) {
    lines.push_back(
        reportSpaceLine(space.name, space.expression, space.candidates, s.searchedAreaDeg2));
  }
  if (run.lensLight) {
    const lenslight::Subtraction& sub = *run.lensLight;
    std::int64_t found = 0;
    for (const Candidate& c : run.result.candidates) found += (c.flags & kCandidateLensLight) != 0;
    const bool local = settings.lensLight.mode == lenslight::SubtractionMode::Local;
    const std::int64_t fitted = sub.fittedCount();
    const std::string band = settings.lensLightBand >= 0
                                 ? ", LENS_LIGHT_BAND " + settings.search.colourBands.at(
                                                              std::size_t(settings.lensLightBand))
                                 : std::string();
    lines.push_back(std::string("Lens light (LENS_LIGHT ") + (local ? "LOCAL" : "IMAGE") + band +
                    "): " + std::to_string(sub.galaxies.size()) + " galaxies chosen (" +
                    settings.lensLight.selectExpression + "), " + std::to_string(fitted) +
                    " galaxies fitted (the others' quick residual holds nothing), " +
                    std::to_string(sub.subtractedCount()) + " subtracted, " +
                    std::to_string(fitted - sub.subtractedCount()) + " left in (fit failed); " +
                    std::to_string(run.lensLightRows) + " residual rows near them; " +
                    std::to_string(found) + " candidate(s) from the residual");
  }
  return lines;
}

namespace {
void fillOutputDirectory(const SearchRun& run, const SearchRunSettings& settings,
                         const std::string& tempPath, const ProgressFn& progress,
                         const std::function<void(const std::string& dir)>& addFiles);
}  // namespace

void writeSearchOutputs(const SearchRun& run, const SearchRunSettings& settings,
                        const ProgressFn& progress, const RunLog& log,
                        const std::function<void(const std::string& dir)>& addFiles) {
  AtomicDirectory dir(settings.outputDir, kSearchMarkerFile, kSearchMarkerText);
  try {
    fillOutputDirectory(run, settings, dir.tempPath(), progress, addFiles);
  } catch (const IoError& e) {
    // Messages name the directory the user knows, not its temporary name.
    std::string message = e.what();
    for (std::size_t at; (at = message.find(dir.tempPath())) != std::string::npos;) {
      message.replace(at, dir.tempPath().size(), settings.outputDir);
    }
    throw IoError(message);
  }
  dir.commit();
  if (log) log("> Wrote " + settings.outputDir);
}

namespace {

// The summary as the vetting page shows it: the input files by their names, as an absolute path
// says nothing to whoever opens the page elsewhere.
std::vector<std::string> withFileNames(std::vector<std::string> lines,
                                       const SearchRunSettings& settings) {
  std::vector<std::string> paths = settings.run.imagePaths;
  paths.push_back(settings.gridPath);
  paths.push_back(settings.modelPath);
  for (std::string& line : lines) {
    for (const std::string& path : paths) {
      const std::string name = fs::path(path).filename().string();
      if (path.empty() || name == path) continue;
      for (std::size_t at; (at = line.find(path)) != std::string::npos;) {
        line.replace(at, path.size(), name);
      }
    }
  }
  return lines;
}

void fillOutputDirectory(const SearchRun& run, const SearchRunSettings& settings,
                         const std::string& tempPath, const ProgressFn& progress,
                         const std::function<void(const std::string& dir)>& addFiles) {
  const fs::path root = tempPath;
  const SearchSettings search = outputSearchSettings(run, settings);
  const Table& catalog = run.catalog;
  const Wcs* wcs = run.image.wcs ? &*run.image.wcs : nullptr;
  // An error names the temporary folder; writeSearchOutputs puts OUTPUT_DIR in its place.
  auto writeText = [&](const std::string& name, const std::string& text) {
    writeTextFile((root / name).string(), text);
  };
  const std::vector<std::string> summary = searchSummaryLines(run, settings);
  std::string summaryText;
  for (const std::string& l : summary) summaryText += l + "\n";
  writeText("summary.txt", summaryText);
  writeText("candidates.cat", candidateAsciiText(catalog, run.result, search));
  const FitsTable objects = candidateObjectsTable(catalog, run.result, search);
  writeText("candidates.reg",
            formatDs9Regions(candidateRegionMarks(catalog, run.result, run.pixelScaleArcsec), wcs));
  if (settings.writeStamps) {
    std::error_code ec;
    fs::create_directory(root / "stamps", ec);
    if (ec) throw IoError(settings.outputDir + "/stamps: cannot create (" + ec.message() + ")");
    // On every thread (cairo draws one surface per thread; the few WCS calls per stamp wait for
    // each other, wcslib's transforms of one Wcs being serialised).
    const std::int64_t n = std::int64_t(run.result.candidates.size());
    // The colour composites: from the image (never the lens-light residual), as the colours.
    const ColourStampBand searchedBand{&run.image.hdu.pixels, settings.run.magZeropoint};
    std::vector<ColourStampBand> colourBands;
    for (std::size_t k = 0; k < run.colourImages.size(); ++k) {
      colourBands.push_back({&run.colourImages[k].hdu.pixels, settings.colourZeropoints.at(k)});
    }
    parallelForDynamic(
        n, resolveThreads(settings.run.threads),
        [&](std::int64_t i) {
          // An arc found in the lens-light residual is shown there: the image hides it. IMAGE:
          // every candidate was found in the residual.
          const bool residual =
              run.lensLight &&
              (settings.lensLight.mode == lenslight::SubtractionMode::Image ||
               (run.result.candidates[std::size_t(i)].flags & kCandidateLensLight));
          const Stamp stamp = candidateStamp(
              residual ? run.lensLight->residual : run.image.hdu.pixels, catalog, run.result,
              std::size_t(i), wcs, run.pixelScaleArcsec, settings.stamps);
          writeStampPng((root / stampFileName(std::size_t(i))).string(), stamp);
          if (!colourBands.empty()) {
            writeStampPng(
                (root / colourStampFileName(std::size_t(i))).string(),
                candidateColourStamp(stamp, searchedBand, colourBands, run.image.sigmaAdu));
          }
          if (settings.writeCutouts) {
            writeImageFile((root / cutoutFileName(std::size_t(i))).string(),
                           {{cutoutHeader(run.image.hdu.header, stamp), &stamp.pixels, nullptr}});
          }
        },
        [&](std::int64_t done) {
          if (progress) progress(done, n);
        });
    VettingPageInfo page;
    page.title = "octarc search: " + fs::path(settings.run.imagePaths.front()).filename().string();
    page.summaryLines = withFileNames(summary, settings);
    page.links = {{"Catalog", "candidates.fits"},
                  {"ASCII catalog", "candidates.cat"},
                  {"DS9 regions", "candidates.reg"}};
    for (std::size_t i = 0; i < run.result.candidates.size(); ++i) {
      page.stampFiles.push_back(stampFileName(i));
      if (!colourBands.empty()) page.colourStampFiles.push_back(colourStampFileName(i));
      if (settings.writeCutouts) page.cutoutFiles.push_back(cutoutFileName(i));
    }
    writeText("index.html", vettingPageHtml(objects, page));
  }
  writeTableCatalog((root / "candidates.fits").string(), settings.catalogType, objects,
                    ldacImheadTable(run.image.hdu.header, run.runCards),
                    candidateColumnUcds(search.colourBands));
  if (run.lensLight) {
    writeFitsTables((root / "lensfit.fits").string(), {lensFitTable(run)});
    if (settings.lensCheckImages) {
      // With the image's header (its WCS), so that DS9 overlays them on the image.
      writeImageFile((root / "lensmodel.fits").string(),
                     {{run.image.hdu.header, &run.lensLight->model, nullptr}});
      writeImageFile((root / "lensresidual.fits").string(),
                     {{run.image.hdu.header, &run.lensLight->residual, nullptr}});
    }
  }
  if (addFiles) addFiles(tempPath);
  // The marker last: it says the directory is complete.
  writeText(kSearchMarkerFile, kSearchMarkerText);
}

}  // namespace

}  // namespace octarc
