#include "octarc/search/Inspection.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "octarc/core/Conventions.h"
#include "octarc/core/Format.h"
#include "octarc/core/Statistics.h"

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

// A number for a data-* attribute (sortable: NaN sorts last through "NaN").
std::string dataNumber(double v) {
  return std::isfinite(v) ? formatNumber(v, "%.8g") : "NaN";
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
  stamp.pixels = ImageF(side, side, std::numeric_limits<float>::quiet_NaN());
  std::vector<double> values;
  values.reserve(std::size_t(side * side));
  for (std::int64_t j = 0; j < side; ++j) {
    const std::int64_t y = j0 + j;
    if (y < 0 || y >= image.height()) continue;
    for (std::int64_t i = 0; i < side; ++i) {
      const std::int64_t x = i0 + i;
      if (x < 0 || x >= image.width()) continue;
      const float v = image(x, y);
      stamp.pixels(i, j) = v;
      if (std::isfinite(v)) values.push_back(v);
    }
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
    l.label = "lens";
    stamp.marks.push_back(l);
  }
  stamp.title = "#" + std::to_string(index + 1) + (cand.name.empty() ? "" : "  " + cand.name);
  std::ostringstream sub;
  sub << "a = " << formatNumber(valueOf(catalog, cand.row, "ARCNESS"), "%.3f", true)
      << "  e = " << formatNumber(valueOf(catalog, cand.row, "E_IMAGE"), "%.2f", true)
      << "  S/N = " << formatNumber(valueOf(catalog, cand.row, "SNR_ISO"), "%.0f", true);
  if (cand.lens) {
    sub << "  theta_E = " << formatNumber(cand.lens->einsteinRadiusArcsec, "%.2f") << "\"";
  } else {
    sub << "  no lens seen";
  }
  stamp.subtitle = sub.str();
  stamp.sizePix = settings.sizePix;
  return stamp;
}

namespace {

// "g 0.21 / 1.35": per band, the arc's and the lens's colour (minus the measurement band).
std::string colourText(const Candidate& c, const std::vector<std::string>& bands) {
  std::string text;
  for (std::size_t k = 0; k < bands.size(); ++k) {
    auto colour = [&](const std::vector<BandMagnitude>& mags) {
      return mags.size() > k + 1 ? colourOf(mags[k + 1], mags[0]).value : std::nan("");
    };
    text += (text.empty() ? "" : "; ") + escapeHtml(bands[k]) + " " +
            formatNumber(colour(c.arcMags), "%.2f", true) + " / " +
            formatNumber(colour(c.lensMags), "%.2f", true);
  }
  return text;
}

}  // namespace

