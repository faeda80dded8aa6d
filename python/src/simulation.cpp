#include "simulation.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arrays.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Table.h"
#include "octarc/simulation/engine/FieldSimulation.h"
#include "octarc/simulation/engine/LensCatalog.h"
#include "octarc/simulation/engine/LensSetup.h"
#include "octarc/simulation/engine/SurveySettings.h"
#include "run_inputs.h"

namespace octarc::python {

namespace py = pybind11;

namespace {

// ---- octarc.simulate_lenses ----

// What octarc.simulate_lenses returns to the Python package.
struct LensOutput {
  LensRun run;
  std::vector<std::string> cards;     // the OCT* header cards of the command's file
  std::vector<std::string> warnings;  // of the survey .sex file
  // The stamps, plane after plane in one block, so that numpy sees them as one 3-D array.
  std::vector<float> stampPixels;
  std::int64_t stampCount = 0, stampSidePix = 0;
};

std::string typeName(py::handle value) {
  return py::str(py::type::of(value).attr("__name__"));
}

// A setup value as a double; ValueError naming the key for anything but a real number.
double setupNumber(const std::string& key, py::handle value) {
  if (!py::isinstance<py::bool_>(value) && !py::isinstance<py::str>(value)) {
    try {
      return value.cast<double>();
    } catch (const py::cast_error&) {
    }
  }
  throw py::value_error("setup: " + key + " must be a number, not " + typeName(value));
}

// A setup value as an int; ValueError naming the key for anything but an integer in int's range.
int setupInteger(const std::string& key, py::handle value) {
  if (!py::isinstance<py::bool_>(value) && !py::isinstance<py::float_>(value)) {
    try {
      const long long v = value.cast<long long>();
      if (v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max()) {
        return int(v);
      }
      throw py::value_error("setup: " + key + " = " + std::to_string(v) + " is out of range");
    } catch (const py::cast_error&) {
    }
  }
  throw py::value_error("setup: " + key + " must be an integer, not " + typeName(value));
}

void assign(double& target, const std::string& key, py::handle v) {
  target = setupNumber(key, v);
}
void assign(int& target, const std::string& key, py::handle v) {
  target = setupInteger(key, v);
}
void assign(std::optional<double>& target, const std::string& key, py::handle v) {
  target = setupNumber(key, v);
}
void assign(std::optional<int>& target, const std::string& key, py::handle v) {
  target = setupInteger(key, v);
}
void assign(std::string& target, const std::string& key, py::handle v) {
  if (!py::isinstance<py::str>(v)) {
    throw py::value_error("setup: " + key + " must be a file name, not " + typeName(v));
  }
  target = v.cast<std::string>();
}

// One key of the `setup` dict: a `simulate lenses` option by its long name, '-' as '_'.
struct SetupKey {
  const char* name;
  std::function<void(LensSetupOptions&, const std::string&, py::handle)> set;
};

template <typename Field>
SetupKey setupKey(const char* name, Field LensSetupOptions::*field) {
  return {name, [field](LensSetupOptions& o, const std::string& key, py::handle value) {
            assign(o.*field, key, value);
          }};
}

const std::vector<SetupKey>& setupKeys() {
  using O = LensSetupOptions;
  static const std::vector<SetupKey> keys = {
      setupKey("pixel_scale", &O::pixelScaleArcsec),
      setupKey("seeing", &O::seeingFwhmArcsec),
      setupKey("gain", &O::gainElectronPerAdu),
      setupKey("zero_point", &O::magZeropoint),
      setupKey("sky_sigma", &O::skySigmaAdu),
      setupKey("limiting_mag", &O::limitingMag),
      setupKey("stamp_size", &O::stampSizePix),
      setupKey("thresh", &O::detectThreshold),
      setupKey("thresh_max", &O::detectThresholdMax),
      setupKey("nlevels", &O::detectLevelCount),
      setupKey("minarea", &O::minAreaPix),
      setupKey("lens_mag_min", &O::lensMagMin),
      setupKey("lens_mag_max", &O::lensMagMax),
      setupKey("source_mag_min", &O::sourceMagMin),
      setupKey("source_mag_max", &O::sourceMagMax),
      setupKey("sigma_min", &O::sigmaMinKmPerS),
      setupKey("sigma_max", &O::sigmaMaxKmPerS),
      setupKey("lens_e_max", &O::lensEllipticityMax),
      setupKey("lens_rhalf_min", &O::lensHalfLightMinArcsec),
      setupKey("lens_rhalf_max", &O::lensHalfLightMaxArcsec),
      setupKey("fine_scale", &O::fineScaleArcsec),
      setupKey("subsamples", &O::subSamples),
      setupKey("max_source_step", &O::maxSourceStepPixels),
      setupKey("population", &O::populationPath),
  };
  return keys;
}

std::unique_ptr<LensOutput> simulateLenses(
    std::int64_t count, std::uint64_t seed, const std::string& preset, const py::dict& setup,
    const std::string& database, int sources, double sourceExtent, const std::string& sampling,
    int stamps, int threads, const std::optional<std::string>& band,
    const std::optional<std::string>& sourceColour, const std::optional<std::string>& lensColour) {
  if (count < 1) {
    throw py::value_error("n: the number of systems must be positive, got " +
                          std::to_string(count));
  }
  auto out = std::make_unique<LensOutput>();
  LensSetupOptions o;
  o.populationPreset = preset;
  for (const auto& [name, value] : setup) {
    const std::string key = py::str(name);
    if (key == "config") {
      // Read below: makeSimulationSetup puts the other keys over it, whatever the dict's order.
      continue;
    }
    const auto& keys = setupKeys();
    const auto known =
        std::find_if(keys.begin(), keys.end(), [&](const SetupKey& k) { return key == k.name; });
    if (known == keys.end()) throw py::value_error("setup: unknown key " + key);
    known->set(o, key, value);
  }
  if (setup.contains("config")) {
    const py::handle config = setup["config"];
    if (!py::isinstance<py::str>(config)) {
      throw py::value_error("setup: config must be a file name, not " + typeName(config));
    }
    o.survey = readSurveySettings(config.cast<std::string>());
    out->warnings = o.survey->warnings;
  }
  o.sampling = parseSampling(sampling);
  o.bandName = band;
  if (sourceColour) o.sourceColour = parseColourDraw(*sourceColour, "source_colour");
  if (lensColour) o.lensColour = parseColourDraw(*lensColour, "lens_colour");
  const SimulationSetup simulationSetup = makeSimulationSetup(o);
  const int stampCount = int(std::min<std::int64_t>(stamps, count));
  {
    py::gil_scoped_release release;
    SignalCheck signals;
    const SourceDatabase sourceDatabase = makeSourceDatabase(database, sources, sourceExtent);
    signals();
    out->run =
        runLensSimulation(simulationSetup, sourceDatabase, seed, count, resolveThreads(threads),
                          stampCount, [&signals](std::int64_t, std::int64_t) { signals(); });
    out->cards = lensRunCards(out->run, simulationSetup, sourceDatabase, seed);
    out->stampCount = std::int64_t(out->run.stamps.size());
    out->stampSidePix = out->run.stamps.empty() ? o.stampSizePix : out->run.stamps[0].width();
    for (ImageF& stamp : out->run.stamps) {
      // One block of equal planes, or numpy's view would read past it.
      if (stamp.width() != out->stampSidePix || stamp.height() != out->stampSidePix) {
        throw Error("stamps: a stamp is not " + std::to_string(out->stampSidePix) +
                    " pixels square");
      }
      out->stampPixels.insert(out->stampPixels.end(), stamp.data(),
                              stamp.data() + stamp.width() * stamp.height());
      stamp = ImageF();
    }
  }
  return out;
}

// ---- octarc.simulate_field ----

// What simulate_field and inject_lenses share: the lenses drawn and how, then the settings
// checked (ConfigError naming the command's option).
void setLensDraw(FieldSimulationSettings& s, int lenses, double minEinsteinRadius,
                 double maxEinsteinRadius, std::uint64_t seed, const std::string& database,
                 const std::string& population, int threads) {
  s.lensCount = lenses;
  s.minEinsteinRadiusArcsec = minEinsteinRadius;
  s.maxEinsteinRadiusArcsec = maxEinsteinRadius;
  s.seed = seed;
  s.databasePath = database;
  s.populationPath = population;
  s.threads = threads;
  s.validate();
}

// What octarc.simulate_field returns to the Python package: the field without its pixels,
// which are handed to numpy when the output is made.
struct FieldOutput {
  SimulatedField field;
  std::vector<std::string> warnings;  // of the survey .sex file
  py::object image, weight;           // numpy float32 arrays owning the pixels
};

std::unique_ptr<FieldOutput> simulateFieldOf(
    int size, std::optional<double> pixelScale, std::optional<double> seeing,
    std::optional<double> gain, std::optional<double> noiseSigma, std::optional<double> limitingMag,
    std::optional<double> magZero, std::optional<double> saturate, int lenses,
    double minEinsteinRadius, double maxEinsteinRadius, std::uint64_t seed, double ra, double dec,
    const std::optional<std::string>& config, const std::string& database,
    const std::string& population, int threads) {
  auto out = std::make_unique<FieldOutput>();
  FieldSimulationSettings s;
  // Survey settings from the .sex file, then the options given (as the command takes them).
  if (config) {
    const SurveySettings survey = readSurveySettings(*config);
    out->warnings = survey.warnings;
    applySurveySettings(s, survey);
  }
  s.pixelScaleArcsec = pixelScale.value_or(s.pixelScaleArcsec);
  s.seeingFwhmArcsec = seeing.value_or(s.seeingFwhmArcsec);
  s.gainElectronsPerAdu = gain.value_or(s.gainElectronsPerAdu);
  s.magZeroPoint = magZero.value_or(s.magZeroPoint);
  s.saturationAdu = saturate.value_or(s.saturationAdu);
  if (noiseSigma && limitingMag) {
    throw py::value_error("noise_sigma and limiting_mag: give one of them, not both");
  }
  s.limitingMag = limitingMag.value_or(s.limitingMag);
  s.noiseSigmaAdu = noiseSigma;
  s.sizePix = size;
  s.raDeg = ra;
  s.decDeg = dec;
  setLensDraw(s, lenses, minEinsteinRadius, maxEinsteinRadius, seed, database, population, threads);
  auto image = std::make_unique<ImageF>();
  auto weight = std::make_unique<ImageF>();
  {
    py::gil_scoped_release release;
    SignalCheck signals;
    out->field = simulateField(s, [&signals](std::int64_t, std::int64_t) { signals(); });
    *image = std::move(out->field.image);
    *weight = std::move(out->field.weight);
  }
  out->image = ownedArray(std::move(image));
  out->weight = ownedArray(std::move(weight));
  return out;
}

std::unique_ptr<FieldOutput> injectLensesInto(const py::array& image, const py::object& weight,
                                              const std::vector<std::string>& headerCards,
                                              int lenses, double pixelScale, double seeing,
                                              double magZero, double gain, double minEinsteinRadius,
                                              double maxEinsteinRadius, std::uint64_t seed,
                                              const std::string& database,
                                              const std::string& population, int threads) {
  const ArrayView imageView = floatViewOf(image, "image");
  std::optional<ArrayView> weightView;
  py::array weightArray;
  if (!weight.is_none()) {
    weightArray = py::array(weight);
    weightView = floatViewOf(weightArray, "weight");
    requireSameShape(*weightView, "weight", imageView, "image");
  }
  const FitsHeader header = headerOf(headerCards);
  FieldSimulationSettings s;
  s.pixelScaleArcsec = pixelScale;
  s.seeingFwhmArcsec = seeing;
  s.magZeroPoint = magZero;
  s.gainElectronsPerAdu = gain;
  setLensDraw(s, lenses, minEinsteinRadius, maxEinsteinRadius, seed, database, population, threads);
  auto out = std::make_unique<FieldOutput>();
  auto pixels = std::make_unique<ImageF>();
  auto weights = std::make_unique<ImageF>();
  {
    py::gil_scoped_release release;
    const ImageHdu imageHdu = imageHduOf(imageView, "image", header);
    std::optional<ImageHdu> weightHdu;
    if (weightView) weightHdu = imageHduOf(*weightView, "weight", FitsHeader());
    // The library's calls take no progress function: one check before the work.
    SignalCheck signals;
    signals();
    out->field = injectLenses(imageHdu, weightHdu ? &*weightHdu : nullptr, s);
    *pixels = std::move(out->field.image);
    *weights = std::move(out->field.weight);
  }
  out->image = ownedArray(std::move(pixels));
  out->weight = weights->empty() ? py::none() : py::object(ownedArray(std::move(weights)));
  return out;
}

// The truth list as columns (name -> numpy array), in the order of the .truth.txt file.
py::dict truthColumns(const FieldOutput& out) {
  const std::vector<TruthRow>& truth = out.field.truth;
  const auto n = py::ssize_t(truth.size());
  py::array_t<std::int64_t> id(n);
  py::array_t<double> x(n), y(n), ra(n), dec(n), mag(n), thetaE(n);
  py::array_t<std::int32_t> kind(n), system(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    const TruthRow& r = truth[std::size_t(i)];
    id.mutable_at(i) = r.id;
    x.mutable_at(i) = r.xFits;
    y.mutable_at(i) = r.yFits;
    ra.mutable_at(i) = r.raDeg;
    dec.mutable_at(i) = r.decDeg;
    kind.mutable_at(i) = std::int32_t(r.kind);
    mag.mutable_at(i) = r.mag;
    thetaE.mutable_at(i) = r.einsteinRadiusArcsec;
    system.mutable_at(i) = r.systemId;
  }
  py::dict columns;
  columns["ID"] = id;
  columns["X_IMAGE"] = x;
  columns["Y_IMAGE"] = y;
  columns["ALPHA_J2000"] = ra;
  columns["DELTA_J2000"] = dec;
  columns["KIND"] = kind;
  columns["MAG"] = mag;
  columns["THETA_E"] = thetaE;
  columns["SYSTEM"] = system;
  return columns;
}

}  // namespace

void bindSimulation(py::module_& m) {
  py::class_<LensOutput>(m, "_LensSimulation",
                         "What octarc.simulate_lenses made: the systems and arc tables, the "
                         "stamps and the counts (octarc.LensSimulation wraps it).")
      .def_property_readonly(
          "systems", [](const LensOutput& o) -> const Table& { return o.run.systems; },
          py::return_value_policy::reference_internal, "One row per rendered system.")
      .def_property_readonly(
          "arcs", [](const LensOutput& o) -> const Table& { return o.run.arcs; },
          py::return_value_policy::reference_internal, "Every arc row at every level.")
      .def_property_readonly(
          "stamps",
          [](py::object self) {
            LensOutput& o = self.cast<LensOutput&>();
            // A read-only view of the output's block: it keeps the output alive, no copy.
            py::array_t<float> stamps({o.stampCount, o.stampSidePix, o.stampSidePix},
                                      o.stampPixels.data(), self);
            stamps.attr("setflags")(py::arg("write") = false);
            return stamps;
          },
          "The stamps of the first systems, (stamps, side, side) float32, read-only.")
      .def_readonly("cards", &LensOutput::cards, "The OCT* header cards of the catalog file.")
      .def_readonly("warnings", &LensOutput::warnings, "Warnings about the survey .sex file.")
      .def_property_readonly(
          "counts",
          [](const LensOutput& o) {
            py::dict c;
            c["drawn"] = o.run.drawn;
            c["rendered"] = o.run.rendered;
            c["skipped"] = o.run.skipped;
            c["systems_with_arc"] = o.run.systemsWithArc;
            c["redraws"] = o.run.redraws;
            c["rejections"] = o.run.rejections;
            c["weight_sum"] = o.run.weightSum;
            c["effective_arcs"] = o.run.effectiveArcs();
            return c;
          },
          "The run's counts and sums of weights.");
  m.def("_simulate_lenses", &simulateLenses, py::arg("count"), py::arg("seed"), py::arg("preset"),
        py::arg("setup"), py::arg("database"), py::arg("sources"), py::arg("source_extent"),
        py::arg("sampling"), py::arg("stamps"), py::arg("threads"), py::arg("band"),
        py::arg("source_colour"), py::arg("lens_colour"),
        "Simulated galaxy-galaxy lenses (octarc.simulate_lenses calls it).");

  py::class_<FieldOutput>(m, "_Field",
                          "What octarc.simulate_field made (octarc.SimulatedField wraps it).")
      .def_readonly("image", &FieldOutput::image, "The image, ADU, sky subtracted (float32).")
      .def_readonly("weight", &FieldOutput::weight,
                    "The weight map, 1 / variance (float32); None for an image injected into "
                    "without one.")
      .def_property_readonly(
          "header_cards", [](const FieldOutput& o) { return o.field.header.cards; },
          "The image's FITS header cards (the WCS), 80 characters each.")
      .def_property_readonly("truth", &truthColumns, "The truth list as columns.")
      .def_property_readonly(
          "sky_sigma", [](const FieldOutput& o) { return o.field.skySigmaAdu; },
          "The per-pixel sky noise, ADU.")
      .def_property_readonly(
          "counts",
          [](const FieldOutput& o) {
            py::dict c;
            c["galaxies"] = o.field.galaxyCount;
            c["stars"] = o.field.starCount;
            c["saturated_pixels"] = o.field.saturatedPixels;
            c["lenses"] = o.field.lenses.size();
            return c;
          },
          "The numbers of galaxies, stars, saturated pixels and lens systems.")
      .def_readonly("warnings", &FieldOutput::warnings, "Warnings about the survey .sex file.");
  m.def("_simulate_field", &simulateFieldOf, py::arg("size"), py::arg("pixel_scale"),
        py::arg("seeing"), py::arg("gain"), py::arg("noise_sigma"), py::arg("limiting_mag"),
        py::arg("mag_zero"), py::arg("saturate"), py::arg("lenses"), py::arg("min_einstein_radius"),
        py::arg("max_einstein_radius"), py::arg("seed"), py::arg("ra"), py::arg("dec"),
        py::arg("config"), py::arg("database"), py::arg("population"), py::arg("threads"),
        "A simulated survey field (octarc.simulate_field calls it).");
  m.def("_inject_lenses", &injectLensesInto, py::arg("image"), py::arg("weight"),
        py::arg("header_cards"), py::arg("lenses"), py::arg("pixel_scale"), py::arg("seeing"),
        py::arg("mag_zero"), py::arg("gain"), py::arg("min_einstein_radius"),
        py::arg("max_einstein_radius"), py::arg("seed"), py::arg("database"), py::arg("population"),
        py::arg("threads"),
        "Simulated lenses injected into an image (octarc.inject_lenses calls it).");
}

}  // namespace octarc::python
