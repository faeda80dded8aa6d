#include "octarc/calibration/Calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Statistics.h"
#include "octarc/selection/ColumnExpression.h"
#include "octarc/selection/GridBinning.h"
#include "octarc/selection/OccupationGrid.h"
#include "octarc/selection/SearchSpace.h"

namespace octarc {

namespace {

// A distribution: what is histogrammed, over which rows, on which range.
struct DistributionSpec {
  std::string name;
  std::string value;         // expression
  std::string simulatedCut;  // expression on the systems table
  std::string surveyCut;     // the same cut on survey rows
  std::string selection;     // in words
  double lo, hi;             // NaN: from the simulated values' quantiles
  std::vector<CutLine> cuts;
  bool fitGaussian = false;    // the widths of s_a and s_b
  bool simulatedOnly = false;  // no survey side (a column survey catalogs lack)
};

std::vector<DistributionSpec> distributionSpecs(const FractionCuts& c) {
  const double nan = std::nan("");
  const std::string e = formatNumber(c.ellipticityMin), snr = formatNumber(c.snrMin);
  const std::string bright = "ARC_FOUND == 1 && E_IMAGE > " + e + " && SNR_ISO > " + snr;
  const std::string brightSurvey = "E_IMAGE > " + e + " && SNR_ISO > " + snr;
  const std::string brightWords = "E_IMAGE > " + e + " and SNR_ISO > " + snr;
  const char* arcCut = "ARC_FOUND == 1 && ARCNESS > 0.1";
  const char* arcWords = "ARCNESS > 0.10";
  return {
      {"ARCNESS",
       "ARCNESS",
       bright,
       brightSurvey,
       brightWords,
       0.0,
       0.3,
       {{0.05, "a = 0.05"}, {0.10, "a = 0.10"}, {0.15, "a = 0.15"}}},
      {"ANTIARCNESS", "ANTIARCNESS", arcCut, "ARCNESS > 0.1", arcWords, nan, nan, {}},
      {"SKEW_MAJOR", "SKEW_MAJOR", arcCut, "ARCNESS > 0.1", arcWords, nan, nan, {}, true},
      {"SKEW_MINOR", "SKEW_MINOR", arcCut, "ARCNESS > 0.1", arcWords, nan, nan, {}, true},
      {"E_IMAGE",
       "E_IMAGE",
       arcCut,
       "ARCNESS > 0.1",
       arcWords,
       0.0,
       1.0,
       {{c.ellipticityMin, "e = " + e}}},
      {"SNR_ISO",
       "log10(SNR_ISO)",
       arcCut,
       "ARCNESS > 0.1",
       arcWords,
       nan,
       nan,
       {{std::log10(c.snrMin), "S/N = " + snr}}},
  };
}

// The values of `value` on the rows of `table` that pass `cut` (finite and non-zero), and their
// weights (SIM_WEIGHT; 1 without the column).
struct SelectedValues {
  std::vector<double> values, weights;
};

SelectedValues selectedValues(const Table& table, const std::string& value, const std::string& cut,
                              const std::string& context) {
  const std::vector<double> v = ColumnExpression(value, context).evaluate(table);
  const std::vector<double> pass = ColumnExpression(cut, context).evaluate(table);
  const std::vector<double> w = systemWeights(table);
  SelectedValues out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::isfinite(pass[i]) && pass[i] != 0.0 && std::isfinite(v[i])) {
      out.values.push_back(v[i]);
      out.weights.push_back(w[i]);
    }
  }
  return out;
}

