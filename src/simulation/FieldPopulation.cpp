#include "octarc/simulation/FieldPopulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/RayTracer.h"
#include "octarc/simulation/SyntheticGalaxy.h"

namespace octarc::simulation {

namespace {

// Largest stamp half-width in pixels: keeps one pathological draw from costing the whole run.
constexpr std::int64_t kMaxStampHalfWidthPix = 600;
// Spirals and irregulars are made at pixelScale / kSubPixels and summed in blocks.
constexpr int kSubPixels = 3;

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

GalaxyType drawType(const FieldPopulationParams& p, double mag, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double fE = mag < p.brightMag ? p.ellipticalFractionBright : p.ellipticalFractionFaint;
  if (u(rng) < fE) return GalaxyType::Elliptical;
  if (mag >= p.brightMag && u(rng) < p.irregularFractionFaint) return GalaxyType::Irregular;
  return GalaxyType::Spiral;
}

// A FITS real value with a decimal point (wcslib and fitsverify want reals written as reals).
// Pixel-integrated 1-D Gaussian of sigmaPix centred at `centre` (0-based), for pixels
// first .. first + n - 1.
std::vector<double> integratedGaussian(double centre, double sigmaPix, std::int64_t first,
                                       std::int64_t n) {
  std::vector<double> g(static_cast<std::size_t>(n));
  const double k = 1.0 / (sigmaPix * std::sqrt(2.0));
  for (std::int64_t i = 0; i < n; ++i) {
    const double d = double(first + i) - centre;
    g[std::size_t(i)] = 0.5 * (std::erf((d + 0.5) * k) - std::erf((d - 0.5) * k));
  }
  return g;
}

}  // namespace

double NumberCounts::expectedCount(double areaDeg2) const {
  const double k = slopePerMag * std::log(10.0);
  const double integral =
      std::abs(k) < 1e-12 ? (magMax - magMin)
                          : (std::exp(k * (magMax - magRef)) - std::exp(k * (magMin - magRef))) / k;
  return areaDeg2 * densityAtRefPerDeg2PerMag * integral;
}

std::vector<FieldObject> drawFieldObjects(const FieldPopulationParams& params, int width,
                                          int height, double pixelScaleArcsec, std::mt19937_64& rng,
                                          const std::vector<Vec2>& keepOutPix,
                                          double keepOutRadiusPix, double keepOutMag) {
  const double areaDeg2 = double(width) * double(height) * std::pow(pixelScaleArcsec / 3600.0, 2);
  std::uniform_real_distribution<double> ux(-0.5, width - 0.5);
  std::uniform_real_distribution<double> uy(-0.5, height - 0.5);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto place = [&](FieldObject& o) {
    // Redraw (a bounded number of times) while a bright object would cover a keep-out point.
    for (int attempt = 0; attempt < 100; ++attempt) {
      o.xPix = ux(rng);
      o.yPix = uy(rng);
      if (!(o.mag < keepOutMag)) return;
      bool clear = true;
      for (const Vec2& p : keepOutPix) {
        if (std::hypot(o.xPix - p[0], o.yPix - p[1]) < keepOutRadiusPix) clear = false;
      }
      if (clear) return;
    }
  };
  std::vector<FieldObject> objects;
  const auto nGalaxies =
      std::poisson_distribution<std::int64_t>(params.galaxies.expectedCount(areaDeg2))(rng);
  const MagnitudePowerLaw galaxyMags = params.galaxies.magnitudes();
  for (std::int64_t i = 0; i < nGalaxies; ++i) {
    FieldObject g;
    g.kind = FieldObjectKind::Galaxy;
    g.mag = galaxyMags.sample(rng);
    g.type = drawType(params, g.mag, rng);
    const MagnitudeSizeRelation& size =
        g.type == GalaxyType::Elliptical ? params.ellipticalSize : params.diskSize;
    g.halfLightArcsec = std::min(size.sample(g.mag, rng), params.maxHalfLightArcsec);
    g.axisRatio = g.type == GalaxyType::Elliptical ? 0.5 + 0.5 * u01(rng) : 1.0;
    g.positionAngleRad = std::numbers::pi * u01(rng);
    g.halo = g.type == GalaxyType::Elliptical && g.mag < params.haloMagLimit;
    place(g);
    objects.push_back(g);
  }
  const auto nStars =
      std::poisson_distribution<std::int64_t>(params.stars.expectedCount(areaDeg2))(rng);
  const MagnitudePowerLaw starMags = params.stars.magnitudes();
  for (std::int64_t i = 0; i < nStars; ++i) {
    FieldObject s;
    s.kind = FieldObjectKind::Star;
    s.mag = starMags.sample(rng);
    place(s);
    objects.push_back(s);
  }
  return objects;
}

void addStamp(ImageD& image, const Stamp& stamp) {
  const std::int64_t xLo = std::max<std::int64_t>(0, -stamp.x0);
  const std::int64_t yLo = std::max<std::int64_t>(0, -stamp.y0);
  const std::int64_t xHi = std::min(stamp.pixels.width(), image.width() - stamp.x0);
  const std::int64_t yHi = std::min(stamp.pixels.height(), image.height() - stamp.y0);
  for (std::int64_t y = yLo; y < yHi; ++y) {
    const double* src = &stamp.pixels(0, y);
    double* dst = &image(stamp.x0, stamp.y0 + y);
    for (std::int64_t x = xLo; x < xHi; ++x) dst[x] += src[x];
  }
}

Stamp renderGalaxyStamp(const FieldObject& galaxy, const FieldPopulationParams& params,
                        double pixelScaleArcsec, double magZeroPoint, std::mt19937_64& rng,
                        double* xUsedPix, double* yUsedPix) {
  const double flux = fluxFromMagnitude(galaxy.mag, magZeroPoint);
  const double re = galaxy.halfLightArcsec;
  Stamp out;
  if (galaxy.type == GalaxyType::Elliptical) {
    const double radii = galaxy.halo ? params.haloRadiusInHalfLight : params.stampHalfLightRadii;
    const std::int64_t half = std::clamp<std::int64_t>(
        std::int64_t(std::ceil(radii * re / pixelScaleArcsec)), 4, kMaxStampHalfWidthPix);
    const auto xc = std::int64_t(std::lround(galaxy.xPix));
    const auto yc = std::int64_t(std::lround(galaxy.yPix));
    SurveyGrid grid;
    grid.width = grid.height = int(2 * half + 1);
    grid.pixelScaleArcsec = pixelScaleArcsec;
    grid.lensXPix = double(half) + (galaxy.xPix - double(xc));
    grid.lensYPix = double(half) + (galaxy.yPix - double(yc));
    out.pixels = ImageD(grid.width, grid.height);
    out.x0 = xc - half;
    out.y0 = yc - half;
    SersicLightParams light;
    light.sersicIndex = 4.0;
    light.halfLightRadiusArcsec = re;
    light.axisRatio = galaxy.axisRatio;
    light.positionAngleRad = galaxy.positionAngleRad;
    light.totalFlux = flux;
    addSersicLight(out.pixels, grid, light);
    if (xUsedPix) *xUsedPix = galaxy.xPix;
    if (yUsedPix) *yUsedPix = galaxy.yPix;
    return out;
  }
  SyntheticGalaxyOptions options;
  options.pixelScaleArcsec = pixelScaleArcsec / kSubPixels;
  options.halfLightRadiusArcsec = re;
  options.stampHalfLightRadii = galaxy.mag > params.faintStampMag ? params.faintStampHalfLightRadii
                                                                  : params.stampHalfLightRadii;
  SourceStamp fine = makeSyntheticGalaxy(galaxy.type, rng, options);
  const std::int64_t fw = fine.fluxPerPixel.width();
  const std::int64_t fh = fine.fluxPerPixel.height();
  // Lower-left fine-pixel edge, in survey pixels, snapped to a third of a pixel: survey pixel i
  // spans [i - 0.5, i + 0.5), and the fine stamp's centre is fw / (2 kSubPixels) from its edge.
  const auto kx =
      std::int64_t(std::lround((galaxy.xPix - double(fw) / (2.0 * kSubPixels) + 0.5) * kSubPixels));
  const auto ky =
      std::int64_t(std::lround((galaxy.yPix - double(fh) / (2.0 * kSubPixels) + 0.5) * kSubPixels));
  out.x0 = floorDiv(kx, kSubPixels);
  out.y0 = floorDiv(ky, kSubPixels);
  const std::int64_t ox = kx - kSubPixels * out.x0;
  const std::int64_t oy = ky - kSubPixels * out.y0;
  out.pixels =
      ImageD((ox + fw + kSubPixels - 1) / kSubPixels, (oy + fh + kSubPixels - 1) / kSubPixels);
  double sum = 0.0;
  for (std::int64_t y = 0; y < fh; ++y)
    for (std::int64_t x = 0; x < fw; ++x) sum += fine.fluxPerPixel(x, y);
  const double norm = sum > 0.0 ? flux / sum : 0.0;
  for (std::int64_t y = 0; y < fh; ++y)
    for (std::int64_t x = 0; x < fw; ++x)
      out.pixels((ox + x) / kSubPixels, (oy + y) / kSubPixels) += norm * fine.fluxPerPixel(x, y);
  if (xUsedPix) *xUsedPix = -0.5 + double(kx) / kSubPixels + double(fw) / (2.0 * kSubPixels);
  if (yUsedPix) *yUsedPix = -0.5 + double(ky) / kSubPixels + double(fh) / (2.0 * kSubPixels);
  return out;
}

Stamp renderStarStamp(double xPix, double yPix, double flux, double seeingFwhmArcsec,
                      double pixelScaleArcsec, double minValueAdu) {
  if (!(seeingFwhmArcsec > 0.0) || !(pixelScaleArcsec > 0.0))
    throw ConfigError("star: seeing and pixel scale must be positive");
  const double sigmaPix = seeingFwhmArcsec / kGaussianFwhmPerSigma / pixelScaleArcsec;
  const double peak = flux / (2.0 * std::numbers::pi * sigmaPix * sigmaPix);
  double radius = 5.0 * sigmaPix;
  if (minValueAdu > 0.0 && peak > minValueAdu)
    radius = std::max(radius, sigmaPix * std::sqrt(2.0 * std::log(peak / minValueAdu)));
  const std::int64_t half =
      std::min<std::int64_t>(std::int64_t(std::ceil(radius)), kMaxStampHalfWidthPix);
  const auto xc = std::int64_t(std::lround(xPix));
  const auto yc = std::int64_t(std::lround(yPix));
  Stamp out;
  out.x0 = xc - half;
  out.y0 = yc - half;
  const std::int64_t n = 2 * half + 1;
  const std::vector<double> gx = integratedGaussian(xPix, sigmaPix, out.x0, n);
  const std::vector<double> gy = integratedGaussian(yPix, sigmaPix, out.y0, n);
  out.pixels = ImageD(n, n);
  for (std::int64_t y = 0; y < n; ++y)
    for (std::int64_t x = 0; x < n; ++x)
      out.pixels(x, y) = flux * gx[std::size_t(x)] * gy[std::size_t(y)];
  return out;
}

std::int64_t clipSaturation(ImageF& image, float saturationAdu) {
  std::int64_t clipped = 0;
  for (float& v : image.pixels()) {
    if (v > saturationAdu) {
      v = saturationAdu;
      ++clipped;
    }
  }
  return clipped;
}

double lensedLightReachArcsec(const LensSystem& system, const SourceStamp& source) {
  const SourcePlacement& placement = system.source;
  const double usedScale =
      placement.pixelScaleArcsec > 0.0 ? placement.pixelScaleArcsec : source.pixelScaleArcsec;
  const double sourceRadius =
      0.5 * std::sqrt(2.0) *
      double(std::max(source.fluxPerPixel.width(), source.fluxPerPixel.height())) * usedScale;
  return std::hypot(placement.betaArcsec[0], placement.betaArcsec[1]) + sourceRadius +
         EllipticalPotentialLens(system.mass).maxDeflectionArcsec();
}

FieldLens renderFieldLens(const LensSystem& system, const SourceStamp& sourceStamp, double xPix,
                          double yPix, double pixelScaleArcsec, double magZeroPoint) {
  FieldLens f;
  f.xPix = xPix;
  f.yPix = yPix;
  f.system = system;
  SourceStamp source = sourceStamp;
  const double stampFlux = totalFlux(source);
  if (!(stampFlux > 0.0)) throw ConfigError(source.name + ": source stamp has no positive flux");
  const double sourceFlux = fluxFromMagnitude(system.sourceMag, magZeroPoint);
  for (double& v : source.fluxPerPixel.pixels()) v *= sourceFlux / stampFlux;
  const SourcePlacement& placement = system.source;

  // The stamp holds every ray that can reach the source and eight lens half-light radii.
  const EllipticalPotentialLens lensModel(system.mass);
  const double reach = lensedLightReachArcsec(system, source);
  const std::int64_t half = std::clamp<std::int64_t>(
      std::int64_t(
          std::ceil(std::max(reach, 8.0 * system.light.halfLightRadiusArcsec) / pixelScaleArcsec)) +
          2,
      16, kMaxStampHalfWidthPix);
  const auto xc = std::int64_t(std::lround(xPix));
  const auto yc = std::int64_t(std::lround(yPix));
  SurveyGrid grid;
  grid.width = grid.height = int(2 * half + 1);
  grid.pixelScaleArcsec = pixelScaleArcsec;
  grid.lensXPix = double(half) + (xPix - double(xc));
  grid.lensYPix = double(half) + (yPix - double(yc));
  f.stamp.x0 = xc - half;
  f.stamp.y0 = yc - half;
  f.stamp.pixels = traceLensedImage(lensModel, source, placement, grid);

  // Separate images: 8-connected parts above 2% of the peak, kept when they hold >= 5% of the
  // traced flux (the rest is faint wings or noise-level slivers).
  ImageD& traced = f.stamp.pixels;
  double peak = 0.0, tracedFlux = 0.0;
  for (double v : traced.pixels()) {
    peak = std::max(peak, v);
    tracedFlux += v;
  }
  f.magnification = tracedFlux / sourceFlux;
  if (peak > 0.0) {
    const double cut = 0.02 * peak;
    ImageI32 label(traced.width(), traced.height(), 0);
    std::vector<std::int64_t> stack;
    int next = 0;
    for (std::int64_t start = 0; start < traced.size(); ++start) {
      if (traced[start] <= cut || label[start] != 0) continue;
      label[start] = ++next;
      stack.assign(1, start);
      // Local origin at the stamp's lens position keeps the centroid sums small.
      double s = 0.0, sx = 0.0, sy = 0.0;
      while (!stack.empty()) {
        const std::int64_t p = stack.back();
        stack.pop_back();
        const std::int64_t px = p % traced.width(), py = p / traced.width();
        s += traced[p];
        sx += traced[p] * (double(px) - grid.lensXPix);
        sy += traced[p] * (double(py) - grid.lensYPix);
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dx = -1; dx <= 1; ++dx) {
            const std::int64_t qx = px + dx, qy = py + dy;
            if (qx < 0 || qy < 0 || qx >= traced.width() || qy >= traced.height()) continue;
            const std::int64_t q = traced.index(qx, qy);
            if (label[q] == 0 && traced[q] > cut) {
              label[q] = next;
              stack.push_back(q);
            }
          }
      }
      if (s >= 0.05 * tracedFlux) {
        FieldLens::LensedImage im;
        im.xPix = xPix + sx / s;
        im.yPix = yPix + sy / s;
        im.mag = magZeroPoint - 2.5 * std::log10(s);
        f.images.push_back(im);
      }
    }
  }

