#include "octarc/sexcompat/Assoc.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc::sexcompat {
namespace {

constexpr double kSearchStart = 1e30;      // SExtractor's starting value of MIN/NEAREST searches
constexpr double kMinTotalWeight = 1e-30;  // MEAN/MAG_MEAN below this: no match
constexpr double kMagnitudeLimit = 99.0;   // |mag| >= 99 is "no magnitude" in MAG_MEAN/MAG_SUM
constexpr double kNoMagnitude = 99.0;      // MAG_SUM of a non-positive flux sum

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t pos = 0;
  constexpr const char* kBlanks = " \t\v\r\f";
  while ((pos = line.find_first_not_of(kBlanks, pos)) != std::string::npos) {
    const std::size_t end = line.find_first_of(kBlanks, pos);
    fields.push_back(line.substr(pos, end == std::string::npos ? std::string::npos : end - pos));
    pos = end;
  }
  return fields;
}

AssocType typeFromKeyword(const std::string& k) {
  if (k == "FIRST") return AssocType::First;
  if (k == "MEAN") return AssocType::Mean;
  if (k == "MAG_MEAN") return AssocType::MagMean;
  if (k == "SUM") return AssocType::Sum;
  if (k == "MAG_SUM") return AssocType::MagSum;
  if (k == "MIN") return AssocType::Min;
  if (k == "MAX") return AssocType::Max;
  if (k == "NEAREST") return AssocType::Nearest;
  throw ConfigError("ASSOC_TYPE " + k + ": unknown association type");
}

}  // namespace

AssocSettings AssocSettings::fromConfig(const Config& config) {
  AssocSettings s;
  s.listPath = config.getString("ASSOC_NAME");
  s.params = config.getInts("ASSOC_PARAMS");
  s.data = config.getInts("ASSOC_DATA");
  s.radiusPix = config.getDouble("ASSOC_RADIUS");
  s.type = typeFromKeyword(config.getString("ASSOC_TYPE"));
  const std::string selection = config.getString("ASSOCSELEC_TYPE");
  s.selection = selection == "ALL"        ? AssocSelection::All
                : selection == "-MATCHED" ? AssocSelection::NotMatched
                                          : AssocSelection::Matched;
  s.worldCoordinates = config.getString("ASSOCCOORD_TYPE") == "WORLD";
  return s;
}

