#include "octarc/lenslight/LensSubtraction.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Parallel.h"
#include "octarc/lenslight/SersicModel.h"
#include "octarc/selection/ColumnExpression.h"

namespace octarc::lenslight {

SubtractionMode parseSubtractionMode(const std::string& word) {
  const std::string w = uppercase(word);
  if (w == "N") return SubtractionMode::Off;
  if (w == "LOCAL") return SubtractionMode::Local;
  if (w == "IMAGE") return SubtractionMode::Image;
  throw ConfigError("LENS_LIGHT: expected N, LOCAL or IMAGE, got " + quoteForMessage(word));
}

double FittedGalaxy::fittedXPix() const {
  return toFitsPixel(double(x0) + fit.params.xPix);
}
double FittedGalaxy::fittedYPix() const {
  return toFitsPixel(double(y0) + fit.params.yPix);
}

std::int64_t Subtraction::subtractedCount() const {
  return std::count_if(galaxies.begin(), galaxies.end(),
                       [](const FittedGalaxy& g) { return g.subtracted(); });
}

namespace {

// The galaxy in its cut-out: pixels, variances, and the fit with its outliers clipped.
void fitGalaxy(FittedGalaxy& g, const ImageF& pixels, const ImageF& varianceAdu2, double sigmaAdu,
               const LensLightSettings& settings) {
  ImageD stamp(g.width, g.height, 0.0), variance(g.width, g.height, 0.0);
  for (std::int64_t y = 0; y < g.height; ++y) {
    for (std::int64_t x = 0; x < g.width; ++x) {
      stamp(x, y) = pixels(g.x0 + x, g.y0 + y);
      // A non-finite or non-positive variance (a rejected weight) leaves the pixel out.
      variance(x, y) =
          varianceAdu2.empty() ? sigmaAdu * sigmaAdu : double(varianceAdu2(g.x0 + x, g.y0 + y));
    }
  }
  // The start from the stamp's moments, centred on the catalog's centroid: a neighbour in the
  // cut-out pulls the moments, not the object's own position.
  SersicParams start = momentsStart(stamp);
  start.xPix = fromFitsPixel(g.xPix) - double(g.x0);
  start.yPix = fromFitsPixel(g.yPix) - double(g.y0);
  LensLightModel model = fitLensLightFrom(stamp, variance, start, settings);
  g.fit = std::move(model.fit);
  if (g.fit.message == kTooFewPixelsMessage) {
    g.failure |= kFitTooFewPixels;
  } else if (!g.fit.converged) {
    g.failure |= kFitNotConverged;
  }
  const SersicParams& p = g.fit.params;
  const double side = double(std::max(g.width, g.height));
  if (!(p.xPix >= 0 && p.xPix <= double(g.width - 1) && p.yPix >= 0 &&
        p.yPix <= double(g.height - 1) && p.halfLightRadiusPix < 0.499 * side &&
        !g.fit.radiusAtLimit && std::isfinite(p.totalFluxAdu) && p.totalFluxAdu > 0)) {
    g.failure |= kFitOutsideCutout;
  }
}

// The catalog columns the choice of galaxies reads besides the expression's; ConfigError when
// one is missing.
struct ChoiceColumns {
  int x, y, level, number;
  explicit ChoiceColumns(const Table& catalog)
      : x(catalog.requireColumn("X_IMAGE", "LENS_SELECT")),
        y(catalog.requireColumn("Y_IMAGE", "LENS_SELECT")),
        level(catalog.requireColumn("THRESH_LEVEL", "LENS_SELECT")),
        number(catalog.requireColumn("NUMBER", "LENS_SELECT")) {}
};

}  // namespace

void checkLensSelectColumns(const Table& catalog, const std::string& selectExpression) {
  [[maybe_unused]] const ChoiceColumns columns(catalog);  // throws when one is missing
  ColumnExpression(selectExpression, "LENS_SELECT").evaluate(catalog);
}

Subtraction subtractLensLight(const ImageF& pixels, const ImageF& varianceAdu2, double sigmaAdu,
                              const Table& catalog, const SubtractionSettings& settings,
                              const ProgressFn& progress) {
  if (!(settings.pixelScaleArcsec > 0)) {
    throw ConfigError("lens light: the pixel scale must be positive");
  }
  if (!(settings.cutoutArcsec > 0)) throw ConfigError("LENS_CUTOUT: must be positive");
  if (!(sigmaAdu > 0) && varianceAdu2.empty()) {
    throw ConfigError("lens light: the image's noise must be known (sigma > 0 or a weight map)");
  }
  const ChoiceColumns columns(catalog);
  const std::vector<double> chosen =
      ColumnExpression(settings.selectExpression, "LENS_SELECT").evaluate(catalog);

  Subtraction out;
  const std::int64_t width = pixels.width(), height = pixels.height();
  const std::int64_t halfPix = std::max<std::int64_t>(
      4, std::int64_t(std::ceil(0.5 * settings.cutoutArcsec / settings.pixelScaleArcsec)));
  for (std::int64_t r = 0; r < catalog.rows(); ++r) {
    if (catalog.value(r, columns.level) != 1.0 || !(chosen[std::size_t(r)] != 0.0)) continue;
    FittedGalaxy g;
    g.row = std::size_t(r);
    g.number = std::int32_t(catalog.value(r, columns.number));
    g.xPix = catalog.value(r, columns.x);
    g.yPix = catalog.value(r, columns.y);
    if (!std::isfinite(g.xPix) || !std::isfinite(g.yPix)) continue;
    const std::int64_t xc = std::llround(fromFitsPixel(g.xPix));
    const std::int64_t yc = std::llround(fromFitsPixel(g.yPix));
    g.x0 = std::clamp<std::int64_t>(xc - halfPix, 0, width - 1);
    g.y0 = std::clamp<std::int64_t>(yc - halfPix, 0, height - 1);
    g.width = std::min(xc + halfPix, width - 1) - g.x0 + 1;
    g.height = std::min(yc + halfPix, height - 1) - g.y0 + 1;
    if (g.width < 2 || g.height < 2) continue;
    out.galaxies.push_back(g);
  }

  LensLightSettings fit = settings.fit;
  fit.fit.psfSigmaPix =
      settings.seeingFwhmArcsec > 0
          ? settings.seeingFwhmArcsec / settings.pixelScaleArcsec / kGaussianFwhmPerSigma
          : 0.0;
  const std::int64_t n = std::int64_t(out.galaxies.size());
  parallelForDynamic(
      n, resolveThreads(settings.threads),
      [&](std::int64_t i) {
        fitGalaxy(out.galaxies[std::size_t(i)], pixels, varianceAdu2, sigmaAdu, fit);
      },
      [&](std::int64_t done) {
        if (progress) progress(done, n);
      });

  // The models of the subtracted galaxies, each drawn over its cut-out, added in catalog order.
  out.model = ImageF(width, height, 0.0f);
  for (const FittedGalaxy& g : out.galaxies) {
    if (!g.subtracted()) continue;
    const ImageD m = renderSersic(g.fit.params, int(g.width), int(g.height), fit.fit.psfSigmaPix);
    for (std::int64_t y = 0; y < g.height; ++y) {
      for (std::int64_t x = 0; x < g.width; ++x) {
        out.model(g.x0 + x, g.y0 + y) += float(m(x, y));
      }
    }
  }
  out.residual = pixels;
  for (std::int64_t i = 0; i < out.residual.size(); ++i) out.residual[i] -= out.model[i];
  return out;
}

ResidualRows residualRowsNearLenses(const Table& residualCatalog, const Subtraction& subtraction,
                                    double radiusArcsec, double pixelScaleArcsec) {
  ResidualRows out;
  const int xColumn = residualCatalog.requireColumn("X_IMAGE", "lens light");
  const int yColumn = residualCatalog.requireColumn("Y_IMAGE", "lens light");
  const double maxPix = radiusArcsec / pixelScaleArcsec;
  const double minPix = kMinLensArcArcsec / pixelScaleArcsec;
  for (std::int64_t r = 0; r < residualCatalog.rows(); ++r) {
    const double x = residualCatalog.value(r, xColumn), y = residualCatalog.value(r, yColumn);
    double nearest = std::numeric_limits<double>::infinity();
    std::size_t nearestGalaxy = 0;
    for (std::size_t k = 0; k < subtraction.galaxies.size(); ++k) {
      const FittedGalaxy& g = subtraction.galaxies[k];
      if (!g.subtracted()) continue;
      const double d = std::hypot(x - g.fittedXPix(), y - g.fittedYPix());
      if (d < nearest) {
        nearest = d;
        nearestGalaxy = k;
      }
    }
    if (nearest >= minPix && nearest <= maxPix) {
      out.rows.push_back(r);
      out.galaxy.push_back(nearestGalaxy);
    }
  }
  return out;
}

}  // namespace octarc::lenslight
