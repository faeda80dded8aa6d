#include "octarc/simulation/RayTracer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc::simulation {

namespace {

// Bilinear interpolation of the stamp at continuous 0-based pixel coordinates; pixels outside
// the stamp count as zero, so the profile fades to zero over the outer half pixel.
double bilinear(const ImageD& img, double px, double py) {
  const double fx = std::floor(px);
  const double fy = std::floor(py);
  const auto x0 = static_cast<std::int64_t>(fx);
  const auto y0 = static_cast<std::int64_t>(fy);
  if (x0 < -1 || y0 < -1 || x0 >= img.width() || y0 >= img.height()) return 0.0;
  const double tx = px - fx;
  const double ty = py - fy;
  if (x0 >= 0 && y0 >= 0 && x0 + 1 < img.width() && y0 + 1 < img.height()) {
    const double* row0 = img.data() + img.index(x0, y0);
    const double* row1 = row0 + img.width();
    return (1.0 - ty) * ((1.0 - tx) * row0[0] + tx * row0[1]) +
           ty * ((1.0 - tx) * row1[0] + tx * row1[1]);
  }
  auto at = [&img](std::int64_t x, std::int64_t y) {
    return (x < 0 || y < 0 || x >= img.width() || y >= img.height()) ? 0.0 : img(x, y);
  };
  return (1.0 - ty) * ((1.0 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
         ty * ((1.0 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
}

// Radius (stamp pixels) about the stamp centre outside which the interpolated stamp is zero.
double supportRadiusPixels(const ImageD& img) {
  const double cx = 0.5 * (img.width() - 1);
  const double cy = 0.5 * (img.height() - 1);
  double r2max = -1.0;
  for (std::int64_t y = 0; y < img.height(); ++y)
    for (std::int64_t x = 0; x < img.width(); ++x)
      if (img(x, y) != 0.0) r2max = std::max(r2max, (x - cx) * (x - cx) + (y - cy) * (y - cy));
  if (r2max < 0.0) return -1.0;              // empty source
  return std::sqrt(r2max) + std::sqrt(2.0);  // plus the bilinear footprint of one pixel
}

struct Overlap {
  int in;
  int out;
  double fraction;  // of the input pixel's length
};

std::vector<Overlap> axisOverlaps(int nIn, double inScale, int nOut, double outScale) {
  std::vector<Overlap> overlaps;
  overlaps.reserve(static_cast<std::size_t>(nIn) * 2);
  for (int i = 0; i < nIn; ++i) {
    const double a = i * inScale;
    const double b = (i + 1) * inScale;
    for (int o = static_cast<int>(std::floor(a / outScale)); o < nOut; ++o) {
      const double lo = std::max(a, o * outScale);
      const double hi = std::min(b, (o + 1) * outScale);
      if (lo >= b) break;
      if (hi > lo && o >= 0) overlaps.push_back({i, o, (hi - lo) / inScale});
    }
  }
  return overlaps;
}

}  // namespace

ImageD rebinFluxConserving(const ImageD& in, double inScaleArcsec, int outWidth, int outHeight,
                           double outScaleArcsec) {
  if (!(inScaleArcsec > 0.0) || !(outScaleArcsec > 0.0) || outWidth < 0 || outHeight < 0)
    throw ConfigError("rebin: pixel scales must be positive, got " + std::to_string(inScaleArcsec) +
                      " and " + std::to_string(outScaleArcsec));
  const int inWidth = static_cast<int>(in.width());
  const int inHeight = static_cast<int>(in.height());
  const auto ox = axisOverlaps(inWidth, inScaleArcsec, outWidth, outScaleArcsec);
  const auto oy = axisOverlaps(inHeight, inScaleArcsec, outHeight, outScaleArcsec);
  // Separable: first along x into (outWidth x inHeight), then along y.
  ImageD rows(outWidth, inHeight);
  for (int y = 0; y < inHeight; ++y)
    for (const Overlap& o : ox) rows(o.out, y) += o.fraction * in(o.in, y);
  ImageD out(outWidth, outHeight);
  for (const Overlap& o : oy)
    for (int x = 0; x < outWidth; ++x) out(x, o.out) += o.fraction * rows(x, o.in);
  return out;
}

ImageD traceLensedImage(const EllipticalPotentialLens& lens, const SourceStamp& source,
                        const SourcePlacement& placement, const SurveyGrid& grid,
                        const RayTraceOptions& options, RayTraceStats* stats) {
  const double stampScale =
      placement.pixelScaleArcsec > 0.0 ? placement.pixelScaleArcsec : source.pixelScaleArcsec;
  if (!(options.fineScaleArcsec > 0.0) || !(grid.pixelScaleArcsec > 0.0) || !(stampScale > 0.0))
    throw ConfigError("ray tracing: pixel scales must be positive");
  if (options.subSamples < 1 || options.blockFinePixels < 1)
    throw ConfigError("ray tracing: subSamples and blockFinePixels must be >= 1");
  if (grid.width < 1 || grid.height < 1)
    throw ConfigError("ray tracing: the survey stamp must have at least one pixel");
  if (source.fluxPerPixel.empty())
    throw ConfigError("ray tracing: source stamp '" + source.name + "' is empty");

  const double sf = options.fineScaleArcsec;
  const int nfx = static_cast<int>(std::ceil(grid.width * grid.pixelScaleArcsec / sf - 1e-9));
  const int nfy = static_cast<int>(std::ceil(grid.height * grid.pixelScaleArcsec / sf - 1e-9));
  // Sky offset from the lens (arcsec) of the stamp's lower-left corner.
  const double x0 = (-0.5 - grid.lensXPix) * grid.pixelScaleArcsec;
  const double y0 = (-0.5 - grid.lensYPix) * grid.pixelScaleArcsec;

  const ImageD& stamp = source.fluxPerPixel;
  const double stampCx = 0.5 * (stamp.width() - 1);
  const double stampCy = 0.5 * (stamp.height() - 1);
  const double cosR = std::cos(placement.rotationRad);
  const double sinR = std::sin(placement.rotationRad);
  const double invScale = 1.0 / stampScale;
  const double surfaceBrightnessPerFlux = invScale * invScale;
  const double supportPix = supportRadiusPixels(stamp);
  ImageD fine(nfx, nfy);
  RayTraceStats local;
  local.finePixelsTotal = static_cast<long long>(nfx) * nfy;
  if (supportPix < 0.0) {
    local.finePixelsSkipped = local.finePixelsTotal;
    if (stats) *stats = local;
    return ImageD(grid.width, grid.height);
  }
  const double sourceRadius = supportPix * stampScale;
  const double alphaMax = lens.maxDeflectionArcsec();
  const double eps = lens.params().ellipticity;
  const double core = lens.params().coreArcsec;
  const Vec2 betaC = placement.betaArcsec;

  // True if no ray from the square of half-diagonal h about theta can reach the source circle.
  auto unreachable = [&](const Vec2& theta, double h) {
    if (!options.skipUnreachable) return false;
    const double rMin = std::max(0.0, std::sqrt(theta[0] * theta[0] + theta[1] * theta[1]) - h);
    const double dMin = std::sqrt(core * core + (1.0 - eps) * rMin * rMin);
    double dAlpha = 2.0 * alphaMax;
    if (dMin > 0.0) dAlpha = std::min(dAlpha, lens.maxDeflectionGradient(dMin) * h);
    const Vec2 beta = lens.sourcePositionArcsec(theta);
    const double dx = beta[0] - betaC[0];
    const double dy = beta[1] - betaC[1];
    const double reach = sourceRadius + h + dAlpha;
    return dx * dx + dy * dy > reach * reach;
  };

  const int ns = options.subSamples;
  const double step = sf / ns;
  const double fineArea = sf * sf;
  const int block = options.blockFinePixels;
  for (int by = 0; by < nfy; by += block) {
    for (int bx = 0; bx < nfx; bx += block) {
      const int ex = std::min(bx + block, nfx);
      const int ey = std::min(by + block, nfy);
      const Vec2 blockCentre{x0 + 0.5 * (bx + ex) * sf, y0 + 0.5 * (by + ey) * sf};
      const double blockHalfDiag = 0.5 * std::hypot(ex - bx, ey - by) * sf;
      if (unreachable(blockCentre, blockHalfDiag)) {
        local.finePixelsSkipped += static_cast<long long>(ex - bx) * (ey - by);
        continue;
      }
      for (int fy = by; fy < ey; ++fy) {
        for (int fx = bx; fx < ex; ++fx) {
          const Vec2 centre{x0 + (fx + 0.5) * sf, y0 + (fy + 0.5) * sf};
          if (unreachable(centre, sf * std::sqrt(0.5))) {
            ++local.finePixelsSkipped;
            continue;
          }
          double sum = 0.0;
          for (int sy = 0; sy < ns; ++sy) {
            const double ty = y0 + fy * sf + (sy + 0.5) * step;
            for (int sx = 0; sx < ns; ++sx) {
              const double tx = x0 + fx * sf + (sx + 0.5) * step;
              const Vec2 beta = lens.sourcePositionArcsec({tx, ty});
              const double dx = beta[0] - betaC[0];
              const double dy = beta[1] - betaC[1];
              // Into the stamp frame: rotate by -rotation, then to stamp pixels.
              const double u = (cosR * dx + sinR * dy) * invScale + stampCx;
              const double v = (-sinR * dx + cosR * dy) * invScale + stampCy;
              sum += bilinear(stamp, u, v);
            }
          }
          local.raysTraced += static_cast<long long>(ns) * ns;
          fine(fx, fy) = sum / (ns * ns) * surfaceBrightnessPerFlux * fineArea;
        }
      }
    }
  }
  if (stats) *stats = local;
  return rebinFluxConserving(fine, sf, grid.width, grid.height, grid.pixelScaleArcsec);
}

}  // namespace octarc::simulation
