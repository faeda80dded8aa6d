#include "octarc/search/Grades.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/catalog/TableCatalog.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/search/VettingPage.h"

namespace octarc {

namespace {

// The fields of one CSV line (RFC 4180 quoting, no line breaks inside a field); nullopt for an
// unterminated quote.
std::optional<std::vector<std::string>> csvFields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  if (quoted) return std::nullopt;
  return fields;
}

std::string trimmed(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

constexpr std::size_t kGradeWidth = 5;  // "maybe"

}  // namespace

std::map<std::int64_t, CandidateGrade> readGradesCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open the grades CSV");
  std::map<std::int64_t, CandidateGrade> grades;
  std::string line;
  int lineNumber = 0;
  std::size_t numberField = 0, gradeField = 0, nameField = 0, fieldCount = 0;
  bool haveName = false;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = path + ":" + std::to_string(lineNumber) + ": ";
    if (lineNumber > 1 && trimmed(line).empty()) continue;
    const std::optional<std::vector<std::string>> fields = csvFields(line);
    if (!fields) throw IoError(where + "a quote is not closed");
    if (lineNumber == 1) {
      bool haveNumber = false, haveGrade = false;
      for (std::size_t k = 0; k < fields->size(); ++k) {
        const std::string name = uppercase(trimmed((*fields)[k]));
        if (name == "NUMBER") numberField = k, haveNumber = true;
        if (name == "GRADE") gradeField = k, haveGrade = true;
        if (name == "NAME") nameField = k, haveName = true;
      }
      if (!haveNumber || !haveGrade) {
        throw IoError(where + "the header line " + quoteForMessage(line) +
                      " must name the columns NUMBER and GRADE (a CSV exported by the vetting "
                      "page)");
      }
      fieldCount = fields->size();
      continue;
    }
    if (fields->size() != fieldCount) {
      throw IoError(where + std::to_string(fields->size()) + " fields, the header has " +
                    std::to_string(fieldCount));
    }
    const std::string numberText = trimmed((*fields)[numberField]);
    std::int64_t number = 0;
    std::size_t used = 0;
    try {
      number = std::stoll(numberText, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != numberText.size() || number < 1) {
      throw IoError(where + "NUMBER " + quoteForMessage(numberText) + " is not a positive integer");
    }
    const std::string grade = lowercase(trimmed((*fields)[gradeField]));
    if (grade.empty()) continue;  // ungraded
    if (grade != "lens" && grade != "maybe" && grade != "no") {
      throw IoError(where + "GRADE " + quoteForMessage(grade) + " is not lens, maybe or no");
    }
    const auto [it, added] = grades.emplace(
        number, CandidateGrade{grade, haveName ? trimmed((*fields)[nameField]) : "", lineNumber});
    if (!added) {
      throw IoError(where + "NUMBER " + numberText + " is graded again (first on line " +
                    std::to_string(it->second.line) + ")");
    }
  }
  if (lineNumber == 0) throw IoError(path + ":1: empty file; expected a header line");
  if (in.bad()) throw IoError(path + ": cannot read the grades CSV");
  return grades;
}

FitsTable gradedCandidates(const FitsTable& candidates,
                           const std::map<std::int64_t, CandidateGrade>& grades,
                           const std::string& csvPath) {
  FitsTable out = candidates;
  std::erase_if(out.columns, [](const FitsColumn& c) { return uppercase(c.name) == "GRADE"; });
  const std::vector<std::int64_t> numbers = candidates.integers("NUMBER");
  const std::vector<std::string> names =
      candidates.findColumn("NAME") ? candidates.strings("NAME") : std::vector<std::string>();
  std::map<std::int64_t, std::size_t> rowOf;
  for (std::size_t r = 0; r < numbers.size(); ++r) rowOf.emplace(numbers[r], r);
  std::vector<std::string> column(numbers.size());
  for (const auto& [number, g] : grades) {
    const std::string where = csvPath + ":" + std::to_string(g.line) + ": ";
    const auto row = rowOf.find(number);
    if (row == rowOf.end()) {
      throw IoError(where + "NUMBER " + std::to_string(number) + " is not in " +
                    candidates.where());
    }
    if (!names.empty() && !g.name.empty() && trimmed(names[row->second]) != g.name) {
      throw IoError(where + "NUMBER " + std::to_string(number) + " is " +
                    quoteForMessage(names[row->second]) + " in " + candidates.where() + ", not " +
                    quoteForMessage(g.name) + ": grades of another catalog?");
    }
    column[row->second] = g.grade;
  }
  FitsColumn grade;
  grade.name = "GRADE";
  grade.comment = "Visual grade: lens, maybe or no (blank: not graded)";
  grade.repeat = int(kGradeWidth);
  grade.values = std::move(column);
  out.columns.push_back(std::move(grade));
  return out;
}

CandidateCatalog readCandidateCatalog(const std::string& path) {
  const std::vector<std::string> tables = listFitsTables(path);
  auto has = [&](const char* name) {
    return std::find(tables.begin(), tables.end(), name) != tables.end();
  };
  CandidateCatalog c;
  c.ldac = has("LDAC_OBJECTS") && has("LDAC_IMHEAD");
  if (!c.ldac && !has("OBJECTS")) {
    throw ConfigError(path +
                      ": not a candidate catalog of octarc search or batch (FITS-LDAC with "
                      "LDAC_OBJECTS, or FITS_1.0 with OBJECTS)");
  }
  c.objects = readFitsTable(path, c.ldac ? "LDAC_OBJECTS" : "OBJECTS");
  if (c.objects.findColumn("NUMBER") == nullptr) {
    throw ConfigError(c.objects.where() + ": no NUMBER column: not a candidate catalog");
  }
  // The image header's cards, as they were (the FITS table reader skips text arrays).
  if (c.ldac) c.imhead = ldacImheadTable(readLdacImageHeader(path), {});
  return c;
}

void writeCandidateCatalog(const std::string& path, const CandidateCatalog& catalog) {
  writeTableCatalog(path, catalog.ldac ? CatalogType::FitsLdac : CatalogType::Fits10,
                    catalog.objects, catalog.imhead);
}

std::string catalogPageHtml(const FitsTable& objects, const std::string& catalogPath,
                            const std::string& pagePath) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::absolute(pagePath).parent_path();
  VettingPageInfo info;
  const std::string catalog = fs::path(catalogPath).filename().string();
  info.title = "octarc: " + catalog;
  info.summaryLines = {std::to_string(objects.rows()) + " candidate(s) of " + catalog};
  info.links = {{"Catalog", fs::absolute(catalogPath).lexically_relative(folder).string()}};
  // The stamps lie beside the catalog: seen from the page's folder.
  const fs::path catalogFolder = fs::absolute(catalogPath).parent_path().lexically_relative(folder);
  for (const std::string& stamp : catalogStampFiles(objects)) {
    info.stampFiles.push_back(
        stamp.empty() || catalogFolder == "." ? stamp : (catalogFolder / stamp).string());
  }
  return vettingPageHtml(objects, info);
}

}  // namespace octarc
