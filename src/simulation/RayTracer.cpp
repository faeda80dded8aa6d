#include "octarc/simulation/RayTracer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc::simulation {

namespace {

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

namespace {

void checkRayTraceInputs(const SourceStamp& source, double stampScale, const SurveyGrid& grid,
                         const RayTraceOptions& options) {
  if (!(options.fineScaleArcsec > 0.0) || !(grid.pixelScaleArcsec > 0.0) || !(stampScale > 0.0))
    throw ConfigError("ray tracing: pixel scales must be positive");
  if (options.subSamples < 1 || options.blockFinePixels < 1)
    throw ConfigError("ray tracing: subSamples and blockFinePixels must be >= 1");
  if (grid.width < 1 || grid.height < 1)
    throw ConfigError("ray tracing: the survey stamp must have at least one pixel");
  if (source.fluxPerPixel.empty())
    throw ConfigError("ray tracing: source stamp '" + source.name + "' is empty");
}

// Lens-frame ray positions to source-stamp pixel coordinates: the deflection of the elliptical
// potential, then one affine map (lens frame -> sky -> stamp frame -> pixels, shifted by +1 into
// the padded stamp). In the lens frame a step along the sky x axis is a constant increment.
struct RayMap {
  double cPa, sPa;  // lens position angle
  double core2, qx, qy, bx, by;
  double m00, m01, m10, m11, u0, v0;  // (u, v) = M (x - alpha_x, y - alpha_y)_lens + (u0, v0)

  double invScale;  // source-stamp pixels per arcsec

  RayMap(const EllipticalPotentialParams& mass, const ImageD& stamp,
         const SourcePlacement& placement, double stampScale) {
    const double cosR = std::cos(placement.rotationRad);
    const double sinR = std::sin(placement.rotationRad);
    invScale = 1.0 / stampScale;
    const Vec2 betaC = placement.betaArcsec;
    cPa = std::cos(mass.positionAngleRad);
    sPa = std::sin(mass.positionAngleRad);
    core2 = mass.coreArcsec * mass.coreArcsec;
    qx = 1.0 - mass.ellipticity;
    qy = 1.0 + mass.ellipticity;
    bx = mass.einsteinRadiusArcsec * qx;
    by = mass.einsteinRadiusArcsec * qy;
    // M = S Rot(-rotation) Rot(pa).
    m00 = invScale * (cosR * cPa + sinR * sPa);
    m01 = invScale * (-cosR * sPa + sinR * cPa);
    m10 = invScale * (-sinR * cPa + cosR * sPa);
    m11 = invScale * (sinR * sPa + cosR * cPa);
    u0 = 0.5 * (stamp.width() - 1) - invScale * (cosR * betaC[0] + sinR * betaC[1]) + 1.0;
    v0 = 0.5 * (stamp.height() - 1) - invScale * (-sinR * betaC[0] + cosR * betaC[1]) + 1.0;
  }

  // The lengths, in source-stamp pixels, of the source-plane images of a lens-plane step of one
  // arcsec along the sky's x and y axes at lens-frame position (x, y): the columns of the lens
  // map's Jacobian A = I - d alpha / d theta (the stamp's rotation keeps lengths).
  std::pair<double, double> stepLengthsPixels(double x, double y) const {
    const double d2 = core2 + qx * x * x + qy * y * y;
    double a00 = 1.0, a01 = 0.0, a10 = 0.0, a11 = 1.0;
    if (d2 > 0.0) {
      const double invD = 1.0 / std::sqrt(d2);
      const double invD3 = invD * invD * invD;
      // alpha = (bx x, by y) / D, D^2 = core^2 + qx x^2 + qy y^2.
      a00 -= bx * invD - bx * x * qx * x * invD3;
      a01 -= -bx * x * qy * y * invD3;
      a10 -= -by * y * qx * x * invD3;
      a11 -= by * invD - by * y * qy * y * invD3;
    }
    // Sky x and y in the lens frame: (cPa, -sPa) and (sPa, cPa).
    const double ux0 = a00 * cPa - a01 * sPa, ux1 = a10 * cPa - a11 * sPa;
    const double uy0 = a00 * sPa + a01 * cPa, uy1 = a10 * sPa + a11 * cPa;
    return {std::hypot(ux0, ux1) * invScale, std::hypot(uy0, uy1) * invScale};
  }

