#include "octarc/search/LensLightSearch.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/detection/Filter.h"
#include "octarc/run/ImageRun.h"
#include "octarc/run/Levels.h"
#include "octarc/sexcompat/ConvFile.h"

namespace octarc {

namespace {

// The residual made ready for detection like the run's image: the same noise, weights, gain and
// WCS; the filtered detection image is the run's minus the filtered model (the filter is linear),
// and a weight map's variance is filtered again when the run's thresholds followed it filtered.
PreparedImage residualImage(const PreparedImage& image, const lenslight::Subtraction& sub,
                            const RunSettings& rs) {
  PreparedImage out = image;
  out.hdu.pixels = sub.residual;
  if (!image.filtered.empty() || (!out.variance.empty() && rs.filter)) {
    const ConvKernel kernel = sexcompat::readConvFile(resolveFilterFile(rs.filterPath));
    if (!image.filtered.empty()) {
      const ImageF filteredModel = applyFilter(sub.model, kernel, rs.threads);
      for (std::int64_t i = 0; i < out.filtered.size(); ++i) out.filtered[i] -= filteredModel[i];
    }
    if (!out.variance.empty() && rs.filter && rs.detectThresholdType == ThresholdType::Relative) {
      ImageF capped = out.variance;
      for (float& v : capped.pixels()) v = std::min(v, 1e30f);
      out.variance = applyFilter(capped, kernel, rs.threads);
      out.varianceFiltered = true;
    }
  }
  return out;
}

struct ResidualCatalog {
  Table table;  // the output columns
  std::vector<std::int64_t> order;
  SegmentationRuns footprints;
};

ResidualCatalog detectResidual(PreparedImage& residual, const SearchRun& run,
                               const SearchRunSettings& settings, const ColumnPlan& columns,
                               const std::function<void()>& checkpoint) {
  const RunSettings& rs = settings.run;
  MeasureContext context = residual.context(rs);
  context.levels = run.levels;
  DetectionRequest request = configuredRequest(rs, run.levels);
  request.keepSegmentation = true;
  request.checkpoint = checkpoint;
  ImageRunResult result = detectAndMeasure(residual, columns.plan, context, request, &rs);
  Table full = std::move(result.rows);
  if (settings.assoc) {
    full = rowsInOrder(full, result.catalogOrder);
    result.catalogOrder.clear();
    applyAssoc(*settings.assoc, columns.assocVectorSize, residual, full, true, true);
  }
  return {outputTable(columns, std::move(full)), std::move(result.catalogOrder),
          std::move(*result.segmentation)};
}

// The highest NUMBER of each level (index level - 1) of a catalog.
std::vector<std::int32_t> highestNumbers(const Table& catalog, std::size_t levelCount) {
  std::vector<std::int32_t> out(levelCount, 0);
  const int level = catalog.requireColumn("THRESH_LEVEL", "lens light");
  const int number = catalog.requireColumn("NUMBER", "lens light");
  for (std::int64_t r = 0; r < catalog.rows(); ++r) {
    const auto k = std::size_t(catalog.value(r, level)) - 1;
    if (k < out.size()) out[k] = std::max(out[k], std::int32_t(catalog.value(r, number)));
  }
  return out;
}

// LOCAL: the residual's rows near a fitted galaxy appended to the run's catalog, their NUMBER
// and PARENT_NUMBER moved past the run's own so that the component trees stay apart (a parent
// left behind ends the walk up the tree, search/LevelMerge.h), their footprints added.
void appendResidualRows(SearchRun& run, ResidualCatalog& residual,
                        const lenslight::ResidualRows& near) {
  const std::vector<std::int32_t> base = highestNumbers(run.catalog, run.levels.size());
  const int level = run.catalog.requireColumn("THRESH_LEVEL", "lens light");
  const int number = run.catalog.requireColumn("NUMBER", "lens light");
  const int parent = run.catalog.requireColumn("PARENT_NUMBER", "lens light");
  std::map<int, std::vector<std::int32_t>> numbersByLevel;  // residual NUMBERs kept, per level
  std::vector<std::int64_t> newRows;
  for (std::size_t i = 0; i < near.rows.size(); ++i) {
    const std::int64_t r = near.rows[i];
    const int k = int(residual.table.value(r, level));
    const auto n = std::int32_t(residual.table.value(r, number));
    const auto p = std::int32_t(residual.table.value(r, parent));
    numbersByLevel[k].push_back(n);
    const std::int64_t at = run.catalog.rows();
    std::copy_n(residual.table.row(r), residual.table.rowWidth(), run.catalog.appendRowUnset());
    run.catalog.setValue(at, number, double(base[std::size_t(k - 1)] + n));
    if (k > 1 && p > 0) run.catalog.setValue(at, parent, double(base[std::size_t(k - 2)] + p));
    run.lensLightOf.push_back(std::int64_t(run.lensLight->galaxies[near.galaxy[i]].row));
    newRows.push_back(at);
  }
  // Their footprints, under the new numbers.
  if (run.footprints) {
    std::vector<Segment> segments;
    for (const auto& [k, numbers] : numbersByLevel) {
      const auto runs = residual.footprints.footprints(k, numbers);
      for (std::size_t j = 0; j < numbers.size(); ++j) {
        Segment s;
        s.level = k;
        s.number = base[std::size_t(k - 1)] + numbers[j];
        s.runs = runs[j];
        segments.push_back(std::move(s));
      }
    }
    run.footprints->add(segments);
  }
  if (!run.catalogOrder.empty()) {
    run.catalogOrder.insert(run.catalogOrder.end(), newRows.begin(), newRows.end());
  }
}

// IMAGE: the residual's catalog in place of the run's, each row near a fitted galaxy marked
// with it, and the fitted galaxies' own level-1 rows appended as lenses only, numbered past the
// residual's level-1 objects, with their footprints in the image (for their magnitudes in the
// colour bands).
void replaceByResidual(SearchRun& run, ResidualCatalog& residual,
                       const lenslight::ResidualRows& near) {
  Table original = std::move(run.catalog);
  std::optional<SegmentationRuns> originalFootprints = std::move(run.footprints);
  run.catalog = std::move(residual.table);
  run.catalogOrder = std::move(residual.order);
  run.footprints = std::move(residual.footprints);
  const std::int32_t base = highestNumbers(run.catalog, run.levels.size())[0];
  const int number = run.catalog.requireColumn("NUMBER", "lens light");
  const int parent = run.catalog.requireColumn("PARENT_NUMBER", "lens light");
  run.lensLightOf.assign(std::size_t(run.catalog.rows()), kNotLensLightRow);
  std::int32_t added = 0;
  std::vector<std::int64_t> lensRowOf(run.lensLight->galaxies.size(), -1);
  run.lensNumbers.assign(run.lensLight->galaxies.size(), 0);
  std::vector<std::int32_t> originalNumbers;
  std::vector<Segment> segments;
  for (std::size_t g = 0; g < run.lensLight->galaxies.size(); ++g) {
    lenslight::FittedGalaxy& galaxy = run.lensLight->galaxies[g];
    if (!galaxy.subtracted()) continue;
    const std::int64_t at = run.catalog.rows();
    std::copy_n(original.row(std::int64_t(galaxy.row)), original.rowWidth(),
                run.catalog.appendRowUnset());
    run.catalog.setValue(at, number, double(base + ++added));
    run.catalog.setValue(at, parent, 0.0);
    run.lensLightOf.push_back(kLensOnlyRow);
    if (!run.catalogOrder.empty()) run.catalogOrder.push_back(at);
    lensRowOf[g] = at;
    galaxy.row = std::size_t(at);  // the galaxy's row in the searched catalog from now on
    run.lensNumbers[g] = base + added;
    originalNumbers.push_back(galaxy.number);
    Segment segment;
    segment.level = 1;
    segment.number = base + added;
    segments.push_back(std::move(segment));
  }
  if (originalFootprints && run.footprints) {
    const auto runs = originalFootprints->footprints(1, originalNumbers);
    for (std::size_t j = 0; j < segments.size(); ++j) segments[j].runs = runs[j];
    run.footprints->add(segments);
  }
  for (std::size_t i = 0; i < near.rows.size(); ++i) {
    run.lensLightOf[std::size_t(near.rows[i])] = lensRowOf[near.galaxy[i]];
  }
}

}  // namespace

void applyLensLight(SearchRun& run, const SearchRunSettings& settings, const ColumnPlan& columns,
                    const RunLog& log, const PreparedImage* fitBand,
                    const std::function<void()>& checkpoint) {
  const lenslight::SubtractionMode mode = settings.lensLight.mode;
  if (mode == lenslight::SubtractionMode::Off) return;
  lenslight::SubtractionSettings ls = settings.lensLight;
  ls.pixelScaleArcsec = run.pixelScaleArcsec;
  ls.seeingFwhmArcsec = settings.run.seeingFwhmArcsec;
  ls.threads = settings.run.threads;
  // A residual object well below the S/N floor or unresolved will not make a candidate (the
  // margin: the residual's detection goes lower and catches more of it than the quick residual).
  ls.prescreenMinSnr = 0.5 * settings.search.snrMin;
  ls.prescreenMinSizeArcsec = 0.75 * settings.search.resolvedMinArcsec;
  ls.searchRadiusArcsec = settings.search.lensRadiusArcsec;
  ls.fitHalfSideArcsec = settings.search.lensRadiusArcsec + 1.0;
  std::optional<lenslight::FitBandImage> band;
  std::string inBand;
  if (fitBand != nullptr) {
    const auto k = std::size_t(settings.lensLightBand);
    band = lenslight::FitBandImage{&fitBand->hdu.pixels, &fitBand->variance, fitBand->sigmaAdu,
                                   settings.colourSeeingFwhmArcsec.at(k)};
    inBand = " in band " + settings.search.colourBands.at(k);
  }
  if (log) log("> Fitting lens galaxies" + inBand + " (LENS_SELECT " + ls.selectExpression + ")");
  // The caller's checkpoint between the galaxies' fits (called on this thread).
  const ProgressFn fitCheckpoint = [&checkpoint](std::int64_t, std::int64_t) {
    if (checkpoint) checkpoint();
  };
  run.lensLight =
      lenslight::subtractLensLight(run.image.hdu.pixels, run.image.variance, run.image.sigmaAdu,
                                   run.catalog, ls, fitCheckpoint, band ? &*band : nullptr);
  const lenslight::Subtraction& sub = *run.lensLight;
  if (log) {
    log("> " + std::to_string(sub.galaxies.size()) + " galaxies chosen, " +
        std::to_string(sub.fittedCount()) + " fitted, " + std::to_string(sub.subtractedCount()) +
        " subtracted; detecting the residual");
  }
  PreparedImage residual = residualImage(run.image, sub, settings.run);
  ResidualCatalog found = detectResidual(residual, run, settings, columns, checkpoint);
  const lenslight::ResidualRows near = lenslight::residualRowsNearLenses(
      found.table, sub, settings.search.lensRadiusArcsec, run.pixelScaleArcsec);
  run.lensLightRows = std::int64_t(near.rows.size());
  if (mode == lenslight::SubtractionMode::Local) {
    run.lensLightOf.assign(std::size_t(run.catalog.rows()), kNotLensLightRow);
    run.lensNumbers.clear();
    for (const lenslight::FittedGalaxy& g : sub.galaxies) run.lensNumbers.push_back(g.number);
    appendResidualRows(run, found, near);
  } else {
    replaceByResidual(run, found, near);
  }
}

FitsTable lensFitTable(const SearchRun& run) {
  FitsTable t;
  t.name = "LENSFIT";
  if (!run.lensLight) return t;
  const auto& galaxies = run.lensLight->galaxies;
  auto column = [&](const char* name, const char* unit, const char* comment, auto value) {
    std::vector<double> v;
    for (const lenslight::FittedGalaxy& g : galaxies) v.push_back(value(g));
    FitsColumn c;
    c.name = name;
    c.unit = unit;
    c.comment = comment;
    c.values = std::move(v);
    t.columns.push_back(std::move(c));
  };
  auto integer = [&](const char* name, const char* comment, auto value) {
    std::vector<std::int32_t> v;
    for (const lenslight::FittedGalaxy& g : galaxies) v.push_back(std::int32_t(value(g)));
    FitsColumn c;
    c.name = name;
    c.comment = comment;
    c.values = std::move(v);
    t.columns.push_back(std::move(c));
  };
  using G = lenslight::FittedGalaxy;
  constexpr double kDeg = 180.0 / std::numbers::pi;
  integer("NUMBER", "NUMBER of the galaxy at level 1 of the image's detection",
          [](const G& g) { return g.number; });
  integer("LENS_NUMBER", "its NUMBER as a lens in the searched catalog (0: not in it)",
          [&](const G& g) {
            const auto k = std::size_t(&g - galaxies.data());
            return k < run.lensNumbers.size() ? run.lensNumbers[k] : 0;
          });
  column("X_IMAGE", "pixel", "catalog centroid x", [](const G& g) { return g.xPix; });
  column("Y_IMAGE", "pixel", "catalog centroid y", [](const G& g) { return g.yPix; });
  column("SERSIC_X", "pixel", "fitted centre x", [](const G& g) { return g.fittedXPix(); });
  column("SERSIC_Y", "pixel", "fitted centre y", [](const G& g) { return g.fittedYPix(); });
  column("SERSIC_FLUX", "count", "total flux of the profile",
         [](const G& g) { return g.fit.params.totalFluxAdu; });
  column("SERSIC_FLUXERR", "count", "its 1-sigma error",
         [](const G& g) { return g.fit.errors.totalFluxAdu; });
  column("SERSIC_RE", "pixel", "half-light radius along the major axis",
         [](const G& g) { return g.fit.params.halfLightRadiusPix; });
  column("SERSIC_REERR", "pixel", "its 1-sigma error",
         [](const G& g) { return g.fit.errors.halfLightRadiusPix; });
  column("SERSIC_N", "", "Sersic index", [](const G& g) { return g.fit.params.sersicIndex; });
  column("SERSIC_NERR", "", "its 1-sigma error",
         [](const G& g) { return g.fit.errors.sersicIndex; });
  column("SERSIC_Q", "", "axis ratio b/a", [](const G& g) { return g.fit.params.axisRatio; });
  column("SERSIC_THETA", "deg", "major axis from +x, counter-clockwise",
         [&](const G& g) { return g.fit.params.positionAngleRad * kDeg; });
  column("SERSIC_CHI2NU", "", "chi^2 per degree of freedom", [](const G& g) {
    return g.fit.degreesOfFreedom > 0 ? g.fit.chi2 / double(g.fit.degreesOfFreedom) : NAN;
  });
  integer("SERSIC_ITER", "solver iterations", [](const G& g) { return g.fit.iterations; });
  column("QUICK_SNR", "", "S/N of the pre-screen's residual object (NaN: none)",
         [](const G& g) { return g.quickResidualSnr; });
  // The comments fit their TTYPE card (47 characters).
  column("BAND_RATIO", "", "flux ratio to LENS_LIGHT_BAND in the core",
         [](const G& g) { return g.bandFluxRatio; });
  integer("LENSFIT_FLAGS", "1,2,4,16,64: left in; 8 bound, 32 other band",
          [](const G& g) { return g.failure; });
  return t;
}

}  // namespace octarc