  SersicLightParams light = system.light;
  light.totalFlux = fluxFromMagnitude(system.lensMag, magZeroPoint);
  addSersicLight(traced, grid, light);
  return f;
}

FitsHeader tanWcsHeader(int width, int height, double pixelScaleArcsec, double raDeg,
                        double decDeg) {
  FitsHeader h;
  h.set("WCSAXES", "2", "Number of WCS axes");
  h.set("CTYPE1", quoteFitsString("RA---TAN"), "Gnomonic projection");
  h.set("CTYPE2", quoteFitsString("DEC--TAN"), "Gnomonic projection");
  h.set("CUNIT1", quoteFitsString("deg"));
  h.set("CUNIT2", quoteFitsString("deg"));
  h.set("CRPIX1", fitsRealValue(0.5 * (width + 1), 15), "Reference pixel: the image centre");
  h.set("CRPIX2", fitsRealValue(0.5 * (height + 1), 15), "Reference pixel: the image centre");
  h.set("CRVAL1", fitsRealValue(raDeg, 15), "RA at the reference pixel (deg)");
  h.set("CRVAL2", fitsRealValue(decDeg, 15), "Dec at the reference pixel (deg)");
  const double scaleDeg = pixelScaleArcsec / 3600.0;
  h.set("CD1_1", fitsRealValue(-scaleDeg, 15), "East to the left");
  h.set("CD1_2", "0.0");
  h.set("CD2_1", "0.0");
  h.set("CD2_2", fitsRealValue(scaleDeg, 15), "North up");
  h.set("RADESYS", quoteFitsString("ICRS"));
  h.set("EQUINOX", "2000.0");
  return h;
}

}  // namespace octarc::simulation
