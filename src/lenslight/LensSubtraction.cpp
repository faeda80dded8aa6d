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

std::int64_t Subtraction::fittedCount() const {
  return std::count_if(galaxies.begin(), galaxies.end(),
                       [](const FittedGalaxy& g) { return g.fitted(); });
}

namespace {

bool usable(double value, double variance) {
  return std::isfinite(value) && variance > 0.0 && std::isfinite(variance);
}

}  // namespace

std::vector<QuickResidualObject> quickResidual(const ImageD& stamp, const ImageD& varianceAdu2,
                                               double xPix, double yPix, double shapeRadiusPix,
                                               double minRadiusPix, double maxRadiusPix) {
  const std::int64_t w = stamp.width(), h = stamp.height();
  // The shape: second moments of the positive pixels in an ellipse of that shape and of the
  // area of a disc of shapeRadiusPix about the centre, a few times from a disc (the moments in
  // a disc make any galaxy rounder; in an ellipse of its own shape they give its shape).
  double q = 1.0, theta = 0.0;
  for (int round = 0; round < 4; ++round) {
    const double cr = std::cos(theta), sr = std::sin(theta);
    const double major2 = shapeRadiusPix * shapeRadiusPix / q,
                 minor2 = shapeRadiusPix * shapeRadiusPix * q;
    double sum = 0, xx = 0, yy = 0, xy = 0;
    for (std::int64_t y = 0; y < h; ++y) {
      for (std::int64_t x = 0; x < w; ++x) {
        const double v = stamp(x, y), dx = double(x) - xPix, dy = double(y) - yPix;
        const double a = cr * dx + sr * dy, b = -sr * dx + cr * dy;
        if (!(v > 0) || !usable(v, varianceAdu2(x, y)) || a * a / major2 + b * b / minor2 > 1.0) {
          continue;
        }
        sum += v;
        xx += v * dx * dx;
        yy += v * dy * dy;
        xy += v * dx * dy;
      }
    }
    if (!(sum > 0)) break;
    const double mean = 0.5 * (xx + yy) / sum, diff = 0.5 * (xx - yy) / sum;
    const double root = std::hypot(diff, xy / sum);
    q = std::clamp(std::sqrt(std::max(mean - root, 0.0) / (mean + root)), 0.3, 1.0);
    theta = 0.5 * std::atan2(2.0 * xy, xx - yy);
  }
  const double c = std::cos(theta), s = std::sin(theta);
  auto radius = [&](std::int64_t x, std::int64_t y) {
    const double dx = double(x) - xPix, dy = double(y) - yPix;
    const double major = c * dx + s * dy, minor = (-s * dx + c * dy) / q;
    return std::sqrt(major * major + minor * minor);
  };
  // The median of each annulus, at the mean radius of its pixels.
  std::vector<std::vector<double>> values;
  std::vector<double> radiusSum;
  for (std::int64_t y = 0; y < h; ++y) {
    for (std::int64_t x = 0; x < w; ++x) {
      if (!usable(stamp(x, y), varianceAdu2(x, y))) continue;
      const double r = radius(x, y);
      const auto k = std::size_t(r);
      if (k >= values.size()) {
        values.resize(k + 1);
        radiusSum.resize(k + 1, 0.0);
      }
      values[k].push_back(stamp(x, y));
      radiusSum[k] += r;
    }
  }
  std::vector<double> knotRadius, knotLevel;
  for (std::size_t k = 0; k < values.size(); ++k) {
    std::vector<double>& v = values[k];
    if (v.empty()) continue;
    const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    knotRadius.push_back(radiusSum[k] / double(v.size()));
    knotLevel.push_back(*mid);
  }
  if (knotRadius.empty()) return {};  // no usable pixel
  // Linear between the annuli (a step would leave each annulus's inner edge above the model
  // where the profile is steep, the edge of a piece at every radius).
  auto level = [&](double r) {
    const auto hi =
        std::size_t(std::lower_bound(knotRadius.begin(), knotRadius.end(), r) - knotRadius.begin());
    if (hi == 0) return knotLevel.front();
    if (hi == knotRadius.size()) return knotLevel.back();
    const double t = (r - knotRadius[hi - 1]) / (knotRadius[hi] - knotRadius[hi - 1]);
    return knotLevel[hi - 1] + t * (knotLevel[hi] - knotLevel[hi - 1]);
  };
  ImageD residual(w, h, 0.0);
  for (std::int64_t y = 0; y < h; ++y) {
    for (std::int64_t x = 0; x < w; ++x) {
      if (usable(stamp(x, y), varianceAdu2(x, y))) {
        residual(x, y) = stamp(x, y) - level(radius(x, y));
      }
    }
  }
  // Pixels above 3 sigma once smoothed on 3 x 3 (the clip of the fit, SersicFit.h), out to just
  // beyond the largest radius and not in the core: the annuli miss the cusp, and an arc near
  // the core would join that residual and take its centroid inside the smallest radius.
  const double reachPix = maxRadiusPix + 3.0, corePix = 0.8 * minRadiusPix;
  std::vector<std::uint8_t> above(std::size_t(w * h), 0);
  for (std::int64_t y = 0; y < h; ++y) {
    for (std::int64_t x = 0; x < w; ++x) {
      const double d = std::hypot(double(x) - xPix, double(y) - yPix);
      if (d > reachPix || d < corePix) continue;
      double r = 0, var = 0;
      for (std::int64_t v = std::max<std::int64_t>(y - 1, 0); v <= std::min(y + 1, h - 1); ++v) {
        for (std::int64_t u = std::max<std::int64_t>(x - 1, 0); u <= std::min(x + 1, w - 1); ++u) {
          if (!usable(stamp(u, v), varianceAdu2(u, v))) continue;
          r += residual(u, v);
          var += varianceAdu2(u, v);
        }
      }
      if (var > 0 && r > 3.0 * std::sqrt(var)) above[std::size_t(y * w + x)] = 1;
    }
  }
  std::vector<QuickResidualObject> out;
  std::vector<std::int64_t> stack;
  for (std::int64_t start = 0; start < w * h; ++start) {
    if (!above[std::size_t(start)]) continue;
    double flux = 0, var = 0, sx = 0, sy = 0, sxx = 0, syy = 0, positive = 0;
    above[std::size_t(start)] = 0;
    stack.assign(1, start);
    while (!stack.empty()) {
      const std::int64_t i = stack.back();
      stack.pop_back();
      const std::int64_t x = i % w, y = i / w;
      const double r = residual(x, y);
      flux += r;
      var += varianceAdu2(x, y);
      if (r > 0) {
        sx += r * double(x);
        sy += r * double(y);
        sxx += r * double(x) * double(x);
        syy += r * double(y) * double(y);
        positive += r;
      }
      for (std::int64_t v = std::max<std::int64_t>(y - 1, 0); v <= std::min(y + 1, h - 1); ++v) {
        for (std::int64_t u = std::max<std::int64_t>(x - 1, 0); u <= std::min(x + 1, w - 1); ++u) {
          const std::int64_t j = v * w + u;
          if (above[std::size_t(j)]) {
            above[std::size_t(j)] = 0;
            stack.push_back(j);
          }
        }
      }
    }
    if (!(positive > 0) || !(var > 0)) continue;
    QuickResidualObject o;
    o.xPix = sx / positive;
    o.yPix = sy / positive;
    const double d = std::hypot(o.xPix - xPix, o.yPix - yPix);
    if (d < minRadiusPix || d > maxRadiusPix) continue;
    o.fluxAdu = flux;
    o.snr = flux / std::sqrt(var);
    // Raw sums: a piece is a few hundred pixels at most, near the stamp's origin.
    o.sizePix = std::sqrt(
        std::max(sxx / positive - o.xPix * o.xPix + syy / positive - o.yPix * o.yPix, 0.0));
    out.push_back(o);
  }
  return out;
}