std::string contactSheetHtml(const Table& catalog, const SearchResult& result,
                             const ContactSheetInfo& info) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
    << "<title>" << escapeHtml(info.title) << "</title>\n"
    << "<style>\n"
       "body{font-family:sans-serif;background:#202020;color:#e8e8e8;margin:1em}\n"
       "a{color:#9cf}\n"
       "#grid{display:flex;flex-wrap:wrap;gap:10px}\n"
       ".card{background:#303030;padding:6px;width:210px;font-size:12px}\n"
       ".card img{width:200px;height:200px;display:block}\n"
       "table{border-collapse:collapse;margin-top:1.5em;font-size:12px}\n"
       "td,th{border:1px solid #555;padding:2px 6px;text-align:right}\n"
       "button{margin-right:4px}\n"
       "</style>\n</head>\n<body>\n"
    << "<h1>" << escapeHtml(info.title) << "</h1>\n<p>";
  for (const std::string& line : info.summaryLines) o << escapeHtml(line) << "<br>\n";
  o << "Catalog: <a href=\"" << escapeHtml(info.catalogFile) << "\">"
    << escapeHtml(info.catalogFile) << "</a>; DS9 regions: <a href=\""
    << escapeHtml(info.regionFile) << "\">" << escapeHtml(info.regionFile) << "</a></p>\n"
    << "<p>Sort by: <button data-key=\"score\">score</button>"
       "<button data-key=\"prob\">probability</button>"
       "<button data-key=\"arcness\">arcness</button><button data-key=\"snr\">S/N</button>"
       "<button data-key=\"mag\" data-asc=\"1\">magnitude</button>"
       "<button data-key=\"number\" data-asc=\"1\">number</button> "
       "<span id=\"status\">loading</span></p>\n"
    << "<div id=\"grid\">\n";
  std::ostringstream rows;
  for (std::size_t i = 0; i < result.candidates.size(); ++i) {
    const Candidate& c = result.candidates[i];
    const std::string stamp = stampFileName(i);
    const double arcness = valueOf(catalog, c.row, "ARCNESS");
    const double snr = valueOf(catalog, c.row, "SNR_ISO");
    const double mag = valueOf(catalog, c.row, "MAG_ISO");
    const std::string id = "c" + std::to_string(i + 1);
    o << "<div class=\"card\" data-number=\"" << (i + 1) << "\" data-score=\""
      << dataNumber(c.lensScore) << "\" data-prob=\"" << dataNumber(c.probability)
      << "\" data-arcness=\"" << dataNumber(arcness) << "\" data-snr=\"" << dataNumber(snr)
      << "\" data-mag=\"" << dataNumber(mag) << "\">"
      << "<a href=\"" << stamp << "\"><img src=\"" << stamp << "\" alt=\"candidate " << (i + 1)
      << "\"></a><a href=\"#" << id << "\">#" << (i + 1) << "</a> " << escapeHtml(c.name)
      << "<br>score " << formatNumber(c.lensScore, "%.3g") << ", a "
      << formatNumber(arcness, "%.3f", true) << ", S/N " << formatNumber(snr, "%.0f", true)
      << "</div>\n";
    rows << "<tr id=\"" << id << "\"><td>" << (i + 1) << "</td><td>" << escapeHtml(c.name)
         << "</td><td>" << formatNumber(valueOf(catalog, c.row, "X_IMAGE"), "%.2f", true)
         << "</td><td>" << formatNumber(valueOf(catalog, c.row, "Y_IMAGE"), "%.2f", true)
         << "</td><td>" << formatNumber(mag, "%.2f", true) << "</td><td>"
         << formatNumber(arcness, "%.4f", true) << "</td><td>"
         << formatNumber(valueOf(catalog, c.row, "E_IMAGE"), "%.3f", true) << "</td><td>"
         << formatNumber(snr, "%.1f", true) << "</td><td>" << formatNumber(c.lensScore, "%.4g")
         << "</td><td>" << formatNumber(c.probability, "%.4g") << "</td><td>"
         << formatNumber(c.contourLevel, "%.4f", true) << "</td><td>";
    for (std::size_t k = 0; k < c.passedLevels.size(); ++k) {
      rows << (k ? "," : "") << c.passedLevels[k];
    }
    rows << "</td><td>"
         << (c.lens ? formatNumber(c.lens->einsteinRadiusArcsec, "%.2f")
                    : std::string(c.flags & kCandidateDarkLensPair ? "dark pair" : "dark?"));
    if (!info.colourBands.empty()) rows << "</td><td>" << colourText(c, info.colourBands);
    rows << "</td><td><a href=\"" << stamp << "\">stamp</a></td></tr>\n";
  }
  o << "</div>\n<table>\n<tr><th>#</th><th>name</th><th>X_IMAGE</th><th>Y_IMAGE</th>"
       "<th>MAG_ISO</th><th>ARCNESS</th><th>E_IMAGE</th><th>SNR_ISO</th><th>LENS_SCORE</th>"
       "<th>PROB</th>"
       "<th>CONTOUR</th><th>levels</th><th>&theta;<sub>E</sub> [\"]</th>"
    << (info.colourBands.empty() ? "" : "<th>colours arc / lens</th>") << "<th></th></tr>\n"
    << rows.str() << "</table>\n"
    << "<script>\n"
       "function sortCards(key, asc) {\n"
       "  const grid = document.getElementById('grid');\n"
       "  const cards = Array.from(grid.children);\n"
       "  const v = c => { const x = parseFloat(c.dataset[key]); return isNaN(x) ? null : x; };\n"
       "  cards.sort((a, b) => { const x = v(a), y = v(b);\n"
       "    if (x === null || y === null) return (x === null) - (y === null);\n"
       "    return asc ? x - y : y - x; });\n"
       "  cards.forEach(c => grid.appendChild(c));\n"
       "  grid.dataset.sorted = key + (asc ? '-asc' : '-desc');\n"
       "}\n"
       "document.querySelectorAll('button[data-key]').forEach(b => b.addEventListener('click',\n"
       "  () => sortCards(b.dataset.key, b.dataset.asc === '1')));\n"
       "const m = /sort=([a-z]+)(-asc)?/.exec(location.hash);\n"
       "if (m) sortCards(m[1], !!m[2]);\n"
       "window.addEventListener('load', () => {\n"
       "  const imgs = Array.from(document.querySelectorAll('#grid img'));\n"
       "  const ok = imgs.filter(i => i.complete && i.naturalWidth > 0).length;\n"
       "  document.getElementById('status').textContent = 'images ' + ok + '/' + imgs.length +\n"
       "    ' loaded; order ' + Array.from(document.getElementById('grid').children)\n"
       "    .map(c => c.dataset.number).join(',');\n"
       "});\n"
       "</script>\n</body>\n</html>\n";
  return o.str();
}

}  // namespace octarc