AssocList AssocList::load(const AssocSettings& settings, int vectorSize, std::int64_t naxis2,
                          const std::function<std::array<double, 2>(double, double)>& worldToPixel,
                          std::vector<std::string>* warnings) {
  const std::string& path = settings.listPath;
  if (settings.params.size() != 2 && settings.params.size() != 3)
    throw ConfigError("ASSOC_PARAMS: expected 2 or 3 column numbers (x, y[, weight])");
  if (settings.worldCoordinates && !worldToPixel)
    throw ConfigError(path + ": ASSOCCOORD_TYPE WORLD needs an image with a celestial WCS");
  if (!(settings.radiusPix > 0.0)) throw ConfigError("ASSOC_RADIUS: must be positive");

  AssocList list;
  list.radiusPix_ = settings.radiusPix;
  list.selection_ = settings.selection;
  list.naxis2_ = naxis2;
  list.type_ = settings.type;
  list.vectorSize_ = std::max(vectorSize, 0);
  const bool hasWeight = settings.params.size() == 3;
  if (!hasWeight && (list.type_ == AssocType::Mean || list.type_ == AssocType::MagMean ||
                     list.type_ == AssocType::Min || list.type_ == AssocType::Max)) {
    if (warnings)
      warnings->push_back("ASSOC_PARAMS has no weight column: ASSOC_TYPE reverts to FIRST");
    list.type_ = AssocType::First;
  }

  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open ASSOC list");
  std::string line;
  int lineNo = 0;
  std::size_t nColumns = 0;
  std::vector<std::size_t> dataColumns;  // 0-based list column of each VECTOR_ASSOC element
  while (std::getline(in, line)) {
    ++lineNo;
    // SExtractor skips a line only on its first character: '#', TAB, or an empty line.
    if (line.empty() || line[0] == '#' || line[0] == '\t') continue;
    const std::string where = path + ":" + std::to_string(lineNo);
    const std::vector<std::string> fields = splitFields(line);
    if (nColumns == 0) {
      if (fields.empty()) throw ConfigError(where + ": empty line");
      nColumns = fields.size();
      for (std::size_t i = 0; i < settings.params.size(); ++i) {
        const int c = settings.params[i];
        if (c < 1 || static_cast<std::size_t>(c) > nColumns)
          throw ConfigError(where + ": ASSOC_PARAMS #" + std::to_string(i + 1) + " = " +
                            std::to_string(c) + " but the list has " + std::to_string(nColumns) +
                            " columns");
      }
      for (int c : settings.data) {
        if (c < 0 || static_cast<std::size_t>(c) > nColumns)
          throw ConfigError(where + ": ASSOC_DATA column " + std::to_string(c) +
                            " but the list has " + std::to_string(nColumns) + " columns");
        if (c > 0 && static_cast<int>(dataColumns.size()) < list.vectorSize_)
          dataColumns.push_back(static_cast<std::size_t>(c - 1));
      }
      if (dataColumns.empty())  // ASSOC_DATA 0: every column, in order
        for (std::size_t c = 0; c < nColumns && static_cast<int>(c) < list.vectorSize_; ++c)
          dataColumns.push_back(c);
      if (static_cast<int>(dataColumns.size()) < list.vectorSize_) {
        if (warnings)
          warnings->push_back(path + ": VECTOR_ASSOC(" + std::to_string(list.vectorSize_) +
                              ") shrunk to " + std::to_string(dataColumns.size()) +
                              ": no more ASSOC data columns available");
        list.vectorSize_ = static_cast<int>(dataColumns.size());
      }
    }
    if (fields.size() < nColumns)
      throw ConfigError(where + ": " + std::to_string(fields.size()) + " fields, expected " +
                        std::to_string(nColumns) + " as on the first line");
    std::vector<double> values(nColumns);
    for (std::size_t i = 0; i < nColumns; ++i) {
      char* end = nullptr;
      values[i] = std::strtod(fields[i].c_str(), &end);
      if (end == fields[i].c_str() || *end != '\0')
        throw ConfigError(where + ": field " + std::to_string(i + 1) + " " +
                          quoteForMessage(fields[i]) + " is not a number");
    }
    Entry e;
    e.x = values[static_cast<std::size_t>(settings.params[0] - 1)];
    e.y = values[static_cast<std::size_t>(settings.params[1] - 1)];
    if (hasWeight) e.weight = values[static_cast<std::size_t>(settings.params[2] - 1)];
    if (settings.worldCoordinates) {
      const auto pix = worldToPixel(e.x, e.y);
      e.x = pix[0];
      e.y = pix[1];
    }
    for (std::size_t c : dataColumns) e.data.push_back(values[c]);
    list.entries_.push_back(std::move(e));
  }
  if (in.bad()) throw IoError(path + ": read error");
  if (list.entries_.empty() && warnings) warnings->push_back(path + ": ASSOC list is empty");
  // FIRST means first in y order (SExtractor sorts the list by y); equal y keep file order.
  std::stable_sort(list.entries_.begin(), list.entries_.end(),
                   [](const Entry& a, const Entry& b) { return a.y < b.y; });
  return list;
}

