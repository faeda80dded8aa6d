#include "octarc/selection/LensModel.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "octarc/core/Error.h"
#include "octarc/io/FitsTable.h"

namespace octarc {

namespace {

constexpr const char* kModelTableName = "LENS_MODEL";
constexpr std::int64_t kFormat = 1;
constexpr std::size_t kChunk = 1000;  // characters per MODEL string

// The catalog columns of the first features, and how each becomes a feature.
enum class Transform { Value, Log10, SizeArcsec };
struct ColumnFeature {
  const char* name;
  const char* column;
  Transform transform;
};
constexpr ColumnFeature kColumnFeatures[] = {
    {"ARCNESS", "ARCNESS", Transform::Value},
    {"ANTIARCNESS", "ANTIARCNESS", Transform::Value},
    {"E_IMAGE", "E_IMAGE", Transform::Value},
    {"log10(SNR_ISO)", "SNR_ISO", Transform::Log10},
    {"SIZE_ARCSEC", "SIZE_IMAGE", Transform::SizeArcsec},
    {"THRESH_LEVEL", "THRESH_LEVEL", Transform::Value},
};

// The values the training cards may hold: what calibrate trains with (MODEL_SNR_MIN,
// MODEL_RESOLVED_MIN, MODEL_TREES; XGBoost's eta and subsample lie in (0, 1]).
bool positiveTrainingCard(double v) {
  return std::isfinite(v) && v > 0.0;
}
bool nonNegativeTrainingCard(double v) {
  return std::isfinite(v) && v >= 0.0;
}
bool fractionTrainingCard(double v) {
  return v > 0.0 && v <= 1.0;
}
constexpr const char* kPositiveTrainingCard = "a finite number > 0";
constexpr const char* kNonNegativeTrainingCard = "a finite number >= 0";
constexpr const char* kFractionTrainingCard = "a number > 0 and <= 1";
constexpr std::int64_t kMaxTrainingRows = std::numeric_limits<std::int64_t>::max();

}  // namespace

const std::vector<std::string>& lensFeatureNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const ColumnFeature& f : kColumnFeatures) out.push_back(f.name);
    for (const ColumnSpec& c : arcContextColumns()) out.push_back(c.name);
    return out;
  }();
  return names;
}

FeatureRows lensFeatures(const Table& table, const std::vector<std::int64_t>& rows,
                         double pixelScaleArcsec, const std::vector<ArcContext>* contexts) {
  std::vector<int> columns;
  for (const ColumnFeature& f : kColumnFeatures) {
    columns.push_back(table.requireColumn(f.column, "lens features"));
  }
  std::vector<int> contextColumns;
  if (contexts == nullptr) {
    for (const ColumnSpec& c : arcContextColumns()) {
      contextColumns.push_back(table.requireColumn(c.name, "lens features"));
    }
  } else if (std::int64_t(contexts->size()) != table.rows()) {
    throw ConfigError("lens features: one context per catalog row is needed");
  }
  FeatureRows out;
  out.features = int(lensFeatureNames().size());
  out.values.reserve(rows.size() * std::size_t(out.features));
  const std::size_t nColumnFeatures = std::size(kColumnFeatures);
  for (const std::int64_t r : rows) {
    for (std::size_t f = 0; f < nColumnFeatures; ++f) {
      const double v = table.value(r, columns[f]);
      switch (kColumnFeatures[f].transform) {
        case Transform::Value:
          out.values.push_back(float(v));
          break;
        case Transform::Log10:
          out.values.push_back(v > 0.0 ? float(std::log10(v))
                                       : std::numeric_limits<float>::quiet_NaN());
          break;
        case Transform::SizeArcsec:
          out.values.push_back(float(std::sqrt(2.0) * v * pixelScaleArcsec));
          break;
      }
    }
    if (contexts == nullptr) {
      for (const int c : contextColumns) out.values.push_back(float(table.value(r, c)));
    } else {
      for (const double v : contextValues((*contexts)[std::size_t(r)])) {
        out.values.push_back(float(v));
      }
    }
  }
  // XGBoost reads NaN as missing, but refuses infinities (a zero flux or size): missing too.
  for (float& v : out.values) {
    if (!std::isfinite(v)) v = std::numeric_limits<float>::quiet_NaN();
  }
  return out;
}

