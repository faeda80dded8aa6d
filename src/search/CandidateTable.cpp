#include "octarc/search/CandidateTable.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <variant>

#include "octarc/catalog/Catalog.h"
#include "octarc/core/Conventions.h"
#include "octarc/search/CandidateName.h"

namespace octarc {

namespace {

// What a column's value is computed from.
struct RowView {
  const Table& catalog;
  const Candidate& candidate;
  std::int64_t number;  // 1-based candidate number
  // A catalog value of the best row, or of the lens row; NaN without such a column (stored as 0
  // in an integer column).
  double best(const char* column) const { return at(std::int64_t(candidate.row), column); }
  double lens(const char* column) const {
    return candidate.lens ? at(std::int64_t(candidate.lens->row), column) : kNaN;
  }
  double at(std::int64_t row, const char* column) const {
    const int c = catalog.findColumn(column);
    return c < 0 ? kNaN : catalog.value(row, c);
  }
};

// A number, a text, or the elements of a vector column.
using Value = std::variant<double, std::string, std::vector<double>>;

struct ColumnDef {
  CandidateColumnSpec column;
  std::function<Value(const RowView&)> value;
};

ColumnDef number(std::string name, std::string description, std::string unit, std::string ucd,
                 ColumnType type, std::string format, std::function<double(const RowView&)> f) {
  return {{{std::move(name), std::move(description), std::move(unit), std::move(ucd), type,
            std::move(format)},
           false},
          [f = std::move(f)](const RowView& v) { return Value(f(v)); }};
}

ColumnDef text(std::string name, std::string description, std::string ucd,
               std::function<std::string(const RowView&)> f) {
  return {{{std::move(name), std::move(description), "", std::move(ucd), ColumnType::Float32, "%s"},
           true},
          [f = std::move(f)](const RowView& v) { return Value(f(v)); }};
}

// A column copied from the catalog's best row, with the UCD its measurement declares (the unit
// test checks that they agree).
ColumnDef copied(const char* name, std::string description, std::string unit, std::string ucd,
                 ColumnType type, std::string format) {
  return number(name, std::move(description), std::move(unit), std::move(ucd), type,
                std::move(format), [name](const RowView& v) { return v.best(name); });
}

// LEVELS: the levels at which the object passed, lowest first, then kCandidateLevelsFill up to
// the run's number of levels (a fixed-length vector, as FITS and VOTable columns are).
ColumnDef levelsColumn(int levelCount) {
  ColumnDef d{
      {{"LEVELS", "Levels at which the object passed (then 0)", "", "meta.id.part",
        ColumnType::Int16, "%3d", std::max(1, levelCount)},
       false},
      [levelCount](const RowView& v) {
        std::vector<double> out(std::size_t(std::max(1, levelCount)), double(kCandidateLevelsFill));
        for (std::size_t k = 0; k < v.candidate.passedLevels.size() && k < out.size(); ++k) {
          out[k] = v.candidate.passedLevels[k];
        }
        return Value(std::move(out));
      }};
  return d;
}

// The columns of colour band `band` (index 1 + k of the candidates' magnitudes).
std::vector<ColumnDef> bandColumns(const std::string& band, std::size_t k) {
  using T = ColumnType;
  const std::size_t i = k + 1;
  auto mag = [i](const std::vector<BandMagnitude>& m) {
    return m.size() > i ? m[i] : BandMagnitude();
  };
  auto colour = [i](const std::vector<BandMagnitude>& m) {
    return m.size() > i ? colourOf(m[i], m[0]) : Colour();
  };
  const std::string in = " in band " + band;
  return {
      number("MAG_" + band, "Isophotal magnitude of the arc" + in, "mag", "phot.mag", T::Float32,
             "%8.4f", [=](const RowView& v) { return mag(v.candidate.arcMags).mag; }),
      number("MAGERR_" + band, "RMS error of MAG_" + band, "mag", "stat.stdev;phot.mag", T::Float32,
             "%8.4f", [=](const RowView& v) { return mag(v.candidate.arcMags).magErr; }),
      number("LENS_MAG_" + band, "Isophotal magnitude of the lens" + in, "mag", "phot.mag",
             T::Float32, "%8.4f", [=](const RowView& v) { return mag(v.candidate.lensMags).mag; }),
      number("LENS_MAGERR_" + band, "RMS error of LENS_MAG_" + band, "mag", "stat.stdev;phot.mag",
             T::Float32, "%8.4f",
             [=](const RowView& v) { return mag(v.candidate.lensMags).magErr; }),
      number("ARC_COLOUR_" + band, "Arc colour: " + band + " minus the measurement band", "mag",
             "phot.color", T::Float32, "%8.4f",
             [=](const RowView& v) { return colour(v.candidate.arcMags).value; }),
      number("ARC_COLOURERR_" + band, "RMS error of ARC_COLOUR_" + band, "mag",
             "stat.stdev;phot.color", T::Float32, "%8.4f",
             [=](const RowView& v) { return colour(v.candidate.arcMags).error; }),
      number("LENS_COLOUR_" + band, "Lens colour: " + band + " minus the measurement band", "mag",
             "phot.color", T::Float32, "%8.4f",
             [=](const RowView& v) { return colour(v.candidate.lensMags).value; }),
      number("LENS_COLOURERR_" + band, "RMS error of LENS_COLOUR_" + band, "mag",
             "stat.stdev;phot.color", T::Float32, "%8.4f",
             [=](const RowView& v) { return colour(v.candidate.lensMags).error; }),
  };
}

double secondaryValue(const RowView& v, double CandidateImage::*field) {
  return v.candidate.secondary ? (*v.candidate.secondary).*field : kNaN;
}

// Every column: the fixed ones, then those of each colour band.
std::vector<ColumnDef> definitions(const std::vector<std::string>& bands, int levelCount) {
  using T = ColumnType;
  std::vector<ColumnDef> defs = {
      number("NUMBER", "Candidate number, by LENS_SCORE", "", "meta.record", T::Int32, "%6d",
             [](const RowView& v) { return double(v.number); }),
      number("LENS_SCORE", "Expected fraction of lens arcs among rows of this score", "",
             "stat.probability", T::Float64, "%12.5e",
             [](const RowView& v) { return v.candidate.lensScore; }),
      number("LENS_RANK", "Rank by LENS_SCORE (1: highest)", "", "meta.number", T::Int32, "%6d",
             [](const RowView& v) { return double(v.number); }),
      text("NAME", "IAU-style designation (J2000, truncated)", "meta.id;meta.main",
           [](const RowView& v) { return v.candidate.name; }),
      number("ALPHA_J2000", "Right ascension of the arc (J2000)", "deg",
             "pos.eq.ra;pos.barycenter;meta.main", T::Float64, "%11.7f",
             [](const RowView& v) { return v.candidate.raDeg; }),
      number("DELTA_J2000", "Declination of the arc (J2000)", "deg",
             "pos.eq.dec;pos.barycenter;meta.main", T::Float64, "%+11.7f",
             [](const RowView& v) { return v.candidate.decDeg; }),
      text("RA_SEX", "Right ascension of the arc (J2000), hh:mm:ss.ss", "pos.eq.ra",
           [](const RowView& v) { return formatRaSexagesimal(v.candidate.raDeg, 2); }),
      text("DEC_SEX", "Declination of the arc (J2000), +dd:mm:ss.s", "pos.eq.dec",
           [](const RowView& v) { return formatDecSexagesimal(v.candidate.decDeg, 1); }),
      copied("X_IMAGE", "Arc centroid x (1-based)", "pixel",
             "pos.cartesian.x;pos.barycenter;instr.det;meta.main", T::Float32, "%10.3f"),
      copied("Y_IMAGE", "Arc centroid y (1-based)", "pixel",
             "pos.cartesian.y;pos.barycenter;instr.det;meta.main", T::Float32, "%10.3f"),
      copied("THRESH_LEVEL", "Threshold level of the best row", "", "meta.id.part", T::Int16,
             "%3d"),
      number("OBJ_NUMBER", "NUMBER of the best row within its level", "", "meta.id.cross", T::Int32,
             "%8d", [](const RowView& v) { return v.best("NUMBER"); }),
      levelsColumn(levelCount),
      number("NLEVELS", "Number of levels at which it passed", "", "meta.number", T::Int16, "%3d",
             [](const RowView& v) { return double(v.candidate.passedLevels.size()); }),
      copied("MAG_ISO", "Isophotal magnitude of the arc", "mag", "phot.mag", T::Float32, "%8.4f"),
      copied("MAGERR_ISO", "RMS error of MAG_ISO", "mag", "stat.stdev;phot.mag", T::Float32,
             "%8.4f"),
      copied("SNR_ISO", "FLUX_ISO / FLUXERR_ISO", "", "stat.snr", T::Float32, "%10.2f"),
      copied("ARCNESS", "|I_aab| / size^3", "", "src.morph", T::Float32, "%8.4f"),
      copied("E_IMAGE", "Distortion (a^2 - b^2)/(a^2 + b^2)", "", "src.ellipticity;instr.det",
             T::Float32, "%7.4f"),
      copied("ANTIARCNESS", "I_abb / size^3", "", "src.morph", T::Float32, "%8.4f"),
      copied("SKEW_MAJOR", "I_aaa / size^3", "", "src.morph", T::Float32, "%8.4f"),
      copied("SKEW_MINOR", "I_bbb / size^3", "", "src.morph", T::Float32, "%8.4f"),
      copied("ARC_SIDE", "Side of the centre of curvature: sign(I_aab)", "", "src.morph;pos.posAng",
             T::Int16, "%2d"),
      copied("A_IMAGE", "Profile RMS along major axis", "pixel",
             "phys.size.smajAxis;instr.det;meta.main", T::Float32, "%9.3f"),
      copied("B_IMAGE", "Profile RMS along minor axis", "pixel",
             "phys.size.sminAxis;instr.det;meta.main", T::Float32, "%9.3f"),
      copied("THETA_IMAGE", "Position angle (CCW/x)", "deg", "pos.posAng;instr.det;meta.main",
             T::Float32, "%5.1f"),
      number("PROB", "Occupation probability of the arc's grid bin (GRID)", "", "stat.probability",
             T::Float64, "%12.5e", [](const RowView& v) { return v.candidate.probability; }),
      number("CONTOUR", "Contour level at which the bin enters", "", "stat.probability", T::Float64,
             "%8.5f", [](const RowView& v) { return v.candidate.contourLevel; }),
      number("SPACES", "Report spaces the arc is in (bit n-1: SPNAMEn)", "", "meta.code", T::Int32,
             "%6d", [](const RowView& v) { return double(v.candidate.spaces); }),
      number("LENS_LEVEL", "Threshold level of the lens row (0: none)", "", "meta.id.part",
             T::Int16, "%3d",
             [](const RowView& v) { return v.candidate.lens ? v.lens("THRESH_LEVEL") : 0.0; }),
      number("LENS_NUMBER", "NUMBER of the lens within its level (0: none)", "", "meta.id.cross",
             T::Int32, "%8d",
             [](const RowView& v) { return v.candidate.lens ? v.lens("NUMBER") : 0.0; }),
      number("LENS_X", "Lens x (1-based; fitted centre if flag 16)", "pixel",
             "pos.cartesian.x;instr.det", T::Float32, "%10.3f",
             [](const RowView& v) { return v.candidate.lens ? v.candidate.lens->xPix : kNaN; }),
      number("LENS_Y", "Lens y (1-based; fitted centre if flag 16)", "pixel",
             "pos.cartesian.y;instr.det", T::Float32, "%10.3f",
             [](const RowView& v) { return v.candidate.lens ? v.candidate.lens->yPix : kNaN; }),
      number("LENS_ALPHA", "Right ascension of the lens (J2000)", "deg", "pos.eq.ra", T::Float64,
             "%11.7f",
             [](const RowView& v) { return v.candidate.lens ? v.candidate.lens->raDeg : kNaN; }),
      number("LENS_DELTA", "Declination of the lens (J2000)", "deg", "pos.eq.dec", T::Float64,
             "%+11.7f",
             [](const RowView& v) { return v.candidate.lens ? v.candidate.lens->decDeg : kNaN; }),
      number("LENS_MAG", "Isophotal magnitude of the lens", "mag", "phot.mag", T::Float32, "%8.4f",
             [](const RowView& v) { return v.lens("MAG_ISO"); }),
      number("THETA_E", "Einstein radius estimate (see THETA_E_METHOD)", "arcsec", "phys.angSize",
             T::Float32, "%7.3f",
             [](const RowView& v) {
               return v.candidate.lens ? v.candidate.lens->einsteinRadiusArcsec : kNaN;
             }),
      number("THETA_E_METHOD", "THETA_E from: 1 counter-image 2 curvature 3 distance", "",
             "meta.code", T::Int16, "%2d",
             [](const RowView& v) {
               return v.candidate.lens ? double(v.candidate.lens->thetaEMethod) : 0.0;
             }),
      number("LENS_DIST", "Arc-lens distance", "arcsec", "pos.angDistance", T::Float32, "%7.3f",
             [](const RowView& v) {
               return v.candidate.lens ? v.candidate.lens->distanceArcsec : kNaN;
             }),
      number("CURV_X", "Centre of curvature x (1-based)", "pixel", "pos.cartesian.x;instr.det",
             T::Float32, "%10.3f",
             [](const RowView& v) {
               return v.candidate.curvature ? v.candidate.curvature->xCentre : kNaN;
             }),
      number("CURV_Y", "Centre of curvature y (1-based)", "pixel", "pos.cartesian.y;instr.det",
             T::Float32, "%10.3f",
             [](const RowView& v) {
               return v.candidate.curvature ? v.candidate.curvature->yCentre : kNaN;
             }),
      number("CURV_RADIUS", "Radius of curvature of the arc", "pixel", "phys.size.radius;instr.det",
             T::Float32, "%9.3f",
             [](const RowView& v) {
               return v.candidate.curvature ? v.candidate.curvature->radius : kNaN;
             }),
      number("SEC_X", "Counter-image of a dark-lens pair: x (1-based)", "pixel",
             "pos.cartesian.x;instr.det", T::Float32, "%10.3f",
             [](const RowView& v) { return secondaryValue(v, &CandidateImage::xPix); }),
      number("SEC_Y", "Counter-image of a dark-lens pair: y (1-based)", "pixel",
             "pos.cartesian.y;instr.det", T::Float32, "%10.3f",
             [](const RowView& v) { return secondaryValue(v, &CandidateImage::yPix); }),
      number("SEC_ALPHA", "Right ascension of the counter-image (J2000)", "deg", "pos.eq.ra",
             T::Float64, "%11.7f",
             [](const RowView& v) { return secondaryValue(v, &CandidateImage::raDeg); }),
      number("SEC_DELTA", "Declination of the counter-image (J2000)", "deg", "pos.eq.dec",
             T::Float64, "%+11.7f",
             [](const RowView& v) { return secondaryValue(v, &CandidateImage::decDeg); }),
      copied("FLAGS", "Extraction flags of the best row", "", "meta.code.qual", T::Int16, "%3d"),
      number("CAND_FLAGS", "1 nolens 2 nocirc 4 noWCS 8 side 16 resid 32 pair 64 blend", "",
             "meta.code.qual", T::Int16, "%3d",
             [](const RowView& v) { return double(v.candidate.flags); }),
  };
  for (std::size_t k = 0; k < bands.size(); ++k) {
    for (ColumnDef& d : bandColumns(bands[k], k)) defs.push_back(std::move(d));
  }
  return defs;
}

FitsColumnValues emptyValues(ColumnType type) {
  switch (type) {
    case ColumnType::Int16:
      return std::vector<std::int16_t>();
    case ColumnType::Int32:
      return std::vector<std::int32_t>();
    case ColumnType::Int64:
      return std::vector<std::int64_t>();
    case ColumnType::Float32:
      return std::vector<float>();
    case ColumnType::Float64:
      return std::vector<double>();
  }
  return std::vector<double>();
}

// Integer storage as the catalogs store it: rounded, NaN as 0.
template <typename I>
I integerOf(double v) {
  return std::isfinite(v) ? I(std::llround(v)) : I(0);
}

void append(FitsColumnValues& values, const Value& v) {
  if (const auto* elements = std::get_if<std::vector<double>>(&v)) {
    for (const double e : *elements) append(values, Value(e));
    return;
  }
  std::visit(
      [&](auto& out) {
        using V = std::decay_t<decltype(out)>;
        if constexpr (std::is_same_v<V, std::vector<std::string>>) {
          out.push_back(std::get<std::string>(v));
        } else if constexpr (std::is_same_v<V, std::vector<float>>) {
          out.push_back(float(std::get<double>(v)));
        } else if constexpr (std::is_same_v<V, std::vector<double>>) {
          out.push_back(std::get<double>(v));
        } else if constexpr (!std::is_same_v<V, std::monostate>) {
          out.push_back(integerOf<typename V::value_type>(std::get<double>(v)));
        }
      },
      values);
}

// The length of LEVELS: the run's number of levels, or the highest level a candidate passed
// when the settings do not say.
int levelsOf(const SearchResult& result, const SearchSettings& settings) {
  int count = std::max(1, settings.levelCount);
  for (const Candidate& c : result.candidates) {
    for (const int level : c.passedLevels) count = std::max(count, level);
  }
  return count;
}

}  // namespace

std::map<std::string, std::string> candidateColumnUcds(
    const std::vector<std::string>& colourBands) {
  std::map<std::string, std::string> out;
  for (const ColumnDef& d : definitions(colourBands, 1))
    out[d.column.spec.name] = d.column.spec.ucd;
  return out;
}

std::vector<CandidateColumnSpec> candidateColumns(const std::vector<std::string>& colourBands,
                                                  int levelCount) {
  std::vector<CandidateColumnSpec> out;
  for (const ColumnDef& d : definitions(colourBands, levelCount)) out.push_back(d.column);
  return out;
}

FitsTable candidateObjectsTable(const Table& catalog, const SearchResult& result,
                                const SearchSettings& settings) {
  FitsTable table;
  table.name = "LDAC_OBJECTS";
  const std::vector<ColumnDef> defs = definitions(settings.colourBands, levelsOf(result, settings));
  for (const ColumnDef& d : defs) {
    FitsColumn column;
    column.name = d.column.spec.name;
    column.comment = d.column.spec.description;
    column.unit = d.column.spec.unit;
    column.repeat = d.column.text ? 0 : d.column.spec.repeat;
    column.values = d.column.text ? FitsColumnValues(std::vector<std::string>())
                                  : emptyValues(d.column.spec.type);
    if (!d.column.text) column.display = tdispFromPrintf(d.column.spec.printfFormat);
    table.columns.push_back(std::move(column));
  }
  for (std::size_t i = 0; i < result.candidates.size(); ++i) {
    const RowView view{catalog, result.candidates[i], std::int64_t(i) + 1};
    for (std::size_t c = 0; c < defs.size(); ++c)
      append(table.columns[c].values, defs[c].value(view));
  }
  const SearchSummary& s = result.summary;
  auto& k = table.keywords;
  k.push_back(FitsKeyword::integer("NCANDID", s.candidates, "lens candidates"));
  k.push_back(
      FitsKeyword::integer("NROWSRCH", s.rowsSearched, "catalog rows in the searched area"));
  k.push_back(FitsKeyword::integer("NOBJSRCH", s.objectsSearched, "level-1 objects searched"));
  k.push_back(FitsKeyword::integer("NROWSEL", s.rowsSelected, "rows that passed the selection"));
  k.push_back(FitsKeyword::integer("SRCHPIX", s.searchedPixels, "searched pixels"));
  k.push_back(FitsKeyword::real("SRCHAREA", s.searchedAreaDeg2, "[deg2] searched area"));
  k.push_back(FitsKeyword::real("CANDDEG2", s.candidatesPerDeg2(), "[deg-2] candidates per deg2"));
  k.push_back(
      FitsKeyword::real("REJFRAC", s.rejectedFraction(), "fraction of searched rows rejected"));
  k.push_back(FitsKeyword::text(
      "SELMETH", settings.method == SelectionMethod::Trees ? "TREES" : "GRID", "SELECTION_METHOD"));
  k.push_back(FitsKeyword::real("LENSDENS", settings.lensDensityPerDeg2,
                                "[deg-2] LENS_DENSITY: lens arcs expected"));
  k.push_back(FitsKeyword::integer("NROWSCOR", s.rowsScored, "rows scored (S/N, resolved)"));
  k.push_back(FitsKeyword::real("SCOREPRI", s.priorFraction, "prior of LENS_SCORE per row"));
  k.push_back(FitsKeyword::real("SCOREMIN", settings.scoreMin, "SCORE_MIN"));
  k.push_back(FitsKeyword::real("SNRMIN", settings.snrMin, "S/N floor (SNR_ISO >)"));
  k.push_back(FitsKeyword::real("RESOLMIN", settings.resolvedMinArcsec,
                                "[arcsec] resolved: sqrt(2) SIZE_IMAGE >"));
  k.push_back(
      FitsKeyword::real("LENSRAD", settings.lensRadiusArcsec, "[arcsec] lens search radius"));
  std::int64_t pairs = 0;
  for (const Candidate& c : result.candidates) pairs += (c.flags & kCandidateDarkLensPair) != 0;
  k.push_back(FitsKeyword::integer("NDARKPR", pairs, "dark-lens pairs (CAND_FLAGS 32)"));
  k.push_back(
      FitsKeyword::integer("NCOLBAND", std::int64_t(settings.colourBands.size()), "colour bands"));
  for (std::size_t i = 0; i < settings.colourBands.size(); ++i) {
    k.push_back(FitsKeyword::text("COLBAND" + std::to_string(i + 1), settings.colourBands[i],
                                  "colour band"));
  }
  if (settings.colourCut) {
    k.push_back(FitsKeyword::text("COLCUTBD", settings.colourCut->band, "band of the colour cut"));
    k.push_back(FitsKeyword::real("COLCUTMX", settings.colourCut->maxArcMinusLensMag,
                                  "[mag] kept: arc minus lens colour <= this"));
  }
  k.push_back(FitsKeyword::integer("NCOLCUT", s.removedByColourCut,
                                   "candidates removed by the colour cut"));
  k.push_back(FitsKeyword::integer("NSPACES", std::int64_t(s.spaces.size()), "report spaces"));
  for (std::size_t i = 0; i < s.spaces.size(); ++i) {
    const std::string n = std::to_string(i + 1);
    k.push_back(FitsKeyword::text("SPNAME" + n, s.spaces[i].name, "report space"));
    k.push_back(FitsKeyword::text("SPEXPR" + n, s.spaces[i].expression, "its cut"));
    k.push_back(FitsKeyword::integer("SPCAND" + n, s.spaces[i].candidates, "candidates in it"));
    k.push_back(FitsKeyword::real(
        "SPDEG2" + n,
        s.searchedAreaDeg2 > 0 ? double(s.spaces[i].candidates) / s.searchedAreaDeg2 : kNaN,
        "[deg-2] its candidates per deg2"));
  }
  return table;
}

std::string candidateAsciiText(const Table& catalog, const SearchResult& result,
                               const SearchSettings& settings) {
  const std::vector<ColumnDef> defs = definitions(settings.colourBands, levelsOf(result, settings));
  std::vector<ColumnSpec> specs;
  for (const ColumnDef& d : defs) specs.push_back(d.column.spec);
  std::string out = asciiHeadHeader(specs);
  for (std::size_t i = 0; i < result.candidates.size(); ++i) {
    const RowView view{catalog, result.candidates[i], std::int64_t(i) + 1};
    bool first = true;
    for (const ColumnDef& d : defs) {
      const Value v = d.value(view);
      if (!first) out += ' ';
      first = false;
      if (d.column.text) {
        out += asciiWord(std::get<std::string>(v));
      } else {
        if (const auto* elements = std::get_if<std::vector<double>>(&v)) {
          for (std::size_t e = 0; e < elements->size(); ++e) {
            out += (e ? " " : "") + formatAsciiValue(d.column.spec, (*elements)[e]);
          }
        } else {
          out += formatAsciiValue(d.column.spec, std::get<double>(v));
        }
      }
    }
    out += '\n';
  }
  return out;
}

}  // namespace octarc