// The range of a histogram or grid axis: quantileRange's, but with tails that leave out at least
// one value each: below 1 / tailFraction values an interpolated tail quantile would leave the
// least and the greatest value outside (with two values, both: an empty histogram or grid), so
// the range is then from the least to the greatest value. NaN values are ignored; nullopt for
// fewer than two distinct finite values.
std::optional<std::pair<double, double>> valueRange(const std::vector<double>& values,
                                                    double tailFraction,
                                                    const std::string& context) {
  std::vector<double> finite;
  for (double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  if (finite.size() < 2) return std::nullopt;
  const double tail = tailFraction * double(finite.size()) >= 1.0 ? tailFraction : 0.0;
  if (!(sampleQuantile(finite, tail) < sampleQuantile(finite, 1.0 - tail))) return std::nullopt;
  return quantileRange(finite, tail, context);
}

// The range of a distribution without a fixed one: valueRange with 1 % tails, else one unit
// around the value (a single value, or values all equal).
std::pair<double, double> distributionRange(const std::vector<double>& values,
                                            const std::string& context) {
  if (const auto range = valueRange(values, 0.01, context)) return *range;
  for (double v : values) {
    if (std::isfinite(v)) return {v - 0.5, v + 0.5};
  }
  return {0.0, 1.0};
}

Distribution makeDistribution(const DistributionSpec& spec, const Table& systems,
                              const Table* survey, int bins) {
  Distribution d;
  d.name = spec.name;
  d.column = spec.value;
  d.selection = spec.selection;
  d.cuts = spec.cuts;
  d.simulatedOnly = spec.simulatedOnly;
  const SelectedValues sim =
      selectedValues(systems, spec.value, spec.simulatedCut, "distribution " + d.name);
  double lo = spec.lo, hi = spec.hi;
  if (std::isnan(lo)) std::tie(lo, hi) = distributionRange(sim.values, "distribution " + d.name);
  d.simulated = normalisedHistogram(sim.values, lo, hi, bins, sim.weights);
  if (spec.fitGaussian) d.gaussian = fitGaussian(d.simulated.edges, d.simulated.fraction);
  if (survey && !spec.simulatedOnly) {
    d.survey = normalisedHistogram(
        selectedValues(*survey, spec.value, spec.surveyCut, "survey distribution " + d.name).values,
        lo, hi, bins);
  }
  return d;
}

// The colour cut study and the distribution of the arc minus lens colour, on the arcs of
// CalibrationSettings::colourCut (in the search space when one is given).
void colourCutStudies(const SimulationOutput& sim, const CalibrationSettings& s,
                      CalibrationResult& out) {
  const std::string arcness = formatNumber(s.colourCutArcnessMin);
  const std::string snr = formatNumber(s.fractionCuts.snrMin);
  std::string selection = "ARC_FOUND == 1 && ARCNESS > " + arcness + " && SNR_ISO > " + snr;
  std::string words = "ARCNESS > " + arcness + " and SNR_ISO > " + snr;
  if (!s.searchSpaceExpression.empty()) {
    selection += " && (" + s.searchSpaceExpression + ")";
    words += ", in " + s.searchSpaceName;
  }
  out.colourCut = colourCutStudy(sim.systems, sim.band, selection, s.colourCut);
  DistributionSpec spec;
  spec.name = "COLOUR_DIFF";
  spec.value = arcColourColumn(sim.band) + " - " + lensColourColumn(sim.band);
  spec.simulatedCut = selection;
  spec.selection = words;
  spec.lo = spec.hi = std::nan("");
  spec.simulatedOnly = true;
  for (const ColourCutLevel& level : out.colourCut->levels) {
    if (!std::isfinite(level.maxMag)) continue;
    spec.cuts.push_back({level.maxMag, formatNumber(100.0 * level.completeness, "%.0f") + "%"});
  }
  out.distributions.push_back(makeDistribution(spec, sim.systems, nullptr, s.histogramBins));
}

std::string joined(const std::vector<std::string>& items, const char* separator = ", ") {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : separator) + item;
  return out;
}

// The binning search on a subset of the axes (indices into `axes` and `samples`); no binning
// tried when no arc falls in a bin of these axes.
BinningSearchResult searchOn(const std::vector<GridAxis>& axes, const AxisSamples& samples,
                             const std::vector<double>& weights, const std::vector<std::size_t>& on,
                             const BinningSearchOptions& options) {
  std::vector<GridAxis> a;
  AxisSamples v;
  for (const std::size_t k : on) {
    a.push_back(axes[k]);
    v.push_back(samples[k]);
  }
  try {
    return findFinestConnectedBinning(a, v, options, weights);
  } catch (const ConfigError&) {
    // No arc in any bin (each has an axis NaN or outside): nothing connects on these axes.
    BinningSearchResult none;
    none.options = options;
    return none;
  }
}

// How near a search came to connecting: its finest connected binning, then the fewest isolated
// bins of any binning tried (less is nearer).
std::pair<int, std::int64_t> nearness(const BinningSearchResult& r) {
  std::int64_t fewest = std::numeric_limits<std::int64_t>::max();
  for (const BinningTrial& t : r.trials) fewest = std::min(fewest, t.connectivity.isolatedBins);
  return {r.finestConnected, -fewest};
}

