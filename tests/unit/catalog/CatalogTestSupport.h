// Helpers of the catalog tests: small FITS images, source-extractor runs, header and table
// reading with cfitsio. Commands and whole files: tests/support/TestCommands.h, TestFiles.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "TestCommands.h"
#include "TestFiles.h"
#include "octarc/core/Table.h"

namespace octarc::test {

// One header card split into keyword, value and comment (as cfitsio parses them).
struct Card {
  std::string key;
  std::string value;
  std::string comment;
  std::string image;  // the 80 characters
};

// A 64x48 float32 image with GAIN=2 and OBJECT='test' holding a 3x2 block of 10, a 5-pixel
// diagonal of 5s and an elliptical Gaussian (peak 100, sigma 3/2 px) cut below 0.5.
void writeSmallImage(const std::filesystem::path& file);
// Primary without data, then two image extensions: the small image and the same image with
// only the block and the diagonal (two objects).
void writeTwoExtensionImage(const std::filesystem::path& file);

// Runs source-extractor in `dir` on `image` in the pure-thresholding configuration (FILTER N,
// DEBLEND_NTHRESH 1, CLEAN N, absolute threshold 1 ADU, BACK_VALUE 0) with `param` as
// PARAMETERS_NAME; returns the catalog path.
std::filesystem::path runSourceExtractor(const std::filesystem::path& dir, const std::string& image,
                                         const std::string& param, const std::string& catalogType,
                                         const std::string& catalogName);

int hduCount(const std::filesystem::path& file);
std::vector<Card> headerCards(const std::filesystem::path& file, int hdu);
// The whole data area of a table HDU (NAXIS1 * NAXIS2 bytes).
std::string tableBytes(const std::filesystem::path& file, int hdu);
// The cards of an LDAC_IMHEAD cell (80 characters each, END included).
std::vector<std::string> imheadCards(const std::filesystem::path& file, int hdu);
// Reads the named columns of a table HDU into a Table declared with `columns`.
Table readTable(const std::filesystem::path& file, int hdu, const std::vector<ColumnSpec>& columns);
// Values of one column (every element of every row) as double.
std::vector<double> columnValues(const std::filesystem::path& file, int hdu,
                                 const std::string& name);

// What `fitsverify -q` says about one file, read from its summary line ("verification OK: FILE",
// or "verification FAILED: FILE, 2 warnings and 0 errors"): the counts, or -1 when the line is
// not there (fitsverify missing or crashed); `text` is the whole report.
struct FitsverifyReport {
  int warnings = -1;
  int errors = -1;
  std::string text;
};
FitsverifyReport fitsverify(const std::filesystem::path& file);

}  // namespace octarc::test