void saveLensModel(const std::string& path, const SavedLensModel& m) {
  FitsTable t;
  t.name = kModelTableName;
  auto& k = t.keywords;
  k.push_back(FitsKeyword::integer("OCTMODEL", kFormat, "octarc lens model format"));
  k.push_back(FitsKeyword::text("METHOD", "TREES", "Gradient-boosted trees (XGBoost)"));
  k.push_back(FitsKeyword::integer("NFEAT", std::int64_t(m.features.size()), "Features"));
  for (std::size_t f = 0; f < m.features.size(); ++f) {
    k.push_back(FitsKeyword::text("FEAT" + std::to_string(f + 1), m.features[f], "Feature"));
  }
  k.push_back(FitsKeyword::real("CTXRAD", m.contextRadiusArcsec, "Context reach (arcsec)"));
  const LensModelTraining& tr = m.training;
  k.push_back(FitsKeyword::integer("NARC", tr.arcRows, "Simulated arc rows trained on"));
  k.push_back(FitsKeyword::real("ARCWEIGH", tr.arcWeight, "Their SIM_WEIGHT sum"));
  k.push_back(FitsKeyword::real("NEFFARC", tr.effectiveArcs, "Their Kish effective number"));
  k.push_back(FitsKeyword::integer("NOTHER", tr.otherRows, "Other rows trained on"));
  k.push_back(FitsKeyword::real("OTHWEIGH", tr.otherWeight, "Their weight sum"));
  k.push_back(FitsKeyword::real("SNRMIN", tr.snrMin, "S/N floor of the rows"));
  k.push_back(FitsKeyword::real("RESMIN", tr.resolvedMinArcsec, "Resolved size of the rows"));
  k.push_back(FitsKeyword::real("ARCROWS", tr.arcRowsPerSystem, "Arc rows per arc system"));
  k.push_back(FitsKeyword::integer("ROUNDS", tr.trees.rounds, "Boosting rounds"));
  k.push_back(FitsKeyword::integer("DEPTH", tr.trees.maxDepth, "Tree depth"));
  k.push_back(FitsKeyword::real("ETA", tr.trees.learningRate, "Learning rate"));
  k.push_back(FitsKeyword::real("SUBSAMPL", tr.trees.subsample, "Rows per tree"));
  k.push_back(FitsKeyword::unsignedInteger("TRSEED", tr.trees.seed, "Training seed"));
  addSetupKeywords(m.setup, k);
  const std::string json = m.trees.toJson();
  k.push_back(FitsKeyword::integer("MODELLEN", std::int64_t(json.size()), "Model characters"));
  std::vector<std::string> chunks;
  for (std::size_t at = 0; at < json.size(); at += kChunk)
    chunks.push_back(json.substr(at, kChunk));
  FitsColumn column;
  column.name = "MODEL";
  column.comment = "XGBoost JSON model, in order";
  column.repeat = int(kChunk);
  column.values = std::move(chunks);
  t.columns.push_back(std::move(column));
  writeFitsTables(path, {t});
}