// The occupation grid of the simulated arcs in the search space, at the finest binning whose
// contour stays connected. When no binning connects on every axis, the least informative axis is
// dropped and the search made again, until one connects: the axis dropped is the one whose
// removal lets the finest binning connect (the finest of them), or, when no removal does, brings
// the contour nearest to connecting (the fewest isolated bins); an axis with no range (fewer
// than two distinct values) goes first. On one axis that still does not connect, or with fewer
// than two arcs, no grid.
void makeGrid(const SimulationOutput& sim, const CalibrationSettings& s, CalibrationResult& out) {
  GridOutcome& g = out.grid;
  g.axes = s.gridAxes.empty() ? defaultAxisExpressions() : s.gridAxes;
  g.options.level = s.gridLevel;
  g.options.minBins = s.minBinsPerAxis;
  g.options.maxBins = s.maxBinsPerAxis;
  const BinningSearchOptions& options = g.options;
  if (!s.makeGrid) {
    g.skipped = true;
    return;
  }
  const Table& systems = sim.systems;
  std::vector<bool> rows(std::size_t(systems.rows()), true);
  const int found = systems.findColumn("ARC_FOUND");
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    rows[std::size_t(r)] = systems.value(r, found) == 1.0;
  }
  if (!s.searchSpaceExpression.empty()) {
    // A space no arc falls in leaves no grid (the warning says so), not an error.
    const std::vector<bool> in =
        SearchSpace(s.searchSpaceName, s.searchSpaceExpression).mask(systems);
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = rows[i] && in[i];
  }
  const std::vector<double> allWeights = systemWeights(systems);
  std::vector<double> weights;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i]) continue;
    weights.push_back(allWeights[i]);
    g.samples.add(allWeights[i]);
  }
  AxisSamples samples;
  std::vector<GridAxis> gridAxes;
  std::vector<std::size_t> on;  // the axes still in
  std::vector<std::string> noRange;
  for (const std::string& axis : g.axes) {
    const std::vector<double> all = ColumnExpression(axis, "grid axis " + axis).evaluate(systems);
    std::vector<double> values;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i]) values.push_back(all[i]);
    }
    GridAxis a;
    a.expression = axis;
    if (const auto range = valueRange(values, s.axisTailFraction, "grid axis " + axis)) {
      std::tie(a.lo, a.hi) = *range;
      on.push_back(gridAxes.size());
    } else {
      noRange.push_back(axis);
    }
    gridAxes.push_back(a);
    samples.push_back(std::move(values));
  }
  g.droppedAxes = noRange;
  const std::string arcs = countWithEffective(g.samples.count, g.samples.effective());
  const std::string remedies =
      "simulate more systems (simulate lenses -n), give fewer GRID_AXES, or GRID_NAME NONE to "
      "make no grid";
  if (g.samples.count < 2 || on.empty()) {
    g.warning =
        "no occupation grid: " + arcs +
        (s.searchSpaceExpression.empty() ? "" : " in search space '" + s.searchSpaceName + "'") +
        (on.empty() && g.samples.count >= 2 ? ", and no axis has a range" : "") + "; " + remedies;
    return;
  }
  while (true) {
    GridOutcome::Search search;
    for (const std::size_t k : on) search.axes.push_back(gridAxes[k].expression);
    search.result = searchOn(gridAxes, samples, weights, on, options);
    const bool connected = search.result.finestConnected > 0;
    g.searches.push_back(std::move(search));
    if (connected) break;
    if (on.size() == 1) {
      g.warning =
          "no occupation grid: " + arcs + "; no binning from " + std::to_string(options.minBins) +
          " to " + std::to_string(options.maxBins) +
          " bins per axis keeps the contour at P = " + formatNumber(options.level) +
          " connected on " + joined(g.axes) +
          (g.droppedAxes.empty() ? "" : ", nor with " + joined(g.droppedAxes) + " dropped") + "; " +
          remedies;
      return;
    }
    // Which axis to drop: the removal that comes nearest to connecting.
    std::size_t drop = 0;
    std::pair<int, std::int64_t> best{-1, std::numeric_limits<std::int64_t>::min()};
    for (std::size_t i = 0; i < on.size(); ++i) {
      std::vector<std::size_t> fewer = on;
      fewer.erase(fewer.begin() + std::ptrdiff_t(i));
      const std::pair<int, std::int64_t> n =
          nearness(searchOn(gridAxes, samples, weights, fewer, options));
      if (n > best) {
        best = n;
        drop = i;
      }
    }
    g.droppedAxes.push_back(gridAxes[on[drop]].expression);
    on.erase(on.begin() + std::ptrdiff_t(drop));
  }
  std::vector<GridAxis> used;
  AxisSamples usedSamples;
  for (const std::size_t k : on) {
    used.push_back(gridAxes[k]);
    usedSamples.push_back(samples[k]);
    g.usedAxes.push_back(gridAxes[k].expression);
  }
  const int n = g.searches.back().result.finestConnected;
  OccupationGrid grid = OccupationGrid::fill(GridBinning(used).withBins(n), usedSamples, weights);
  const Contour contour = grid.contour(s.gridLevel);
  g.grid.emplace(SavedGrid{
      std::move(grid), contour,
      GridProvenance{s.searchSpaceName, s.searchSpaceExpression, sim.setup, g.droppedAxes}});
  if (!g.droppedAxes.empty()) {
    std::vector<std::string> dropped = g.droppedAxes;
    for (std::size_t k = 0; k < noRange.size(); ++k) dropped[k] += " (no range)";
    g.warning = "the occupation grid is made on " + std::to_string(g.usedAxes.size()) + " of " +
                std::to_string(g.axes.size()) + " axes (" + joined(g.usedAxes) + "): " + arcs +
                (g.searches.size() > 1
                     ? " do not keep the contour at P = " + formatNumber(options.level) +
                           " connected at any binning from " + std::to_string(options.minBins) +
                           " to " + std::to_string(options.maxBins) + " bins per axis on " +
                           joined(g.searches.front().axes)
                     : " give no range on every axis") +
                "; dropped " + joined(dropped) + " (in that order); " + remedies;
  }
}

FitsColumn doubles(std::string name, std::vector<double> v, std::string comment,
                   std::string unit = "") {
  FitsColumn c;
  c.name = std::move(name);
  c.comment = std::move(comment);
  c.unit = std::move(unit);
  c.values = std::move(v);
  return c;
}

FitsColumn integers(std::string name, std::vector<std::int64_t> v, std::string comment) {
  FitsColumn c;
  c.name = std::move(name);
  c.comment = std::move(comment);
  c.values = std::move(v);
  return c;
}

// FRACTION, FRACTION_LO, FRACTION_HI and FRACTION_ERR of a list of fractions, declared once for
// every table that has them.
std::vector<FitsColumn> fractionColumns(const std::vector<FractionInterval>& f,
                                        const std::string& what) {
  std::vector<double> fraction, lo, hi, err;
  for (const FractionInterval& i : f) {
    fraction.push_back(i.fraction);
    lo.push_back(i.lo);
    hi.push_back(i.hi);
    err.push_back(i.halfWidth());
  }
  return {doubles("FRACTION", fraction, what),
          doubles("FRACTION_LO", lo, "lower bound, Clopper-Pearson 68.27%"),
          doubles("FRACTION_HI", hi, "upper bound, Clopper-Pearson 68.27%"),
          doubles("FRACTION_ERR", err, "half the interval FRACTION_HI - FRACTION_LO")};
}

FitsKeyword effectiveKeyword(const char* name, const WeightedCount& c, const std::string& what) {
  return FitsKeyword::real(name, c.effective(), "Kish effective number of " + what);
}

