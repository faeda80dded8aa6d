#include "octarc/selection/TreeModel.h"

#include <xgboost/c_api.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

// XGBoost's last error on one line: its first, without the "[hh:mm:ss] source:line: " prefix
// (a stack trace follows on the next lines).
std::string lastError() {
  std::string text = XGBGetLastError();
  text = text.substr(0, text.find('\n'));
  if (!text.empty() && text[0] == '[') {
    const std::size_t time = text.find("] ");
    const std::size_t source = text.find(": ", time == std::string::npos ? 0 : time);
    if (time != std::string::npos && source != std::string::npos) text = text.substr(source + 2);
  }
  return text;
}

// Throws Error with XGBoost's own message when a call fails.
void check(int status, const char* what) {
  if (status != 0) throw Error(std::string("trees: ") + what + ": " + lastError());
}

// A DMatrix freed on scope exit. NaN marks a missing feature.
class Matrix {
 public:
  explicit Matrix(const FeatureRows& rows) {
    check(XGBSetGlobalConfig("{\"verbosity\": 0}"), "configuring");
    check(
        XGDMatrixCreateFromMat(rows.values.data(), bst_ulong(rows.rows()), bst_ulong(rows.features),
                               std::numeric_limits<float>::quiet_NaN(), &handle_),
        "reading the feature rows");
  }
  ~Matrix() { XGDMatrixFree(handle_); }
  Matrix(const Matrix&) = delete;
  Matrix& operator=(const Matrix&) = delete;
  DMatrixHandle handle() const { return handle_; }

 private:
  DMatrixHandle handle_ = nullptr;
};

void setParam(void* booster, const char* name, const std::string& value) {
  check(XGBoosterSetParam(booster, name, value.c_str()), name);
}

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

}  // namespace

TreeModel::TreeModel() = default;

TreeModel::~TreeModel() {
  if (booster_ != nullptr) XGBoosterFree(booster_);
}

TreeModel::TreeModel(TreeModel&& other) noexcept
    : booster_(std::exchange(other.booster_, nullptr)), features_(other.features_) {}

TreeModel& TreeModel::operator=(TreeModel&& other) noexcept {
  if (this != &other) {
    if (booster_ != nullptr) XGBoosterFree(booster_);
    booster_ = std::exchange(other.booster_, nullptr);
    features_ = other.features_;
  }
  return *this;
}

TreeModel TreeModel::train(const FeatureRows& rows, const std::vector<int>& labels,
                           const std::vector<double>& weights, const TreeTraining& settings) {
  const std::int64_t n = rows.rows();
  if (rows.features <= 0 || std::int64_t(rows.values.size()) != n * rows.features ||
      std::int64_t(labels.size()) != n || std::int64_t(weights.size()) != n) {
    throw ConfigError("trees: the feature rows, labels and weights do not match");
  }
  std::int64_t positives = 0;
  std::vector<float> label(labels.size()), weight(weights.size());
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] != 0 && labels[i] != 1) throw ConfigError("trees: a label is not 0 or 1");
    if (!(std::isfinite(weights[i]) && weights[i] > 0.0)) {
      throw ConfigError("trees: a training weight is not finite and positive");
    }
    positives += labels[i];
    label[i] = float(labels[i]);
    weight[i] = float(weights[i]);
  }
  if (positives == 0 || positives == n) {
    throw ConfigError("trees: training needs rows of both classes (lens arcs and others)");
  }
  const Matrix matrix(rows);
  check(XGDMatrixSetFloatInfo(matrix.handle(), "label", label.data(), bst_ulong(n)), "labels");
  check(XGDMatrixSetFloatInfo(matrix.handle(), "weight", weight.data(), bst_ulong(n)), "weights");
  TreeModel model;
  model.features_ = rows.features;
  DMatrixHandle handles[] = {matrix.handle()};
  check(XGBoosterCreate(handles, 1, &model.booster_), "creating the model");
  setParam(model.booster_, "objective", "binary:logistic");
  setParam(model.booster_, "tree_method", "hist");
  // One thread: the histogram sums, hence the trees, never depend on the thread count.
  setParam(model.booster_, "nthread", "1");
  setParam(model.booster_, "seed", std::to_string(settings.seed));
  setParam(model.booster_, "max_depth", std::to_string(settings.maxDepth));
  setParam(model.booster_, "eta", number(settings.learningRate));
  setParam(model.booster_, "subsample", number(settings.subsample));
  setParam(model.booster_, "min_child_weight", number(settings.minChildWeight));
  for (int round = 0; round < settings.rounds; ++round) {
    check(XGBoosterUpdateOneIter(model.booster_, round, matrix.handle()), "training");
  }
  return model;
}

std::string TreeModel::toJson() const {
  if (booster_ == nullptr) throw ConfigError("trees: no model");
  bst_ulong length = 0;
  const char* bytes = nullptr;
  check(XGBoosterSaveModelToBuffer(booster_, "{\"format\": \"json\"}", &length, &bytes),
        "saving the model");
  return std::string(bytes, std::size_t(length));
}

TreeModel TreeModel::fromJson(const std::string& json, int features) {
  if (features <= 0) throw ConfigError("trees: a model needs at least one feature");
  TreeModel model;
  model.features_ = features;
  check(XGBoosterCreate(nullptr, 0, &model.booster_), "creating the model");
  if (XGBoosterLoadModelFromBuffer(model.booster_, json.data(), bst_ulong(json.size())) != 0) {
    throw ConfigError("trees: not a model: " + lastError());
  }
  bst_ulong modelFeatures = 0;
  check(XGBoosterGetNumFeature(model.booster_, &modelFeatures), "reading the model");
  if (std::int64_t(modelFeatures) != features) {
    throw ConfigError("trees: the model reads " + std::to_string(modelFeatures) +
                      " features, its file names " + std::to_string(features));
  }
  return model;
}

std::vector<double> TreeModel::logOdds(const FeatureRows& rows, int threads) const {
  if (booster_ == nullptr) throw ConfigError("trees: no model");
  if (rows.features != features_) {
    throw ConfigError("trees: rows of " + std::to_string(rows.features) +
                      " features for a model of " + std::to_string(features_));
  }
  if (rows.rows() == 0) return {};
  setParam(booster_, "nthread", std::to_string(std::max(threads, 0)));
  const Matrix matrix(rows);
  bst_ulong length = 0;
  const float* margin = nullptr;
  // Option 1: the margin (log-odds) rather than the probability.
  check(XGBoosterPredict(booster_, matrix.handle(), 1, 0, 0, &length, &margin), "predicting");
  return std::vector<double>(margin, margin + length);
}

}  // namespace octarc