AssocList::Match AssocList::match(double xFits, double yFits) const {
  Match m;
  m.values.assign(static_cast<std::size_t>(vectorSize_), 0.0);
  if (!std::isfinite(xFits) || !std::isfinite(yFits)) return m;
  // SExtractor's row look-up: the row index (int)(y + 0.499999) must lie inside the image, so
  // objects in the top half-row (Y_IMAGE + 0.5 >= NAXIS2) never match.
  const double rowGuess = yFits + 0.499999;
  if (rowGuess <= -1.0 || static_cast<std::int64_t>(rowGuess) >= naxis2_) return m;

  const double r2 = radiusPix_ * radiusPix_;
  double best =
      (type_ == AssocType::Min || type_ == AssocType::Nearest) ? kSearchStart : -kSearchStart;
  double totalWeight = 0.0;
  const std::size_t n = m.values.size();
  auto it = std::lower_bound(entries_.begin(), entries_.end(), yFits - radiusPix_,
                             [](const Entry& e, double y) { return e.y < y; });
  for (; it != entries_.end() && it->y - radiusPix_ < yFits; ++it) {
    const double dx = it->x - xFits;
    const double dy = it->y - yFits;
    const double d2 = dx * dx + dy * dy;
    if (!(d2 < r2)) continue;
    ++m.count;
    const Entry& e = *it;
    switch (type_) {
      case AssocType::First:
        m.values = e.data;
        m.count = 1;
        return m;
      case AssocType::Nearest:
        if (d2 < best) {
          m.values = e.data;
          best = d2;
        }
        break;
      case AssocType::Mean:
        totalWeight += e.weight;
        for (std::size_t i = 0; i < n; ++i) m.values[i] += e.data[i] * e.weight;
        break;
      case AssocType::MagMean: {
        const double w =
            std::fabs(e.weight) < kMagnitudeLimit ? std::pow(10.0, -0.4 * e.weight) : 0.0;
        totalWeight += w;
        for (std::size_t i = 0; i < n; ++i) m.values[i] += e.data[i] * w;
        break;
      }
      case AssocType::Sum:
        for (std::size_t i = 0; i < n; ++i) m.values[i] += e.data[i];
        break;
      case AssocType::MagSum:
        for (std::size_t i = 0; i < n; ++i)
          if (std::fabs(e.data[i]) < kMagnitudeLimit)
            m.values[i] += std::pow(10.0, -0.4 * e.data[i]);
        break;
      case AssocType::Min:
        if (e.weight < best) {
          m.values = e.data;
          best = e.weight;
        }
        break;
      case AssocType::Max:
        if (e.weight > best) {
          m.values = e.data;
          best = e.weight;
        }
        break;
    }
  }
  if (m.count == 0) return m;
  if (type_ == AssocType::Mean || type_ == AssocType::MagMean) {
    // SExtractor quirk: a total weight below 1e-30 reports no match but leaves the weighted sums.
    if (totalWeight < kMinTotalWeight) {
      m.count = 0;
      return m;
    }
    for (double& v : m.values) v /= totalWeight;
  }
  if (type_ == AssocType::MagSum)
    for (double& v : m.values) v = v > 0.0 ? -2.5 * std::log10(v) : kNoMagnitude;
  return m;
}

bool AssocList::keeps(const Match& m) const {
  switch (selection_) {
    case AssocSelection::All:
      return true;
    case AssocSelection::Matched:
      return m.count > 0;
    case AssocSelection::NotMatched:
      return m.count == 0;
  }
  return true;
}

ColumnSpec vectorAssocColumn(int n) {
  ColumnSpec c;
  c.name = "VECTOR_ASSOC";
  c.description = "ASSOCiated parameter vector";
  c.unit = "";
  c.ucd = "src";
  c.type = ColumnType::Float64;
  c.printfFormat = "%12.7g";
  c.repeat = n;
  return c;
}

ColumnSpec numberAssocColumn() {
  ColumnSpec c;
  c.name = "NUMBER_ASSOC";
  c.description = "Number of ASSOCiated IDs";
  c.unit = "";
  c.ucd = "meta.number;src";
  c.type = ColumnType::Int32;
  c.printfFormat = "%10d";
  c.repeat = 1;
  return c;
}

}  // namespace octarc::sexcompat
