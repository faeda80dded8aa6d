#include "octarc/search/Inspection.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <utility>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Statistics.h"
#include "octarc/plot/LuptonColour.h"

namespace octarc {

namespace {

constexpr double kArcEllipseScale = 3.0;  // the arc's ellipse: 3 A x 3 B
constexpr double kLensCircleArcsec = 1.0;

double valueOf(const Table& catalog, std::size_t row, const char* column) {
  const int c = catalog.findColumn(column);
  return c < 0 ? kNaN : catalog.value(std::int64_t(row), c);
}

RegionMark arcMark(const Table& catalog, const Candidate& cand, std::size_t index) {
  RegionMark m;
  m.kind = RegionShapeKind::Ellipse;
  m.xCentre = valueOf(catalog, cand.row, "X_IMAGE");
  m.yCentre = valueOf(catalog, cand.row, "Y_IMAGE");
  m.semiAxis1Pix = kArcEllipseScale * valueOf(catalog, cand.row, "A_IMAGE");
  m.semiAxis2Pix = kArcEllipseScale * valueOf(catalog, cand.row, "B_IMAGE");
  m.angleRad = valueOf(catalog, cand.row, "THETA_IMAGE") * kRadPerDeg;
  if (!std::isfinite(m.semiAxis1Pix) || !std::isfinite(m.semiAxis2Pix)) {
    m.semiAxis1Pix = m.semiAxis2Pix = 3.0;  // a catalog without A_IMAGE / B_IMAGE
  }
  if (!std::isfinite(m.angleRad)) m.angleRad = 0.0;
  m.colour = "green";
  m.text = std::to_string(index + 1);
  return m;
}

RegionMark lensMark(const CandidateLens& lens, double pixelScaleArcsec) {
  RegionMark m;
  m.kind = RegionShapeKind::Circle;
  m.xCentre = lens.xPix;
  m.yCentre = lens.yPix;
  m.semiAxis1Pix = m.semiAxis2Pix = kLensCircleArcsec / pixelScaleArcsec;
  m.colour = "red";
  return m;
}

// A unit vector in pixel coordinates towards a small offset on the sky; nullopt without one.
std::optional<std::array<double, 2>> skyDirection(const Wcs& wcs, double x, double y, double dRaDeg,
                                                  double dDecDeg) {
  const auto sky = wcs.pixelToWorld(x, y);
  const auto p = wcs.worldToPixel(sky[0] + dRaDeg, sky[1] + dDecDeg);
  const double dx = p[0] - x, dy = p[1] - y;
  const double len = std::hypot(dx, dy);
  if (!std::isfinite(len) || len <= 0) return std::nullopt;
  return std::array<double, 2>{dx / len, dy / len};
}

}  // namespace

std::vector<RegionMark> candidateRegionMarks(const Table& catalog, const SearchResult& result,
                                             double pixelScaleArcsec) {
  std::vector<RegionMark> marks;
  for (std::size_t i = 0; i < result.candidates.size(); ++i) {
    const Candidate& cand = result.candidates[i];
    marks.push_back(arcMark(catalog, cand, i));
    if (cand.lens) marks.push_back(lensMark(*cand.lens, pixelScaleArcsec));
  }
  return marks;
}

std::string stampFileName(std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "stamps/%04zu.png", index + 1);
  return name;
}

std::string colourStampFileName(std::size_t index) {
  std::string name = stampFileName(index);
  return name.replace(name.size() - 4, 4, ".colour.png");
}

std::string cutoutFileName(std::size_t index) {
  std::string name = stampFileName(index);
  return name.replace(name.size() - 4, 4, ".fits");
}

FitsHeader cutoutHeader(const FitsHeader& imageHeader, const Stamp& stamp) {
  FitsHeader h = imageHeader;
  // The cut-out's pixel 1 is the image's pixel xFirstFits: every pixel coordinate drops by
  // xFirstFits - 1.
  const double dx = stamp.xFirstFits - 1.0, dy = stamp.yFirstFits - 1.0;
  for (const auto& [key, shift] : {std::pair{"CRPIX1", dx}, std::pair{"CRPIX2", dy}}) {
    if (const std::optional<double> v = h.number(key)) h.set(key, fitsRealValue(*v - shift, 17));
  }
  // IRAF's image = LTM physical + LTV: the cut-out's image pixels drop by dx, so LTV does,
  // from the image's own (a cut-out of a cut-out keeps the first one's physical pixels).
  const double ltv1 = h.number("LTV1").value_or(0.0), ltv2 = h.number("LTV2").value_or(0.0);
  h.set("LTV1", fitsRealValue(ltv1 - dx, 17), "physical = (image - LTV) / LTM");
  h.set("LTV2", fitsRealValue(ltv2 - dy, 17));
  if (!h.number("LTM1_1")) h.set("LTM1_1", "1.0");
  if (!h.number("LTM2_2")) h.set("LTM2_2", "1.0");
  return h;
}

namespace {

// The side x side pixels of `image` from 0-based pixel (i0, j0) on, NaN beyond its edges.
ImageF cutOut(const ImageF& image, std::int64_t i0, std::int64_t j0, std::int64_t side) {
  ImageF out(side, side, std::numeric_limits<float>::quiet_NaN());
  for (std::int64_t j = std::max<std::int64_t>(0, -j0); j < side && j0 + j < image.height(); ++j) {
    for (std::int64_t i = std::max<std::int64_t>(0, -i0); i < side && i0 + i < image.width(); ++i) {
      out(i, j) = image(i0 + i, j0 + j);
    }
  }
  return out;
}

}  // namespace

