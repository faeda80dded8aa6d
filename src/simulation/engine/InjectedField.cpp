#include "octarc/simulation/engine/InjectedField.h"

#include <fstream>
#include <optional>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/DataFiles.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc {

namespace fs = std::filesystem;

namespace {

// The catalog's ASSOC radius, pixels: the truth list entry nearest to each object.
constexpr double kAssocRadiusPix = 5.0;

}  // namespace

InjectedFieldFiles makeInjectedFieldDirectory(const fs::path& dir) {
  InjectedFieldFiles p;
  p.dir = dir;
  std::error_code ec;
  p.madeDir = !fs::exists(dir, ec);
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw IoError(dir.string() + ": cannot create the output directory (" +
                  (ec ? ec.message() : std::string("not a directory")) + ")");
  }
  p.field = FieldOutputPaths::fromImagePath((dir / "field.fits").string());
  p.param = (dir / "demo.param").string();
  p.catalog = (dir / "field.ldac").string();
  return p;
}

std::vector<std::pair<std::string, std::string>> recoveryDetectionKeys(
    const InjectedFieldFiles& paths, int threads) {
  const std::string assocData =
      std::to_string(kTruthColumnId) + "," + std::to_string(kTruthColumnKind) + "," +
      std::to_string(kTruthColumnMag) + "," + std::to_string(kTruthColumnEinsteinRadius) + "," +
      std::to_string(kTruthColumnSystem);
  return {{"PARAMETERS_NAME", paths.param},
          {"CATALOG_NAME", paths.catalog},
          {"CATALOG_TYPE", "FITS_LDAC"},
          {"WEIGHT_TYPE", "MAP_WEIGHT"},
          {"WEIGHT_IMAGE", paths.field.weight},
          {"ASSOC_NAME", paths.field.truth},
          {"ASSOC_PARAMS", std::to_string(kTruthColumnX) + "," + std::to_string(kTruthColumnY)},
          {"ASSOC_DATA", assocData},
          {"ASSOC_RADIUS", formatNumber(kAssocRadiusPix, "%.1f", true)},
          {"ASSOC_TYPE", "NEAREST"},
          {"ASSOCSELEC_TYPE", "ALL"},
          {"CHECKIMAGE_TYPE", "NONE"},
          {"NTHREADS", std::to_string(threads)},
          {"VERBOSE_TYPE", "QUIET"}};
}

SimulatedField writeInjectedField(const FieldSimulationSettings& s, const InjectedFieldFiles& paths,
                                  const ProgressFn& progress, const RealImageInput& real) {
  const std::string shippedParam = dataFile("octarc.param");
  OutputFiles outputs;
  addFieldOutputs(outputs, paths.field);
  outputs.add(paths.param);
  SimulatedField field;
  if (real.imagePath.empty()) {
    field = simulateField(s, progress);
  } else {
    const ImageHdu image = readImage(real.imagePath);
    std::optional<ImageHdu> weight;
    if (!real.weightPath.empty()) weight = readImage(real.weightPath);
    field = injectLenses(image, weight ? &*weight : nullptr, s);
  }
  writeSimulatedField(field, s, paths.field, outputs);
  outputs.write(3, [&](const std::string& path) {
    std::ifstream in(shippedParam);
    if (!in) throw IoError(shippedParam + ": cannot read the demo's column list");
    std::ofstream f(path);
    f << in.rdbuf() << "VECTOR_ASSOC(5)          # truth: id, kind, mag, theta_E, system\n"
      << "NUMBER_ASSOC\n";
    if (!f) throw IoError(paths.param + ": write failed");
  });
  outputs.commit();
  return field;
}

}  // namespace octarc