SavedLensModel loadLensModel(const std::string& path) {
  const std::vector<std::string> tables = listFitsTables(path);
  if (std::find(tables.begin(), tables.end(), kModelTableName) == tables.end()) {
    throw IoError(path +
                  ": not an octarc lens model (no LENS_MODEL table; make one with "
                  "octarc calibrate -MODEL_NAME)");
  }
  const FitsTable t = readFitsTable(path, kModelTableName);
  if (t.integer("OCTMODEL") != kFormat) {
    throw IoError(t.where() + ": lens model format " + std::to_string(t.integer("OCTMODEL")) +
                  ", this octarc reads format " + std::to_string(kFormat));
  }
  SavedLensModel m;
  const std::int64_t nFeatures = t.integer("NFEAT");
  for (std::int64_t f = 1; f <= nFeatures; ++f) {
    m.features.push_back(t.text("FEAT" + std::to_string(f)));
  }
  if (m.features != lensFeatureNames()) {
    throw IoError(t.where() + ": the model's features are not the ones this octarc computes");
  }
  m.contextRadiusArcsec = t.number("CTXRAD", positiveTrainingCard, kPositiveTrainingCard);
  LensModelTraining& tr = m.training;
  // Training needs rows of both classes.
  tr.arcRows = t.integer("NARC", 1, kMaxTrainingRows);
  tr.arcWeight = t.number("ARCWEIGH", positiveTrainingCard, kPositiveTrainingCard);
  tr.effectiveArcs = t.number("NEFFARC", positiveTrainingCard, kPositiveTrainingCard);
  tr.otherRows = t.integer("NOTHER", 1, kMaxTrainingRows);
  tr.otherWeight = t.number("OTHWEIGH", positiveTrainingCard, kPositiveTrainingCard);
  tr.snrMin = t.number("SNRMIN", nonNegativeTrainingCard, kNonNegativeTrainingCard);
  tr.resolvedMinArcsec = t.number("RESMIN", nonNegativeTrainingCard, kNonNegativeTrainingCard);
  tr.arcRowsPerSystem = t.number("ARCROWS", positiveTrainingCard, kPositiveTrainingCard);
  tr.trees.rounds = int(t.integer("ROUNDS", 1, kMaxTreeRoundsOrDepth));
  tr.trees.maxDepth = int(t.integer("DEPTH", 1, kMaxTreeRoundsOrDepth));
  tr.trees.learningRate = t.number("ETA", fractionTrainingCard, kFractionTrainingCard);
  tr.trees.subsample = t.number("SUBSAMPL", fractionTrainingCard, kFractionTrainingCard);
  tr.trees.seed = t.unsignedInteger("TRSEED");
  m.setup = readSetup(t);
  // At most what the MODEL strings hold: the length is reserved before they are read.
  const std::int64_t modelLength = t.integer("MODELLEN", 1, t.rows() * std::int64_t(kChunk));
  const auto length = std::size_t(modelLength);
  std::string json;
  json.reserve(length);
  // Reading strips trailing blanks: each string is padded back to its written length.
  for (const std::string& chunk : t.strings("MODEL")) {
    const std::size_t want = std::min(kChunk, length - std::min(length, json.size()));
    json += chunk;
    if (chunk.size() < want) json.append(want - chunk.size(), ' ');
  }
  if (json.size() != length) {
    throw IoError(t.where() + ": the model holds " + std::to_string(json.size()) +
                  " characters, MODELLEN says " + std::to_string(length));
  }
  try {
    m.trees = TreeModel::fromJson(json, int(nFeatures));
  } catch (const ConfigError& e) {
    throw IoError(t.where() + ": " + e.what());
  }
  return m;
}

double priorLogOddsShift(const LensModelTraining& training, double priorFraction) {
  return std::log(priorFraction / (1.0 - priorFraction)) -
         std::log(training.arcWeight / training.otherWeight);
}

double searchPriorFraction(double lensesPerDeg2, double areaDeg2, std::int64_t rowsScored,
                           double arcRowsPerSystem) {
  if (!(rowsScored > 0) || !(areaDeg2 > 0.0)) return 0.5;
  const double fraction = lensesPerDeg2 * areaDeg2 * arcRowsPerSystem / double(rowsScored);
  return std::clamp(fraction, 1e-12, 0.5);
}

}  // namespace octarc