Stamp candidateStamp(const ImageF& image, const Table& catalog, const SearchResult& result,
                     std::size_t index, const Wcs* wcs, double pixelScaleArcsec,
                     const StampSettings& settings) {
  const Candidate& cand = result.candidates.at(index);
  const double xArc = valueOf(catalog, cand.row, "X_IMAGE");
  const double yArc = valueOf(catalog, cand.row, "Y_IMAGE");
  // The system's centre: the lens when there is one.
  const double xc = cand.lens ? cand.lens->xPix : xArc;
  const double yc = cand.lens ? cand.lens->yPix : yArc;
  const std::int64_t side =
      std::max<std::int64_t>(8, std::llround(settings.sideArcsec / pixelScaleArcsec));
  // 0-based index of the cut-out's first pixel: the centre pixel in its middle.
  const std::int64_t i0 = std::int64_t(std::floor(fromFitsPixel(xc) + 0.5)) - side / 2;
  const std::int64_t j0 = std::int64_t(std::floor(fromFitsPixel(yc) + 0.5)) - side / 2;
  Stamp stamp;
  stamp.pixels = cutOut(image, i0, j0, side);
  std::vector<double> values;
  values.reserve(std::size_t(side * side));
  for (const float v : stamp.pixels.pixels()) {
    if (std::isfinite(v)) values.push_back(v);
  }
  stamp.xFirstFits = toFitsPixel(double(i0));
  stamp.yFirstFits = toFitsPixel(double(j0));
  const std::vector<double> q = sampleQuantiles(values, {0.1587, 0.5, 0.997});
  const double sigma = q[1] - q[0];
  stamp.displayLowAdu = std::isfinite(q[1]) ? q[1] - std::max(sigma, 0.0) : 0.0;
  stamp.displayHighAdu = std::isfinite(q[2]) ? q[2] : 1.0;
  if (!(stamp.displayHighAdu > stamp.displayLowAdu)) {
    stamp.displayHighAdu = stamp.displayLowAdu + 1.0;
  }
  if (wcs != nullptr && wcs->isJ2000Equatorial()) {
    const double cosDec = std::max(std::cos(cand.decDeg * kRadPerDeg), 1e-9);
    const auto north = skyDirection(*wcs, xc, yc, 0.0, 1.0 / 3600.0);
    const auto east = skyDirection(*wcs, xc, yc, 1.0 / 3600.0 / cosDec, 0.0);
    if (north && east) {
      stamp.hasSkyDirections = true;
      stamp.northX = (*north)[0];
      stamp.northY = (*north)[1];
      stamp.eastX = (*east)[0];
      stamp.eastY = (*east)[1];
    }
  }
  stamp.pixelScaleArcsec = pixelScaleArcsec;
  stamp.scaleBarArcsec = settings.scaleBarArcsec;
  const RegionMark arc = arcMark(catalog, cand, index);
  StampMark a;
  a.xFits = arc.xCentre;
  a.yFits = arc.yCentre;
  a.semiAxis1Pix = arc.semiAxis1Pix;
  a.semiAxis2Pix = arc.semiAxis2Pix;
  a.angleRad = arc.angleRad;
  a.red = 60;
  a.green = 230;
  a.blue = 60;
  stamp.marks.push_back(a);
  if (cand.lens) {
    StampMark l;
    l.ellipse = false;
    l.xFits = cand.lens->xPix;
    l.yFits = cand.lens->yPix;
    l.semiAxis1Pix = l.semiAxis2Pix = kLensCircleArcsec / pixelScaleArcsec;
    l.red = 240;
    l.green = 60;
    l.blue = 60;
    stamp.marks.push_back(l);
  }
  stamp.sizePix = settings.sizePix;
  return stamp;
}

Stamp candidateColourStamp(const Stamp& grey, const ColourStampBand& searched,
                           const std::vector<ColourStampBand>& others, double skySigmaAdu) {
  if (others.empty()) throw ConfigError("colour stamp: no band besides the searched one");
  // The grey stamp's cut-out of every band (NaN, hence black, beyond the image), each scaled to
  // the searched band's flux.
  const std::int64_t side = grey.pixels.width();
  const std::int64_t i0 = std::llround(fromFitsPixel(grey.xFirstFits));
  const std::int64_t j0 = std::llround(fromFitsPixel(grey.yFirstFits));
  const ImageF red = cutOut(*searched.pixels, i0, j0, side);
  const ImageF blue = cutOut(*others[0].pixels, i0, j0, side);
  const ImageF other = others.size() > 1 ? cutOut(*others[1].pixels, i0, j0, side) : ImageF();
  const auto scale = [&](const ColourStampBand& b) {
    return std::pow(10.0, -0.4 * (b.magZeropoint - searched.magZeropoint));
  };
  const double blueScale = scale(others[0]);
  const double otherScale = others.size() > 1 ? scale(others[1]) : 0.0;
  const LuptonStretch stretch{kColourStampQ, kColourStampSofteningSigmas * skySigmaAdu};
  Stamp stamp = grey;
  stamp.marks.clear();
  stamp.rgbPixels = Image<std::uint32_t>(side, side, 0u);
  for (std::int64_t j = 0; j < side; ++j) {
    for (std::int64_t i = 0; i < side; ++i) {
      const double r = red(i, j), b = blueScale * double(blue(i, j));
      // Green: the mean of the two bands, or the second other band.
      const double g = other.empty() ? 0.5 * r + 0.5 * b : otherScale * double(other(i, j));
      const Rgb8 c = luptonRgb(r, g, b, stretch);
      stamp.rgbPixels(i, j) = std::uint32_t(c.red) << 16 | std::uint32_t(c.green) << 8 | c.blue;
    }
  }
  return stamp;
}

}  // namespace octarc
