#include "octarc/simulation/engine/LensCatalog.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/core/Conventions.h"
#include "octarc/core/Parallel.h"
#include "octarc/io/FitsImage.h"
#include "octarc/selection/ArcContext.h"

namespace octarc {

namespace {

// The second band's values of one arc row (or of none) and of its lens.
struct BandRow {
  BandPair arc, lens;
};

// What one system leaves for the output tables.
struct SystemResult {
  LensSystemDraw draw;
  double magnification = 0.0;
  double sourceColourMag = 0.0, lensColourMag = 0.0;  // the second band's, drawn
  SecondBandMagnitudes band;                          // of the arc rows and the lens
  std::int64_t objectCount = 0;
  // Arc rows, measuredColumns() then arcContextColumns() each, in table order.
  std::vector<double> arcValues;
  std::vector<double> arcDistanceArcsec;
  int chosenArc = -1;  // index into the arc rows
  ImageF image;        // kept for the stamps file only
  StageTimings timings;
};

ColumnSpec column(const char* name, ColumnType type, const char* format, const char* unit,
                  const char* description) {
  ColumnSpec c;
  c.name = name;
  c.type = type;
  c.printfFormat = format;
  c.unit = unit;
  c.description = description;
  return c;
}

// A second band's measured column and how a row fills it: declared and filled in one place.
struct BandColumn {
  ColumnSpec spec;
  double (*value)(const BandRow&);
};

std::vector<BandColumn> bandColumns(const std::string& b) {
  using T = ColumnType;
  auto spec = [](const std::string& name, const std::string& description) {
    return column(name.c_str(), T::Float32, "%8.4f", "mag", description.c_str());
  };
  return {
      {spec("MAG_" + b, "Isophotal magnitude of the arc in " + b + " (its footprint)"),
       [](const BandRow& r) { return r.arc.band.mag; }},
      {spec("MAGERR_" + b, "RMS error of MAG_" + b),
       [](const BandRow& r) { return r.arc.band.magErr; }},
      {spec("LENS_MAG_" + b, "Isophotal magnitude of the lens in " + b + " (its footprint)"),
       [](const BandRow& r) { return r.lens.band.mag; }},
      {spec("LENS_MAGERR_" + b, "RMS error of LENS_MAG_" + b),
       [](const BandRow& r) { return r.lens.band.magErr; }},
      {spec("ARC_COLOUR_" + b, "Arc colour: " + b + " minus the measurement band"),
       [](const BandRow& r) { return colourOf(r.arc.band, r.arc.measurement).value; }},
      {spec("ARC_COLOURERR_" + b, "RMS error of ARC_COLOUR_" + b),
       [](const BandRow& r) { return colourOf(r.arc.band, r.arc.measurement).error; }},
      {spec("LENS_COLOUR_" + b, "Lens colour: " + b + " minus the measurement band"),
       [](const BandRow& r) { return colourOf(r.lens.band, r.lens.measurement).value; }},
      {spec("LENS_COLOURERR_" + b, "RMS error of LENS_COLOUR_" + b),
       [](const BandRow& r) { return colourOf(r.lens.band, r.lens.measurement).error; }},
  };
}

// A systems-table column before the chosen arc's and how a rendered system fills it: declared
// and filled in one place.
struct SystemColumn {
  ColumnSpec spec;
  double (*value)(const SystemResult&, const SourceDatabase&);
};

const std::vector<SystemColumn>& systemColumns() {
  using T = ColumnType;
  using R = const SystemResult&;
  using S = const SourceDatabase&;
  static const std::vector<SystemColumn> columns = {
      {column("SYSTEM", T::Int32, "%9d", "", "Index of the simulated system (seed stream)"),
       [](R r, S) { return double(r.draw.index); }},
      {column("Z_LENS", T::Float32, "%8.4f", "", "Lens redshift"),
       [](R r, S) { return r.draw.lens.redshift; }},
      {column("Z_SOURCE", T::Float32, "%8.4f", "", "Source redshift"),
       [](R r, S) { return r.draw.source.redshift; }},
      {column("SIGMA_V", T::Float32, "%8.2f", "km/s", "Lens velocity dispersion"),
       [](R r, S) { return r.draw.lens.sigmaKmPerS; }},
      {column("LENS_MAG", T::Float32, "%8.4f", "mag", "Lens apparent magnitude"),
       [](R r, S) { return r.draw.lens.mag; }},
      {column("LENS_ABSMAG", T::Float32, "%8.4f", "mag", "Lens absolute magnitude"),
       [](R r, S) { return r.draw.lens.absoluteMag; }},
      {column("LENS_ELLIPTICITY", T::Float32, "%8.4f", "", "Lens light ellipticity 1 - b/a"),
       [](R r, S) { return r.draw.lensEllipticity; }},
      {column("LENS_EPSILON", T::Float32, "%8.5f", "", "Potential ellipticity 0.2 e/(0.6 + e)"),
       [](R r, S) { return r.draw.system.mass.ellipticity; }},
      {column("LENS_THETA", T::Float32, "%8.3f", "deg", "Lens position angle (CCW from x)"),
       [](R r, S) { return r.draw.system.mass.positionAngleRad * kDegPerRad; }},
      {column("LENS_RHALF", T::Float32, "%8.4f", "arcsec", "Lens light half-light radius"),
       [](R r, S) { return r.draw.system.light.halfLightRadiusArcsec; }},
      {column("EINSTEIN_RADIUS", T::Float32, "%8.4f", "arcsec", "SIS Einstein radius"),
       [](R r, S) { return r.draw.einsteinRadiusArcsec; }},
      {column("SOURCE_MAG", T::Float32, "%8.4f", "mag", "Unlensed source magnitude"),
       [](R r, S) { return r.draw.source.mag; }},
      {column("SOURCE_RHALF", T::Float32, "%8.4f", "arcsec", "Source half-light radius"),
       [](R r, S) { return r.draw.source.halfLightArcsec; }},
      {column("SOURCE_X", T::Float32, "%9.5f", "arcsec", "Source position beta_x from the lens"),
       [](R r, S) { return r.draw.system.source.betaArcsec[0]; }},
      {column("SOURCE_Y", T::Float32, "%9.5f", "arcsec", "Source position beta_y from the lens"),
       [](R r, S) { return r.draw.system.source.betaArcsec[1]; }},
      {column("SOURCE_ROTATION", T::Float32, "%8.3f", "deg", "Source stamp rotation (CCW)"),
       [](R r, S) { return r.draw.system.source.rotationRad * kDegPerRad; }},
      {column("SOURCE_INDEX", T::Int32, "%6d", "", "Row of the source database"),
       [](R r, S) { return double(r.draw.sourceIndex); }},
      {column("SOURCE_TYPE", T::Int16, "%2d", "", "0 elliptical, 1 spiral, 2 irregular"),
       [](R r, S sources) { return double(int(sources.stamp(r.draw.sourceIndex).type)); }},
      {column("MAGNIFICATION", T::Float32, "%10.4f", "", "Traced source flux / unlensed flux"),
       [](R r, S) { return r.magnification; }},
      {column("N_OBJECTS", T::Int32, "%6d", "", "Objects detected over all levels"),
       [](R r, S) { return double(r.objectCount); }},
      {column("N_ARC_ROWS", T::Int32, "%4d", "", "Arc rows over all qualifying levels"),
       [](R r, S) { return double(r.arcDistanceArcsec.size()); }},
      {column("SIM_WEIGHT", T::Float64, "%12.6f", "",
              "Population systems this one stands for: 1 / render probability"),
       [](R r, S) { return r.draw.weight(); }},
      {column("ARC_FOUND", T::Int16, "%2d", "", "1 if an arc passed the arc rules"),
       [](R r, S) { return r.chosenArc >= 0 ? 1.0 : 0.0; }},
      {column("LENS_DISTANCE", T::Float32, "%8.4f", "arcsec",
              "Distance of the chosen arc to the lens centre"),
       [](R r, S) {
         return r.chosenArc >= 0 ? r.arcDistanceArcsec[std::size_t(r.chosenArc)] : std::nan("");
       }},
  };
  return columns;
}

// The injected colours of the systems table.
std::vector<ColumnSpec> bandTruthColumns(const std::string& band) {
  using T = ColumnType;
  const std::string source = "SOURCE_COLOUR_TRUE_" + band, lens = "LENS_COLOUR_TRUE_" + band;
  const std::string sourceText = "Injected source colour " + band + " minus the measurement band";
  const std::string lensText = "Injected lens colour " + band + " minus the measurement band";
  return {column(source.c_str(), T::Float32, "%8.4f", "mag", sourceText.c_str()),
          column(lens.c_str(), T::Float32, "%8.4f", "mag", lensText.c_str())};
}

// Writes the band columns of `row` from position `at` on.
void fillBandColumns(const std::vector<BandColumn>& columns, const BandRow& row, double* at) {
  for (const BandColumn& c : columns) *at++ = c.value(row);
}

}  // namespace

std::vector<ColumnSpec> secondBandColumns(const std::string& band) {
  std::vector<ColumnSpec> out;
  for (const BandColumn& c : bandColumns(band)) out.push_back(c.spec);
  return out;
}

std::vector<ColumnSpec> lensSystemColumns(const std::string& band) {
  std::vector<ColumnSpec> c;
  for (const SystemColumn& t : systemColumns()) c.push_back(t.spec);
  for (const ColumnSpec& m : measuredColumns()) c.push_back(m);
  for (const ColumnSpec& m : arcContextColumns()) c.push_back(m);
  if (!band.empty()) {
    for (const ColumnSpec& t : bandTruthColumns(band)) c.push_back(t);
    for (const ColumnSpec& m : secondBandColumns(band)) c.push_back(m);
  }
  return c;
}

std::vector<ColumnSpec> lensArcColumns(const std::string& band) {
  using T = ColumnType;
  std::vector<ColumnSpec> c = {
      column("SYSTEM", T::Int32, "%9d", "", "Index of the simulated system"),
      column("CHOSEN", T::Int16, "%2d", "", "1 for the system's chosen arc row"),
      column("LENS_DISTANCE", T::Float32, "%8.4f", "arcsec", "Distance to the lens centre"),
  };
  for (const ColumnSpec& m : measuredColumns()) c.push_back(m);
  for (const ColumnSpec& m : arcContextColumns()) c.push_back(m);
  if (!band.empty()) {
    for (const ColumnSpec& m : secondBandColumns(band)) c.push_back(m);
  }
  return c;
}

LensRun runLensSimulation(const SimulationSetup& setup, const SourceDatabase& sources,
                          std::uint64_t seed, std::int64_t count, int threads, int stampCount,
                          const ProgressFn& progress, std::int64_t firstIndex) {
  std::vector<SystemResult> results(static_cast<std::size_t>(count));
  parallelForDynamic(
      count, threads,
      [&](std::int64_t i) {
        SystemResult& r = results[std::size_t(i)];
        SimulatedSystem s =
            simulateSystem(setup, sources, seed, firstIndex + i, i < stampCount, &r.timings);
        r.draw = std::move(s.draw);
        r.magnification = s.magnification;
        r.sourceColourMag = s.sourceColourMag;
        r.lensColourMag = s.lensColourMag;
        r.band = std::move(s.band);
        r.objectCount = s.objects.rows();
        // The arcs' context among the stamp's objects, as the search sees a survey row's.
        const std::vector<ArcContext> context =
            s.arcs.arcRows.empty()
                ? std::vector<ArcContext>()
                : arcContexts(s.objects, {setup.observing.grid.pixelScaleArcsec});
        for (std::size_t a = 0; a < s.arcs.arcRows.size(); ++a) {
          const std::int64_t row = s.arcs.arcRows[a];
          const double* values = s.objects.row(row);
          r.arcValues.insert(r.arcValues.end(), values, values + s.objects.rowWidth());
          const std::vector<double> c = contextValues(context[std::size_t(row)]);
          r.arcValues.insert(r.arcValues.end(), c.begin(), c.end());
          r.arcDistanceArcsec.push_back(s.arcs.distanceArcsec[std::size_t(row)]);
          if (row == s.arcs.chosenRow) r.chosenArc = int(a);
        }
        r.image = std::move(s.image);
      },
      [&](std::int64_t done) {
        if (progress) progress(done, count);
      });

  // Tables, in system order.
  const int measuredWidth = measuredPlan().rowWidth() + int(arcContextColumns().size());
  const std::string bandName = setup.band ? setup.band->name : "";
  const std::vector<BandColumn> band =
      setup.band ? bandColumns(bandName) : std::vector<BandColumn>();
  LensRun out;
  out.systems = Table(lensSystemColumns(bandName));
  out.arcs = Table(lensArcColumns(bandName));
  out.drawn = count;
  for (const SystemResult& r : results) {
    out.redraws += r.draw.redraws;
    out.rejections += r.draw.rejections;
    if (r.draw.skipped) ++out.skipped;
    out.timings.add(r.timings);
    const LensSystemDraw& d = r.draw;
    if (!d.rendered) continue;  // counted, and stood for by the weights of the others
    ++out.rendered;
    double* row = out.systems.appendRow();
    const double nan = std::nan("");
    const std::vector<SystemColumn>& truth = systemColumns();
    const int truthCount = int(truth.size());
    for (int k = 0; k < truthCount; ++k) row[k] = truth[std::size_t(k)].value(r, sources);
    if (r.chosenArc >= 0) {
      ++out.systemsWithArc;
      std::copy_n(r.arcValues.data() + std::size_t(r.chosenArc) * std::size_t(measuredWidth),
                  measuredWidth, row + truthCount);
    } else {
      std::fill_n(row + truthCount, measuredWidth, nan);
    }
    // The second band's row of arc row `a`; without an arc (-1), the lens at level 1 alone.
    auto bandRow = [&r](int a) {
      if (a < 0) return BandRow{BandPair(), r.band.levelOneLens};
      return BandRow{r.band.arcs[std::size_t(a)], r.band.lenses[std::size_t(a)]};
    };
    if (setup.band) {
      double* at = row + truthCount + measuredWidth;
      *at++ = r.sourceColourMag;
      *at++ = r.lensColourMag;
      fillBandColumns(band, bandRow(r.chosenArc), at);
    }
    for (std::size_t a = 0; a < r.arcDistanceArcsec.size(); ++a) {
      double* arcRow = out.arcs.appendRow();
      arcRow[0] = double(d.index);
      arcRow[1] = int(a) == r.chosenArc ? 1.0 : 0.0;
      arcRow[2] = r.arcDistanceArcsec[a];
      std::copy_n(r.arcValues.data() + a * std::size_t(measuredWidth), measuredWidth, arcRow + 3);
      if (setup.band) fillBandColumns(band, bandRow(int(a)), arcRow + 3 + measuredWidth);
    }
  }

  for (int k = 0; k < stampCount; ++k)
    out.stamps.push_back(std::move(results[std::size_t(k)].image));
  out.sumWeights();
  return out;
}

void LensRun::sumWeights() {
  const int weight = systems.requireColumn("SIM_WEIGHT", "lens run");
  const int found = systems.requireColumn("ARC_FOUND", "lens run");
  weightSum = arcWeightSum = arcWeightSquaredSum = 0;
  for (std::int64_t r = 0; r < systems.rows(); ++r) {
    const double w = systems.value(r, weight);
    weightSum += w;
    if (systems.value(r, found) == 1.0) {
      arcWeightSum += w;
      arcWeightSquaredSum += w * w;
    }
  }
}

double LensRun::effectiveArcs() const {
  return arcWeightSquaredSum > 0 ? arcWeightSum * arcWeightSum / arcWeightSquaredSum : 0.0;
}

std::vector<std::string> lensRunCards(const LensRun& run, const SimulationSetup& setup,
                                      const SourceDatabase& sources, std::uint64_t seed) {
  const simulation::ObservingSetup& obs = setup.observing;
  const simulation::PopulationModel& pop = setup.population;
  auto real = [](double v) { return RealValue(v, RealFormat::RoundTrip); };
  // A setup made by hand may give its levels in ADU only.
  const double loSigma = setup.thresholdsSigma.empty()
                             ? setup.thresholdsAdu.front() / obs.skySigmaAdu
                             : setup.thresholdsSigma.front();
  const double hiSigma = setup.thresholdsSigma.empty()
                             ? setup.thresholdsAdu.back() / obs.skySigmaAdu
                             : setup.thresholdsSigma.back();
  std::vector<std::string> cards = {
      formatCard("OCTSEED", std::int64_t(seed), "Master seed of the simulation"),
      formatCard("OCTNSYS", run.drawn, "Systems drawn from the population"),
      formatCard("OCTNREND", run.rendered, "Systems rendered (the rows)"),
      formatCard("OCTSUMW", real(run.weightSum), "Sum of SIM_WEIGHT (estimates rendered+not)"),
      formatCard("OCTNARC", run.systemsWithArc, "Rendered systems with an arc"),
      formatCard("OCTNEFF", real(run.effectiveArcs()), "Effective arcs (Kish)"),
      formatCard("OCTSAMPL",
                 std::string(setup.sampling == Sampling::Importance ? "IMPORTANCE" : "PLAIN"),
                 "Sampling of the rendered systems"),
      formatCard("OCTPIXSC", RealValue(obs.grid.pixelScaleArcsec, RealFormat::Fixed),
                 "Pixel scale (arcsec)"),
      formatCard("OCTSEEIN", RealValue(obs.seeingFwhmArcsec, RealFormat::Fixed),
                 "PSF FWHM (arcsec)"),
      formatCard("OCTSKYSG", RealValue(obs.skySigmaAdu, RealFormat::RoundTrip),
                 "Sky noise sigma (ADU)"),
      formatCard("OCTGAIN", RealValue(obs.gainElectronsPerAdu), "Gain (e-/ADU)"),
      formatCard("OCTMAGZP", RealValue(obs.magZeroPoint, RealFormat::Fixed), "Zero point"),
      formatCard("OCTNLEV", std::int64_t(setup.thresholdsAdu.size()), "Detection levels"),
      formatCard("OCTTHLO", RealValue(setup.thresholdsAdu.front(), RealFormat::RoundTrip),
                 "Lowest level (ADU)"),
      formatCard("OCTTHHI", RealValue(setup.thresholdsAdu.back(), RealFormat::RoundTrip),
                 "Highest level (ADU)"),
      formatCard("OCTSGLO", RealValue(loSigma, RealFormat::RoundTrip), "Lowest level (sky sigma)"),
      formatCard("OCTSGHI", RealValue(hiSigma, RealFormat::RoundTrip), "Highest level (sky sigma)"),
      formatCard("OCTMINAR", std::int64_t(setup.minAreaPix), "DETECT_MINAREA"),
      formatCard("OCTSRCDB", sources.description().substr(0, 60), "Source database"),
      formatCard("OCTREDRW", run.redraws, "Lens-source pairs redrawn (no source redshift)"),
      formatCard("OCTREJCT", run.rejections, "Draws rejected (lens mag window, cross-section)"),
      formatCard("OCTNSKIP", run.skipped, "Systems skipped (theta_E below OCTSKIPT)"),
      formatCard("OCTSKIPT", RealValue(setup.population.skipEinsteinRadiusBelowArcsec),
                 "Skip limit on theta_E (arcsec)"),
      formatCard("OCTPOPUL", setup.population.name.substr(0, 60), "Population file"),
      // What a later run needs to remake these systems (calibrate's studies).
      formatCard("OCTPRSET", setup.populationPreset, "Population preset ('': own file)"),
      formatCard("OCTLMMIN", real(pop.lensMagMin), "Lens magnitude window"),
      formatCard("OCTLMMAX", real(pop.lensMagMax), "Lens magnitude window"),
      formatCard("OCTSMMIN", real(pop.sourceMagnitude.magMin), "Source magnitude window"),
      formatCard("OCTSMMAX", real(pop.sourceMagnitude.magMax), "Source magnitude window"),
      formatCard("OCTSVMIN", real(pop.sigmaMinKmPerS), "sigma_v window (km/s)"),
      formatCard("OCTSVMAX", real(pop.sigmaMaxKmPerS), "sigma_v window (km/s)"),
      formatCard("OCTLEMAX", real(setup.lensEllipticityMax), "Lens light ellipticity maximum"),
      formatCard("OCTLRHLO", real(setup.lensHalfLightMinArcsec), "Lens half-light radius min"),
      formatCard("OCTLRHHI", real(setup.lensHalfLightMaxArcsec), "Lens half-light radius max"),
      formatCard("OCTSTAMP", std::int64_t(obs.grid.width), "Stamp size (pixels)"),
      formatCard("OCTFINE", real(obs.rayTrace.fineScaleArcsec), "Ray-tracing step (arcsec)"),
      formatCard("OCTSUBS", std::int64_t(obs.rayTrace.subSamples), "Rays per fine pixel per axis"),
      formatCard("OCTSSTEP", real(obs.rayTrace.maxSourceStepPixels),
                 "Adaptive rays: source-plane step (px; 0: off)"),
      formatCard("OCTSRCEX", real(sources.syntheticExtentHalfLightRadii()),
                 "Synthetic source extent (r_half; 0: catalog)"),
      formatCard("OCTFILTR", setup.filter.has_value(), "Detection filtered (FILTER Y)"),
  };
  if (setup.sampling == Sampling::Importance) {
    const ImportanceSampling& is = setup.importance;
    cards.push_back(formatCard("OCTISSCL", real(is.scale), "Render probability scale"));
    cards.push_back(formatCard("OCTISFLR", real(is.floor), "Render probability floor"));
    for (int k = 0; k < 5; ++k) {
      cards.push_back(formatCard("OCTISC" + std::to_string(k), real(is.coefficients[k]),
                                 "Arc logit coefficient (LensSimulation.h)"));
    }
  }
  if (setup.band) {
    const SecondBand& band = *setup.band;
    cards.push_back(formatCard("OCTBAND", band.name, "Second band (colours: it minus this one)"));
    cards.push_back(formatCard("OCTSCOLM", real(band.source.meanMag), "Source colour mean (mag)"));
    cards.push_back(
        formatCard("OCTSCOLS", real(band.source.scatterMag), "Source colour scatter (mag)"));
    cards.push_back(formatCard("OCTLCOLM", real(band.lens.meanMag), "Lens colour mean (mag)"));
    cards.push_back(
        formatCard("OCTLCOLS", real(band.lens.scatterMag), "Lens colour scatter (mag)"));
  }
  return cards;
}

void writeLensCatalog(const std::string& path, const LensRun& run,
                      const std::vector<std::string>& cards) {
  writeLdacTables(path, cards, {{"LDAC_OBJECTS", &run.systems}, {"ARCS", &run.arcs}});
}

void writeLensStamps(const std::string& path, const LensRun& run, double pixelScaleArcsec) {
  std::vector<const ImageF*> planes;
  for (const ImageF& stamp : run.stamps) planes.push_back(&stamp);
  FitsHeader header;
  char scale[32];
  std::snprintf(scale, sizeof scale, "%.6f", pixelScaleArcsec);
  header.set("PIXSCALE", scale, "arcsec/pixel");
  header.set("BUNIT", quoteFitsString("ADU"), "background-subtracted counts");
  header.set("COMMENT", "Plane k (1-based) is simulated system k - 1 of the catalog.");
  writeImageCube(path, planes, header);
}

std::string lensRunSummary(const LensRun& run, const SimulationSetup& setup,
                           const LensRunContext& context) {
  const StageTimings& total = run.timings;
  const double n = double(std::max<std::int64_t>(run.rendered, 1));
  const double cpuSec = total.totalSec();
  // The output path goes in whole, whatever its length; the numbers fit the buffer.
  char head[256];
  std::snprintf(head, sizeof head,
                "> %lld systems drawn (%s sampling), %lld skipped (theta_E < %g\"), %lld rendered, "
                "sum of weights %.1f -> ",
                static_cast<long long>(run.drawn), context.samplingName.c_str(),
                static_cast<long long>(run.skipped), setup.population.skipEinsteinRadiusBelowArcsec,
                static_cast<long long>(run.rendered), run.weightSum);
  char tail[1024];
  std::snprintf(
      tail, sizeof tail,
      "\n> %lld rendered with an arc, %.1f effective arcs (Kish), %lld arc rows\n"
      "> %lld lens-source pairs redrawn (the relations gave no source redshift)\n"
      "> wall %.1f s on %d rank(s) of %d thread(s); CPU %.1f s, %.2f effective arcs per "
      "CPU second; per rendered system: draw %.3f, ray trace %.3f, lens light %.3f, PSF %.3f, "
      "noise %.3f, detection and measurement %.3f, arc rules %.3f ms\n",
      static_cast<long long>(run.systemsWithArc), run.effectiveArcs(),
      static_cast<long long>(run.arcs.rows()), static_cast<long long>(run.redraws), context.wallSec,
      context.ranks, context.threads, cpuSec, cpuSec > 0 ? run.effectiveArcs() / cpuSec : 0.0,
      1e3 * total.drawSec / n, 1e3 * total.rayTraceSec / n, 1e3 * total.lensLightSec / n,
      1e3 * total.psfSec / n, 1e3 * total.noiseSec / n, 1e3 * total.detectionSec / n,
      1e3 * total.arcRulesSec / n);
  return std::string(head) + context.outputPath + tail;
}

}  // namespace octarc