FitsTable fractionTable(const LensingFractions& f) {
  FitsTable t;
  t.name = "LENSING_FRACTION";
  std::vector<double> lo, hi, weight;
  std::vector<std::int64_t> distorted, n;
  std::vector<FractionInterval> fraction;
  for (const FractionRow& r : f.rows) {
    lo.push_back(r.arcnessLo);
    hi.push_back(std::isfinite(r.arcnessHi) ? r.arcnessHi : std::nan(""));
    distorted.push_back(r.distortedAndBright ? 1 : 0);
    n.push_back(r.systems);
    weight.push_back(r.weight);
    fraction.push_back(r.fraction);
  }
  t.columns = {doubles("ARCNESS_LO", lo, "lowest arcness of the bin"),
               doubles("ARCNESS_HI", hi, "arcness bound of the bin (NaN: none)"),
               integers("DISTORTED", distorted, "1: also E_IMAGE and SNR_ISO above the cuts"),
               integers("N_SYSTEMS", n, "systems whose chosen arc is in the bin"),
               doubles("WEIGHT", weight, "their SIM_WEIGHT sum")};
  for (FitsColumn& c : fractionColumns(fraction, "WEIGHT / that of the systems with an arc")) {
    t.columns.push_back(std::move(c));
  }
  t.keywords = {FitsKeyword::integer("NSYSTEMS", f.simulatedSystems, "simulated systems"),
                FitsKeyword::integer("NARCSYS", f.arcSystems.count,
                                     "systems with an arc >= 1\" from the lens (normalisation)"),
                FitsKeyword::real("WARCSYS", f.arcSystems.weightSum, "their SIM_WEIGHT sum"),
                effectiveKeyword("NEFFARC", f.arcSystems, "them")};
  return t;
}

FitsTable distributionTable(const Distribution& d) {
  FitsTable t;
  t.name = "DIST_" + d.name;
  std::vector<double> lo(d.simulated.edges.begin(), d.simulated.edges.end() - 1);
  std::vector<double> hi(d.simulated.edges.begin() + 1, d.simulated.edges.end());
  // The colour difference is in magnitudes; the other distributions are dimensionless.
  const std::string unit = d.name == "COLOUR_DIFF" ? "mag" : "";
  t.columns = {doubles("BIN_LO", lo, "bin lower edge", unit),
               doubles("BIN_HI", hi, "bin upper edge", unit),
               doubles("SIM_FRACTION", d.simulated.fraction,
                       "weighted fraction of simulated arcs (SIM_WEIGHT)")};
  t.keywords = {FitsKeyword::text("VALUE", d.column, "what is histogrammed"),
                FitsKeyword::text("SELECT", d.selection, "the rows taken"),
                FitsKeyword::integer("NSIM", d.simulated.values, "simulated arcs"),
                FitsKeyword::real("NEFFSIM", d.simulated.effective,
                                  "Kish effective number of simulated arcs"),
                FitsKeyword::integer("NSIMOUT", d.simulated.outside, "of them outside the bins")};
  if (d.gaussian) {
    t.keywords.push_back(
        FitsKeyword::real("GAUSMEAN", d.gaussian->mean, "mean of the Gaussian fit"));
    t.keywords.push_back(
        FitsKeyword::real("GAUSSIG", d.gaussian->sigma, "sigma of the Gaussian fit"));
    t.keywords.push_back(
        FitsKeyword::real("GAUSFWHM", d.gaussian->fwhm, "FWHM of the Gaussian fit"));
    t.keywords.push_back(
        FitsKeyword::logical("GAUSCONV", d.gaussian->converged, "T: the fit converged"));
  }
  if (d.survey) {
    t.columns.push_back(
        doubles("SURVEY_FRACTION", d.survey->fraction, "fraction of survey objects"));
    t.keywords.push_back(FitsKeyword::integer("NSURVEY", d.survey->values, "survey objects"));
    t.keywords.push_back(
        FitsKeyword::integer("NSURVOUT", d.survey->outside, "of them outside the bins"));
  }
  return t;
}

FitsTable noiseTable(const NoiseThresholdResult& n) {
  FitsTable t;
  t.name = "NOISE_THRESHOLD";
  t.columns = {doubles("THRESHOLD", n.thresholdsSigma, "detection threshold", "sigma"),
               integers("N_WITH_OBJECTS", n.realisationsWithObjects, "realisations with an object"),
               doubles("MEAN_OBJECTS", n.meanObjects, "objects per noise image")};
  t.keywords = {FitsKeyword::real("NOISETHR", n.noiseOnlyThresholdSigma,
                                  "lowest threshold with no object in any realisation"),
                FitsKeyword::logical("NOISELOW", n.atLowestRung,
                                     "T: no object even at the lowest threshold tried")};
  return t;
}

FitsTable thresholdCountTable(const ThresholdCountCurve& c) {
  FitsTable t;
  t.name = "THRESHOLD_COUNT";
  std::vector<std::int64_t> levels, systems, rendered, arcs, with;
  std::vector<double> weight, effective;
  std::vector<FractionInterval> fraction;
  for (const ThresholdCountRow& r : c.rows) {
    levels.push_back(r.levels);
    systems.push_back(r.systems);
    rendered.push_back(r.rendered);
    arcs.push_back(r.arcSystems);
    with.push_back(r.withArcness.count);
    weight.push_back(r.withArcness.weightSum);
    effective.push_back(r.withArcness.effective());
    fraction.push_back(r.fraction);
  }
  t.columns = {integers("NLEVELS", levels, "detection thresholds"),
               integers("N_SYSTEMS", systems, "systems drawn"),
               integers("N_RENDERED", rendered, "of them rendered"),
               integers("N_ARC", arcs, "rendered systems with an arc"),
               integers("N_ARCNESS", with, "systems with an arc row above the arcness cut"),
               doubles("WEIGHT", weight, "their SIM_WEIGHT sum"),
               doubles("NEFF_ARCNESS", effective, "their Kish effective number")};
  for (FitsColumn& col : fractionColumns(fraction, "WEIGHT / N_SYSTEMS")) {
    t.columns.push_back(std::move(col));
  }
  t.keywords = {FitsKeyword::integer("FLATNLEV", c.flattensAtLevels,
                                     "fewest levels within 1 sigma of the most tried")};
  return t;
}

