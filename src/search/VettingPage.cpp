#include "octarc/search/VettingPage.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/search/Inspection.h"

namespace octarc {

namespace {

// A JSON string; '<' escaped so that no "</script>" can end the embedding element.
std::string jsonString(std::string_view text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == '<' || c == '>' || c == '&') {
      char code[8];
      std::snprintf(code, sizeof code, "\\u%04x", unsigned(c));
      out += code;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// A JSON number (null when not finite: JSON has no NaN); 12 digits keep RA to 1e-9 degree.
std::string jsonNumber(double v) {
  return std::isfinite(v) ? formatNumber(v, "%.12g") : "null";
}

// A numeric column's values, or NaN per row when the catalog has no such column.
std::vector<double> numbersOr(const FitsTable& t, const char* name) {
  if (t.findColumn(name) != nullptr) return t.doubles(name);
  return std::vector<double>(std::size_t(t.rows()), std::nan(""));
}

std::vector<std::string> textsOr(const FitsTable& t, const char* name) {
  if (t.findColumn(name) != nullptr) return t.strings(name);
  return std::vector<std::string>(std::size_t(t.rows()));
}

// The colour bands of the catalog: B of every ARC_COLOUR_B column (not ARC_COLOURERR_B).
std::vector<std::string> colourBandsOf(const FitsTable& t) {
  std::vector<std::string> bands;
  const std::string prefix = "ARC_COLOUR_";
  for (const FitsColumn& c : t.columns) {
    if (c.name.rfind(prefix, 0) == 0 &&
        t.findColumn("LENS_COLOUR_" + c.name.substr(prefix.size()))) {
      bands.push_back(c.name.substr(prefix.size()));
    }
  }
  return bands;
}

// The candidates as JSON: {"key", "tiles", "bands", "rows": [{...}, ...]}.
std::string candidatesJson(const FitsTable& t, const VettingPageInfo& info) {
  const std::size_t n = std::size_t(t.rows());
  const std::vector<std::int64_t> number = t.integers("NUMBER");
  const std::vector<std::string> name = textsOr(t, "NAME"), tile = textsOr(t, "TILE"),
                                 grade = textsOr(t, "GRADE");
  const std::vector<double> ra = numbersOr(t, "ALPHA_J2000"), dec = numbersOr(t, "DELTA_J2000"),
                            score = numbersOr(t, "LENS_SCORE"), prob = numbersOr(t, "PROB"),
                            arcness = numbersOr(t, "ARCNESS"), snr = numbersOr(t, "SNR_ISO"),
                            mag = numbersOr(t, "MAG_ISO"), dist = numbersOr(t, "LENS_DIST"),
                            thetaE = numbersOr(t, "THETA_E"), flags = numbersOr(t, "CAND_FLAGS"),
                            tileNumber = numbersOr(t, "TILE_NUMBER");
  const std::vector<std::string> bands = colourBandsOf(t);
  std::vector<std::vector<double>> arcColour, lensColour;
  for (const std::string& b : bands) {
    arcColour.push_back(t.doubles("ARC_COLOUR_" + b));
    lensColour.push_back(t.doubles("LENS_COLOUR_" + b));
  }
  const bool tiles = t.findColumn("TILE") != nullptr;
  std::ostringstream o;
  o << "{\"key\":" << jsonString(vettingStorageKey(t, info.title))
    << ",\"tiles\":" << (tiles ? "true" : "false") << ",\"bands\":[";
  for (std::size_t k = 0; k < bands.size(); ++k) o << (k ? "," : "") << jsonString(bands[k]);
  o << "],\"rows\":[";
  for (std::size_t i = 0; i < n; ++i) {
    o << (i ? ",\n" : "\n") << "{\"n\":" << number[i] << ",\"name\":" << jsonString(name[i])
      << ",\"ra\":" << jsonNumber(ra[i]) << ",\"dec\":" << jsonNumber(dec[i])
      << ",\"score\":" << jsonNumber(score[i]) << ",\"prob\":" << jsonNumber(prob[i])
      << ",\"arcness\":" << jsonNumber(arcness[i]) << ",\"snr\":" << jsonNumber(snr[i])
      << ",\"mag\":" << jsonNumber(mag[i]) << ",\"dist\":" << jsonNumber(dist[i])
      << ",\"te\":" << jsonNumber(thetaE[i])
      << ",\"flags\":" << (std::isfinite(flags[i]) ? std::int64_t(flags[i]) : 0);
    if (tiles) o << ",\"tile\":" << jsonString(tile[i]) << ",\"tn\":" << jsonNumber(tileNumber[i]);
    if (!bands.empty()) {
      o << ",\"colours\":[";
      for (std::size_t k = 0; k < bands.size(); ++k) {
        o << (k ? "," : "") << "[" << jsonNumber(arcColour[k][i]) << ","
          << jsonNumber(lensColour[k][i]) << "]";
      }
      o << "]";
    }
    if (!grade[i].empty()) o << ",\"grade\":" << jsonString(grade[i]);
    o << ",\"stamp\":" << jsonString(info.stampFiles[i]);
    if (i < info.colourStampFiles.size() && !info.colourStampFiles[i].empty()) {
      o << ",\"colour\":" << jsonString(info.colourStampFiles[i]);
    }
    if (i < info.cutoutFiles.size() && !info.cutoutFiles[i].empty()) {
      o << ",\"cutout\":" << jsonString(info.cutoutFiles[i]);
    }
    o << "}";
  }
  o << "]}";
  return o.str();
}

constexpr const char* kStyle = R"CSS(
body{font-family:sans-serif;background:#202020;color:#e8e8e8;margin:1em}
a{color:#9cf}
summary{cursor:pointer}
#controls{position:sticky;top:0;background:#202020;padding:6px 0;z-index:1;
  display:flex;flex-wrap:wrap;gap:4px 14px;align-items:center;font-size:13px}
#controls input[type=number]{width:6em}
#grid{display:flex;flex-wrap:wrap;gap:10px;margin-top:8px}
.card{background:#303030;padding:5px;width:200px;font-size:12px;border:2px solid #303030}
.card.current{border-color:#fc3}
.card img{width:200px;height:200px;display:block;background:#181818}
.card .nostamp{width:200px;height:40px;color:#888}
.caption{margin:3px 0;line-height:1.35;overflow-wrap:anywhere}
.grades button{font-size:11px;margin-right:2px;background:#444;color:#eee;border:1px solid #666}
.card[data-grade=lens] button[data-grade=lens]{background:#2a7a2a}
.card[data-grade=maybe] button[data-grade=maybe]{background:#8a7a10}
.card[data-grade=no] button[data-grade=no]{background:#8a2a2a}
.card[data-grade=lens]{border-color:#2a7a2a}
.card[data-grade=maybe]{border-color:#8a7a10}
.card[data-grade=no]{border-color:#8a2a2a}
.card.current[data-grade]{outline:2px solid #fc3}
#pager{margin:10px 0}
.keys{color:#aaa;font-size:12px}
)CSS";

// Draws the cards of the page shown from the embedded JSON; the grades live in localStorage.
constexpr const char* kScript = R"JS(
'use strict';
const data = JSON.parse(document.getElementById('candidates').textContent);
const rows = data.rows;
const perPage = PER_PAGE;
const storageKey = 'octarc-grades:' + data.key;
const gradeNames = ['lens', 'maybe', 'no'];
const $ = id => document.getElementById(id);
let grades = {};
try { grades = JSON.parse(localStorage.getItem(storageKey)) || {}; } catch (e) { grades = {}; }
// A graded catalog's own grades, until the browser has some for it.
if (Object.keys(grades).length === 0) for (const r of rows) if (r.grade) grades[r.n] = r.grade;
let shown = [];   // the rows passing the filters, in sort order
let pageIndex = 0;
let current = 0;  // index in shown of the current card

const entities = {'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;'};
const esc = s => String(s).replace(/[&<>"]/g, c => entities[c]);
const fixed = (v, digits) => v === null ? '&ndash;' : v.toFixed(digits);
const general = v => v === null ? '&ndash;' : v.toPrecision(3);
const flagNames = {1: 'no visible lens', 2: 'no curvature', 4: 'no WCS', 8: 'side unknown',
                   16: 'lens-light residual', 32: 'dark-lens pair', 64: 'lens in arc'};

function saveGrades() {
  try { localStorage.setItem(storageKey, JSON.stringify(grades)); } catch (e) { /* private mode */ }
}

function passes(r, f) {
  const atLeast = (v, min) => isNaN(min) || (v !== null && v >= min);
  return atLeast(r.score, f.minScore) && atLeast(r.arcness, f.minArcness) &&
    (f.flag === '' || (f.flag === '0' ? r.flags === 0 : (r.flags & Number(f.flag)) !== 0)) &&
    (f.lens === '' || (f.lens === 'dark') === ((r.flags & 1) !== 0)) &&
    (f.tile === '' || r.tile === f.tile) &&
    (f.grade === '' || (grades[r.n] || 'none') === f.grade);
}

function apply() {
  const f = {minScore: parseFloat($('min-score').value),
             minArcness: parseFloat($('min-arcness').value), flag: $('flag').value,
             lens: $('lens').value, tile: $('tile').value, grade: $('grade').value};
  const key = $('sort').value, sign = $('ascending').checked ? 1 : -1;
  shown = rows.filter(r => passes(r, f));
  // Missing values last in either direction; ties by number.
  shown.sort((a, b) => (a[key] === null) - (b[key] === null) ||
             (a[key] === null ? 0 : sign * (a[key] - b[key])) || a.n - b.n);
  pageIndex = 0;
  current = 0;
  render();
}

function card(r) {
  const div = document.createElement('div');
  div.className = 'card';
  div.dataset.number = r.n;
  if (grades[r.n]) div.dataset.grade = grades[r.n];
  const lens = r.flags & 1 ? 'no visible lens'
      : 'lens ' + fixed(r.dist, 2) + '&Prime;, &theta;<sub>E</sub> ' + fixed(r.te, 2) + '&Prime;';
  const flags = Object.keys(flagNames).filter(b => b > 1 && (r.flags & b)).map(b => flagNames[b]);
  const colours = (data.bands || []).map((b, k) =>
      esc(b) + ' ' + fixed(r.colours[k][0], 2) + ' / ' + fixed(r.colours[k][1], 2)).join('; ');
  const stamp = r.colour && $('colour').checked ? r.colour : r.stamp;
  div.innerHTML =
      (stamp ? '<a href="' + esc(stamp) + '"><img src="' + esc(stamp) +
                 '" loading="lazy" width="200" height="200" alt="candidate ' + r.n + '"></a>'
               : '<div class="nostamp">no stamp</div>') +
      '<div class="caption"><b>#' + r.n + '</b> ' + esc(r.name) +
      '<br>score ' + general(r.score) + ' &middot; arcness ' + fixed(r.arcness, 3) +
      '<br>S/N ' + fixed(r.snr, 0) + ' &middot; ' + lens +
      (flags.length ? '<br>' + flags.join(', ') : '') +
      (colours ? '<br>colours arc / lens: ' + colours : '') +
      (data.tiles ? '<br>tile ' + esc(r.tile) + ' #' + r.tn : '') +
      (r.cutout ? '<br><a href="' + esc(r.cutout) + '">FITS cut-out</a>' : '') + '</div>' +
      '<div class="grades">' + gradeNames.map((g, k) =>
          '<button data-grade="' + g + '" title="key ' + (k + 1) + '">' + g + '</button>')
        .join('') +
      '</div>';
  return div;
}

function render() {
  const pages = Math.max(1, Math.ceil(shown.length / perPage));
  pageIndex = Math.min(Math.max(pageIndex, 0), pages - 1);
  const first = pageIndex * perPage;
  $('grid').replaceChildren(...shown.slice(first, first + perPage).map(card));
  const count = $('count');
  count.textContent = shown.length + ' of ' + rows.length + ' candidates shown; page ' +
      (pageIndex + 1) + ' of ' + pages;
  count.dataset.matching = shown.length;
  count.dataset.page = pageIndex + 1;
  $('previous').disabled = pageIndex === 0;
  $('next').disabled = pageIndex + 1 >= pages;
  markCurrent(false);
}

function markCurrent(scroll) {
  const cards = $('grid').children;
  for (const c of cards) c.classList.remove('current');
  const c = cards[current - pageIndex * perPage];
  if (!c) return;
  c.classList.add('current');
  if (scroll) c.scrollIntoView({block: 'nearest'});
}

function move(step) {
  if (shown.length === 0) return;
  current = Math.min(Math.max(current + step, 0), shown.length - 1);
  const page = Math.floor(current / perPage);
  if (page !== pageIndex) {
    pageIndex = page;
    render();
  }
  markCurrent(true);
}

function setGrade(number, grade) {
  if (grade) grades[number] = grade; else delete grades[number];
  saveGrades();
  const c = $('grid').querySelector('.card[data-number="' + number + '"]');
  if (c && grade) c.dataset.grade = grade; else if (c) delete c.dataset.grade;
}

const csvField = v => v === null || v === undefined ? '' : /[",\n]/.test(String(v))
    ? '"' + String(v).replace(/"/g, '""') + '"' : String(v);

function exportCsv(link) {
  const columns = ['NUMBER'].concat(data.tiles ? ['TILE', 'TILE_NUMBER'] : [],
                                    ['NAME', 'ALPHA_J2000', 'DELTA_J2000', 'GRADE']);
  const lines = [columns.join(',')];
  for (const r of rows) {
    if (!grades[r.n]) continue;
    const values = [r.n].concat(data.tiles ? [r.tile, r.tn] : [],
                                [r.name, r.ra, r.dec, grades[r.n]]);
    lines.push(values.map(csvField).join(','));
  }
  link.href = 'data:text/csv;charset=utf-8,' + encodeURIComponent(lines.join('\n') + '\n');
}

$('grid').addEventListener('click', e => {
  const button = e.target.closest('button[data-grade]');
  const c = e.target.closest('.card');
  if (!c) return;
  current = pageIndex * perPage + Array.prototype.indexOf.call($('grid').children, c);
  markCurrent(false);
  // A second click on the card's grade clears it.
  if (button) {
    const grade = button.dataset.grade;
    setGrade(c.dataset.number, c.dataset.grade === grade ? '' : grade);
  }
});
document.addEventListener('keydown', e => {
  const typing = e.target instanceof Element && e.target.closest('input, select, textarea');
  if (typing || e.ctrlKey || e.metaKey || e.altKey) return;
  const r = shown[current];
  if (e.key === 'j') move(1);
  else if (e.key === 'k') move(-1);
  else if (r && '123'.includes(e.key)) setGrade(r.n, gradeNames[Number(e.key) - 1]);
  else if (r && e.key === '0') setGrade(r.n, '');
  else return;
  e.preventDefault();
});
function turnPage(step) {
  pageIndex += step;
  current = pageIndex * perPage;
  render();
}
$('previous').addEventListener('click', () => turnPage(-1));
$('next').addEventListener('click', () => turnPage(1));
$('export').addEventListener('click', e => exportCsv(e.currentTarget));
$('sort').addEventListener('change', () => {
  $('ascending').checked = $('sort').selectedOptions[0].dataset.ascending === '1';
  apply();
});
for (const id of ['ascending', 'min-score', 'min-arcness', 'flag', 'lens', 'tile', 'grade']) {
  $(id).addEventListener('change', apply);
}
if (rows.some(r => r.colour)) $('colour-toggle').hidden = false;
$('colour').addEventListener('change', render);
if (data.tiles) {
  const tiles = [...new Set(rows.map(r => r.tile))].sort();
  for (const t of tiles) $('tile').add(new Option(t, t));
  $('tile-filter').hidden = false;
}
// "#sort=KEY" or "#sort=KEY-asc" in the address picks the order.
const wanted = /sort=([a-z]+)(-asc)?/.exec(location.hash);
if (wanted && $('sort').querySelector('option[value="' + wanted[1] + '"]')) {
  $('sort').value = wanted[1];
  $('ascending').checked = !!wanted[2];
}
apply();
)JS";

constexpr const char* kControls = R"HTML(<div id="controls">
<label>Sort <select id="sort">
<option value="score">LENS_SCORE</option><option value="prob">PROB</option>
<option value="arcness">ARCNESS</option><option value="snr">S/N</option>
<option value="mag" data-ascending="1">MAG_ISO</option>
<option value="n" data-ascending="1">NUMBER</option></select></label>
<label><input type="checkbox" id="ascending"> ascending</label>
<label>score &ge; <input type="number" id="min-score" step="any"></label>
<label>arcness &ge; <input type="number" id="min-arcness" step="any"></label>
<label>flags <select id="flag"><option value="">any</option><option value="0">none</option>
<option value="2">2 no curvature</option><option value="8">8 side unknown</option>
<option value="16">16 lens-light residual</option><option value="32">32 dark-lens pair</option>
<option value="64">64 lens in arc</option></select></label>
<label>lens <select id="lens"><option value="">any</option>
<option value="dark">no visible lens</option><option value="seen">visible lens</option>
</select></label>
<label id="tile-filter" hidden>tile <select id="tile"><option value="">all</option></select></label>
<label>grade <select id="grade"><option value="">any</option><option value="none">ungraded</option>
<option value="lens">lens</option><option value="maybe">maybe</option><option value="no">no</option>
</select></label>
<label id="colour-toggle" hidden><input type="checkbox" id="colour"> colour stamps</label>
<a id="export" href="#" download="grades.csv">Export CSV</a>
<span id="count"></span>
</div>
)HTML";

std::uint64_t fnv1a(std::uint64_t hash, std::string_view text) {
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace

std::vector<std::string> catalogStampFiles(const FitsTable& candidates) {
  std::vector<std::string> files;
  if (candidates.findColumn("TILE") != nullptr && candidates.findColumn("TILE_NUMBER") != nullptr) {
    const std::vector<std::string> tile = candidates.strings("TILE");
    const std::vector<std::int64_t> number = candidates.integers("TILE_NUMBER");
    for (std::size_t i = 0; i < tile.size(); ++i) {
      files.push_back(number[i] >= 1 ? "tiles/" + tile[i] + "/" + stampFileName(number[i] - 1)
                                     : std::string());
    }
  } else {
    for (const std::int64_t n : candidates.integers("NUMBER")) {
      files.push_back(n >= 1 ? stampFileName(std::size_t(n - 1)) : std::string());
    }
  }
  return files;
}

std::string vettingStorageKey(const FitsTable& candidates, const std::string& title) {
  std::uint64_t hash = 14695981039346656037ull;
  const std::vector<std::int64_t> number = candidates.integers("NUMBER");
  const std::vector<std::string> name = textsOr(candidates, "NAME");
  const std::vector<double> score = numbersOr(candidates, "LENS_SCORE");
  for (std::size_t i = 0; i < number.size(); ++i) {
    hash = fnv1a(hash, std::to_string(number[i]) + "|" + name[i] + "|" +
                           formatNumber(score[i], "%.10g") + "\n");
  }
  char hex[24];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return title + ":" + hex;
}

std::string vettingPageHtml(const FitsTable& candidates, const VettingPageInfo& info) {
  if (info.stampFiles.size() != std::size_t(candidates.rows())) {
    throw IoError(candidates.where() + ": " + std::to_string(info.stampFiles.size()) +
                  " stamp names for " + std::to_string(candidates.rows()) + " candidates");
  }
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
    << "<title>" << escapeHtml(info.title) << "</title>\n<style>" << kStyle << "</style>\n"
    << "</head>\n<body>\n<h1>" << escapeHtml(info.title) << "</h1>\n"
    << "<details open><summary>Summary</summary><p>";
  for (const std::string& line : info.summaryLines) o << escapeHtml(line) << "<br>\n";
  o << "</p></details>\n<p>";
  for (std::size_t k = 0; k < info.links.size(); ++k) {
    o << (k ? " &middot; " : "") << escapeHtml(info.links[k].first) << ": <a href=\""
      << escapeHtml(info.links[k].second) << "\">" << escapeHtml(info.links[k].second) << "</a>";
  }
  o << "</p>\n<p class=\"keys\">Keys: j / k next / previous candidate; 1 lens, 2 maybe, 3 no, "
       "0 clears. Grades stay in this browser until exported. Stamps: the arc's ellipse "
       "(green), the lens (red circle), North and East, a scale bar.</p>\n"
    << kControls << "<div id=\"grid\"></div>\n"
    << "<div id=\"pager\"><button id=\"previous\">previous page</button> "
       "<button id=\"next\">next page</button></div>\n"
    << "<script type=\"application/json\" id=\"candidates\">" << candidatesJson(candidates, info)
    << "</script>\n<script>";
  std::string script = kScript;
  const std::string marker = "PER_PAGE";
  script.replace(script.find(marker), marker.size(), std::to_string(kVettingCardsPerPage));
  o << script << "</script>\n</body>\n</html>\n";
  return o.str();
}

}  // namespace octarc