namespace {

// The catalog's rows as the pre-screen sees them: centroids (1-based) and isophotal fluxes.
struct SeparatedObjects {
  std::vector<double> x, y, flux;
  // A row within `radiusPix` of (xPix, yPix) (1-based) with at least half of `fluxAdu`: the
  // image already separates that light from the galaxy at some threshold.
  bool near(double xPix, double yPix, double fluxAdu, double radiusPix) const {
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (std::hypot(x[i] - xPix, y[i] - yPix) <= radiusPix && flux[i] >= 0.5 * fluxAdu) {
        return true;
      }
    }
    return false;
  }
};

struct Stamp {
  ImageD pixels, variance;
};

Stamp stampOf(const FittedGalaxy& g, const ImageF& pixels, const ImageF& varianceAdu2,
              double sigmaAdu) {
  Stamp out{ImageD(g.width, g.height, 0.0), ImageD(g.width, g.height, 0.0)};
  for (std::int64_t y = 0; y < g.height; ++y) {
    for (std::int64_t x = 0; x < g.width; ++x) {
      out.pixels(x, y) = pixels(g.x0 + x, g.y0 + y);
      // A non-finite or non-positive variance (a rejected weight) leaves the pixel out.
      out.variance(x, y) =
          varianceAdu2.empty() ? sigmaAdu * sigmaAdu : double(varianceAdu2(g.x0 + x, g.y0 + y));
    }
  }
  return out;
}

