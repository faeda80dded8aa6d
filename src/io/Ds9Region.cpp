#include "octarc/io/Ds9Region.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <utility>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/io/Wcs.h"

namespace octarc {

namespace {

constexpr double kArcsecPerDeg = 3600.0;

enum class RegionSystem { Image, Physical, SkyJ2000 };

std::string_view trimWhitespace(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

// Everything a line's shapes need to become pixel shapes, and where to point in messages.
struct ParseContext {
  std::string where;         // "regions.reg:12"
  const Wcs* wcs = nullptr;  // null when sky shapes cannot be placed: wcsProblem says why
  std::string wcsProblem;
  double ltm = 1.0;  // physical -> image: x_image = ltm * x_physical + ltv
  double ltv1 = 0.0;
  double ltv2 = 0.0;
  double pointRadiusPix = 0.0;  // radius of a point shape; 0: a point is an error
};

[[noreturn]] void fail(const ParseContext& context, const std::string& problem) {
  throw ConfigError(context.where + ": " + problem);
}

std::optional<double> plainNumber(std::string_view text) {
  text = trimWhitespace(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

double number(const ParseContext& context, std::string_view text, const char* what) {
  const auto value = plainNumber(text);
  if (!value) fail(context, "cannot read '" + std::string(text) + "' as " + what);
  return *value;
}

// "12:34:56.7", "-05:06:07" or "12h34m56.7s", "-5d06m07s": the value in the unit of the first
// field (hours or degrees); the sign of the first field applies to the whole.
std::optional<double> sexagesimal(std::string_view text) {
  std::string normalised(trimWhitespace(text));
  for (char& c : normalised) {
    if (c == ':' || c == 'h' || c == 'd' || c == 'm' || c == 's') c = ' ';
  }
  std::istringstream fields(normalised);
  std::string field;
  double value = 0.0;
  double unit = 1.0;
  const bool negative = trimWhitespace(text).starts_with('-');
  std::vector<double> parts;
  while (fields >> field) {
    const auto part = plainNumber(field);
    if (!part || parts.size() == 3) return std::nullopt;
    if (!parts.empty() && (field.front() == '-' || field.front() == '+' || *part >= 60.0)) {
      return std::nullopt;
    }
    parts.push_back(*part);
  }
  if (parts.empty()) return std::nullopt;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    // Every field but the last is a whole number: 10.5:30:00 is not a position.
    if (i + 1 < parts.size() && parts[i] != std::floor(parts[i])) return std::nullopt;
    value += std::fabs(parts[i]) * unit;
    unit /= 60.0;
  }
  return negative ? -value : value;
}

double skyLongitudeDeg(const ParseContext& context, std::string_view text) {
  const std::string t = lowercase(trimWhitespace(text));
  std::optional<double> deg;
  if (t.find(':') != std::string::npos || t.find('h') != std::string::npos) {
    const auto hours = sexagesimal(t);
    if (hours && *hours >= 0.0 && *hours < 24.0) deg = *hours * 15.0;
  } else if (t.ends_with('d')) {
    deg = plainNumber(std::string_view(t).substr(0, t.size() - 1));
  } else {
    deg = plainNumber(t);
  }
  if (!deg) fail(context, "cannot read '" + std::string(text) + "' as a right ascension");
  return *deg;
}

double skyLatitudeDeg(const ParseContext& context, std::string_view text) {
  const std::string t = lowercase(trimWhitespace(text));
  std::optional<double> deg;
  if (t.find(':') != std::string::npos || t.find('m') != std::string::npos) {
    deg = sexagesimal(t);
  } else if (t.ends_with('d')) {
    deg = plainNumber(std::string_view(t).substr(0, t.size() - 1));
  } else {
    deg = plainNumber(t);
  }
  if (!deg || std::fabs(*deg) > 90.0) {
    fail(context, "cannot read '" + std::string(text) + "' as a declination");
  }
  return *deg;
}

// A sky size in arcsec: degrees unless marked ", ', d or r.
double skySizeArcsec(const ParseContext& context, std::string_view text) {
  const std::string_view t = trimWhitespace(text);
  double scale = kArcsecPerDeg;
  std::string_view digits = t;
  if (!t.empty()) {
    switch (t.back()) {
      case '"':
        scale = 1.0;
        break;
      case '\'':
        scale = 60.0;
        break;
      case 'd':
        scale = kArcsecPerDeg;
        break;
      case 'r':
        scale = kArcsecPerDeg * kDegPerRad;
        break;
      default:
        break;
    }
    if (std::string_view("\"'dr").find(t.back()) != std::string_view::npos) {
      digits = t.substr(0, t.size() - 1);
    }
  }
  const double value = number(context, digits, "a size");
  if (value < 0.0) fail(context, "negative size '" + std::string(text) + "'");
  return value * scale;
}

// A size in image pixels: `ltm` image pixels per unit of the shape's system, unless marked i
// (image pixels) or p (physical pixels).
double pixelSize(const ParseContext& context, std::string_view text, double ltm) {
  std::string_view t = trimWhitespace(text);
  if (!t.empty() && t.back() == 'i') {
    ltm = 1.0;
    t.remove_suffix(1);
  } else if (!t.empty() && t.back() == 'p') {
    ltm = context.ltm;
    t.remove_suffix(1);
  }
  const double value = number(context, t, "a size");
  if (value < 0.0) fail(context, "negative size '" + std::string(text) + "'");
  return value * ltm;
}

// The local frame of a sky position on the image: its pixel position, pixels per arcsec, the
// angle of North from +x and whether East lies counter-clockwise of North (East left of North
// up, the sky as seen) or clockwise (a mirrored image).
struct LocalSkyFrame {
  double x = 0.0;
  double y = 0.0;
  double pixPerArcsec = 0.0;
  double northRad = 0.0;
  bool eastCounterClockwise = true;
};

const Wcs& requireWcs(const ParseContext& context) {
  if (context.wcs == nullptr)
    fail(context, "a shape in sky coordinates, but " + context.wcsProblem);
  return *context.wcs;
}

std::array<double, 2> skyToPixel(const ParseContext& context, double raDeg, double decDeg) {
  const auto pixel = requireWcs(context).worldToPixel(raDeg, decDeg);
  if (!std::isfinite(pixel[0]) || !std::isfinite(pixel[1])) {
    fail(context, "a sky position outside the image's WCS");
  }
  return pixel;
}

// The local frame at a sky position; nullopt where the WCS gives no pixel for it.
std::optional<LocalSkyFrame> localSkyFrameOf(const Wcs& wcs, double raDeg, double decDeg) {
  auto pixel = [&](double ra, double dec) -> std::optional<std::array<double, 2>> {
    const auto p = wcs.worldToPixel(ra, dec);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) return std::nullopt;
    return p;
  };
  const auto centre = pixel(raDeg, decDeg);
  // One arcsec towards North (towards South at the pole, the direction then reversed).
  const double stepDeg =
      decDeg + 1.0 / kArcsecPerDeg <= 90.0 ? 1.0 / kArcsecPerDeg : -1.0 / kArcsecPerDeg;
  const auto north = pixel(raDeg, decDeg + stepDeg);
  // One arcsec towards East (RA grows by 1 / cos(Dec) arcsec), for the parity of the image.
  const double cosDec = std::max(std::cos(decDeg * kRadPerDeg), 1e-9);
  const auto east = pixel(raDeg + 1.0 / kArcsecPerDeg / cosDec, decDeg);
  if (!centre || !north || !east) return std::nullopt;
  double dx = (*north)[0] - (*centre)[0];
  double dy = (*north)[1] - (*centre)[1];
  if (stepDeg < 0.0) {
    dx = -dx;
    dy = -dy;
  }
  LocalSkyFrame frame;
  frame.x = (*centre)[0];
  frame.y = (*centre)[1];
  frame.pixPerArcsec = std::hypot(dx, dy);
  frame.northRad = std::atan2(dy, dx);
  frame.eastCounterClockwise =
      dx * ((*east)[1] - (*centre)[1]) - dy * ((*east)[0] - (*centre)[0]) > 0.0;
  return frame;
}

LocalSkyFrame localSkyFrame(const ParseContext& context, double raDeg, double decDeg) {
  const std::optional<LocalSkyFrame> frame = localSkyFrameOf(requireWcs(context), raDeg, decDeg);
  if (!frame) fail(context, "a sky position outside the image's WCS");
  return *frame;
}

// The image angle of a sky angle (degrees from the longitude axis, counter-clockwise on the
// sky): counter-clockwise on the image when East is counter-clockwise of North, clockwise on a
// mirrored image.
double imageAngleRad(const LocalSkyFrame& frame, double skyAngleDeg) {
  return frame.eastCounterClockwise
             ? frame.northRad - 0.5 * std::numbers::pi + skyAngleDeg * kRadPerDeg
             : frame.northRad + 0.5 * std::numbers::pi - skyAngleDeg * kRadPerDeg;
}

// Its inverse.
double skyAngleDeg(const LocalSkyFrame& frame, double imageAngleRad) {
  const double deg = frame.eastCounterClockwise
                         ? (imageAngleRad - frame.northRad + 0.5 * std::numbers::pi) / kRadPerDeg
                         : (frame.northRad + 0.5 * std::numbers::pi - imageAngleRad) / kRadPerDeg;
  return deg - 360.0 * std::floor(deg / 360.0);
}

// The arguments of "name(a, b, c)": split on commas (blanks around them allowed) or on blanks
// alone. An empty field ("1,,2" or a trailing comma) is an error.
std::vector<std::string> splitArguments(const ParseContext& context, std::string_view inside) {
  std::vector<std::string> args;
  std::string current;
  bool commaPending = false;  // a comma seen since the last argument
  for (const char c : inside) {
    if (c == ',' || c == ' ' || c == '\t') {
      if (!current.empty()) {
        args.push_back(current);
        current.clear();
        commaPending = false;
      }
      if (c == ',') {
        if (commaPending || args.empty())
          fail(context, "empty argument in '" + std::string(inside) + "'");
        commaPending = true;
      }
    } else {
      current += c;
    }
  }
  if (!current.empty()) {
    args.push_back(current);
  } else if (commaPending) {
    fail(context, "empty argument in '" + std::string(inside) + "'");
  }
  return args;
}

// The position of argument pair i as 1-based image pixels.
std::array<double, 2> position(const ParseContext& context, RegionSystem system,
                               const std::vector<std::string>& args, std::size_t i) {
  if (system == RegionSystem::SkyJ2000) {
    return skyToPixel(context, skyLongitudeDeg(context, args[i]),
                      skyLatitudeDeg(context, args[i + 1]));
  }
  const double x = number(context, args[i], "a pixel position");
  const double y = number(context, args[i + 1], "a pixel position");
  if (system == RegionSystem::Physical) {
    return {context.ltm * x + context.ltv1, context.ltm * y + context.ltv2};
  }
  return {x, y};
}

// Circle, box, ellipse and annulus: centre, two sizes (the circle's radius twice; the annulus's
// inner and outer radius) and an angle.
RegionShape centredShape(const ParseContext& context, RegionSystem system, RegionShapeKind kind,
                         const std::vector<std::string>& args) {
  RegionShape shape;
  shape.kind = kind;
  const bool circle = kind == RegionShapeKind::Circle;
  const std::string size2 = circle ? args[2] : args[3];
  const double angleDeg =
      (!circle && args.size() == 5) ? number(context, args[4], "an angle") : 0.0;
  // Boxes are given by full sides, ellipses and circles by semi-axes.
  const double sizeToSemiAxis = kind == RegionShapeKind::Box ? 0.5 : 1.0;
  if (system == RegionSystem::SkyJ2000) {
    const LocalSkyFrame frame =
        localSkyFrame(context, skyLongitudeDeg(context, args[0]), skyLatitudeDeg(context, args[1]));
    shape.xCentre = frame.x;
    shape.yCentre = frame.y;
    shape.semiAxis1Pix = sizeToSemiAxis * skySizeArcsec(context, args[2]) * frame.pixPerArcsec;
    shape.semiAxis2Pix = sizeToSemiAxis * skySizeArcsec(context, size2) * frame.pixPerArcsec;
    shape.angleRad = imageAngleRad(frame, angleDeg);
  } else {
    const auto centre = position(context, system, args, 0);
    const double ltm = system == RegionSystem::Physical ? context.ltm : 1.0;
    shape.xCentre = centre[0];
    shape.yCentre = centre[1];
    shape.semiAxis1Pix = sizeToSemiAxis * pixelSize(context, args[2], ltm);
    shape.semiAxis2Pix = sizeToSemiAxis * pixelSize(context, size2, ltm);
    shape.angleRad = angleDeg * kRadPerDeg;
  }
  if (kind == RegionShapeKind::Annulus) {
    std::swap(shape.semiAxis1Pix, shape.semiAxis2Pix);  // outer radius first
    shape.angleRad = 0.0;
    if (shape.semiAxis2Pix > shape.semiAxis1Pix) {
      fail(context, "annulus: the inner radius is larger than the outer one");
    }
  }
  return shape;
}

// A point: its pixel position (x, y in the shape's system), as a circle of the point radius.
RegionShape pointShape(const ParseContext& context, RegionSystem system,
                       const std::vector<std::string>& args) {
  if (args.size() != 2) fail(context, "point needs x, y");
  if (!(context.pointRadiusPix > 0.0)) {
    fail(context,
         "a point has no area to mask; give points a radius (octarc search: MASK_POINT_RADIUS, "
         "arcsec) or draw circles");
  }
  const auto centre = position(context, system, args, 0);
  RegionShape shape;
  shape.kind = RegionShapeKind::Circle;
  shape.xCentre = centre[0];
  shape.yCentre = centre[1];
  shape.semiAxis1Pix = context.pointRadiusPix;
  shape.semiAxis2Pix = context.pointRadiusPix;
  return shape;
}

bool isAreaLessShape(const std::string& name) {
  static const char* const kNames[] = {"line",    "text",    "vector",    "ruler",
                                       "compass", "segment", "projection"};
  return std::find(std::begin(kNames), std::end(kNames), name) != std::end(kNames);
}

bool isUnsupportedShape(const std::string& name) {
  static const char* const kNames[] = {"panda", "epanda", "bpanda", "composite"};
  return std::find(std::begin(kNames), std::end(kNames), name) != std::end(kNames);
}

// A coordinate-system word, or nullopt if `word` is not one; throws for systems not supported.
std::optional<RegionSystem> coordinateSystem(const ParseContext& context, const std::string& word) {
  if (word == "image") return RegionSystem::Image;
  if (word == "physical") return RegionSystem::Physical;
  if (word == "fk5" || word == "icrs" || word == "j2000") return RegionSystem::SkyJ2000;
  static const char* const kUnsupported[] = {"fk4",    "b1950",     "galactic", "ecliptic",
                                             "linear", "amplifier", "detector", "wcs"};
  if (std::find(std::begin(kUnsupported), std::end(kUnsupported), word) != std::end(kUnsupported) ||
      (word.size() == 4 && word.starts_with("wcs") && std::isalpha(word[3]))) {
    fail(context, "coordinate system '" + word + "' is not supported (image, physical, fk5, icrs)");
  }
  return std::nullopt;
}

// One ';'-separated part of a line: a coordinate system, a global line or a shape.
void parsePart(const ParseContext& context, std::string_view part, RegionSystem& system,
               bool& systemSet, int lineNumber, std::vector<RegionShape>& shapes) {
  part = trimWhitespace(part);
  if (part.empty()) return;
  const std::string word = lowercase(part);
  if (word.starts_with("global")) return;
  if (const auto named = coordinateSystem(context, word)) {
    system = *named;
    systemSet = true;
    return;
  }
  bool exclude = false;
  std::string_view body = part;
  if (body.front() == '-' || body.front() == '+') {
    exclude = body.front() == '-';
    body = trimWhitespace(body.substr(1));
  }
  const auto open = body.find('(');
  const auto close = body.rfind(')');
  if (open == std::string_view::npos || close == std::string_view::npos || close < open ||
      !trimWhitespace(body.substr(close + 1)).empty()) {
    fail(context, "cannot read '" + std::string(part) + "' as a region shape");
  }
  std::string name = lowercase(trimWhitespace(body.substr(0, open)));
  // DS9 also writes points as "circle point(x, y)", "box point(x, y)", ...
  if (name.size() > 6 && name.ends_with(" point")) name = "point";
  const auto args = splitArguments(context, body.substr(open + 1, close - open - 1));
  if (isAreaLessShape(name)) return;
  if (isUnsupportedShape(name)) fail(context, "shape '" + name + "' is not supported");
  if (!systemSet) system = RegionSystem::Physical;  // DS9's default coordinate system
  RegionShape shape;
  if (name == "circle") {
    if (args.size() != 3) fail(context, "circle needs x, y, radius");
    shape = centredShape(context, system, RegionShapeKind::Circle, args);
  } else if (name == "box" || name == "ellipse") {
    const auto kind = name == "box" ? RegionShapeKind::Box : RegionShapeKind::Ellipse;
    if (args.size() != 4 && args.size() != 5) {
      fail(context, name +
                        " needs x, y, two sizes and an optional angle (annuli are not "
                        "supported)");
    }
    shape = centredShape(context, system, kind, args);
  } else if (name == "annulus") {
    if (args.size() != 4) {
      fail(context, "annulus needs x, y, inner and outer radius (one annulus per shape)");
    }
    shape = centredShape(context, system, RegionShapeKind::Annulus, args);
  } else if (name == "point") {
    shape = pointShape(context, system, args);
  } else if (name == "polygon") {
    if (args.size() < 6 || args.size() % 2 != 0) {
      fail(context, "polygon needs at least three x, y vertices");
    }
    shape.kind = RegionShapeKind::Polygon;
    for (std::size_t i = 0; i < args.size(); i += 2) {
      shape.vertices.push_back(position(context, system, args, i));
    }
  } else {
    fail(context, "unknown region shape '" + name + "'");
  }
  shape.exclude = exclude;
  shape.lineNumber = lineNumber;
  shapes.push_back(std::move(shape));
}

// The ';'-separated parts of a line up to its comment or properties ('#' outside parentheses).
std::vector<std::string_view> lineParts(std::string_view line) {
  std::vector<std::string_view> parts;
  int depth = 0;
  std::size_t start = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '(') {
      ++depth;
    } else if (c == ')') {
      --depth;
    } else if (c == '#' && depth == 0) {
      line = line.substr(0, i);
      break;
    } else if (c == ';' && depth == 0) {
      parts.push_back(line.substr(start, i - start));
      start = i + 1;
    }
  }
  if (start < line.size()) parts.push_back(line.substr(start));
  return parts;
}

}  // namespace

