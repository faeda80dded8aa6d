// The S/N floor: bin statistics and the floor on constructed measurements with known answers,
// and the study on a small simulation (scaling to the reference arcness, threads, remaking).
#include "octarc/calibration/SnrFloor.h"

#include <gtest/gtest.h>

#include <cmath>

#include "octarc/core/Error.h"
#include "octarc/core/Statistics.h"
#include "octarc/simulation/engine/LensCatalog.h"

namespace octarc {
namespace {

// Bins of a factor 2 from 10: [10, 20), [20, 40), [40, 80), [80, 160).
SnrFloorSettings fourBins() {
  SnrFloorSettings s;
  s.snrLo = 10;
  s.snrHi = 160;
  s.snrBinCount = 4;
  s.minPerBin = 5;
  s.medianTolerance = 0.01;
  s.spreadMax = 0.05;
  return s;
}

void add(std::vector<double>& snr, std::vector<double>& a, double atSnr,
         const std::vector<double>& values) {
  for (double v : values) {
    snr.push_back(atSnr);
    a.push_back(v);
  }
}

TEST(SnrFloor, BinStatisticsAndTheFloor) {
  std::vector<double> snr, a;
  add(snr, a, 100, {0.10, 0.10, 0.11, 0.09, 0.10});  // reliable
  add(snr, a, 50, {0.08, 0.10, 0.12, 0.10, 0.11});   // 20-80 %: 0.096 .. 0.112, reliable
  add(snr, a, 15, {0.02, 0.10, 0.20, 0.10, 0.30});   // spread 0.18: unreliable
  add(snr, a, 5, {0.10});                            // below the bins: left out
  add(snr, a, std::nan(""), {0.10});                 // NaN: left out
  const std::vector<SnrFloorBin> bins = snrFloorBins(snr, a, fourBins());
  ASSERT_EQ(bins.size(), 4u);
  EXPECT_DOUBLE_EQ(bins[0].snrLo, 10);
  EXPECT_DOUBLE_EQ(bins[1].snrLo, 20);
  EXPECT_DOUBLE_EQ(bins[3].snrHi, 160);
  EXPECT_EQ(bins[0].measurements, 5);
  EXPECT_EQ(bins[1].measurements, 0);
  EXPECT_TRUE(std::isnan(bins[1].median));
  EXPECT_EQ(bins[2].measurements, 5);
  // Sorted 0.08 0.10 0.10 0.11 0.12: h = 0.8 and 3.2.
  EXPECT_NEAR(bins[2].q20, 0.096, 1e-12);
  EXPECT_NEAR(bins[2].median, 0.10, 1e-12);
  EXPECT_NEAR(bins[2].q80, 0.112, 1e-12);
  EXPECT_TRUE(bins[2].reliable);
  EXPECT_TRUE(bins[3].reliable);
  EXPECT_FALSE(bins[0].reliable);
  // The empty bin [20, 40) is passed over: the floor is the lower edge of [40, 80).
  EXPECT_DOUBLE_EQ(snrFloor(bins, 5), 40);
}

// Each measurement weighs its arc's SIM_WEIGHT: weighted quantiles per bin (core/Statistics.h,
// value k at p_k = (C_k - w_k) / (W - w_last)), which unit weights make sampleQuantiles' (type 7).
TEST(SnrFloor, WeightedQuantilesPerBin) {
  const std::vector<double> v = {0.08, 0.10, 0.12, 0.10, 0.11};
  EXPECT_EQ(weightedSampleQuantiles(v, {1, 1, 1, 1, 1}, {0.2, 0.5, 0.8}),
            sampleQuantiles(v, {0.2, 0.5, 0.8}));
  // Weight 4 on 0.08: sorted 0.08 (4), 0.10, 0.10, 0.11, 0.12 (1 each), W - w_last = 7, p = 0,
  // 4/7, 5/7, 6/7, 1; the median (q = 0.5) is 0.08 + (0.5 / (4/7)) (0.10 - 0.08) = 0.0975.
  const std::vector<double> median = weightedSampleQuantiles(v, {4, 1, 1, 1, 1}, {0.5});
  EXPECT_NEAR(median[0], 0.08 + 0.5 / (4.0 / 7.0) * 0.02, 1e-12);
  std::vector<double> snr, a;
  add(snr, a, 50, v);
  const std::vector<SnrFloorBin> bins = snrFloorBins(snr, a, fourBins(), {4, 1, 1, 1, 1});
  EXPECT_EQ(bins[2].measurements, 5);
  EXPECT_NEAR(bins[2].median, median[0], 1e-12);
}

TEST(SnrFloor, ABiasedMedianBreaksTheRunAndNoReliableTopGivesNaN) {
  std::vector<double> snr, a;
  add(snr, a, 100, {0.10, 0.10, 0.10, 0.10, 0.10});
  add(snr, a, 50, {0.12, 0.12, 0.12, 0.12, 0.12});  // no spread, but the median is off by 0.02
  add(snr, a, 25, {0.10, 0.10, 0.10, 0.10, 0.10});  // reliable, below the break: not counted
  std::vector<SnrFloorBin> bins = snrFloorBins(snr, a, fourBins());
  EXPECT_FALSE(bins[2].reliable);
  EXPECT_DOUBLE_EQ(snrFloor(bins, 5), 80);
  bins[3].reliable = false;
  EXPECT_TRUE(std::isnan(snrFloor(bins, 5)));
}

TEST(SnrFloor, SettingsOutOfRangeAreRefused) {
  SnrFloorSettings s;
  s.noiseFactorHi = s.noiseFactorLo;
  EXPECT_THROW(checkSnrFloorSettings(s), ConfigError);
  s = SnrFloorSettings();
  s.arcs = 0;
  EXPECT_THROW(checkSnrFloorSettings(s), ConfigError);
  s = SnrFloorSettings();
  s.snrBinCount = 0;
  EXPECT_THROW(checkSnrFloorSettings(s), ConfigError);
  EXPECT_NO_THROW(checkSnrFloorSettings(SnrFloorSettings()));
}

// A small simulation with bright sources, so that a few hundred systems give arcs.
struct SmallSimulation {
  LensSetupOptions options;
  SourceChoice sources;
  SourceDatabase database;  // sources.make()
  SimulationOutput output;
};

const SmallSimulation& smallSimulation() {
  static const SmallSimulation s = [] {
    SmallSimulation out;
    out.options.populationPreset = "dls";
    out.options.sourceMagMin = 21.0;
    out.options.sourceMagMax = 22.0;
    out.sources.syntheticCount = 12;
    out.database = out.sources.make();
    const LensRun run =
        runLensSimulation(makeSimulationSetup(out.options), out.database, 7, 400, 2, 0, {});
    out.output.path = "small simulation";
    out.output.systems = run.systems;
    out.output.arcs = run.arcs;
    out.output.setup.seed = 7;
    return out;
  }();
  return s;
}

SnrFloorSettings quickStudy() {
  SnrFloorSettings f;
  f.arcs = 2;
  f.arcnessMin = 0.0;
  f.arcnessMax = 1.0;
  f.noiseFactorLo = 0.5;
  f.noiseFactorHi = 2.0;
  f.noiseFactorCount = 3;
  f.realisations = 8;
  f.minPerBin = 1;
  return f;
}

TEST(SnrFloor, EachArcIsScaledToTheReferenceAtItsHighestSnr) {
  const SmallSimulation& sim = smallSimulation();
  SnrFloorSettings f = quickStudy();
  f.noiseFactorHi = f.noiseFactorLo * 1.0001;  // two factors, the same noise: S/N alike
  f.noiseFactorCount = 2;
  f.arcs = 1;
  // An arc far from the reference, so that only the scaling brings its median to 0.10.
  f.arcnessMin = 0.0;
  f.arcnessMax = 0.06;
  f.snrLo = 1;
  f.snrHi = 1e5;
  f.snrBinCount = 1;  // one bin holds every measurement
  const SnrFloorResult r = snrFloorStudy(sim.output, sim.options, sim.database, f);
  ASSERT_EQ(r.systems.size(), 1u);
  ASSERT_GT(r.foundPerFactor[0], f.realisations / 2);
  ASSERT_EQ(r.bins.size(), 1u);
  // Half of the measurements are those of the lowest factor, whose median is scaled to 0.10;
  // the other half are the same noise again: the median of all stays near 0.10.
  ASSERT_GT(r.referenceArcness[0], 0.0);
  ASSERT_LT(r.referenceArcness[0], 0.07);
  EXPECT_NEAR(r.bins[0].median, 0.10, 0.01);
}

TEST(SnrFloor, TheResultDoesNotDependOnTheThreads) {
  const SmallSimulation& sim = smallSimulation();
  SnrFloorSettings f = quickStudy();
  f.threads = 1;
  const SnrFloorResult one = snrFloorStudy(sim.output, sim.options, sim.database, f);
  f.threads = 3;
  const SnrFloorResult three = snrFloorStudy(sim.output, sim.options, sim.database, f);
  ASSERT_EQ(one.bins.size(), three.bins.size());
  EXPECT_EQ(one.foundPerFactor, three.foundPerFactor);
  for (std::size_t k = 0; k < one.bins.size(); ++k) {
    EXPECT_EQ(one.bins[k].measurements, three.bins[k].measurements);
    if (one.bins[k].measurements > 0) {
      EXPECT_EQ(one.bins[k].median, three.bins[k].median);
    }
  }
  // More noise, lower S/N: the arc is found less often or as often at the highest factor.
  EXPECT_LE(one.foundPerFactor.back(), one.foundPerFactor.front());
}

TEST(SnrFloor, CombinedOutputsAreRefused) {
  SmallSimulation sim = smallSimulation();
  sim.output.outputs = 2;
  EXPECT_THROW(snrFloorStudy(sim.output, sim.options, sim.database, quickStudy()), ConfigError);
}

TEST(SnrFloor, ASimulationThatCannotBeRemadeIsAnError) {
  SmallSimulation sim = smallSimulation();
  LensSetupOptions other = sim.options;
  other.sourceMagMin = 22.0;  // other draws than the simulation's
  other.sourceMagMax = 23.0;
  try {
    snrFloorStudy(sim.output, other, sim.database, quickStudy());
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be remade"), std::string::npos) << e.what();
  }
  SnrFloorSettings none = quickStudy();
  none.arcnessMin = 5.0;
  none.arcnessMax = 6.0;
  EXPECT_THROW(snrFloorStudy(sim.output, sim.options, sim.database, none), ConfigError);
}

}  // namespace
}  // namespace octarc
