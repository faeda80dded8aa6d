#include "octarc/calibration/SimulationOutput.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

#include "octarc/calibration/Weights.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Image.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/io/FitsTable.h"
#include "octarc/selection/SurveySetup.h"

namespace octarc {

namespace {

double card(const FitsHeader& h, const char* key) {
  return h.number(key).value_or(std::nan(""));
}

// OCTSEED as simulate lenses writes it: the 64-bit seed as a signed integer card (seeds from
// 2^63 on come out negative), or written unsigned; read exactly: as a double it would round
// seeds above 2^53.
std::optional<std::uint64_t> seedCard(const FitsHeader& h) {
  const std::optional<std::string> text = h.value("OCTSEED");
  if (!text || text->empty()) return std::nullopt;
  const char* begin = text->data() + ((*text)[0] == '+' ? 1 : 0);
  const char* end = text->data() + text->size();
  std::int64_t signedValue = 0;
  if (const auto r = std::from_chars(begin, end, signedValue);
      r.ec == std::errc() && r.ptr == end) {
    return std::uint64_t(signedValue);
  }
  std::uint64_t unsignedValue = 0;
  if (const auto r = std::from_chars(begin, end, unsignedValue);
      r.ec == std::errc() && r.ptr == end) {
    return unsignedValue;
  }
  return std::nullopt;
}

bool wholeIn(double v, double min, double max) {
  return v >= min && v <= max && std::floor(v) == v;
}

// The setup cards hold what simulate lenses itself accepts (simulation/engine/LensSetup.cpp);
// a value outside that was written by hand, and would go on into the grid's setup.
void checkSetupCards(const std::string& path, const FitsHeader& h) {
  const auto require = [&](const char* key, bool accepted, const std::string& expected) {
    if (!accepted) {
      throw IoError(path + ": LDAC_IMHEAD card " + key + " = " +
                    formatNumber(card(h, key), "%.17g") + " is not " + expected);
    }
  };
  require("OCTNSYS", wholeIn(card(h, "OCTNSYS"), 0, 0x1p53), "a whole number >= 0");
  require("OCTSEED", seedCard(h).has_value(), "a 64-bit integer");
  for (const char* key : {"OCTPIXSC", "OCTSEEIN", "OCTGAIN", "OCTSKYSG", "OCTTHLO", "OCTTHHI"}) {
    require(key, std::isfinite(card(h, key)) && card(h, key) > 0.0, "a finite number > 0");
  }
  // The grid and the lens model record each level (THRESHn): calibrate takes as many as they
  // can hold, before any work.
  require("OCTNLEV", wholeIn(card(h, "OCTNLEV"), 1, kMaxSetupLevels),
          "a whole number from 1 to " + std::to_string(kMaxSetupLevels) +
              " (a grid or lens model records at most " + std::to_string(kMaxSetupLevels) +
              " levels)");
  // Several levels are spaced from OCTTHLO to OCTTHHI, and the detector takes them strictly
  // increasing.
  const bool oneLevel = card(h, "OCTNLEV") == 1.0;
  require(
      "OCTTHHI",
      oneLevel ? card(h, "OCTTHHI") >= card(h, "OCTTHLO") : card(h, "OCTTHHI") > card(h, "OCTTHLO"),
      oneLevel ? "at least OCTTHLO" : "above OCTTHLO (OCTNLEV > 1)");
  require("OCTMAGZP", std::isfinite(card(h, "OCTMAGZP")), "a finite number");
  require("OCTMINAR", wholeIn(card(h, "OCTMINAR"), 1, std::numeric_limits<int>::max()),
          "a whole number >= 1");
  // The levels in sigma (outputs since they were recorded): both or neither, in order.
  if (h.value("OCTSGLO") || h.value("OCTSGHI")) {
    for (const char* key : {"OCTSGLO", "OCTSGHI"}) {
      require(key, std::isfinite(card(h, key)) && card(h, key) > 0.0, "a finite number > 0");
    }
    require("OCTSGHI",
            oneLevel ? card(h, "OCTSGHI") >= card(h, "OCTSGLO")
                     : card(h, "OCTSGHI") > card(h, "OCTSGLO"),
            oneLevel ? "at least OCTSGLO" : "above OCTSGLO (OCTNLEV > 1)");
  }
}

}  // namespace

SimulationOutput readSimulationOutput(const std::string& path) {
  const std::vector<std::string> tables = listFitsTables(path);
  auto has = [&](const char* name) {
    return std::find(tables.begin(), tables.end(), name) != tables.end();
  };
  if (!has("LDAC_OBJECTS") || !has("ARCS") || !has("LDAC_IMHEAD")) {
    throw IoError(path +
                  ": not an octarc simulate lenses output (it needs LDAC_IMHEAD, "
                  "LDAC_OBJECTS and ARCS tables)");
  }
  const FitsTable systems = readFitsTable(path, "LDAC_OBJECTS");
  if (!systems.findColumn("SYSTEM") || !systems.findColumn("ARC_FOUND")) {
    throw IoError(path +
                  ": not an octarc simulate lenses output (LDAC_OBJECTS has no SYSTEM "
                  "and ARC_FOUND columns)");
  }
  const FitsHeader h = readLdacImageHeader(path);
  for (const char* key : {"OCTNSYS", "OCTSEED", "OCTPIXSC", "OCTSEEIN", "OCTGAIN", "OCTSKYSG",
                          "OCTMAGZP", "OCTNLEV", "OCTTHLO", "OCTTHHI", "OCTMINAR"}) {
    if (!h.number(key)) {
      throw IoError(path + ": not an octarc simulate lenses output (no numeric " + key +
                    " card in its LDAC_IMHEAD)");
    }
  }
  checkSetupCards(path, h);
  SimulationOutput out;
  out.path = path;
  out.systems = tableFromFits(systems);
  out.arcs = tableFromFits(readFitsTable(path, "ARCS"));
  // The rows are the rendered systems (OCTNREND; all of them in older outputs): importance
  // sampling may render none of a few systems drawn, which is no error.
  if (!(card(h, "OCTNSYS") > 0)) throw IoError(path + ": the simulation holds no system");
  SurveySetup& s = out.setup;
  s.pixelScaleArcsec = card(h, "OCTPIXSC");
  s.seeingFwhmArcsec = card(h, "OCTSEEIN");
  s.gainElectronsPerAdu = card(h, "OCTGAIN");
  s.skySigmaAdu = card(h, "OCTSKYSG");
  s.minAreaPix = int(card(h, "OCTMINAR"));
  s.seed = *seedCard(h);
  s.systems = std::int64_t(card(h, "OCTNSYS"));
  // The population file is not recorded (the grid's POPFILE stays empty); the sources are.
  out.sourceDatabase = h.value("OCTSRCDB").value_or("");
  out.magZeropoint = card(h, "OCTMAGZP");
  out.band = h.value("OCTBAND").value_or("");
  out.header = h;
  // The levels are recorded by their count and ends; simulate lenses spaces them
  // logarithmically (DETECT_NLEVELS), as octarc detect does.
  const int levels = int(card(h, "OCTNLEV"));
  // In sigma as configured (OCTSGLO/OCTSGHI); older outputs give them in ADU only.
  const double lo = h.number("OCTSGLO").value_or(card(h, "OCTTHLO") / s.skySigmaAdu);
  const double hi = h.number("OCTSGHI").value_or(card(h, "OCTTHHI") / s.skySigmaAdu);
  for (int k = 0; k < levels; ++k) {
    s.thresholdsSigma.push_back(levels == 1 ? lo
                                            : lo * std::pow(hi / lo, double(k) / (levels - 1)));
  }
  return out;
}

namespace {

// The cards a remake reads beside the survey setup: combined outputs must agree on them.
constexpr const char* kRemakeCards[] = {
    "OCTPRSET", "OCTLMMIN", "OCTLMMAX", "OCTSMMIN", "OCTSMMAX", "OCTSVMIN", "OCTSVMAX", "OCTLEMAX",
    "OCTLRHLO", "OCTLRHHI", "OCTSTAMP", "OCTFINE",  "OCTSUBS",  "OCTSRCEX", "OCTSRCDB", "OCTPOPUL",
    "OCTFILTR", "OCTBAND",  "OCTSCOLM", "OCTSCOLS", "OCTLCOLM", "OCTLCOLS", "OCTSAMPL", "OCTSSTEP",
    "OCTSKIPT", "OCTISSCL", "OCTISFLR", "OCTISC0",  "OCTISC1",  "OCTISC2",  "OCTISC3",  "OCTISC4"};

// A card of the run; ConfigError for an output made before the cards were recorded.
std::string remakeCard(const SimulationOutput& sim, const char* key) {
  const std::optional<std::string> v = sim.header.value(key);
  if (!v) {
    throw ConfigError(sim.path + ": no " + key +
                      " card: made by an older octarc, whose options are not recorded; simulate "
                      "it again to study it");
  }
  return *v;
}

double remakeNumber(const SimulationOutput& sim, const char* key) {
  (void)remakeCard(sim, key);
  const std::optional<double> v = sim.header.number(key);
  if (!v) throw ConfigError(sim.path + ": its " + key + " card is not a number");
  return *v;
}

// The same, in the range simulate lenses accepts for the option it records
// (simulation/engine/LensSetup.cpp): a value outside it was written by hand.
double remakeNumber(const SimulationOutput& sim, const char* key, bool accepted(double),
                    const std::string& expected) {
  const double v = remakeNumber(sim, key);
  if (!accepted(v)) {
    throw IoError(sim.path + ": LDAC_IMHEAD card " + key + " = " + formatNumber(v, "%.17g") +
                  " is not " + expected);
  }
  return v;
}

bool finiteCard(double v) {
  return std::isfinite(v);
}
bool nonNegativeCard(double v) {
  return std::isfinite(v) && v >= 0.0;
}
bool positiveCard(double v) {
  return std::isfinite(v) && v > 0.0;
}
// --stamp-size's least value and the longest image side.
bool stampSideCard(double v) {
  return wholeIn(v, 9, double(kMaxImageSidePix));
}
bool positiveIntCard(double v) {
  return wholeIn(v, 1, std::numeric_limits<int>::max());
}

}  // namespace

LensSetupOptions resimulationOptions(const SimulationOutput& sim) {
  LensSetupOptions o;
  const SurveySetup& s = sim.setup;
  o.pixelScaleArcsec = s.pixelScaleArcsec;
  o.seeingFwhmArcsec = s.seeingFwhmArcsec;
  o.gainElectronPerAdu = s.gainElectronsPerAdu;
  o.magZeropoint = sim.magZeropoint;
  o.skySigmaAdu = s.skySigmaAdu;
  if (!s.thresholdsSigma.empty()) {
    o.detectThreshold = s.thresholdsSigma.front();
    o.detectThresholdMax = s.thresholdsSigma.back();
    o.detectLevelCount = int(s.thresholdsSigma.size());
  }
  if (s.minAreaPix > 0) o.minAreaPix = s.minAreaPix;
  const std::string preset = remakeCard(sim, "OCTPRSET");
  if (preset.empty()) {
    throw ConfigError(sim.path + ": simulated with a population file of one's own ('" +
                      sim.header.value("OCTPOPUL").value_or("") +
                      "'), which the studies that simulate again cannot remake");
  }
  o.populationPreset = preset;
  if (remakeCard(sim, "OCTFILTR") == "T") {
    throw ConfigError(sim.path +
                      ": simulated with FILTER Y, which the studies that simulate again cannot "
                      "remake yet (its kernel is not recorded)");
  }
  o.lensMagMin = remakeNumber(sim, "OCTLMMIN");
  o.lensMagMax = remakeNumber(sim, "OCTLMMAX");
  o.sourceMagMin = remakeNumber(sim, "OCTSMMIN");
  o.sourceMagMax = remakeNumber(sim, "OCTSMMAX");
  o.sigmaMinKmPerS = remakeNumber(sim, "OCTSVMIN");
  o.sigmaMaxKmPerS = remakeNumber(sim, "OCTSVMAX");
  o.lensEllipticityMax = remakeNumber(sim, "OCTLEMAX");
  o.lensHalfLightMinArcsec = remakeNumber(sim, "OCTLRHLO");
  o.lensHalfLightMaxArcsec = remakeNumber(sim, "OCTLRHHI");
  o.stampSizePix =
      int(remakeNumber(sim, "OCTSTAMP", stampSideCard,
                       "a whole number from 9 to " + std::to_string(kMaxImageSidePix)));
  o.fineScaleArcsec = remakeNumber(sim, "OCTFINE", positiveCard, "a finite number > 0");
  o.subSamples = int(
      remakeNumber(sim, "OCTSUBS", positiveIntCard,
                   "a whole number from 1 to " + std::to_string(std::numeric_limits<int>::max())));
  // The population's skip limit is the preset's; the card must still be one it may hold.
  (void)remakeNumber(sim, "OCTSKIPT", nonNegativeCard, "a finite number >= 0");
  // Sampled as the run sampled: older outputs rendered every system above the skip limit, with
  // every ray (no adaptive step).
  const std::string sampling = sim.header.value("OCTSAMPL").value_or("PLAIN");
  if (sampling == "IMPORTANCE") {
    o.sampling = Sampling::Importance;
    // The render probabilities are this octarc's (LensSetupOptions does not carry others).
    const ImportanceSampling is;
    const std::pair<const char*, double> parameters[] = {
        {"OCTISSCL", is.scale},          {"OCTISFLR", is.floor},
        {"OCTISC0", is.coefficients[0]}, {"OCTISC1", is.coefficients[1]},
        {"OCTISC2", is.coefficients[2]}, {"OCTISC3", is.coefficients[3]},
        {"OCTISC4", is.coefficients[4]}};
    for (const auto& [key, value] : parameters) {
      const double recorded = remakeNumber(sim, key);
      if (!(std::abs(recorded - value) <= 1e-9 * std::max(1.0, std::abs(value)))) {
        throw ConfigError(sim.path + ": its render probabilities (" + key + " = " +
                          formatNumber(recorded, "%.6g") + ") are not this octarc's (" +
                          formatNumber(value, "%.6g") +
                          "): the studies that simulate again cannot remake its sampling");
      }
    }
  } else if (sampling == "PLAIN") {
    o.sampling = Sampling::Plain;
  } else {
    throw ConfigError(sim.path + ": its OCTSAMPL card is '" + sampling + "' (IMPORTANCE or PLAIN)");
  }
  o.maxSourceStepPixels =
      sim.header.has("OCTSSTEP")
          ? remakeNumber(sim, "OCTSSTEP", nonNegativeCard, "a finite number >= 0 (0: every ray)")
          : 0.0;
  if (!sim.band.empty()) {
    o.bandName = sim.band;
    // Colours in mag: a mean and a scatter >= 0.
    const auto colour = [&](const char* mean, const char* scatter) {
      return ColourDraw{remakeNumber(sim, mean, finiteCard, "a finite number"),
                        remakeNumber(sim, scatter, nonNegativeCard, "a finite number >= 0")};
    };
    o.sourceColour = colour("OCTSCOLM", "OCTSCOLS");
    o.lensColour = colour("OCTLCOLM", "OCTLCOLS");
  }
  return o;
}

SourceDatabase SourceChoice::make() const {
  if (!catalogPath.empty()) return SourceDatabase::fromRealGalaxyCatalog(catalogPath);
  simulation::SyntheticGalaxyOptions galaxy;
  galaxy.stampHalfLightRadii = syntheticExtentHalfLightRadii;
  return SourceDatabase::synthetic(syntheticCount, kSyntheticSourceSeed, galaxy);
}

SourceChoice resimulationSources(const SimulationOutput& sim) {
  SourceChoice c;
  const std::string& db = sim.sourceDatabase;
  int count = 0;
  if (std::sscanf(db.c_str(), "synthetic (%d galaxies)", &count) == 1) {
    if (count < 1) {
      throw IoError(sim.path + ": LDAC_IMHEAD card OCTSRCDB = '" + db +
                    "' does not name a number of synthetic galaxies >= 1");
    }
    c.syntheticCount = count;
    c.syntheticExtentHalfLightRadii =
        remakeNumber(sim, "OCTSRCEX", positiveCard, "a finite number > 0");
  } else if (!db.empty()) {
    // The card holds at most 60 characters of the path.
    if (!std::filesystem::exists(db)) {
      throw ConfigError(sim.path + ": the source catalog its OCTSRCDB card names ('" + db +
                        "') is not there (a path over 60 characters is cut): the studies that "
                        "simulate again need it");
    }
    c.catalogPath = db;
  }
  return c;
}

void requireRemadeDraw(const SimulationOutput& sim, std::int64_t row, const LensSystemDraw& d) {
  const Table& t = sim.systems;
  if (!d.rendered) {
    throw ConfigError(sim.path + ": system " + std::to_string(d.index) +
                      " is not rendered when remade: it was simulated with a sampling its "
                      "header does not record");
  }
  // The columns are stored in single precision.
  auto same = [&](double remade, const char* column) {
    const double recorded = t.value(row, t.requireColumn(column, sim.path));
    return std::abs(remade - recorded) <= 1e-5 * std::max(1.0, std::abs(recorded));
  };
  if (!same(d.einsteinRadiusArcsec, "EINSTEIN_RADIUS") ||
      !same(d.system.light.halfLightRadiusArcsec, "LENS_RHALF") ||
      !same(d.system.source.betaArcsec[0], "SOURCE_X") ||
      !same(d.system.source.betaArcsec[1], "SOURCE_Y") ||
      (t.findColumn(kWeightColumn) >= 0 && !same(d.weight(), kWeightColumn))) {
    throw ConfigError(sim.path + ": system " + std::to_string(d.index) +
                      " cannot be remade (its Einstein radius, lens size, source position or "
                      "weight differ): it was simulated with options its header does not record");
  }
}

void checkRemade(const SimulationOutput& sim, const LensSetupOptions& options,
                 const SourceDatabase& sources, std::vector<std::int64_t> rows) {
  const SimulationSetup setup = makeSimulationSetup(options);
  if (rows.empty()) {
    for (std::int64_t r = 0; r < std::min<std::int64_t>(20, sim.systems.rows()); ++r) {
      rows.push_back(r);
    }
  }
  const int index = sim.systems.requireColumn("SYSTEM", sim.path);
  for (const std::int64_t r : rows) {
    const auto system = std::int64_t(sim.systems.value(r, index));
    requireRemadeDraw(sim, r, drawLensSystem(setup, sources, sim.setup.seed, system));
  }
}

SimulationOutput combineSimulationOutputs(std::vector<SimulationOutput> outputs) {
  if (outputs.empty()) throw ConfigError("no simulation output given");
  SimulationOutput out = std::move(outputs.front());
  std::vector<std::uint64_t> seeds = {out.setup.seed};
  for (std::size_t i = 1; i < outputs.size(); ++i) {
    SimulationOutput& o = outputs[i];
    // The same systems twice would be counted twice.
    if (std::find(seeds.begin(), seeds.end(), o.setup.seed) != seeds.end()) {
      throw ConfigError(o.path + ": simulated with seed " + std::to_string(o.setup.seed) +
                        " as an output given before: the same systems would count twice");
    }
    seeds.push_back(o.setup.seed);
    for (const char* key : kRemakeCards) {
      if (out.header.value(key) != o.header.value(key)) {
        throw ConfigError(o.path + ": simulated with another " + key + " than " + out.path +
                          " (population or sources)");
      }
    }
    const std::vector<std::string> differences = compareSetups(out.setup, o.setup);
    if (!differences.empty()) {
      throw ConfigError(o.path + ": simulated for another survey setup than " + out.path + " (" +
                        differences.front() + ")");
    }
    out.systemsStart.push_back(out.systems.rows());
    out.arcsStart.push_back(out.arcs.rows());
    for (Table* t : {&o.systems, &o.arcs}) {
      Table& into = t == &o.systems ? out.systems : out.arcs;
      bool sameColumns = t->columns().size() == into.columns().size();
      for (std::size_t c = 0; sameColumns && c < into.columns().size(); ++c) {
        sameColumns = t->columns()[c].name == into.columns()[c].name;
      }
      if (!sameColumns || t->rowWidth() != into.rowWidth()) {
        throw ConfigError(o.path + ": its tables have other columns than " + out.path);
      }
      for (std::int64_t r = 0; r < t->rows(); ++r) {
        std::copy_n(t->row(r), t->rowWidth(), into.appendRowUnset());
      }
    }
    out.setup.systems += o.setup.systems;
    ++out.outputs;
    out.path += "," + o.path;
  }
  return out;
}

}  // namespace octarc