bool RegionShape::contains(double xFits, double yFits) const {
  if (kind == RegionShapeKind::Polygon) {
    // Even-odd rule: count the edges crossed by a ray towards +x.
    bool inside = false;
    const std::size_t n = vertices.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
      const auto& a = vertices[i];
      const auto& b = vertices[j];
      if ((a[1] > yFits) != (b[1] > yFits)) {
        const double xCross = a[0] + (yFits - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
        if (xFits < xCross) inside = !inside;
      }
    }
    return inside;
  }
  const double dx = xFits - xCentre;
  const double dy = yFits - yCentre;
  if (kind == RegionShapeKind::Circle) return dx * dx + dy * dy <= semiAxis1Pix * semiAxis1Pix;
  if (kind == RegionShapeKind::Annulus) {
    const double r2 = dx * dx + dy * dy;
    return r2 <= semiAxis1Pix * semiAxis1Pix && r2 >= semiAxis2Pix * semiAxis2Pix;
  }
  const double c = std::cos(angleRad);
  const double s = std::sin(angleRad);
  const double u = c * dx + s * dy;
  const double v = -s * dx + c * dy;
  if (kind == RegionShapeKind::Box) {
    return std::fabs(u) <= semiAxis1Pix && std::fabs(v) <= semiAxis2Pix;
  }
  if (semiAxis1Pix <= 0.0 || semiAxis2Pix <= 0.0) return false;
  const double p = u / semiAxis1Pix;
  const double q = v / semiAxis2Pix;
  return p * p + q * q <= 1.0;
}