  // Source-plane stamp coordinates of n rays (lens-frame positions xl, yl), written to u, v.
  // Branch-free so that the compiler can vectorise the square roots and divisions.
  void map(const double* xl, const double* yl, double* u, double* v, int n) const {
    for (int k = 0; k < n; ++k) {
      const double d2 = core2 + qx * xl[k] * xl[k] + qy * yl[k] * yl[k];
      // d2 == 0 only at the centre of a coreless lens, where the deflection is taken as zero.
      const double invD = d2 > 0.0 ? 1.0 / std::sqrt(d2) : 0.0;
      const double px = xl[k] - bx * xl[k] * invD;
      const double py = yl[k] - by * yl[k] * invD;
      u[k] = m00 * px + m01 * py + u0;
      v[k] = m10 * px + m11 * py + v0;
    }
  }
};

// The source stamp with a one-pixel zero border: bilinear interpolation then needs no edge cases.
class PaddedStamp {
 public:
  explicit PaddedStamp(const ImageD& stamp)
      : width_(stamp.width() + 2),
        uMax_(double(stamp.width() + 1)),
        vMax_(double(stamp.height() + 1)),
        pixels_(static_cast<std::size_t>(width_ * (stamp.height() + 2)), 0.0) {
    for (std::int64_t y = 0; y < stamp.height(); ++y)
      std::copy_n(stamp.data() + y * stamp.width(), stamp.width(),
                  pixels_.data() + (y + 1) * width_ + 1);
  }
  double sample(double u, double v) const {
    if (!(u >= 0.0 && v >= 0.0 && u < uMax_ && v < vMax_)) return 0.0;
    const double fu = std::floor(u);
    const double fv = std::floor(v);
    const double tu = u - fu;
    const double tv = v - fv;
    const double* r0 =
        pixels_.data() + static_cast<std::int64_t>(fv) * width_ + static_cast<std::int64_t>(fu);
    const double* r1 = r0 + width_;
    return (1.0 - tv) * ((1.0 - tu) * r0[0] + tu * r0[1]) + tv * ((1.0 - tu) * r1[0] + tu * r1[1]);
  }

 private:
  std::int64_t width_;
  double uMax_, vMax_;
  std::vector<double> pixels_;
};

// Each fine pixel overlaps at most a few survey pixels along each axis: its flux goes straight
// to them with the overlap fractions of rebinFluxConserving, so no fine-grid image is needed.
class FluxSpreader {
 public:
  FluxSpreader(int nfx, int nfy, double fineScale, const SurveyGrid& grid) {
    sharesX_ = shares(nfx, fineScale, grid.width, grid.pixelScaleArcsec, overlapsX_);
    sharesY_ = shares(nfy, fineScale, grid.height, grid.pixelScaleArcsec, overlapsY_);
  }
  void add(ImageD& out, int fx, int fy, double flux) const {
    const AxisShare& ax = sharesX_[static_cast<std::size_t>(fx)];
    const AxisShare& ay = sharesY_[static_cast<std::size_t>(fy)];
    for (int j = ay.first; j < ay.first + ay.count; ++j) {
      const Overlap& oy = overlapsY_[static_cast<std::size_t>(j)];
      double* row = out.data() + out.index(0, oy.out);
      for (int i = ax.first; i < ax.first + ax.count; ++i) {
        const Overlap& ox = overlapsX_[static_cast<std::size_t>(i)];
        row[ox.out] += ox.fraction * oy.fraction * flux;
      }
    }
  }

