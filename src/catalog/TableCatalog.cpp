#include "octarc/catalog/TableCatalog.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <variant>

#include "octarc/catalog/RunXml.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

bool isTextColumn(const FitsColumn& c) {
  return c.type() == FitsColumnType::String;
}

// The catalog declaration of a numeric column: storage type, and the printf format of its TDISP
// ("F8.4" -> "%8.4f"; integers "%d" and floats with round-trip digits without one).
ColumnSpec tableColumnSpec(const FitsColumn& c) {
  ColumnSpec spec;
  spec.name = c.name;
  spec.description = c.comment;
  spec.unit = c.unit;
  spec.repeat = std::max(1, c.repeat);
  switch (c.type()) {
    case FitsColumnType::Int16:
      spec.type = ColumnType::Int16;
      break;
    case FitsColumnType::Int32:
      spec.type = ColumnType::Int32;
      break;
    case FitsColumnType::Int64:
      spec.type = ColumnType::Int64;
      break;
    case FitsColumnType::Float32:
      spec.type = ColumnType::Float32;
      break;
    case FitsColumnType::Float64:
      spec.type = ColumnType::Float64;
      break;
    default:
      throw IoError("column " + c.name + ": no values to write");
  }
  const bool integer = spec.type == ColumnType::Int16 || spec.type == ColumnType::Int32 ||
                       spec.type == ColumnType::Int64;
  spec.printfFormat = integer ? "%d" : spec.type == ColumnType::Float32 ? "%.9g" : "%.17g";
  if (c.display.size() >= 2) {
    const char code = c.display[0];
    const std::string size = c.display.substr(1);
    const char conversion = code == 'I' ? 'd' : code == 'F' ? 'f' : code == 'E' ? 'e' : 'g';
    spec.printfFormat = "%" + size + conversion;
  }
  return spec;
}

// Element e of row r of a numeric column, as a double.
double tableValue(const FitsColumn& c, std::int64_t r, int e) {
  const std::size_t i = std::size_t(r) * std::size_t(std::max(1, c.repeat)) + std::size_t(e);
  return std::visit(
      [&](const auto& v) -> double {
        using V = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::monostate> ||
                      std::is_same_v<V, std::vector<std::string>>) {
          return std::nan("");
        } else {
          return double(v[i]);
        }
      },
      c.values);
}

const std::string& tableText(const FitsColumn& c, std::int64_t r) {
  return std::get<std::vector<std::string>>(c.values)[std::size_t(r)];
}

std::string asciiTableText(const FitsTable& objects, bool withHeader) {
  std::vector<ColumnSpec> specs;
  for (const FitsColumn& c : objects.columns) {
    specs.push_back(isTextColumn(c)
                        ? ColumnSpec{c.name, c.comment, c.unit, "", ColumnType::Float32, "%s", 1}
                        : tableColumnSpec(c));
  }
  std::string out = withHeader ? asciiHeadHeader(specs) : "";
  for (std::int64_t r = 0; r < objects.rows(); ++r) {
    bool first = true;
    for (std::size_t k = 0; k < specs.size(); ++k) {
      const FitsColumn& c = objects.columns[k];
      if (isTextColumn(c)) {
        if (!first) out += ' ';
        first = false;
        out += asciiWord(tableText(c, r));
        continue;
      }
      for (int e = 0; e < specs[k].repeat; ++e) {
        if (!first) out += ' ';
        first = false;
        out += formatAsciiValue(specs[k], tableValue(c, r, e));
      }
    }
    out += '\n';
  }
  return out;
}