std::array<double, 4> RegionShape::bounds() const {
  if (kind == RegionShapeKind::Polygon) {
    std::array<double, 4> box = {vertices[0][0], vertices[0][0], vertices[0][1], vertices[0][1]};
    for (const auto& v : vertices) {
      box[0] = std::min(box[0], v[0]);
      box[1] = std::max(box[1], v[0]);
      box[2] = std::min(box[2], v[1]);
      box[3] = std::max(box[3], v[1]);
    }
    return box;
  }
  double halfX = semiAxis1Pix;
  double halfY = semiAxis1Pix;
  const double c = std::fabs(std::cos(angleRad));
  const double s = std::fabs(std::sin(angleRad));
  if (kind == RegionShapeKind::Box) {
    halfX = c * semiAxis1Pix + s * semiAxis2Pix;
    halfY = s * semiAxis1Pix + c * semiAxis2Pix;
  } else if (kind == RegionShapeKind::Ellipse) {
    halfX = std::hypot(semiAxis1Pix * c, semiAxis2Pix * s);
    halfY = std::hypot(semiAxis1Pix * s, semiAxis2Pix * c);
  }
  return {xCentre - halfX, xCentre + halfX, yCentre - halfY, yCentre + halfY};
}

std::vector<RegionShape> parseDs9Regions(const std::string& text,
                                         const std::string& regionFileForErrors,
                                         const FitsHeader& imageHeader,
                                         const std::string& imageNameForErrors,
                                         double pointRadiusPix) {
  ParseContext context;
  context.pointRadiusPix = pointRadiusPix;
  // Checked only when a sky shape is read: image-coordinate files work on any image, even one
  // whose WCS cards are broken.
  std::optional<Wcs> wcs;
  try {
    wcs = Wcs::fromHeader(imageHeader, imageNameForErrors);
  } catch (const Error& e) {
    context.wcsProblem = e.what();
  }
  if (!context.wcsProblem.empty()) {
    // the WCS error already names the image
  } else if (!wcs) {
    context.wcsProblem = imageNameForErrors + " has no celestial WCS (use image coordinates)";
  } else if (wcs->radesys() != "ICRS" && !(wcs->radesys() == "FK5" && wcs->equinox() == 2000.0)) {
    const std::string frame = wcs->radesys().empty() ? "not equatorial" : wcs->radesys();
    context.wcsProblem = "the WCS of " + imageNameForErrors + " is " + frame +
                         ", not ICRS or FK5 J2000 as the region file";
  } else {
    context.wcs = &*wcs;
  }
  // Like the WCS, the LTV / LTM cards matter only to shapes in physical coordinates: a card
  // that is no number (a string, "NaN") is reported when one is read.
  std::string physicalProblem;
  const auto physicalCard = [&](const char* key, double absent) {
    const std::optional<std::string> text = imageHeader.value(key);
    if (!text) return absent;
    const std::optional<double> v = imageHeader.number(key);
    if (!v && physicalProblem.empty()) {
      physicalProblem = "the " + std::string(key) + " card of " + imageNameForErrors + " (" +
                        quoteForMessage(*text) + ") is not a finite number";
    }
    return v.value_or(absent);
  };
  const double ltm1 = physicalCard("LTM1_1", 1.0);
  const double ltm2 = physicalCard("LTM2_2", 1.0);
  const double cross1 = physicalCard("LTM1_2", 0.0);
  const double cross2 = physicalCard("LTM2_1", 0.0);
  context.ltm = ltm1;
  context.ltv1 = physicalCard("LTV1", 0.0);
  context.ltv2 = physicalCard("LTV2", 0.0);
  if (physicalProblem.empty() && !(ltm1 == ltm2 && ltm1 > 0.0 && cross1 == 0.0 && cross2 == 0.0)) {
    physicalProblem = "the LTM cards of " + imageNameForErrors + " are not a uniform scale";
  }

  std::vector<RegionShape> shapes;
  std::istringstream lines(text);
  std::string line;
  int lineNumber = 0;
  RegionSystem system = RegionSystem::Physical;
  bool systemSet = false;
  while (std::getline(lines, line)) {
    ++lineNumber;
    context.where = regionFileForErrors + ":" + std::to_string(lineNumber);
    for (const auto part : lineParts(line)) {
      const std::size_t before = shapes.size();
      parsePart(context, part, system, systemSet, lineNumber, shapes);
      if (shapes.size() > before && system == RegionSystem::Physical && !physicalProblem.empty()) {
        fail(context, "physical coordinates, but " + physicalProblem);
      }
    }
  }
  return shapes;
}