FitsTable snrFloorTable(const SnrFloorResult& f) {
  FitsTable t;
  t.name = "SNR_FLOOR";
  std::vector<double> lo, hi, median, q20, q80;
  std::vector<std::int64_t> n, reliable;
  for (const SnrFloorBin& b : f.bins) {
    lo.push_back(b.snrLo);
    hi.push_back(b.snrHi);
    n.push_back(b.measurements);
    median.push_back(b.median);
    q20.push_back(b.q20);
    q80.push_back(b.q80);
    reliable.push_back(b.reliable ? 1 : 0);
  }
  t.columns = {doubles("SNR_LO", lo, "bin lower edge (SNR_ISO)"),
               doubles("SNR_HI", hi, "bin upper edge"),
               integers("N_MEASURED", n, "arc measurements in the bin"),
               doubles("ARCNESS_MEDIAN", median, "median of the scaled arcness"),
               doubles("ARCNESS_Q20", q20, "20% quantile of the scaled arcness"),
               doubles("ARCNESS_Q80", q80, "80% quantile of the scaled arcness"),
               integers("RELIABLE", reliable, "1: median and spread within the criterion")};
  double found = 0;
  for (std::int64_t k : f.foundPerFactor) found += double(k);
  t.keywords = {
      FitsKeyword::real("SNRFLOOR", f.floorSnr, "S/N below which arcness is unreliable"),
      FitsKeyword::integer("NARCS", std::int64_t(f.systems.size()), "arcs remeasured"),
      FitsKeyword::real("NEFFARCS", f.effectiveArcs, "Kish effective number of those arcs"),
      FitsKeyword::integer("NMEASURE", f.measurements, "measurements (arc found)"),
      FitsKeyword::real(
          "FOUNDFRC", found / double(f.realisationsPerFactor * std::int64_t(f.noiseFactors.size())),
          "fraction of realisations in which the arc was found")};
  return t;
}

FitsTable colourCutTable(const ColourCutStudy& c) {
  FitsTable t;
  t.name = "COLOUR_CUT";
  std::vector<double> max, weight;
  std::vector<std::int64_t> kept;
  std::vector<FractionInterval> fraction;
  for (const ColourCutRow& r : c.rows) {
    max.push_back(r.maxMag);
    kept.push_back(r.kept);
    weight.push_back(r.keptWeight);
    fraction.push_back(r.fraction);
  }
  t.columns = {
      doubles("COLOUR_MAX", max,
              "MAX of COLOUR_CUT " + c.band + ",MAX (ARC_COLOUR - LENS_COLOUR <= MAX kept)", "mag"),
      integers("N_KEPT", kept, "arcs kept (those without both colours included)"),
      doubles("WEIGHT", weight, "their SIM_WEIGHT sum")};
  for (FitsColumn& col : fractionColumns(fraction, "WEIGHT / that of the arcs: completeness")) {
    t.columns.push_back(std::move(col));
  }
  t.keywords = {FitsKeyword::text("BAND", c.band, "the second band"),
                FitsKeyword::text("SELECT", c.arcSelection, "the arcs (systems table)"),
                FitsKeyword::integer("NARCS", c.arcs.count, "arcs (the normalisation)"),
                FitsKeyword::real("WARCS", c.arcs.weightSum, "their SIM_WEIGHT sum"),
                effectiveKeyword("NEFFARCS", c.arcs, "the arcs"),
                FitsKeyword::integer("NCOLOUR", c.withColours, "of them with both colours")};
  for (const ColourCutLevel& l : c.levels) {
    // -inf (any MAX keeps that many) is written as an undefined value.
    const std::string percent = formatNumber(100.0 * l.completeness, "%.0f");
    t.keywords.push_back(
        FitsKeyword::real("MAXC" + percent, std::isfinite(l.maxMag) ? l.maxMag : std::nan(""),
                          "[mag] smallest MAX keeping " + percent + "% (undefined: any)"));
  }
  return t;
}

