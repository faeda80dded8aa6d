#include "octarc/calibration/Calibration.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
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
  static std::vector<std::string> texts;  // keeps the composed cut texts alive
  texts = {"ARC_FOUND == 1 && E_IMAGE > " + e + " && SNR_ISO > " + snr,
           "E_IMAGE > " + e + " && SNR_ISO > " + snr, "E_IMAGE > " + e + " and SNR_ISO > " + snr};
  const char* bright = texts[0].c_str();
  const char* brightSurvey = texts[1].c_str();
  const char* brightWords = texts[2].c_str();
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

// The values of `value` on the rows of `table` that pass `cut` (finite and non-zero).
std::vector<double> selectedValues(const Table& table, const std::string& value,
                                   const std::string& cut, const std::string& context) {
  const std::vector<double> v = ColumnExpression(value, context).evaluate(table);
  const std::vector<double> pass = ColumnExpression(cut, context).evaluate(table);
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::isfinite(pass[i]) && pass[i] != 0.0 && std::isfinite(v[i])) out.push_back(v[i]);
  }
  return out;
}

Distribution makeDistribution(const DistributionSpec& spec, const Table& systems,
                              const Table* survey, int bins) {
  Distribution d;
  d.name = spec.name;
  d.column = spec.value;
  d.selection = spec.selection;
  d.cuts = spec.cuts;
  d.simulatedOnly = spec.simulatedOnly;
  const std::vector<double> sim =
      selectedValues(systems, spec.value, spec.simulatedCut, "distribution " + d.name);
  double lo = spec.lo, hi = spec.hi;
  if (std::isnan(lo)) {
    if (sim.size() >= 2 &&
        std::adjacent_find(sim.begin(), sim.end(), std::not_equal_to<>()) != sim.end()) {
      std::tie(lo, hi) = quantileRange(sim, 0.01, "distribution " + d.name);
    } else {
      lo = sim.empty() ? 0.0 : sim.front() - 0.5;
      hi = sim.empty() ? 1.0 : sim.front() + 0.5;
    }
  }
  d.simulated = normalisedHistogram(sim, lo, hi, bins);
  if (spec.fitGaussian) d.gaussian = fitGaussian(d.simulated.edges, d.simulated.fraction);
  if (survey && !spec.simulatedOnly) {
    d.survey = normalisedHistogram(
        selectedValues(*survey, spec.value, spec.surveyCut, "survey distribution " + d.name), lo,
        hi, bins);
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

// The occupation grid of the simulated arcs in the search space, at the finest binning whose
// contour stays connected.
void makeGrid(const SimulationOutput& sim, const CalibrationSettings& s, CalibrationResult& out) {
  const Table& systems = sim.systems;
  std::vector<bool> rows(std::size_t(systems.rows()), true);
  const int found = systems.findColumn("ARC_FOUND");
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    rows[std::size_t(r)] = systems.value(r, found) == 1.0;
  }
  if (!s.searchSpaceExpression.empty()) {
    const std::vector<bool> in =
        SearchSpace(s.searchSpaceName, s.searchSpaceExpression).simulatedMask(systems);
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = rows[i] && in[i];
  }
  const std::vector<std::string> axes = s.gridAxes.empty() ? defaultAxisExpressions() : s.gridAxes;
  AxisSamples samples;
  std::vector<GridAxis> gridAxes;
  for (const std::string& axis : axes) {
    const std::vector<double> all = ColumnExpression(axis, "grid axis " + axis).evaluate(systems);
    std::vector<double> values;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i]) values.push_back(all[i]);
    }
    GridAxis a;
    a.expression = axis;
    std::tie(a.lo, a.hi) = quantileRange(values, s.axisTailFraction, "grid axis " + axis);
    gridAxes.push_back(a);
    samples.push_back(std::move(values));
  }
  out.gridSamples = std::int64_t(samples.front().size());
  BinningSearchOptions options;
  options.level = s.gridLevel;
  options.minBins = s.minBinsPerAxis;
  options.maxBins = s.maxBinsPerAxis;
  out.binning = findFinestConnectedBinning(gridAxes, samples, options);
  const int n = out.binning.requireFinest();
  OccupationGrid grid = OccupationGrid::fill(GridBinning(gridAxes).withBins(n), samples);
  const Contour contour = grid.contour(s.gridLevel);
  out.grid.emplace(
      SavedGrid{std::move(grid), contour,
                GridProvenance{s.searchSpaceName, s.searchSpaceExpression, sim.setup}});
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