std::vector<RegionShape> readDs9Regions(const std::filesystem::path& regionFile,
                                        const FitsHeader& imageHeader,
                                        const std::string& imageNameForErrors,
                                        double pointRadiusPix) {
  std::ifstream in(regionFile, std::ios::binary);
  if (!in) throw IoError(regionFile.string() + ": cannot open region file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(regionFile.string() + ": cannot read region file");
  return parseDs9Regions(text.str(), regionFile.string(), imageHeader, imageNameForErrors,
                         pointRadiusPix);
}

bool regionContains(const std::vector<RegionShape>& shapes, double xFits, double yFits) {
  bool anyInclude = false;
  bool inInclude = false;
  for (const auto& shape : shapes) {
    if (shape.exclude) {
      if (shape.contains(xFits, yFits)) return false;
    } else {
      anyInclude = true;
      if (!inInclude && shape.contains(xFits, yFits)) inInclude = true;
    }
  }
  return inInclude || !anyInclude;
}

std::string formatDs9Regions(const std::vector<RegionMark>& marks, const Wcs* skyWcs) {
  const Wcs* wcs = skyWcs != nullptr && skyWcs->isJ2000Equatorial() ? skyWcs : nullptr;
  std::ostringstream out;
  out.precision(12);  // 1e-9 degree (4 micro-arcsec) on the sky, 1e-8 pixel
  out << "# Region file format: DS9 version 4.1\n"
      << "global color=green width=1 font=\"helvetica 10 normal roman\"\n"
      << (wcs != nullptr ? "fk5\n" : "image\n");
  for (const RegionMark& m : marks) {
    if (m.kind != RegionShapeKind::Circle && m.kind != RegionShapeKind::Ellipse) {
      throw ConfigError("region marks: only circles and ellipses are written");
    }
    const bool circle = m.kind == RegionShapeKind::Circle;
    double x = m.xCentre, y = m.yCentre, r1 = m.semiAxis1Pix, r2 = m.semiAxis2Pix;
    double angleDeg = m.angleRad / kRadPerDeg;
    const char* sizeUnit = "";
    if (wcs != nullptr) {
      const auto sky = wcs->pixelToWorld(m.xCentre, m.yCentre);
      const std::optional<LocalSkyFrame> frame = std::isfinite(sky[0]) && std::isfinite(sky[1])
                                                     ? localSkyFrameOf(*wcs, sky[0], sky[1])
                                                     : std::nullopt;
      if (!frame) {
        throw ConfigError("region marks: the WCS gives no sky position for pixel (" +
                          std::to_string(m.xCentre) + ", " + std::to_string(m.yCentre) + ")");
      }
      x = sky[0] - 360.0 * std::floor(sky[0] / 360.0);
      y = sky[1];
      r1 /= frame->pixPerArcsec;
      r2 /= frame->pixPerArcsec;
      angleDeg = skyAngleDeg(*frame, m.angleRad);
      sizeUnit = "\"";
    }
    out << (circle ? "circle(" : "ellipse(") << x << "," << y << "," << r1 << sizeUnit;
    if (!circle) out << "," << r2 << sizeUnit << "," << angleDeg;
    out << ") # color=" << m.colour;
    if (!m.text.empty()) {
      std::string label;
      for (const char c : m.text) {
        if (c != '{' && c != '}' && c != '\n') label += c;
      }
      out << " text={" << label << "}";
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace octarc
