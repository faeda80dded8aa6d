#include "CatalogTestSupport.h"

#include <cmath>
#include <regex>
#include <stdexcept>

#include "octarc/io/detail/Cfitsio.h"

namespace octarc::test {

namespace {

void check(int status, const std::string& what) {
  if (status != 0) throw std::runtime_error(what + ": " + detail::cfitsioMessage(status));
}

std::vector<float> smallPixels(bool withGaussian) {
  const int nx = 64;
  const int ny = 48;
  std::vector<float> pixels(std::size_t(nx * ny), 0.0f);
  auto at = [&](int x, int y) -> float& { return pixels[std::size_t(y * nx + x)]; };
  for (int y = 4; y <= 5; ++y) {
    for (int x = 9; x <= 11; ++x) at(x, y) = 10.0f;  // 1-based x 10-12, y 5-6
  }
  for (int i = 0; i < 5; ++i) at(20 + i, 20 + i) = 5.0f;
  if (withGaussian) {
    for (int y = 0; y < ny; ++y) {
      for (int x = 0; x < nx; ++x) {
        const double dx = (x - 45.3) / 3.0;
        const double dy = (y - 35.7) / 2.0;
        const double v = 100.0 * std::exp(-0.5 * (dx * dx + dy * dy));
        if (v >= 0.5) at(x, y) += float(v);
      }
    }
  }
  return pixels;
}

// cfitsio adds COMMENT cards about the FITS definition to a primary header; dropped so that the
// image header is SIMPLE..NAXIS2, EXTEND, GAIN, OBJECT.
void dropComments(fitsfile* f) {
  int status = 0;
  while (status == 0) fits_delete_key(f, "COMMENT", &status);
  fits_clear_errmsg();
}

void writeImageHdu(fitsfile* f, const std::vector<float>& pixels) {
  int status = 0;
  long naxes[2] = {64, 48};
  fits_create_img(f, FLOAT_IMG, 2, naxes, &status);
  dropComments(f);
  double gain = 2.0;
  fits_write_key(f, TDOUBLE, "GAIN", &gain, "", &status);
  fits_write_key(f, TSTRING, "OBJECT", const_cast<char*>("test"), "", &status);
  fits_write_img(f, TFLOAT, 1, LONGLONG(pixels.size()), const_cast<float*>(pixels.data()), &status);
  check(status, "write test image");
}

}  // namespace

void writeSmallImage(const std::filesystem::path& file) {
  std::filesystem::remove(file);
  detail::FitsPtr f = detail::createFits(file.string());
  writeImageHdu(f.get(), smallPixels(true));
}

void writeTwoExtensionImage(const std::filesystem::path& file) {
  std::filesystem::remove(file);
  detail::FitsPtr f = detail::createFits(file.string());
  int status = 0;
  fits_create_img(f.get(), FLOAT_IMG, 0, nullptr, &status);
  dropComments(f.get());
  check(status, "write primary");
  writeImageHdu(f.get(), smallPixels(true));
  writeImageHdu(f.get(), smallPixels(false));
}

FitsverifyReport fitsverify(const std::filesystem::path& file) {
  FitsverifyReport report;
  runCommand("fitsverify -q '" + file.string() + "' 2>&1", &report.text);
  // The summary ends the report; the counts are matched whole, so "10 errors" is not "0 errors".
  static const std::regex failed(
      R"(verification FAILED: .*, (\d+) warnings? and (\d+) errors?\s*$)");
  static const std::regex ok(R"(verification OK: .*\s*$)");
  std::smatch m;
  if (std::regex_search(report.text, m, failed)) {
    report.warnings = std::stoi(m[1].str());
    report.errors = std::stoi(m[2].str());
  } else if (std::regex_search(report.text, ok)) {
    report.warnings = 0;
    report.errors = 0;
  }
  return report;
}

std::filesystem::path runSourceExtractor(const std::filesystem::path& dir, const std::string& image,
                                         const std::string& param, const std::string& catalogType,
                                         const std::string& catalogName) {
  const std::string cd = "cd '" + dir.string() + "' && ";
  if (!std::filesystem::exists(dir / "full.sex")) {
    if (runCommand(cd + "source-extractor -dd > full.sex 2>/dev/null") != 0) {
      throw std::runtime_error("source-extractor -dd failed");
    }
  }
  const std::string command =
      cd + "source-extractor " + image + " -c full.sex -PARAMETERS_NAME " + param +
      " -FILTER_NAME /usr/share/source-extractor/default.conv"
      " -STARNNW_NAME /usr/share/source-extractor/default.nnw -CATALOG_TYPE " +
      catalogType + " -CATALOG_NAME " + catalogName +
      " -CHECKIMAGE_TYPE NONE -DETECT_THRESH 1.0 -ANALYSIS_THRESH 1.0 -THRESH_TYPE ABSOLUTE"
      " -DETECT_MINAREA 1 -FILTER N -DEBLEND_NTHRESH 1 -DEBLEND_MINCONT 1.0 -CLEAN N"
      " -BACK_TYPE MANUAL -BACK_VALUE 0.0 -GAIN 0 -PHOT_APERTURES 3,5,7 -PHOT_FLUXFRAC 0.5,0.9"
      " -MAG_ZEROPOINT 25 -VERBOSE_TYPE QUIET > se.log 2>&1";
  if (runCommand(command) != 0) {
    throw std::runtime_error("source-extractor failed: " + readFile(dir / "se.log"));
  }
  return dir / catalogName;
}

int hduCount(const std::filesystem::path& file) {
  detail::FitsPtr f = detail::openFits(file.string());
  int n = 0;
  int status = 0;
  fits_get_num_hdus(f.get(), &n, &status);
  check(status, "count HDUs");
  return n;
}

std::vector<Card> headerCards(const std::filesystem::path& file, int hdu) {
  detail::FitsPtr f = detail::openFits(file.string());
  int status = 0;
  fits_movabs_hdu(f.get(), hdu, nullptr, &status);
  int nkeys = 0;
  fits_get_hdrspace(f.get(), &nkeys, nullptr, &status);
  check(status, "read header");
  std::vector<Card> cards;
  for (int k = 1; k <= nkeys; ++k) {
    char record[FLEN_CARD] = {0};
    char key[FLEN_KEYWORD] = {0};
    char value[FLEN_VALUE] = {0};
    char comment[FLEN_COMMENT] = {0};
    int length = 0;
    fits_read_record(f.get(), k, record, &status);
    fits_get_keyname(record, key, &length, &status);
    fits_parse_value(record, value, comment, &status);
    check(status, "parse card");
    std::string image = record;
    image.resize(80, ' ');
    cards.push_back({key, value, comment, image});
  }
  return cards;
}

std::string tableBytes(const std::filesystem::path& file, int hdu) {
  detail::FitsPtr f = detail::openFits(file.string());
  int status = 0;
  fits_movabs_hdu(f.get(), hdu, nullptr, &status);
  long width = 0;
  long rows = 0;
  fits_read_key_lng(f.get(), "NAXIS1", &width, nullptr, &status);
  fits_get_num_rows(f.get(), &rows, &status);
  check(status, "read table size");
  std::string bytes(std::size_t(width * rows), '\0');
  if (!bytes.empty()) {
    fits_read_tblbytes(f.get(), 1, 1, LONGLONG(bytes.size()),
                       reinterpret_cast<unsigned char*>(bytes.data()), &status);
  }
  check(status, "read table bytes");
  return bytes;
}

std::vector<std::string> imheadCards(const std::filesystem::path& file, int hdu) {
  const std::string cell = tableBytes(file, hdu);
  std::vector<std::string> cards;
  for (std::size_t at = 0; at + 80 <= cell.size(); at += 80) cards.push_back(cell.substr(at, 80));
  return cards;
}

std::vector<double> columnValues(const std::filesystem::path& file, int hdu,
                                 const std::string& name) {
  detail::FitsPtr f = detail::openFits(file.string());
  int status = 0;
  fits_movabs_hdu(f.get(), hdu, nullptr, &status);
  int col = 0;
  fits_get_colnum(f.get(), CASESEN, const_cast<char*>(name.c_str()), &col, &status);
  int type = 0;
  long repeat = 0;
  long width = 0;
  long rows = 0;
  fits_get_coltype(f.get(), col, &type, &repeat, &width, &status);
  fits_get_num_rows(f.get(), &rows, &status);
  check(status, "find column " + name);
  std::vector<double> values(std::size_t(rows * repeat));
  int anyNull = 0;
  if (!values.empty()) {
    fits_read_col(f.get(), TDOUBLE, col, 1, 1, LONGLONG(values.size()), nullptr, values.data(),
                  &anyNull, &status);
  }
  check(status, "read column " + name);
  return values;
}

Table readTable(const std::filesystem::path& file, int hdu,
                const std::vector<ColumnSpec>& columns) {
  Table table(columns);
  std::vector<std::vector<double>> values;
  for (const ColumnSpec& c : columns) values.push_back(columnValues(file, hdu, c.name));
  const std::size_t rows = values.empty() ? 0 : values[0].size() / std::size_t(columns[0].repeat);
  for (std::size_t r = 0; r < rows; ++r) {
    table.appendRow();
    for (std::size_t c = 0; c < columns.size(); ++c) {
      for (int e = 0; e < columns[c].repeat; ++e) {
        table.setValue(std::int64_t(r), int(c),
                       values[c][r * std::size_t(columns[c].repeat) + std::size_t(e)], e);
      }
    }
  }
  return table;
}

}  // namespace octarc::test