FitsTable fractionTable(const LensingFractions& f) {
  FitsTable t;
  t.name = "LENSING_FRACTION";
  std::vector<double> lo, hi, frac, err;
  std::vector<std::int64_t> distorted, n;
  for (const FractionRow& r : f.rows) {
    lo.push_back(r.arcnessLo);
    hi.push_back(std::isfinite(r.arcnessHi) ? r.arcnessHi : std::nan(""));
    distorted.push_back(r.distortedAndBright ? 1 : 0);
    n.push_back(r.systems);
    frac.push_back(r.fraction);
    err.push_back(r.fractionSigma);
  }
  t.columns = {doubles("ARCNESS_LO", lo, "lowest arcness of the bin"),
               doubles("ARCNESS_HI", hi, "arcness bound of the bin (NaN: none)"),
               integers("DISTORTED", distorted, "1: also E_IMAGE and SNR_ISO above the cuts"),
               integers("N_SYSTEMS", n, "systems whose chosen arc is in the bin"),
               doubles("FRACTION", frac, "N_SYSTEMS / systems with an arc"),
               doubles("FRACTION_ERR", err, "binomial sigma of FRACTION")};
  t.keywords = {FitsKeyword::integer("NSYSTEMS", f.simulatedSystems, "simulated systems"),
                FitsKeyword::integer("NARCSYS", f.arcSystems,
                                     "systems with an arc >= 1\" from the lens (normalisation)")};
  return t;
}

FitsTable distributionTable(const Distribution& d) {
  FitsTable t;
  t.name = "DIST_" + d.name;
  std::vector<double> lo(d.simulated.edges.begin(), d.simulated.edges.end() - 1);
  std::vector<double> hi(d.simulated.edges.begin() + 1, d.simulated.edges.end());
  t.columns = {doubles("BIN_LO", lo, "bin lower edge"), doubles("BIN_HI", hi, "bin upper edge"),
               doubles("SIM_FRACTION", d.simulated.fraction, "fraction of simulated arcs")};
  t.keywords = {FitsKeyword::text("VALUE", d.column, "what is histogrammed"),
                FitsKeyword::text("SELECT", d.selection, "the rows taken"),
                FitsKeyword::integer("NSIM", d.simulated.values, "simulated arcs"),
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
  std::vector<std::int64_t> levels, systems, arcs, with;
  std::vector<double> fraction, sigma;
  for (const ThresholdCountRow& r : c.rows) {
    levels.push_back(r.levels);
    systems.push_back(r.systems);
    arcs.push_back(r.arcSystems);
    with.push_back(r.withArcness);
    fraction.push_back(r.fraction);
    sigma.push_back(r.fractionSigma);
  }
  t.columns = {integers("NLEVELS", levels, "detection thresholds"),
               integers("N_SYSTEMS", systems, "simulated systems"),
               integers("N_ARC", arcs, "systems with an arc"),
               integers("N_ARCNESS", with, "systems with an arc row above the arcness cut"),
               doubles("FRACTION", fraction, "N_ARCNESS / N_SYSTEMS"),
               doubles("FRACTION_ERR", sigma, "binomial sigma of FRACTION")};
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
      FitsKeyword::integer("NMEASURE", f.measurements, "measurements (arc found)"),
      FitsKeyword::real(
          "FOUNDFRC", found / double(f.realisationsPerFactor * std::int64_t(f.noiseFactors.size())),
          "fraction of realisations in which the arc was found")};
  return t;
}