// The pre-screen (SubtractionSettings::prescreenMinSnr): false, with kFitSkipped set, when the
// quick residual holds nothing the search could use.
bool worthFitting(FittedGalaxy& g, const Stamp& stamp, const SeparatedObjects& separated,
                  const SubtractionSettings& settings) {
  if (!(settings.prescreenMinSnr > 0)) return true;
  const double pixPerArcsec = 1.0 / settings.pixelScaleArcsec;
  // An arc's centroid may sit a little inside 1" (kMinLensArcArcsec), its row's centroid
  // being measured at another threshold.
  const std::vector<QuickResidualObject> objects = quickResidual(
      stamp.pixels, stamp.variance, fromFitsPixel(g.xPix) - double(g.x0),
      fromFitsPixel(g.yPix) - double(g.y0), 2.0 * pixPerArcsec,
      0.75 * kMinLensArcArcsec * pixPerArcsec, settings.searchRadiusArcsec * pixPerArcsec);
  bool worth = false;
  for (const QuickResidualObject& o : objects) {
    // Neither too faint nor too small (a knot, a misfit of the annuli) for the search.
    if (o.snr < settings.prescreenMinSnr ||
        std::sqrt(2.0) * o.sizePix * settings.pixelScaleArcsec < settings.prescreenMinSizeArcsec) {
      continue;
    }
    if (separated.near(toFitsPixel(double(g.x0) + o.xPix), toFitsPixel(double(g.y0) + o.yPix),
                       o.fluxAdu, 0.5 * pixPerArcsec)) {
      continue;
    }
    if (!(o.snr <= g.quickResidualSnr)) g.quickResidualSnr = o.snr;  // NaN at first
    worth = true;
  }
  if (!worth) g.failure |= kFitSkipped;
  return worth;
}

// The fit of `stamp` from `start` within the fitted square (SubtractionSettings::
// fitHalfSideArcsec about the start, within the cut-out), its centre in cut-out pixels, and the
// flags it earns.
void fitInSquare(FittedGalaxy& g, const Stamp& cut, const SersicParams& start,
                 const SubtractionSettings& subtraction, const LensLightSettings& settings) {
  const ImageD& stamp = cut.pixels;
  const ImageD& variance = cut.variance;
  std::int64_t fx0 = 0, fy0 = 0, fw = g.width, fh = g.height;
  if (subtraction.fitHalfSideArcsec > 0) {
    const auto half =
        std::int64_t(std::ceil(subtraction.fitHalfSideArcsec / subtraction.pixelScaleArcsec));
    const std::int64_t xc = std::llround(start.xPix), yc = std::llround(start.yPix);
    fx0 = std::clamp<std::int64_t>(xc - half, 0, g.width - 1);
    fy0 = std::clamp<std::int64_t>(yc - half, 0, g.height - 1);
    fw = std::min(xc + half, g.width - 1) - fx0 + 1;
    fh = std::min(yc + half, g.height - 1) - fy0 + 1;
  }
  LensLightModel model;
  if (fw == g.width && fh == g.height) {
    model = fitLensLightFrom(stamp, variance, start, settings);
  } else {
    ImageD part(fw, fh, 0.0), partVariance(fw, fh, 0.0);
    for (std::int64_t y = 0; y < fh; ++y) {
      for (std::int64_t x = 0; x < fw; ++x) {
        part(x, y) = stamp(fx0 + x, fy0 + y);
        partVariance(x, y) = variance(fx0 + x, fy0 + y);
      }
    }
    SersicParams partStart = start;
    partStart.xPix -= double(fx0);
    partStart.yPix -= double(fy0);
    model = fitLensLightFrom(part, partVariance, partStart, settings);
    model.fit.params.xPix += double(fx0);
    model.fit.params.yPix += double(fy0);
  }
  g.fit = std::move(model.fit);
  if (g.fit.message == kTooFewPixelsMessage) {
    g.failure |= kFitTooFewPixels;
  } else if (!g.fit.converged) {
    g.failure |= kFitNotConverged;
  }
  if (g.fit.shapeAtBound) g.failure |= kFitAtBound;
  const SersicParams& p = g.fit.params;
  const double side = double(std::max(fw, fh));
  if (!(p.xPix >= double(fx0) && p.xPix <= double(fx0 + fw - 1) && p.yPix >= double(fy0) &&
        p.yPix <= double(fy0 + fh - 1) && p.halfLightRadiusPix < 0.499 * side &&
        !g.fit.radiusAtLimit && std::isfinite(p.totalFluxAdu) && p.totalFluxAdu > 0)) {
    g.failure |= kFitOutsideCutout;
  }
}

