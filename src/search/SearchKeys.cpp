#include "octarc/search/SearchKeys.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/measure/Colour.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/Levels.h"
#include "octarc/run/RunKeys.h"
#include "octarc/selection/ColumnExpression.h"
#include "octarc/sexcompat/KeyRow.h"

namespace octarc {

namespace {

using sexcompat::KeySpec;
using Kind = KeySpec::Kind;
using Row = sexcompat::KeyRow;

// The paper's two spaces of "significantly distorted and extended" arcs (METHOD.md section 4).
const std::vector<std::string>& defaultSearchSpaces() {
  static const std::vector<std::string> spaces = {
      "A015: ARCNESS > 0.15 && E_IMAGE > 0.6 && SNR_ISO > 40",
      "A010_015: ARCNESS > 0.10 && ARCNESS <= 0.15 && E_IMAGE > 0.6 && SNR_ISO > 40"};
  return spaces;
}

// SEARCH_SPACE values, read as blank-separated words: a word ending in ':' names a space, the
// words after it are its cut.
std::vector<SearchSpace> parseSearchSpaces(const std::vector<std::string>& values) {
  std::vector<SearchSpace> spaces;
  std::string name, expression;
  auto flush = [&] {
    if (name.empty()) return;
    if (expression.empty()) throw ConfigError("SEARCH_SPACE " + name + ": no cut after the name");
    spaces.emplace_back(name, expression, "SEARCH_SPACE");
  };
  for (const std::string& value : values) {
    std::istringstream words(value);
    std::string w;
    while (words >> w) {
      if (w.size() > 1 && w.back() == ':') {
        flush();
        name = w.substr(0, w.size() - 1);
        expression.clear();
      } else if (name.empty()) {
        throw ConfigError(
            "SEARCH_SPACE: give each space a name first, as in 'A015: ARCNESS > "
            "0.15 && E_IMAGE > 0.6' (found " +
            quoteForMessage(w) + ")");
      } else {
        expression += (expression.empty() ? "" : " ") + w;
      }
    }
  }
  flush();
  return spaces;
}

// The colour keys, checked against each other.
void readColourSettings(const sexcompat::Config& c, SearchRunSettings& s) {
  if (c.count("COLOUR_IMAGE") > 0) s.colourImagePaths = c.getStrings("COLOUR_IMAGE");
  if (c.count("COLOUR_BAND") > 0) s.search.colourBands = c.getStrings("COLOUR_BAND");
  const std::size_t n = s.colourImagePaths.size();
  if (s.search.colourBands.size() != n) {
    throw ConfigError("COLOUR_BAND: " + std::to_string(s.search.colourBands.size()) +
                      " band name(s) for " + std::to_string(n) +
                      " COLOUR_IMAGE(s); give one name per image");
  }
  for (std::size_t k = 0; k < n; ++k) {
    const std::string& band = s.search.colourBands[k];
    if (!isBandName(band)) {
      throw ConfigError("COLOUR_BAND: " + quoteForMessage(band) +
                        " is not a band name for column names (1-16 letters, digits or _)");
    }
    if (std::find(s.search.colourBands.begin(), s.search.colourBands.begin() + std::ptrdiff_t(k),
                  band) != s.search.colourBands.begin() + std::ptrdiff_t(k)) {
      throw ConfigError("COLOUR_BAND: " + band + " is named twice");
    }
  }
  const int zeropoints = c.count("COLOUR_ZEROPOINT");
  if (zeropoints == 0) {
    s.colourZeropoints.assign(n, s.run.magZeropoint);
  } else if (std::size_t(zeropoints) == n) {
    s.colourZeropoints = c.getDoubles("COLOUR_ZEROPOINT");
  } else {
    throw ConfigError("COLOUR_ZEROPOINT: " + std::to_string(zeropoints) + " value(s) for " +
                      std::to_string(n) +
                      " COLOUR_IMAGE(s); give one per image, or none for "
                      "MAG_ZEROPOINT");
  }
  const int seeings = c.count("COLOUR_SEEING_FWHM");
  if (seeings == 0) {
    s.colourSeeingFwhmArcsec.assign(n, s.run.seeingFwhmArcsec);
  } else if (std::size_t(seeings) == n) {
    s.colourSeeingFwhmArcsec = c.getDoubles("COLOUR_SEEING_FWHM");
  } else {
    throw ConfigError("COLOUR_SEEING_FWHM: " + std::to_string(seeings) + " value(s) for " +
                      std::to_string(n) +
                      " COLOUR_IMAGE(s); give one per image, or none for SEEING_FWHM");
  }
  if (c.givenWithoutValue("COLOUR_CUT")) {
    throw ConfigError(
        "COLOUR_CUT: a comma but no band and no MAX; give both, as in 'COLOUR_CUT g,-0.3', or "
        "leave the key out for no colour cut");
  }
  if (c.count("COLOUR_CUT") > 0) {
    const std::vector<std::string> cut = c.getStrings("COLOUR_CUT");
    char* end = nullptr;
    const double maxMag = cut.size() == 2 ? std::strtod(cut[1].c_str(), &end) : std::nan("");
    if (cut.size() != 2 || end == cut[1].c_str() || *end != '\0' || !std::isfinite(maxMag)) {
      throw ConfigError(
          "COLOUR_CUT: give a band and the largest arc minus lens colour, as in "
          "'COLOUR_CUT g,-0.3'");
    }
    if (std::find(s.search.colourBands.begin(), s.search.colourBands.end(), cut[0]) ==
        s.search.colourBands.end()) {
      throw ConfigError("COLOUR_CUT: band " + quoteForMessage(cut[0]) +
                        " is not one of COLOUR_BAND");
    }
    s.search.colourCut = ColourCut{cut[0], maxMag};
  }
  s.search.pairColourMatch.sigmas = c.getDouble("DARK_PAIR_COLOUR", 0);
  s.search.pairColourMatch.floorMag = c.getDouble("DARK_PAIR_COLOUR", 1);
  // A colour image's background is estimated like the measurement image's (BACK_TYPE AUTO),
  // or is already subtracted (MANUAL with BACK_VALUE 0); another band's sky is not the
  // measurement image's constant.
  const MeasurementImageSettings& measured = s.run.measurement;
  if (n > 0 && measured.backgroundType == BackgroundType::Manual &&
      measured.backgroundValueAdu != 0) {
    throw ConfigError(
        "COLOUR_IMAGE: BACK_TYPE MANUAL with BACK_VALUE " +
        formatNumber(measured.backgroundValueAdu) +
        " is the measurement image's sky, not the other bands'; use BACK_TYPE AUTO, or subtract "
        "the backgrounds first and give BACK_VALUE 0");
  }
}

// LENS_LIGHT_BAND: one of COLOUR_BAND, with LENS_LIGHT LOCAL or IMAGE.
void readLensLightBand(const sexcompat::Config& c, SearchRunSettings& s) {
  if (c.count("LENS_LIGHT_BAND") == 0) return;
  const std::string band = c.getString("LENS_LIGHT_BAND");
  if (s.lensLight.mode == lenslight::SubtractionMode::Off) {
    throw ConfigError("LENS_LIGHT_BAND " + band +
                      ": the lens models are fitted only with LENS_LIGHT LOCAL or IMAGE");
  }
  if (s.colourImagePaths.empty()) {
    throw ConfigError("LENS_LIGHT_BAND " + band +
                      ": no COLOUR_IMAGE; give the band's image in COLOUR_IMAGE and its name in "
                      "COLOUR_BAND");
  }
  const auto& bands = s.search.colourBands;
  const auto at = std::find(bands.begin(), bands.end(), band);
  if (at == bands.end()) {
    std::string names;
    for (const std::string& b : bands) names += (names.empty() ? "" : ", ") + b;
    throw ConfigError("LENS_LIGHT_BAND: band " + quoteForMessage(band) +
                      " is not one of COLOUR_BAND (" + names + ")");
  }
  s.lensLightBand = int(at - bands.begin());
}

}  // namespace

std::vector<KeySpec> searchKeys() {
  std::vector<KeySpec> keys = octarcKeys();
  // The arc search's own defaults (those of the shipped octarc.sex), not SExtractor's one
  // filtered level: what -d prints and a run without a configuration file uses.
  for (KeySpec& k : keys) {
    if (k.name == "DETECT_THRESH" || k.name == "ANALYSIS_THRESH") {
      k.defaults = {"2.5"};
    } else if (k.name == "DETECT_NLEVELS") {
      k.defaults = {"15"};
    } else if (k.name == "FILTER") {
      k.defaults = {"N"};
    } else if (k.name == "PARAMETERS_NAME") {
      k.defaults = {"octarc.param"};  // the shipped column list
    } else if (k.name == "CATALOG_TYPE") {
      // candidates.fits is FITS-LDAC unless asked otherwise (SExtractor's default is ASCII_HEAD).
      k.defaults = {"FITS_LDAC"};
      k.comment =
          "format of OUTPUT_DIR/candidates.fits: FITS_LDAC,\nFITS_1.0, ASCII_HEAD, ASCII or "
          "ASCII_VOTABLE";
    } else if (k.name == "WRITE_XML" || k.name == "XML_NAME" || k.name == "XSL_URL") {
      sexcompat::KeyRow::markIgnored(k);  // a search reports in OUTPUT_DIR/summary.txt
    }
  }
  // clang-format off
  const std::vector<KeySpec> own = {
    Row("SELECTION_METHOD", Kind::Keyword, {"GRID"}, "GRID (the occupation grid, GRID_NAME) or\n"
        "TREES (the learned selection, MODEL_NAME)").keywords({"GRID", "TREES"}),
    Row("GRID_NAME", Kind::String, {"arcs.grid.fits"},
        "the occupation grid (octarc calibrate)"),
    Row("MODEL_NAME", Kind::String, {"lens.model.fits"},
        "the lens model (octarc calibrate -MODEL_NAME)"),
    Row("LENS_DENSITY", Kind::Float, {"1.0"}, "lens arcs expected per deg2: the prior of\n"
        "LENS_SCORE").range(1e-9, 1e9),
    Row("SCORE_MIN", Kind::Float, {"0"}, "candidates have LENS_SCORE at least this").range(0, 1),
    Row("SEARCH_SPACE", Kind::String, defaultSearchSpaces(),
        "report spaces: NAME: cut, ... (a word ending in ':'\nstarts a space)")
        .list(0, 1024).expression(),
    Row("MASK_NAME", Kind::String, {}, "DS9 region file of the searched area (include and\n"
        "'-' exclude shapes)").list(0, 1),
    Row("MASK_BORDER", Kind::Int, {"0"}, "pixels this close to an edge are not searched")
        .range(0, 1e9),
    Row("MASK_POINT_RADIUS", Kind::Float, {"0"}, "radius of the circle a MASK_NAME point masks\n"
        "(arcsec; 0: points are refused)").range(0, 3600),
    Row("OUTPUT_DIR", Kind::String, {"candidates"}, "directory of the candidates, stamps and\n"
        "vetting page"),
    Row("SNR_MIN", Kind::Float, {"40"}, "S/N floor: SNR_ISO above it").range(0, 1e30),
    Row("RESOLVED_MIN", Kind::Float, {"1.0"}, "resolved: sqrt(2) SIZE_IMAGE above it (arcsec)")
        .range(0, 1e30),
    Row("LENS_RADIUS", Kind::Float, {"6.0"}, "farthest lens from the arc (arcsec)")
        .range(0, 60),
    Row("LENS_SIDE_ARCNESS", Kind::Float, {"0.05"}, "below this |ARCNESS| the concave side is\n"
        "unknown: the lens is the nearest galaxy").range(0, 1e30),
    Row("STAMP_SIZE", Kind::Float, {"26.0"}, "side of the postage stamps (arcsec)")
        .range(1, 300),
    Row("STAMP_PIXELS", Kind::Int, {"400"}, "side of the stamp images (PNG pixels)")
        .range(64, 4096),
    Row("STAMPS", Kind::Bool, {"Y"}, "write the stamps and vetting page"),
    Row("STAMP_CUTOUTS", Kind::Bool, {"Y"}, "with the stamps, stamps/NNNN.fits: each stamp's\n"
        "pixels with the image's WCS, for DS9"),
    Row("NAME_PREFIX", Kind::String, {"OCTARC"}, "prefix of the designations"),
    Row("LENS_LIGHT", Kind::String, {"N"}, "subtract fitted Sersic models of bright galaxies:\n"
        "N, LOCAL (also search the residual around each)\nor IMAGE (search the residual image)"),
    Row("LENS_SELECT", Kind::String, {"MAG_ISO < 20.5 && E_IMAGE < 0.5 && FLAGS < 4"},
        "which level-1 objects are fitted (an expression\non the catalog's columns)")
        .expression(),
    Row("LENS_CUTOUT", Kind::Float, {"20.0"}, "side of the square fitted around each (arcsec)")
        .range(1, 600),
    Row("LENS_CHECKIMAGES", Kind::Bool, {"Y"}, "write lensmodel.fits and lensresidual.fits"),
    Row("LENS_LIGHT_BAND", Kind::String, {}, "fit the lens models in this COLOUR_BAND's image\n"
        "(a redder band), scaled and PSF-matched to this one").list(0, 1),
    Row("COLOUR_IMAGE", Kind::String, {}, "images of other bands on the measurement image's\n"
        "pixel grid: colours of arcs and lenses").list(0, 16),
    Row("COLOUR_BAND", Kind::String, {}, "their band names, one per image (in column names)")
        .list(0, 16),
    Row("COLOUR_ZEROPOINT", Kind::Float, {}, "their magnitude zero-points (none: MAG_ZEROPOINT)")
        .list(0, 16),
    Row("COLOUR_SEEING_FWHM", Kind::Float, {}, "their seeing FWHM, arcsec (none: SEEING_FWHM)")
        .list(0, 16).range(0, 1e10),
    Row("COLOUR_CUT", Kind::String, {}, "BAND,MAX: remove candidates whose arc minus lens\n"
        "colour in BAND exceeds MAX (mag)").list(0, 2),
    Row("DARK_PAIR_COLOUR", Kind::Float, {"2.0", "0.1"}, "a dark-lens pair's colours agree\n"
        "within N sigma, with a floor (mag)").list(2, 2).range(0, 1e30),
  };
  // clang-format on
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}

SearchRunSettings searchSettingsFromConfig(const sexcompat::Config& c, RunSettings run) {
  SearchRunSettings s;
  s.run = std::move(run);
  if (planColumns(s.run, true, int(detectionLevels(s.run, 1.0).size())).assoc) {
    s.assoc = sexcompat::AssocSettings::fromConfig(c);
    if (c.getString("ASSOCSELEC_TYPE") != "ALL") {
      throw ConfigError("ASSOCSELEC_TYPE: a search keeps every row (the component tree); use ALL");
    }
  }
  s.catalogType = parseCatalogType(s.run.catalogType);
  if (s.catalogType == CatalogType::None) {
    throw ConfigError(
        "CATALOG_TYPE NONE: a search always writes its candidates (use FITS_LDAC, "
        "FITS_1.0, ASCII_HEAD, ASCII or ASCII_VOTABLE)");
  }
  s.search.method =
      c.getString("SELECTION_METHOD") == "TREES" ? SelectionMethod::Trees : SelectionMethod::Grid;
  s.gridPath = c.getString("GRID_NAME");
  s.modelPath = c.getString("MODEL_NAME");
  s.search.lensDensityPerDeg2 = c.getDouble("LENS_DENSITY");
  s.search.scoreMin = c.getDouble("SCORE_MIN");
  s.search.reportSpaces = parseSearchSpaces(c.getStrings("SEARCH_SPACE"));
  if (s.search.reportSpaces.size() > std::size_t(kMaxReportSpaces)) {
    throw ConfigError("SEARCH_SPACE: at most " + std::to_string(kMaxReportSpaces) + " spaces");
  }
  if (c.count("MASK_NAME") > 0) s.maskPath = c.getString("MASK_NAME");
  s.borderPix = c.getInt("MASK_BORDER");
  s.maskPointRadiusArcsec = c.getDouble("MASK_POINT_RADIUS");
  if (c.isExplicit("INPUT_CATALOG")) {
    if (c.count("INPUT_CATALOG") != 1) throw ConfigError("INPUT_CATALOG: give one catalog");
    s.inputCatalogPath = c.getString("INPUT_CATALOG");
  }
  s.outputDir = c.getString("OUTPUT_DIR");
  s.search.snrMin = c.getDouble("SNR_MIN");
  s.search.resolvedMinArcsec = c.getDouble("RESOLVED_MIN");
  s.search.lensRadiusArcsec = c.getDouble("LENS_RADIUS");
  s.search.sideMinArcness = c.getDouble("LENS_SIDE_ARCNESS");
  s.search.namePrefix = c.getString("NAME_PREFIX");
  s.stamps.sideArcsec = c.getDouble("STAMP_SIZE");
  s.stamps.sizePix = c.getInt("STAMP_PIXELS");
  s.writeStamps = c.getBool("STAMPS");
  s.writeCutouts = c.getBool("STAMP_CUTOUTS");
  s.lensLight.mode = lenslight::parseSubtractionMode(c.getString("LENS_LIGHT"));
  s.lensLight.selectExpression = c.getString("LENS_SELECT");
  s.lensLight.cutoutArcsec = c.getDouble("LENS_CUTOUT");
  s.lensCheckImages = c.getBool("LENS_CHECKIMAGES");
  if (s.lensLight.mode != lenslight::SubtractionMode::Off) {
    // Parsed now, so that a bad expression stops the run before any pixel is read.
    ColumnExpression(s.lensLight.selectExpression, "LENS_SELECT");
    if (!s.inputCatalogPath.empty()) {
      throw ConfigError(
          "LENS_LIGHT: the residual is detected here; it cannot be used with "
          "INPUT_CATALOG " +
          s.inputCatalogPath);
    }
    if (s.run.dualImage()) {
      throw ConfigError("LENS_LIGHT: not available in dual-image mode (give one image)");
    }
  }
  readColourSettings(c, s);
  readLensLightBand(c, s);
  if (!s.colourImagePaths.empty() && !s.inputCatalogPath.empty()) {
    throw ConfigError(
        "COLOUR_IMAGE: colours are measured in the detection footprints, which "
        "INPUT_CATALOG " +
        s.inputCatalogPath + " does not hold; leave one out");
  }
  return s;
}

}  // namespace octarc