std::string votableKeywordParam(const FitsKeyword& k) {
  std::string datatype;
  std::string value;
  char buffer[40];
  if (const bool* b = std::get_if<bool>(&k.value)) {
    datatype = "boolean";
    value = *b ? "T" : "F";
  } else if (const std::int64_t* i = std::get_if<std::int64_t>(&k.value)) {
    datatype = "long";
    value = std::to_string(*i);
  } else if (const std::uint64_t* u = std::get_if<std::uint64_t>(&k.value)) {
    // VOTable has no unsigned 64-bit type: above a long's range the digits go as text.
    datatype = *u <= std::uint64_t(std::numeric_limits<std::int64_t>::max())
                   ? "long"
                   : "char\" arraysize=\"*";
    value = std::to_string(*u);
  } else if (const double* d = std::get_if<double>(&k.value)) {
    datatype = "double";
    if (std::isnan(*d)) {
      value = "NaN";
    } else if (std::isinf(*d)) {
      value = *d > 0 ? "+Inf" : "-Inf";  // VOTable's spelling, as the cells have it
    } else {
      std::snprintf(buffer, sizeof buffer, "%.17g", *d);
      value = buffer;
    }
  } else {
    datatype = "char\" arraysize=\"*";
    value = std::get<std::string>(k.value);
  }
  std::string out = "  <PARAM name=\"" + xmlEscaped(k.name) + "\" datatype=\"" + datatype +
                    "\" value=\"" + xmlEscaped(value) + "\"";
  if (k.comment.empty()) return out + "/>\n";
  return out + ">\n   <DESCRIPTION>" + xmlEscaped(k.comment) + "</DESCRIPTION>\n  </PARAM>\n";
}

std::string votableTableText(const FitsTable& objects,
                             const std::map<std::string, std::string>& ucdByColumn) {
  std::string out =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<VOTABLE version=\"1.3\" xmlns=\"http://www.ivoa.net/xml/VOTable/v1.3\" "
      "xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\">\n"
      "<RESOURCE name=\"octarc\">\n"
      " <TABLE name=\"" +
      xmlEscaped(objects.name) + "\">\n";
  for (const FitsKeyword& k : objects.keywords) out += votableKeywordParam(k);
  std::vector<ColumnSpec> specs;
  for (const FitsColumn& c : objects.columns) {
    out += "  <FIELD name=\"" + xmlEscaped(c.name) + "\"";
    if (isTextColumn(c)) {
      out += " datatype=\"char\" arraysize=\"*\"";
      specs.emplace_back();
    } else {
      specs.push_back(tableColumnSpec(c));
      out += std::string(" datatype=\"") + votableDatatype(specs.back().type) + "\"";
      if (specs.back().repeat > 1) out += " arraysize=\"" + std::to_string(c.repeat) + "\"";
    }
    if (!c.unit.empty()) out += " unit=\"" + xmlEscaped(votableUnit(c.unit)) + "\"";
    const auto ucd = ucdByColumn.find(c.name);
    if (ucd != ucdByColumn.end() && !ucd->second.empty()) {
      out += " ucd=\"" + xmlEscaped(ucd->second) + "\"";
    }
    out += ">\n   <DESCRIPTION>" + xmlEscaped(c.comment) + "</DESCRIPTION>\n  </FIELD>\n";
  }
  out += "  <DATA><TABLEDATA>\n";
  for (std::int64_t r = 0; r < objects.rows(); ++r) {
    out += "   <TR>";
    for (std::size_t k = 0; k < specs.size(); ++k) {
      const FitsColumn& c = objects.columns[k];
      out += "<TD>";
      if (isTextColumn(c)) {
        out += xmlEscaped(tableText(c, r));
      } else {
        for (int e = 0; e < specs[k].repeat; ++e) {
          if (e > 0) out += ' ';
          out += formatVotableValue(specs[k], tableValue(c, r, e));
        }
      }
      out += "</TD>";
    }
    out += "</TR>\n";
  }
  out += "  </TABLEDATA></DATA>\n </TABLE>\n</RESOURCE>\n</VOTABLE>\n";
  return out;
}

}  // namespace

void writeTableCatalog(const std::string& path, CatalogType type, const FitsTable& objects,
                       const FitsTable& ldacImhead,
                       const std::map<std::string, std::string>& ucdByColumn) {
  FitsTable table = objects;
  switch (type) {
    case CatalogType::FitsLdac:
      table.name = "LDAC_OBJECTS";
      writeFitsTables(path, {ldacImhead, table});
      return;
    case CatalogType::Fits10:
      table.name = "OBJECTS";
      writeFitsTables(path, {table});
      return;
    case CatalogType::AsciiHead:
    case CatalogType::Ascii:
      writeTextFile(path, asciiTableText(objects, type == CatalogType::AsciiHead));
      return;
    case CatalogType::AsciiVotable:
      writeTextFile(path, votableTableText(objects, ucdByColumn));
      return;
    case CatalogType::None:
      break;
  }
  throw ConfigError(path + ": CATALOG_TYPE NONE writes no catalog");
}

}  // namespace octarc
