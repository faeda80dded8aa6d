// Grades of a vetting page (search/VettingPage.h) merged back into the candidate catalog.
//
// The CSV the page exports: a header line naming its columns, among them NUMBER and GRADE (in
// any order; others such as TILE, NAME, ALPHA_J2000 are allowed), then one line per graded
// candidate; GRADE is lens, maybe or no (any case), or empty for none. Fields may be quoted
// ("a, b"; "" for a quote inside). When both the CSV and the catalog have NAME, they must agree:
// a CSV exported from another catalog is refused rather than merged by number.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "octarc/io/FitsTable.h"

namespace octarc {

struct CandidateGrade {
  std::string grade;  // "lens", "maybe" or "no"
  std::string name;   // NAME in the CSV ("" when it has no such column)
  int line = 0;       // 1-based line of the CSV, for messages
};

// NUMBER -> grade. IoError "PATH:LINE: ..." (one line) for a file that cannot be read, a header
// without NUMBER or GRADE, a line of another field count, a NUMBER that is not a positive
// integer or is repeated, an unknown grade.
std::map<std::int64_t, CandidateGrade> readGradesCsv(const std::string& path);

// A copy of `candidates` with a GRADE column (5 characters; "" for ungraded candidates) after
// its last column, replacing an earlier GRADE. IoError "CSV:LINE: ..." naming `csvPath` for a
// NUMBER the catalog does not hold or a NAME that differs from the catalog's.
FitsTable gradedCandidates(const FitsTable& candidates,
                           const std::map<std::int64_t, CandidateGrade>& grades,
                           const std::string& csvPath);

// A candidate catalog of octarc search or batch as read: FITS-LDAC (LDAC_IMHEAD, LDAC_OBJECTS)
// or FITS_1.0 (OBJECTS). ConfigError naming the file for any other kind.
struct CandidateCatalog {
  FitsTable objects;
  FitsTable imhead;  // LDAC_IMHEAD, kept as it is; empty for FITS_1.0
  bool ldac = true;
};
CandidateCatalog readCandidateCatalog(const std::string& path);

// Writes `catalog` at `path` (a temporary path the caller commits) in the type it was read as.
void writeCandidateCatalog(const std::string& path, const CandidateCatalog& catalog);

// The vetting page of a catalog, to be written at `pagePath`: its links and stamps
// (catalogStampFiles) relative to the page's folder.
std::string catalogPageHtml(const FitsTable& objects, const std::string& catalogPath,
                            const std::string& pagePath);

}  // namespace octarc
