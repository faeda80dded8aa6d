// `octarc grades`: the grades exported by a vetting page (index.html of octarc search,
// candidates.html of octarc batch) merged into a copy of the candidate catalog; or the vetting
// page of a catalog (say, one filtered with STILTS).
//
//   CATALOG [, GRADES.csv] --> readCandidateCatalog, gradedCandidates (search/Grades.h)
//   --> OUT.fits with a GRADE column and / or PAGE.html (search/VettingPage.h), written together

#include <boost/program_options.hpp>
#include <iostream>

#include "octarc/app/Commands.h"
#include "octarc/app/Options.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/search/Grades.h"

namespace octarc {

namespace {

namespace po = boost::program_options;

void printGradesUsage(const po::options_description& options) {
  std::cout
      << "Usage: octarc grades CATALOG GRADES.csv -o OUT.fits [options]\n"
         "       octarc grades CATALOG [GRADES.csv] --page PAGE.html\n"
         "\n"
         "Writes OUT.fits: a copy of the candidate catalog CATALOG (candidates.fits of octarc\n"
         "search or octarc batch, FITS-LDAC or FITS_1.0, kept as it is) with a GRADE column:\n"
         "lens, maybe or no as graded on the vetting page and exported with its Export CSV\n"
         "link, blank for a candidate not graded. Rows are matched by NUMBER (the survey's\n"
         "number in a batch's catalog); a CSV whose NAME differs from the catalog's, a NUMBER\n"
         "the catalog does not hold or a malformed line is an error naming the file and line,\n"
         "and nothing is written. CATALOG is never modified; an earlier GRADE column of it is\n"
         "replaced by the CSV's.\n"
         "\n"
         "With --page, writes the vetting page of CATALOG (with the CSV's grades, or the GRADE\n"
         "column it has, as the page's first grades): its stamps are looked up beside CATALOG,\n"
         "stamps/NNNN.png by NUMBER, or tiles/TILE/stamps/NNNN.png by TILE_NUMBER for a survey.\n"
         "\n"
      << kOptionsAsKeys << "\n"
      << options << "\n";
}

po::options_description gradesOptions() {
  po::options_description options("Options");
  // clang-format off
  options.add_options()
    ("help,h", "this help")
    ("output,o", po::value<std::string>(), "the graded catalog (not CATALOG)")
    ("page", po::value<std::string>(), "the vetting page of the (graded) catalog")
    ("quiet", "no summary line on stderr");
  // clang-format on
  return options;
}

}  // namespace

int runGrades(const std::vector<std::string>& args) {
  const po::options_description options = gradesOptions();
  const std::optional<ParsedOptions> parsed =
      parseOptions(args, {"grades", [&] { printGradesUsage(options); }, nullptr}, options, 2);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->values;
  const std::vector<std::string>& files = parsed->positional;
  const std::string output = vm.count("output") ? vm["output"].as<std::string>() : "";
  const std::string page = vm.count("page") ? vm["page"].as<std::string>() : "";
  if (files.empty() || (output.empty() && page.empty())) {
    throw ConfigError(
        "grades: give the catalog, the grades CSV and -o OUT.fits, or --page "
        "PAGE.html (see octarc grades -h)");
  }
  if (!output.empty() && files.size() < 2) {
    throw ConfigError("grades: -o " + output + " needs the grades CSV after the catalog");
  }
  if (!output.empty()) refuseOutputOverInput(output, "-o", files[0], "CATALOG");
  CandidateCatalog catalog = readCandidateCatalog(files[0]);
  std::int64_t graded = 0;
  if (files.size() == 2) {
    const std::map<std::int64_t, CandidateGrade> grades = readGradesCsv(files[1]);
    catalog.objects = gradedCandidates(catalog.objects, grades, files[1]);
    graded = std::int64_t(grades.size());
  }
  OutputFiles outputs;
  if (!output.empty()) outputs.add(output);
  if (!page.empty()) outputs.add(page);
  std::size_t next = 0;
  if (!output.empty()) {
    outputs.write(next++, [&](const std::string& path) { writeCandidateCatalog(path, catalog); });
  }
  if (!page.empty()) {
    outputs.write(next++, [&](const std::string& path) {
      writeTextFile(path, catalogPageHtml(catalog.objects, files[0], page));
    });
  }
  outputs.commit();
  if (vm.count("quiet") == 0) {
    std::cerr << "> Wrote " << (output.empty() ? page : output)
              << (page.empty() || output.empty() ? "" : " and " + page);
    if (files.size() == 2) {
      std::cerr << ": " << graded << " graded candidate(s) from " << files[1];
    }
    std::cerr << "\n";
  }
  return 0;
}

}  // namespace octarc