FitsTable binningTable(const GridOutcome& g) {
  FitsTable t;
  t.name = "GRID_BINNING";
  std::vector<std::int64_t> axes, bins, occupied, selected, connected, isolated, components;
  std::vector<std::string> names;
  std::vector<double> probability;
  for (const GridOutcome::Search& search : g.searches) {
    for (const BinningTrial& trial : search.result.trials) {
      axes.push_back(std::int64_t(search.axes.size()));
      names.push_back(joined(search.axes, ","));
      bins.push_back(trial.binsPerAxis);
      occupied.push_back(trial.occupiedBins);
      selected.push_back(trial.selectedBins);
      probability.push_back(trial.selectedProbability);
      connected.push_back(trial.connectivity.connected ? 1 : 0);
      isolated.push_back(trial.connectivity.isolatedBins);
      components.push_back(trial.connectivity.components);
    }
  }
  FitsColumn axisNames;
  axisNames.name = "AXES";
  axisNames.comment = "the grid axes of the binning";
  axisNames.repeat = 0;
  axisNames.values = std::move(names);
  t.columns = {integers("NAXES", axes, "grid axes"),
               std::move(axisNames),
               integers("BINS_PER_AXIS", bins, "bins on every axis"),
               integers("OCCUPIED", occupied, "occupied bins"),
               integers("SELECTED", selected, "bins of the contour"),
               doubles("SELECTED_PROB", probability, "probability the contour holds"),
               integers("CONNECTED", connected, "1: every selected bin has a selected neighbour"),
               integers("ISOLATED", isolated, "selected bins without a selected neighbour"),
               integers("COMPONENTS", components, "face-connected components")};
  const int finest = g.grid ? g.searches.back().result.finestConnected : 0;
  const double level = g.options.level;
  t.keywords = {
      FitsKeyword::integer("FINEST", finest, "finest connected binning (0: no grid)"),
      FitsKeyword::real("PLEVEL", level, "contour level P"),
      FitsKeyword::integer("NSAMPLES", g.samples.count, "simulated arcs in the grid"),
      effectiveKeyword("NEFFSAMP", g.samples, "them"),
      FitsKeyword::logical("GRIDMADE", g.grid.has_value(), "T: a grid was made"),
      FitsKeyword::integer("NGRIDAX", std::int64_t(g.usedAxes.size()), "axes of the grid")};
  for (std::size_t a = 0; a < g.usedAxes.size(); ++a) {
    t.keywords.push_back(
        FitsKeyword::text("GRIDAX" + std::to_string(a + 1), g.usedAxes[a], "grid axis"));
  }
  t.keywords.push_back(FitsKeyword::integer("NDROPAX", std::int64_t(g.droppedAxes.size()),
                                            "axes dropped to keep the contour connected"));
  for (std::size_t a = 0; a < g.droppedAxes.size(); ++a) {
    t.keywords.push_back(
        FitsKeyword::text("DROPAX" + std::to_string(a + 1), g.droppedAxes[a], "dropped axis"));
  }
  return t;
}

PlotSeries steps(const std::string& label, const Histogram& h) {
  PlotSeries s;
  s.label = label;
  s.steps = true;
  s.x = h.edges;
  s.y = h.fraction;
  return s;
}

}  // namespace

Histogram normalisedHistogram(const std::vector<double>& values, double lo, double hi, int bins,
                              const std::vector<double>& weights) {
  if (!(hi > lo) || bins < 1) throw ConfigError("histogram: empty range or no bin");
  if (!weights.empty() && weights.size() != values.size()) {
    throw ConfigError("histogram: " + std::to_string(values.size()) + " values and " +
                      std::to_string(weights.size()) + " weights");
  }
  Histogram h;
  for (int k = 0; k <= bins; ++k) h.edges.push_back(lo + (hi - lo) * k / bins);
  h.fraction.assign(std::size_t(bins), 0.0);
  std::vector<double> binWeight(std::size_t(bins), 0.0);
  WeightedCount given;
  std::int64_t inside = 0;
  double insideWeight = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (!std::isfinite(v)) continue;
    const double w = weights.empty() ? 1.0 : weights[i];
    given.add(w);
    if (v < lo || v >= hi) continue;
    // The bin whose printed edges hold v: floor() first, then the edges decide.
    int k = std::clamp(int(std::floor((v - lo) / (hi - lo) * bins)), 0, bins - 1);
    if (v < h.edges[std::size_t(k)] && k > 0) --k;
    if (v >= h.edges[std::size_t(k) + 1] && k + 1 < bins) ++k;
    binWeight[std::size_t(k)] += w;
    ++inside;
    insideWeight += w;
  }
  h.values = given.count;
  h.effective = given.effective();
  h.outside = h.values - inside;
  for (int k = 0; k < bins; ++k) {
    h.fraction[std::size_t(k)] = insideWeight > 0 ? binWeight[std::size_t(k)] / insideWeight : 0.0;
  }
  return h;
}

CalibrationResult calibrate(const SimulationOutput& simulation, const Table* survey,
                            const CalibrationSettings& s) {
  CalibrationResult out;
  // The studies that simulate again: the simulation's options and sources (read once), and a
  // check that they remake its systems (cheap), before any other work.
  std::optional<LensSetupOptions> remake;
  std::optional<SourceDatabase> sources;
  if (s.thresholdCount || s.snrFloor) {
    remake = resimulationOptions(simulation);
    sources = resimulationSources(simulation).make();
    checkRemade(simulation, *remake, *sources);
  }
  out.simulatedSystems = simulation.setup.systems;
  out.fractions = lensingFractions(simulation.systems, s.fractionCuts);
  out.fractions.simulatedSystems = simulation.setup.systems;
  out.arcSystems = out.fractions.arcSystems;
  for (const DistributionSpec& spec : distributionSpecs(s.fractionCuts)) {
    out.distributions.push_back(
        makeDistribution(spec, simulation.systems, survey, s.histogramBins));
  }
  if (!simulation.band.empty()) colourCutStudies(simulation, s, out);
  makeGrid(simulation, s, out);
  if (s.noise) out.noise = noiseOnlyThreshold(*s.noise);
  if (s.thresholdCount) {
    out.thresholdCount = thresholdCountCurve(*remake, *sources, *s.thresholdCount);
  }
  if (s.snrFloor) out.snrFloor = snrFloorStudy(simulation, *remake, *sources, *s.snrFloor);
  return out;
}