// The start from the stamp's moments, centred on the catalog's centroid: a neighbour in the
// cut-out pulls the moments, not the object's own position.
SersicParams startOf(const FittedGalaxy& g, const ImageD& stamp) {
  SersicParams start = momentsStart(stamp);
  start.xPix = fromFitsPixel(g.xPix) - double(g.x0);
  start.yPix = fromFitsPixel(g.yPix) - double(g.y0);
  return start;
}

// The band a galaxy is fitted in, when not the searched image (FitBandImage), with its fit
// settings (its own PSF) and the searched image's PSF, with which its model is drawn here.
struct OtherBand {
  const FitBandImage* image = nullptr;
  LensLightSettings fit;
  double searchedPsfSigmaPix = 0.0;
};

// The galaxy in its cut-out: pixels, variances, the pre-screen, and the fit with its outliers
// masked, in the searched image or in the other band's (then scaled to the searched image).
void fitGalaxy(FittedGalaxy& g, const ImageF& pixels, const ImageF& varianceAdu2, double sigmaAdu,
               const SeparatedObjects& separated, const SubtractionSettings& subtraction,
               const LensLightSettings& settings, const OtherBand& other) {
  const Stamp cut = stampOf(g, pixels, varianceAdu2, sigmaAdu);
  const SersicParams start = startOf(g, cut.pixels);
  if (!worthFitting(g, cut, separated, subtraction)) {
    g.fit.params = start;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    g.fit.errors = {nan, nan, nan, nan, nan, nan, nan};
    return;
  }
  if (other.image == nullptr) {
    fitInSquare(g, cut, start, subtraction, settings);
    return;
  }
  static const ImageF kNoVariance;
  const Stamp bandCut =
      stampOf(g, *other.image->pixels,
              other.image->varianceAdu2 != nullptr ? *other.image->varianceAdu2 : kNoVariance,
              other.image->sigmaAdu);
  fitInSquare(g, bandCut, startOf(g, bandCut.pixels), subtraction, other.fit);
  g.failure |= kFitOtherBand;
  if (!g.subtracted()) return;
  // The model as this image sees it (its PSF), at that band's flux; its amplitude here, in the
  // core, is the flux ratio.
  const ImageD seen =
      renderSersic(g.fit.params, int(g.width), int(g.height), other.searchedPsfSigmaPix);
  const double ratio = coreFluxRatio(
      cut.pixels, cut.variance, seen, g.fit.params.xPix, g.fit.params.yPix,
      std::max(kBandRatioCoreArcsec / subtraction.pixelScaleArcsec, kBandRatioCoreMinPix));
  if (!(std::isfinite(ratio) && ratio > 0)) {
    g.failure |= kFitNoBandRatio;
    return;
  }
  g.bandFluxRatio = ratio;
  g.fit.params.totalFluxAdu *= ratio;
  g.fit.errors.totalFluxAdu *= ratio;
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

double coreFluxRatio(const ImageD& stamp, const ImageD& varianceAdu2, const ImageD& model,
                     double xPix, double yPix, double radiusPix) {
  if (model.width() != stamp.width() || model.height() != stamp.height() ||
      varianceAdu2.width() != stamp.width() || varianceAdu2.height() != stamp.height()) {
    throw ConfigError("lens light: the core's stamp, variances and model differ in size");
  }
  double dataTimesModel = 0.0, modelSquared = 0.0;
  const std::int64_t x0 = std::max<std::int64_t>(0, std::int64_t(std::floor(xPix - radiusPix)));
  const std::int64_t x1 =
      std::min<std::int64_t>(stamp.width() - 1, std::int64_t(std::ceil(xPix + radiusPix)));
  const std::int64_t y0 = std::max<std::int64_t>(0, std::int64_t(std::floor(yPix - radiusPix)));
  const std::int64_t y1 =
      std::min<std::int64_t>(stamp.height() - 1, std::int64_t(std::ceil(yPix + radiusPix)));
  for (std::int64_t y = y0; y <= y1; ++y) {
    for (std::int64_t x = x0; x <= x1; ++x) {
      if (std::hypot(double(x) - xPix, double(y) - yPix) > radiusPix) continue;
      const double v = varianceAdu2(x, y), m = model(x, y);
      if (!usable(stamp(x, y), v) || !std::isfinite(m)) continue;
      dataTimesModel += stamp(x, y) * m / v;
      modelSquared += m * m / v;
    }
  }
  return modelSquared > 0 ? dataTimesModel / modelSquared
                          : std::numeric_limits<double>::quiet_NaN();
}

Subtraction subtractLensLight(const ImageF& pixels, const ImageF& varianceAdu2, double sigmaAdu,
                              const Table& catalog, const SubtractionSettings& settings,
                              const ProgressFn& progress, const FitBandImage* fitBand) {
  if (!(settings.pixelScaleArcsec > 0)) {
    throw ConfigError("lens light: the pixel scale must be positive");
  }
  if (!(settings.cutoutArcsec > 0)) throw ConfigError("LENS_CUTOUT: must be positive");
  if (!(sigmaAdu > 0) && varianceAdu2.empty()) {
    throw ConfigError("lens light: the image's noise must be known (sigma > 0 or a weight map)");
  }
  if (settings.prescreenMinSnr > 0 && !(settings.searchRadiusArcsec > 0)) {
    throw ConfigError("lens light: the pre-screen's search radius must be positive");
  }
  if (fitBand != nullptr) {
    const bool noVariance = fitBand->varianceAdu2 == nullptr || fitBand->varianceAdu2->empty();
    if (fitBand->pixels == nullptr || fitBand->pixels->width() != pixels.width() ||
        fitBand->pixels->height() != pixels.height() ||
        (!noVariance && (fitBand->varianceAdu2->width() != pixels.width() ||
                         fitBand->varianceAdu2->height() != pixels.height()))) {
      throw ConfigError("lens light: the fitted band's image is not the searched image's size");
    }
    if (!(fitBand->sigmaAdu > 0) && noVariance) {
      throw ConfigError("lens light: the fitted band's noise must be known (sigma > 0)");
    }
  }
  const ChoiceColumns columns(catalog);
  SeparatedObjects separated;
  const int fluxColumn = catalog.findColumn("FLUX_ISO");
  if (settings.prescreenMinSnr > 0 && fluxColumn >= 0) {
    for (std::int64_t r = 0; r < catalog.rows(); ++r) {
      separated.x.push_back(catalog.value(r, columns.x));
      separated.y.push_back(catalog.value(r, columns.y));
      separated.flux.push_back(catalog.value(r, fluxColumn));
    }
  }
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

  const auto psfSigmaPix = [&](double seeingFwhmArcsec) {
    return seeingFwhmArcsec > 0
               ? seeingFwhmArcsec / settings.pixelScaleArcsec / kGaussianFwhmPerSigma
               : 0.0;
  };
  LensLightSettings fit = settings.fit;
  fit.fit.psfSigmaPix = psfSigmaPix(settings.seeingFwhmArcsec);
  OtherBand other;
  if (fitBand != nullptr) {
    other.image = fitBand;
    other.fit = settings.fit;
    other.fit.fit.psfSigmaPix = psfSigmaPix(fitBand->seeingFwhmArcsec);
    other.searchedPsfSigmaPix = fit.fit.psfSigmaPix;
  }
  const std::int64_t n = std::int64_t(out.galaxies.size());
  parallelForDynamic(
      n, resolveThreads(settings.threads),
      [&](std::int64_t i) {
        fitGalaxy(out.galaxies[std::size_t(i)], pixels, varianceAdu2, sigmaAdu, separated, settings,
                  fit, other);
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