 private:
  struct AxisShare {
    int first = 0;  // index into the overlap list
    int count = 0;
  };
  static std::vector<AxisShare> shares(int nIn, double inScale, int nOut, double outScale,
                                       std::vector<Overlap>& overlaps) {
    overlaps = axisOverlaps(nIn, inScale, nOut, outScale);
    std::vector<AxisShare> out(static_cast<std::size_t>(nIn));
    for (int k = 0; k < static_cast<int>(overlaps.size()); ++k) {
      AxisShare& a = out[static_cast<std::size_t>(overlaps[std::size_t(k)].in)];
      if (a.count == 0) a.first = k;
      ++a.count;
    }
    return out;
  }
  std::vector<Overlap> overlapsX_, overlapsY_;
  std::vector<AxisShare> sharesX_, sharesY_;
};

}  // namespace

ImageD traceLensedImage(const EllipticalPotentialLens& lens, const SourceStamp& source,
                        const SourcePlacement& placement, const SurveyGrid& grid,
                        const RayTraceOptions& options, RayTraceStats* stats) {
  const double stampScale =
      placement.pixelScaleArcsec > 0.0 ? placement.pixelScaleArcsec : source.pixelScaleArcsec;
  checkRayTraceInputs(source, stampScale, grid, options);

  const double sf = options.fineScaleArcsec;
  const int nfx = static_cast<int>(std::ceil(grid.width * grid.pixelScaleArcsec / sf - 1e-9));
  const int nfy = static_cast<int>(std::ceil(grid.height * grid.pixelScaleArcsec / sf - 1e-9));
  // Sky offset from the lens (arcsec) of the stamp's lower-left corner.
  const double x0 = (-0.5 - grid.lensXPix) * grid.pixelScaleArcsec;
  const double y0 = (-0.5 - grid.lensYPix) * grid.pixelScaleArcsec;

  const ImageD& stamp = source.fluxPerPixel;
  const double invScale = 1.0 / stampScale;
  const double surfaceBrightnessPerFlux = invScale * invScale;
  const double supportPix = supportRadiusPixels(stamp);
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
  const double fineArea = sf * sf;
  const int block = options.blockFinePixels;
  const RayMap rays(lens.params(), stamp, placement, stampScale);
  const PaddedStamp padded(stamp);
  const FluxSpreader spreader(nfx, nfy, sf, grid);
  const int raysPerFine = ns * ns;
  std::vector<double> rayBuffer(4 * static_cast<std::size_t>(raysPerFine));
  double* rxl = rayBuffer.data();
  double* ryl = rxl + raysPerFine;
  double* ru = ryl + raysPerFine;
  double* rv = ru + raysPerFine;
  ImageD out(grid.width, grid.height);

  const double fineFlux = surfaceBrightnessPerFlux * fineArea;
  for (int by0 = 0; by0 < nfy; by0 += block) {
    for (int bx0 = 0; bx0 < nfx; bx0 += block) {
      const int ex = std::min(bx0 + block, nfx);
      const int ey = std::min(by0 + block, nfy);
      const Vec2 blockCentre{x0 + 0.5 * (bx0 + ex) * sf, y0 + 0.5 * (by0 + ey) * sf};
      const double blockHalfDiag = 0.5 * std::hypot(ex - bx0, ey - by0) * sf;
      if (unreachable(blockCentre, blockHalfDiag)) {
        local.finePixelsSkipped += static_cast<long long>(ex - bx0) * (ey - by0);
        continue;
      }
      for (int fy = by0; fy < ey; ++fy) {
        for (int fx = bx0; fx < ex; ++fx) {
          const Vec2 centre{x0 + (fx + 0.5) * sf, y0 + (fy + 0.5) * sf};
          if (unreachable(centre, sf * std::sqrt(0.5))) {
            ++local.finePixelsSkipped;
            continue;
          }
          // Sub-pixels along each sky axis: subSamples, or with adaptive sampling as many as
          // keep the rays' source-plane spacing within maxSourceStepPixels (at least one).
          int nx = ns, ny = ns;
          if (options.maxSourceStepPixels > 0.0) {
            const double cxl = rays.cPa * centre[0] + rays.sPa * centre[1];
            const double cyl = -rays.sPa * centre[0] + rays.cPa * centre[1];
            const auto [lx, ly] = rays.stepLengthsPixels(cxl, cyl);
            nx = std::clamp(int(std::ceil(sf * lx / options.maxSourceStepPixels)), 1, ns);
            ny = std::clamp(int(std::ceil(sf * ly / options.maxSourceStepPixels)), 1, ns);
          }
          const double stepX = sf / nx, stepY = sf / ny;
          // Sub-pixel ray positions in the lens frame, row by row.
          for (int sy = 0; sy < ny; ++sy) {
            const double ty = y0 + fy * sf + (sy + 0.5) * stepY;
            for (int sx = 0; sx < nx; ++sx) {
              const double tx = x0 + fx * sf + (sx + 0.5) * stepX;
              rxl[sy * nx + sx] = rays.cPa * tx + rays.sPa * ty;
              ryl[sy * nx + sx] = -rays.sPa * tx + rays.cPa * ty;
            }
          }
          const int raysHere = nx * ny;
          rays.map(rxl, ryl, ru, rv, raysHere);
          double sum = 0.0;
          for (int k = 0; k < raysHere; ++k) sum += padded.sample(ru[k], rv[k]);
          local.raysTraced += raysHere;
          if (sum == 0.0) continue;
          spreader.add(out, fx, fy, sum * fineFlux / raysHere);
        }
      }
    }
  }
  if (stats) *stats = local;
  return out;
}

}  // namespace octarc::simulation
