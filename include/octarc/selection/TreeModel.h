// Gradient-boosted decision trees (XGBoost's C API, wrapped here once): the learned selection
// (SELECTION_METHOD TREES). A binary classifier of feature rows, lens arc (label 1) against
// anything else (label 0), each row with a weight.
//
// Reproducible: training runs on one thread with a fixed seed, so a model depends on its rows,
// weights and settings only, never on the machine's thread count; prediction of a row depends
// on that row alone. Missing features are NaN (XGBoost learns a default branch for them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace octarc {

// The most boosting rounds, and the deepest trees, that calibrate trains (MODEL_TREES) and a
// model file may record.
inline constexpr int kMaxTreeRoundsOrDepth = 100000;

struct TreeTraining {
  int rounds = 300;  // boosting rounds (trees)
  int maxDepth = 5;  // of each tree
  double learningRate = 0.1;
  double subsample = 0.8;  // of the rows per tree
  double minChildWeight = 1.0;
  std::uint64_t seed = 1;
};

// Feature rows, row-major: values[r * features + f].
struct FeatureRows {
  int features = 0;
  std::vector<float> values;
  std::int64_t rows() const { return features > 0 ? std::int64_t(values.size()) / features : 0; }
};

class TreeModel {
 public:
  TreeModel();
  ~TreeModel();
  TreeModel(TreeModel&&) noexcept;
  TreeModel& operator=(TreeModel&&) noexcept;

  // Trains on rows with labels (0 or 1) and positive weights. ConfigError for mismatched sizes,
  // a label other than 0 and 1, a weight that is not finite and positive, or a class without
  // rows; Error with XGBoost's message when it fails.
  static TreeModel train(const FeatureRows& rows, const std::vector<int>& labels,
                         const std::vector<double>& weights, const TreeTraining& settings);
  // The model's own serialisation (XGBoost's JSON) and back; ConfigError when `json` is no
  // model of `features` features.
  std::string toJson() const;
  static TreeModel fromJson(const std::string& json, int features);

  int features() const { return features_; }
  // The log-odds (margin) of label 1 for each row, as the training weights gave it. `threads`:
  // 0 for every core. ConfigError for rows of another width. It sets the model's thread count,
  // so one model is not to be used from two threads at once.
  std::vector<double> logOdds(const FeatureRows& rows, int threads = 0) const;

 private:
  void* booster_ = nullptr;  // BoosterHandle
  int features_ = 0;
};

}  // namespace octarc
