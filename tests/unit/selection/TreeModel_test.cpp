// The learned selection's trees and model file: a rule the trees must find, reproducibility,
// and the file read back.
#include "octarc/selection/TreeModel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "ExpectError.h"
#include "SelectionTestSupport.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsTable.h"
#include "octarc/selection/LensModel.h"

namespace octarc {
namespace {

// Two features uniform on [0, 1); label 1 exactly when x0 > 0.6 (x1 is noise), every 7th row's
// x1 missing.
struct Sample {
  FeatureRows rows;
  std::vector<int> labels;
  std::vector<double> weights;
};

Sample separable(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Sample s;
  s.rows.features = 2;
  for (int i = 0; i < n; ++i) {
    const double x0 = u(rng), x1 = u(rng);
    s.rows.values.push_back(float(x0));
    s.rows.values.push_back(i % 7 == 0 ? std::nanf("") : float(x1));
    s.labels.push_back(x0 > 0.6 ? 1 : 0);
    s.weights.push_back(1.0);
  }
  return s;
}

TreeTraining smallTraining() {
  TreeTraining t;
  t.rounds = 40;
  t.maxDepth = 3;
  return t;
}

TEST(TreeModel, LearnsAThresholdRuleAndKeepsItThroughJson) {
  const Sample train = separable(2000, 1);
  const TreeModel model =
      TreeModel::train(train.rows, train.labels, train.weights, smallTraining());
  EXPECT_EQ(model.features(), 2);
  // Rows away from the edge at 0.6: the sign of the log-odds is the rule.
  FeatureRows probe;
  probe.features = 2;
  const std::vector<double> x0 = {0.05, 0.3, 0.55, 0.65, 0.8, 0.99};
  for (double v : x0) {
    probe.values.push_back(float(v));
    probe.values.push_back(0.5f);
  }
  const std::vector<double> odds = model.logOdds(probe);
  ASSERT_EQ(odds.size(), x0.size());
  for (std::size_t i = 0; i < x0.size(); ++i) {
    EXPECT_EQ(odds[i] > 0.0, x0[i] > 0.6) << "x0 = " << x0[i] << ": " << odds[i];
  }
  // Back from its JSON, the same numbers; on one thread or two, the same numbers.
  const TreeModel again = TreeModel::fromJson(model.toJson(), 2);
  EXPECT_EQ(again.logOdds(probe), odds);
  EXPECT_EQ(model.logOdds(probe, 1), model.logOdds(probe, 2));
  // Trained again from the same rows and seed: the same model.
  const TreeModel twin = TreeModel::train(train.rows, train.labels, train.weights, smallTraining());
  EXPECT_EQ(twin.toJson(), model.toJson());
}

TEST(TreeModel, WeightsMoveTheOddsByTheirRatio) {
  // Features that say nothing (one value for all): the log-odds is the weighted base rate,
  // ln(W1 / W0), whatever the labels' order. 100 rows of each label, label 1 weighted 3.
  FeatureRows rows;
  rows.features = 1;
  std::vector<int> labels;
  std::vector<double> weights;
  for (int i = 0; i < 200; ++i) {
    rows.values.push_back(1.0f);
    labels.push_back(i % 2);
    weights.push_back(i % 2 ? 3.0 : 1.0);
  }
  TreeTraining t;
  t.rounds = 200;
  t.learningRate = 0.3;
  t.subsample = 1.0;
  const TreeModel model = TreeModel::train(rows, labels, weights, t);
  const std::vector<double> odds = model.logOdds(rows);
  EXPECT_NEAR(odds[0], std::log(3.0), 1e-3);
}

TEST(TreeModel, BadInputIsAConfigError) {
  const Sample s = separable(10, 2);
  std::vector<int> one(10, 1);
  test::expectError<ConfigError>([&] { TreeModel::train(s.rows, one, s.weights, smallTraining()); },
                                 {"both classes"});
  std::vector<double> zero = s.weights;
  zero[3] = 0.0;
  test::expectError<ConfigError>([&] { TreeModel::train(s.rows, s.labels, zero, smallTraining()); },
                                 {"weight"});
  test::expectError<ConfigError>([&] { TreeModel::fromJson("{not a model", 2); }, {"not a model"});
  const TreeModel model = TreeModel::train(s.rows, s.labels, s.weights, smallTraining());
  FeatureRows three;
  three.features = 3;
  three.values = {1, 2, 3};
  test::expectError<ConfigError>([&] { model.logOdds(three); }, {"3 features"});
}

// A model of the lens features' width, trained on random rows (300 of them, in `rows`).
SavedLensModel randomLensModel(FeatureRows& rows) {
  const int width = int(lensFeatureNames().size());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  rows = FeatureRows();
  rows.features = width;
  std::vector<int> labels;
  std::vector<double> weights;
  for (int i = 0; i < 300; ++i) {
    for (int f = 0; f < width; ++f) rows.values.push_back(float(u(rng)));
    labels.push_back(rows.values[std::size_t(i * width)] > 0.5f ? 1 : 0);
    weights.push_back(1.0 + (i % 3));
  }
  SavedLensModel saved;
  saved.trees = TreeModel::train(rows, labels, weights, smallTraining());
  saved.features = lensFeatureNames();
  saved.training.arcRows = 150;
  saved.training.arcWeight = 300.0;
  saved.training.otherRows = 150;
  saved.training.otherWeight = 100.0;
  saved.training.arcRowsPerSystem = 2.5;
  saved.setup.pixelScaleArcsec = 0.257;
  saved.training.effectiveArcs = 120.0;
  saved.setup.thresholdsSigma = {2.5, 3.0};
  return saved;
}

TEST(LensModel, FileRoundTripAndPrior) {
  FeatureRows rows;
  const SavedLensModel saved = randomLensModel(rows);
  const std::string path = std::string(::testing::TempDir()) + "/octarc_lens_model_test.fits";
  std::remove(path.c_str());
  saveLensModel(path, saved);
  const SavedLensModel back = loadLensModel(path);
  EXPECT_EQ(back.trees.logOdds(rows), saved.trees.logOdds(rows));
  EXPECT_EQ(back.training.arcRows, 150);
  EXPECT_EQ(back.training.otherWeight, 100.0);
  EXPECT_EQ(back.training.effectiveArcs, 120.0);
  EXPECT_EQ(back.setup.thresholdsSigma, saved.setup.thresholdsSigma);
  // Training mix 3:1; a survey prior of 1/4 (odds 1/3): the shift is ln(1/3) - ln(3).
  EXPECT_NEAR(priorLogOddsShift(back.training, 0.25), -2.0 * std::log(3.0), 1e-12);
  // 10 lenses per deg2 on 0.5 deg2, 2.5 rows each, among 1000 rows: 1.25%.
  EXPECT_NEAR(searchPriorFraction(10.0, 0.5, 1000, 2.5), 0.0125, 1e-15);
  std::remove(path.c_str());
  // A file that is no model, say a grid: a clear error naming it.
  const std::string grid = std::string(OCTARC_SOURCE_DIR) + "/params/demo.grid.fits";
  test::expectIoError([&] { loadLensModel(grid); }, {grid, "not an octarc lens model"});
}

// Training cards that calibrate never writes are refused, naming the file, the card, its value
// and the range; the ends of the ranges are read.
TEST(LensModel, TrainingCardsOutOfTheirRangeAreRefused) {
  FeatureRows rows;
  const std::string dir = std::string(::testing::TempDir());
  const std::string good = dir + "/octarc_lens_model_cards.fits";
  std::remove(good.c_str());
  saveLensModel(good, randomLensModel(rows));
  const auto withCard = [&](const std::string& key, const FitsKeywordValue& value) {
    FitsTable t = readFitsTable(good, "LENS_MODEL");
    bool found = false;
    for (FitsKeyword& k : t.keywords) {
      if (k.name == key) {
        k.value = value;
        found = true;
      }
    }
    EXPECT_TRUE(found) << key;
    const std::string path = dir + "/octarc_lens_model_" + key + ".fits";
    std::remove(path.c_str());
    writeFitsTables(path, {t});
    return path;
  };
  struct Case {
    std::string key;
    FitsKeywordValue value;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"CTXRAD", 0.0, "CTXRAD = 0 is not a finite number > 0"},
      {"NARC", std::int64_t(0), "NARC = 0 is not an integer from 1 to 9223372036854775807"},
      {"NOTHER", std::int64_t(-5), "NOTHER = -5 is not an integer from 1 to"},
      {"ARCWEIGH", -2.0, "ARCWEIGH = -2 is not a finite number > 0"},
      {"NEFFARC", 0.0, "NEFFARC = 0 is not a finite number > 0"},
      {"OTHWEIGH", kNaN, "OTHWEIGH = nan is not a finite number > 0"},
      {"SNRMIN", -1.0, "SNRMIN = -1 is not a finite number >= 0"},
      {"RESMIN", kNaN, "RESMIN = nan is not a finite number >= 0"},
      {"ARCROWS", 0.0, "ARCROWS = 0 is not a finite number > 0"},
      {"ROUNDS", std::int64_t(0), "ROUNDS = 0 is not an integer from 1 to 100000"},
      {"DEPTH", std::int64_t(4294967297), "DEPTH = 4294967297 is not an integer from 1 to 100000"},
      {"ETA", 1.5, "ETA = 1.5 is not a number > 0 and <= 1"},
      {"SUBSAMPL", 0.0, "SUBSAMPL = 0 is not a number > 0 and <= 1"},
      {"MODELLEN", std::int64_t(1000000000000),
       "MODELLEN = 1000000000000 is not an integer from 1"},
      {"THRESH2", 2.0, "THRESH2 = 2 is not above THRESH1 = 2.5"},
  };
  for (const Case& c : cases) {
    const std::string path = withCard(c.key, c.value);
    test::expectIoError([&] { loadLensModel(path); }, {path + "[LENS_MODEL]: " + c.message});
    std::remove(path.c_str());
  }
  EXPECT_EQ(loadLensModel(withCard("ETA", 1.0)).training.trees.learningRate, 1.0);
  EXPECT_EQ(loadLensModel(withCard("SUBSAMPL", 1.0)).training.trees.subsample, 1.0);
  EXPECT_EQ(loadLensModel(withCard("SNRMIN", 0.0)).training.snrMin, 0.0);
  EXPECT_EQ(loadLensModel(withCard("ROUNDS", std::int64_t(100000))).training.trees.rounds, 100000);
  EXPECT_EQ(loadLensModel(withCard("NARC", std::int64_t(1))).training.arcRows, 1);
  std::remove(good.c_str());
}

}  // namespace
}  // namespace octarc