std::vector<FitsTable> calibrationTables(const CalibrationResult& r) {
  std::vector<FitsTable> tables = {fractionTable(r.fractions)};
  for (const Distribution& d : r.distributions) tables.push_back(distributionTable(d));
  if (r.noise) tables.push_back(noiseTable(*r.noise));
  if (r.thresholdCount) tables.push_back(thresholdCountTable(*r.thresholdCount));
  if (r.snrFloor) tables.push_back(snrFloorTable(*r.snrFloor));
  if (r.colourCut) tables.push_back(colourCutTable(*r.colourCut));
  tables.push_back(binningTable(r.grid));
  return tables;
}

std::vector<std::string> calibrationPlotTypes() {
  return {"ARCNESS",    "ANTIARCNESS",      "SKEW_MAJOR",      "SKEW_MINOR",      "E_IMAGE",
          "SNR_ISO",    "LENSING_FRACTION", "NOISE_THRESHOLD", "THRESHOLD_COUNT", "SNR_FLOOR",
          "COLOUR_CUT", "COLOUR_DIFF",      "GRID_BINNING"};
}

namespace {

// A fraction with its 68.27 % interval as the error bar.
void addWithErrorBar(PlotSeries& s, const FractionInterval& f) {
  s.y.push_back(f.fraction);
  s.yLow.push_back(f.lo);
  s.yHigh.push_back(f.hi);
}

// One check-plot per study (calibrationPlot dispatches on CHECKPLOT_TYPE).
Plot distributionPlot(const Distribution& d) {
  Plot p;
  p.title = d.name + " (" + d.selection + ")";
  p.xLabel = d.name == "SNR_ISO"       ? "log#d10#u S/N (ISO)"
             : d.name == "COLOUR_DIFF" ? d.column + " [mag]"
                                       : d.name;
  p.yLabel = "fraction per bin";
  p.series.push_back(steps(
      "simulated: " + countWithEffective(d.simulated.values, d.simulated.effective), d.simulated));
  if (d.survey) {
    p.series.push_back(
        steps("survey objects (" + std::to_string(d.survey->values) + ")", *d.survey));
  }
  if (d.gaussian && std::isfinite(d.gaussian->fwhm)) {
    const GaussianFit& g = *d.gaussian;
    PlotSeries curve;
    curve.label = "Gaussian fit, FWHM " + formatNumber(g.fwhm, "%.3f");
    const double lo = d.simulated.edges.front(), hi = d.simulated.edges.back();
    for (int k = 0; k <= 200; ++k) {
      const double x = lo + (hi - lo) * k / 200.0, u = (x - g.mean) / g.sigma;
      curve.x.push_back(x);
      curve.y.push_back(g.amplitude * std::exp(-0.5 * u * u));
    }
    p.series.push_back(curve);
  }
  p.cuts = d.cuts;
  return p;
}

Plot fractionPlot(const CalibrationResult& r) {
  Plot p;
  p.title = "Lensing fraction (" +
            countWithEffective(r.fractions.arcSystems.count, r.fractions.arcSystems.effective(),
                               "systems") +
            " with an arc)";
  p.xLabel = "ARCNESS of the chosen arc";
  p.yLabel = "fraction of systems with an arc";
  for (const bool distorted : {false, true}) {
    PlotSeries s;
    s.label = distorted ? "also e > " + formatNumber(r.fractions.cuts.ellipticityMin) + ", S/N > " +
                              formatNumber(r.fractions.cuts.snrMin)
                        : "all";
    s.steps = true;
    for (const FractionRow& row : r.fractions.rows) {
      if (row.distortedAndBright != distorted) continue;
      if (s.x.empty()) s.x.push_back(row.arcnessLo);
      s.x.push_back(std::isfinite(row.arcnessHi) ? row.arcnessHi : row.arcnessLo + 0.05);
      addWithErrorBar(s, row.fraction);
    }
    p.series.push_back(s);
  }
  return p;
}

Plot noisePlot(const CalibrationResult& r) {
  Plot p;
  if (!r.noise) throw ConfigError("CHECKPLOT_TYPE NOISE_THRESHOLD: the noise study is off");
  p.title = "Noise alone: realisations with an object";
  p.xLabel = "detection threshold [sigma]";
  p.yLabel = "realisations with an object";
  PlotSeries s;
  s.label = "pure noise";
  s.x = r.noise->thresholdsSigma;
  for (std::int64_t n : r.noise->realisationsWithObjects) s.y.push_back(double(n));
  p.series.push_back(s);
  if (std::isfinite(r.noise->noiseOnlyThresholdSigma)) {
    p.cuts.push_back({r.noise->noiseOnlyThresholdSigma,
                      "none from " + formatNumber(r.noise->noiseOnlyThresholdSigma, "%.2f")});
  }
  return p;
}

Plot thresholdCountPlot(const CalibrationResult& r) {
  Plot p;
  if (!r.thresholdCount) throw ConfigError("CHECKPLOT_TYPE THRESHOLD_COUNT: the study is off");
  p.title = "Arcs with ARCNESS > 0.10 against the number of thresholds";
  p.xLabel = "number of detection thresholds";
  p.yLabel = "fraction of simulated systems";
  PlotSeries s;
  s.label = "same systems, same lowest and highest threshold";
  for (const ThresholdCountRow& row : r.thresholdCount->rows) {
    s.x.push_back(row.levels);
    addWithErrorBar(s, row.fraction);
  }
  p.series.push_back(s);
  p.cuts.push_back({double(r.thresholdCount->flattensAtLevels),
                    "flat from " + std::to_string(r.thresholdCount->flattensAtLevels)});
  return p;
}

Plot snrFloorPlot(const CalibrationResult& r) {
  Plot p;
  if (!r.snrFloor) throw ConfigError("CHECKPLOT_TYPE SNR_FLOOR: the study is off");
  p.title = "Arcs scaled to ARCNESS " + formatNumber(r.snrFloor->scaledToArcness, "%.2f") +
            " at their highest S/N, " +
            countWithEffective(std::int64_t(r.snrFloor->systems.size()), r.snrFloor->effectiveArcs);
  p.xLabel = "S/N (ISO)";
  p.yLabel = "ARCNESS (scaled)";
  p.logX = true;
  PlotSeries median;
  median.label = "median, 20% and 80% quantiles";
  for (const SnrFloorBin& b : r.snrFloor->bins) {
    if (b.measurements == 0) continue;
    median.x.push_back(std::sqrt(b.snrLo * b.snrHi));
    median.y.push_back(b.median);
    median.yLow.push_back(b.q20);
    median.yHigh.push_back(b.q80);
  }
  p.series.push_back(median);
  if (std::isfinite(r.snrFloor->floorSnr)) {
    p.cuts.push_back(
        {r.snrFloor->floorSnr, "S/N floor " + formatNumber(r.snrFloor->floorSnr, "%.0f")});
  }
  return p;
}

Plot colourCutPlot(const CalibrationResult& r) {
  if (!r.colourCut)
    throw ConfigError("CHECKPLOT_TYPE COLOUR_CUT: the simulation has no second band");
  const ColourCutStudy& c = *r.colourCut;
  Plot p;
  p.title = "Colour cut in " + c.band + ": arcs kept (" +
            countWithEffective(c.arcs.count, c.arcs.effective()) + ", " +
            std::to_string(c.withColours) + " with both colours)";
  p.xLabel = "MAX of COLOUR_CUT " + c.band + ",MAX [mag]";
  p.yLabel = "fraction of simulated arcs kept";
  PlotSeries s;
  s.label = "ARC_COLOUR_" + c.band + " - LENS_COLOUR_" + c.band + " <= MAX, or no colour";
  for (const ColourCutRow& row : c.rows) {
    s.x.push_back(row.maxMag);
    addWithErrorBar(s, row.fraction);
  }
  p.series.push_back(s);
  for (const ColourCutLevel& l : c.levels) {
    if (!std::isfinite(l.maxMag)) continue;
    p.cuts.push_back({l.maxMag, formatNumber(100.0 * l.completeness, "%.0f") + "% kept from " +
                                    formatNumber(l.maxMag, "%.2f")});
  }
  return p;
}

Plot binningPlot(const CalibrationResult& r) {
  const GridOutcome& g = r.grid;
  Plot p;
  p.title = "Occupation grid: binning search, " +
            countWithEffective(g.samples.count, g.samples.effective());
  if (g.skipped) p.title += " (GRID_NAME NONE: no grid)";
  p.xLabel = "bins per axis";
  p.yLabel = "selected bins without a selected neighbour";
  for (const GridOutcome::Search& search : g.searches) {
    PlotSeries s;
    s.label = std::to_string(search.axes.size()) + " axes" +
              (search.axes.size() == g.axes.size() ? "" : " (" + joined(search.axes) + ")");
    for (const BinningTrial& t : search.result.trials) {
      s.x.push_back(t.binsPerAxis);
      s.y.push_back(double(t.connectivity.isolatedBins));
    }
    p.series.push_back(s);
  }
  if (g.searches.empty()) {
    // Nothing searched: a line at zero over the range that would have been, so the plot says so.
    PlotSeries s;
    s.label = g.skipped ? "no grid asked for" : "too few arcs: no binning searched";
    s.x = {double(g.options.minBins), double(g.options.maxBins)};
    s.y = {0.0, 0.0};
    p.series.push_back(s);
  }
  if (g.grid) {
    const int finest = g.searches.back().result.finestConnected;
    p.cuts.push_back({double(finest), "finest connected: " + std::to_string(finest)});
  }
  return p;
}

}  // namespace

Plot calibrationPlot(const CalibrationResult& r, const std::string& type) {
  for (const Distribution& d : r.distributions) {
    if (d.name == type) return distributionPlot(d);
  }
  if (type == "LENSING_FRACTION") return fractionPlot(r);
  if (type == "NOISE_THRESHOLD") return noisePlot(r);
  if (type == "THRESHOLD_COUNT") return thresholdCountPlot(r);
  if (type == "SNR_FLOOR") return snrFloorPlot(r);
  if (type == "COLOUR_CUT") return colourCutPlot(r);
  if (type == "COLOUR_DIFF") {
    throw ConfigError("CHECKPLOT_TYPE COLOUR_DIFF: the simulation has no second band");
  }
  if (type == "GRID_BINNING") return binningPlot(r);
  const std::vector<std::string> types = calibrationPlotTypes();
  if (std::find(types.begin(), types.end(), type) != types.end()) {
    throw ConfigError("CHECKPLOT_TYPE " + quoteForMessage(type) +
                      ": the calibration has no such distribution");
  }
  throw ConfigError("CHECKPLOT_TYPE " + quoteForMessage(type) + " is not a calibration plot");
}

}  // namespace octarc