FitsTable colourCutTable(const ColourCutStudy& c) {
  FitsTable t;
  t.name = "COLOUR_CUT";
  std::vector<double> max, fraction, sigma;
  std::vector<std::int64_t> kept;
  for (const ColourCutRow& r : c.rows) {
    max.push_back(r.maxMag);
    kept.push_back(r.kept);
    fraction.push_back(r.fraction);
    sigma.push_back(r.fractionSigma);
  }
  t.columns = {
      doubles("COLOUR_MAX", max,
              "MAX of COLOUR_CUT " + c.band + ",MAX (ARC_COLOUR - LENS_COLOUR <= MAX kept)", "mag"),
      integers("N_KEPT", kept, "arcs kept (those without both colours included)"),
      doubles("FRACTION", fraction, "N_KEPT / arcs: the completeness of the cut"),
      doubles("FRACTION_ERR", sigma, "binomial sigma of FRACTION")};
  t.keywords = {FitsKeyword::text("BAND", c.band, "the second band"),
                FitsKeyword::text("SELECT", c.arcSelection, "the arcs (systems table)"),
                FitsKeyword::integer("NARCS", c.arcs, "arcs (the normalisation)"),
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

FitsTable binningTable(const BinningSearchResult& b, std::int64_t samples) {
  FitsTable t;
  t.name = "GRID_BINNING";
  std::vector<std::int64_t> bins, occupied, selected, connected, isolated, components;
  std::vector<double> probability;
  for (const BinningTrial& trial : b.trials) {
    bins.push_back(trial.binsPerAxis);
    occupied.push_back(trial.occupiedBins);
    selected.push_back(trial.selectedBins);
    probability.push_back(trial.selectedProbability);
    connected.push_back(trial.connectivity.connected ? 1 : 0);
    isolated.push_back(trial.connectivity.isolatedBins);
    components.push_back(trial.connectivity.components);
  }
  t.columns = {integers("BINS_PER_AXIS", bins, "bins on every axis"),
               integers("OCCUPIED", occupied, "occupied bins"),
               integers("SELECTED", selected, "bins of the contour"),
               doubles("SELECTED_PROB", probability, "probability the contour holds"),
               integers("CONNECTED", connected, "1: every selected bin has a selected neighbour"),
               integers("ISOLATED", isolated, "selected bins without a selected neighbour"),
               integers("COMPONENTS", components, "face-connected components")};
  t.keywords = {FitsKeyword::integer("FINEST", b.finestConnected, "finest connected binning"),
                FitsKeyword::real("PLEVEL", b.options.level, "contour level P"),
                FitsKeyword::integer("NSAMPLES", samples, "simulated arcs in the grid")};
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

Histogram normalisedHistogram(const std::vector<double>& values, double lo, double hi, int bins) {
  if (!(hi > lo) || bins < 1) throw ConfigError("histogram: empty range or no bin");
  Histogram h;
  for (int k = 0; k <= bins; ++k) h.edges.push_back(lo + (hi - lo) * k / bins);
  h.fraction.assign(std::size_t(bins), 0.0);
  std::vector<std::int64_t> counts(std::size_t(bins), 0);
  std::int64_t inside = 0;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    ++h.values;
    if (v < lo || v >= hi) continue;
    // The bin whose printed edges hold v: floor() first, then the edges decide.
    int k = std::clamp(int(std::floor((v - lo) / (hi - lo) * bins)), 0, bins - 1);
    if (v < h.edges[std::size_t(k)] && k > 0) --k;
    if (v >= h.edges[std::size_t(k) + 1] && k + 1 < bins) ++k;
    ++counts[std::size_t(k)];
    ++inside;
  }
  h.outside = h.values - inside;
  for (int k = 0; k < bins; ++k) {
    h.fraction[std::size_t(k)] = inside > 0 ? double(counts[std::size_t(k)]) / inside : 0.0;
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
  out.simulatedSystems = simulation.systems.rows();
  out.fractions = lensingFractions(simulation.systems, s.fractionCuts);
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
  tables.push_back(binningTable(r.binning, r.gridSamples));
  return tables;
}

std::vector<std::string> calibrationPlotTypes() {
  return {"ARCNESS",    "ANTIARCNESS",      "SKEW_MAJOR",      "SKEW_MINOR",      "E_IMAGE",
          "SNR_ISO",    "LENSING_FRACTION", "NOISE_THRESHOLD", "THRESHOLD_COUNT", "SNR_FLOOR",
          "COLOUR_CUT", "COLOUR_DIFF",      "GRID_BINNING"};
}

namespace {

// A value with its 1-sigma error bar.
void addWithErrorBar(PlotSeries& s, double y, double sigma) {
  s.y.push_back(y);
  s.yLow.push_back(y - sigma);
  s.yHigh.push_back(y + sigma);
}

// One check-plot per study (calibrationPlot dispatches on CHECKPLOT_TYPE).
Plot distributionPlot(const Distribution& d) {
  Plot p;
  p.title = d.name + " (" + d.selection + ")";
  p.xLabel = d.name == "SNR_ISO"       ? "log#d10#u S/N (ISO)"
             : d.name == "COLOUR_DIFF" ? d.column + " [mag]"
                                       : d.name;
  p.yLabel = "fraction per bin";
  p.series.push_back(
      steps("simulated arcs (" + std::to_string(d.simulated.values) + ")", d.simulated));
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
  p.title = "Lensing fraction (" + std::to_string(r.fractions.arcSystems) + " systems with an arc)";
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
      addWithErrorBar(s, row.fraction, row.fractionSigma);
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
    addWithErrorBar(s, row.fraction, row.fractionSigma);
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
            " at their highest S/N, " + std::to_string(r.snrFloor->systems.size()) + " arcs";
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
  p.title = "Colour cut in " + c.band + ": arcs kept (" + std::to_string(c.arcs) + " arcs, " +
            std::to_string(c.withColours) + " with both colours)";
  p.xLabel = "MAX of COLOUR_CUT " + c.band + ",MAX [mag]";
  p.yLabel = "fraction of simulated arcs kept";
  PlotSeries s;
  s.label = "ARC_COLOUR_" + c.band + " - LENS_COLOUR_" + c.band + " <= MAX, or no colour";
  for (const ColourCutRow& row : c.rows) {
    s.x.push_back(row.maxMag);
    addWithErrorBar(s, row.fraction, row.fractionSigma);
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
  Plot p;
  p.title = "Occupation grid: binning search at P = " + formatNumber(r.binning.options.level);
  p.xLabel = "bins per axis";
  p.yLabel = "selected bins without a selected neighbour";
  PlotSeries s;
  s.label = "isolated selected bins";
  for (const BinningTrial& t : r.binning.trials) {
    s.x.push_back(t.binsPerAxis);
    s.y.push_back(double(t.connectivity.isolatedBins));
  }
  p.series.push_back(s);
  p.cuts.push_back({double(r.binning.finestConnected),
                    "finest connected: " + std::to_string(r.binning.finestConnected)});
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
  throw ConfigError("CHECKPLOT_TYPE " + quoteForMessage(type) + " is not a calibration plot");
}

}  // namespace octarc
