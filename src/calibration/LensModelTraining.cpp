#include "octarc/calibration/LensModelTraining.h"

#include <cmath>
#include <unordered_map>
#include <vector>

#include "octarc/calibration/Weights.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

// Rows above the S/N floor and resolved (sqrt(2) SIZE_IMAGE above the size), as the search.
bool eligible(const Table& t, std::int64_t r, int snr, int size, double pixelScaleArcsec,
              const LensModelSettings& s) {
  return t.value(r, snr) > s.snrMin &&
         std::sqrt(2.0) * t.value(r, size) * pixelScaleArcsec > s.resolvedMinArcsec;
}

}  // namespace

SavedLensModel trainLensModel(const SimulationOutput& simulation, const Table& survey,
                              const LensModelSettings& settings) {
  const double scale = simulation.setup.pixelScaleArcsec;
  if (!(scale > 0.0)) throw ConfigError(simulation.path + ": no pixel scale (OCTPIXSC)");
  const Table& systems = simulation.systems;
  if (simulation.arcs.findColumn(arcContextColumns().front().name) < 0) {
    throw ConfigError(simulation.path +
                      ": no context columns (CTX_...): made by an older octarc simulate lenses; "
                      "simulate again to train a model");
  }
  const int found = systems.requireColumn("ARC_FOUND", "model training");
  const int weightColumn = systems.requireColumn("SIM_WEIGHT", "model training");
  const int systemColumn = systems.requireColumn("SYSTEM", "model training");
  // Every arc row (every level) above the floor and resolved, as the search scores every row:
  // each arc system weighs its SIM_WEIGHT, shared among its rows. Within each combined output
  // the ARCS table follows the systems table by SYSTEM, so its rows are matched to their
  // systems in one walk per output (SYSTEM alone repeats across outputs).
  const Table& arcTable = simulation.arcs;
  const int arcSystem = arcTable.requireColumn("SYSTEM", "model training");
  const int arcSnr = arcTable.requireColumn("SNR_ISO", "model training");
  const int arcSize = arcTable.requireColumn("SIZE_IMAGE", "model training");
  std::vector<std::int64_t> arcs, systemOfArc;
  const std::size_t outputs = simulation.systemsStart.size();
  for (std::size_t k = 0; k < outputs; ++k) {
    std::int64_t at = simulation.systemsStart[k];
    const std::int64_t systemsEnd =
        k + 1 < outputs ? simulation.systemsStart[k + 1] : systems.rows();
    const std::int64_t arcsEnd = k + 1 < outputs ? simulation.arcsStart[k + 1] : arcTable.rows();
    for (std::int64_t r = simulation.arcsStart[k]; r < arcsEnd; ++r) {
      const double system = arcTable.value(r, arcSystem);
      while (at < systemsEnd && systems.value(at, systemColumn) != system) ++at;
      if (at == systemsEnd) {
        throw ConfigError(simulation.path + ": ARCS row " + std::to_string(r + 1) +
                          " belongs to no system of its output's systems table, in order");
      }
      if (systems.value(at, found) != 1.0 ||
          !eligible(arcTable, r, arcSnr, arcSize, scale, settings)) {
        continue;
      }
      arcs.push_back(r);
      systemOfArc.push_back(at);
    }
  }
  std::unordered_map<std::int64_t, int> rowsOfSystem;
  for (const std::int64_t system : systemOfArc) ++rowsOfSystem[system];
  std::vector<double> arcWeights;
  double systemsWeight = 0.0, rowsPerSystem = 0.0;
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    if (systems.value(r, found) == 1.0) systemsWeight += systems.value(r, weightColumn);
  }
  for (const std::int64_t system : systemOfArc) {
    const double w = systems.value(system, weightColumn);
    arcWeights.push_back(w / rowsOfSystem[system]);
    rowsPerSystem += w;  // summed over the system's rows: its weight times its rows
  }
  const int surveySnr = survey.requireColumn("SNR_ISO", "model training (survey catalog)");
  const int surveySize = survey.requireColumn("SIZE_IMAGE", "model training (survey catalog)");
  std::vector<std::int64_t> others;
  for (std::int64_t r = 0; r < survey.rows(); ++r) {
    if (eligible(survey, r, surveySnr, surveySize, scale, settings)) others.push_back(r);
  }
  if (arcs.empty() || others.empty()) {
    throw ConfigError("model training: " + std::to_string(arcs.size()) + " simulated arcs and " +
                      std::to_string(others.size()) +
                      " survey rows above the S/N floor and resolved; both are needed");
  }
  const std::vector<ArcContext> contexts =
      arcContexts(survey, {scale, settings.contextRadiusArcsec});
  const FeatureRows arcFeatures = lensFeatures(arcTable, arcs, scale, nullptr);
  const FeatureRows otherFeatures = lensFeatures(survey, others, scale, &contexts);

  // The arcs' weights scaled to the survey rows' sum: the classes weigh the same.
  WeightedCount arcCount;
  for (const double w : arcWeights) arcCount.add(w);
  const double otherWeight = double(others.size());
  const double scaleArcs = otherWeight / arcCount.weightSum;
  FeatureRows rows;
  rows.features = arcFeatures.features;
  rows.values = arcFeatures.values;
  rows.values.insert(rows.values.end(), otherFeatures.values.begin(), otherFeatures.values.end());
  std::vector<int> labels(arcs.size(), 1);
  labels.resize(arcs.size() + others.size(), 0);
  std::vector<double> weights;
  for (const double w : arcWeights) weights.push_back(w * scaleArcs);
  weights.resize(labels.size(), 1.0);

  SavedLensModel model;
  model.trees = TreeModel::train(rows, labels, weights, settings.trees);
  model.features = lensFeatureNames();
  model.contextRadiusArcsec = settings.contextRadiusArcsec;
  LensModelTraining& t = model.training;
  t.arcRows = std::int64_t(arcs.size());
  t.arcWeight = otherWeight;  // after scaling
  t.effectiveArcs = arcCount.effective();
  t.otherRows = std::int64_t(others.size());
  t.otherWeight = otherWeight;
  t.snrMin = settings.snrMin;
  t.resolvedMinArcsec = settings.resolvedMinArcsec;
  t.arcRowsPerSystem = systemsWeight > 0.0 ? rowsPerSystem / systemsWeight : 1.0;
  t.trees = settings.trees;
  model.setup = simulation.setup;
  return model;
}

}  // namespace octarc
