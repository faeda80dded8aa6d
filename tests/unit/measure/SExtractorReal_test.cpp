// The measurement plan on the objects of a real source-extractor run: the NTT/EMMI image of the
// shared reference data, pure thresholding (FILTER N or Y, DEBLEND_NTHRESH 1, CLEAN N, manual
// background), its SEGMENTATION map read back as footprints. Every object's isophotal columns
// must agree with source-extractor's catalog to the precision it prints them with.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "ConvKernels.h"
#include "TestCommands.h"
#include "TestPaths.h"
#include "octarc/detection/Filter.h"
#include "octarc/io/FitsImage.h"
#include "octarc/measure/Registry.h"

namespace octarc {
namespace {

constexpr double kBackgroundAdu = 6850.0;  // about the image median
constexpr double kDetectSigma = 3.0;
constexpr double kAnalysisSigma = 4.0;
constexpr double kGain = 1.5;
constexpr double kZeropoint = 25.0;
constexpr double kSaturAdu = 50000.0;
const char* const kConv = "/usr/share/source-extractor/default.conv";

// An ASCII_HEAD catalog: "#   n NAME  description [unit]" lines, then rows.
struct AsciiCatalog {
  std::map<std::string, int> column;
  std::vector<std::vector<double>> rows;
  double get(std::size_t row, const std::string& name) const {
    return rows[row].at(column.at(name) - 1);
  }
};

AsciiCatalog readAsciiHead(const std::string& path) {
  AsciiCatalog cat;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    if (line.rfind('#', 0) == 0) {
      std::string hash, name;
      int n = 0;
      ss >> hash >> n >> name;
      cat.column[name] = n;
      continue;
    }
    std::vector<double> values;
    double v;
    while (ss >> v) values.push_back(v);
    if (!values.empty()) cat.rows.push_back(values);
  }
  return cat;
}

// Footprints from a SEGMENTATION map: label -> pixels in raster order.
std::map<int, Segment> segmentsOf(const ImageI32& seg) {
  std::map<int, Segment> out;
  for (std::int64_t p = 0; p < seg.size(); ++p) {
    if (seg[p] <= 0) continue;
    Segment& s = out[seg[p]];
    s.number = seg[p];
    s.pixels.push_back(p);
  }
  return out;
}

void compareWithSExtractor(bool filter) {
  OCTARC_REQUIRE_SHARED_DATA(shared);
  if (!test::haveProgram("source-extractor")) {
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  }
  if (filter && !std::ifstream(kConv)) OCTARC_SKIP_MISSING() << kConv << " not found";
  const std::string image = (shared / "ntt-emmi" / "galaxies.fits").string();
  const std::filesystem::path dir = test::scratchDir();
  {
    std::ofstream param(dir / "r.param");
    for (const char* n :
         {"NUMBER",        "X_IMAGE",        "Y_IMAGE",     "X2_IMAGE",    "Y2_IMAGE",  "XY_IMAGE",
          "A_IMAGE",       "B_IMAGE",        "THETA_IMAGE", "CXX_IMAGE",   "CYY_IMAGE", "CXY_IMAGE",
          "ISOAREA_IMAGE", "ISOAREAF_IMAGE", "FLUX_ISO",    "FLUXERR_ISO", "MAG_ISO",   "FLUX_MAX",
          "XMIN_IMAGE",    "YMAX_IMAGE",     "THRESHOLD",   "FLAGS"}) {
      param << n << "\n";
    }
  }
  std::ostringstream cmd;
  cmd << "cd '" << dir.string() << "' && source-extractor '" << image << "'"
      << " -PARAMETERS_NAME r.param -CATALOG_TYPE ASCII_HEAD -CATALOG_NAME r.cat"
      << " -CHECKIMAGE_TYPE SEGMENTATION -CHECKIMAGE_NAME seg.fits"
      << " -FILTER " << (filter ? "Y" : "N") << " -FILTER_NAME " << kConv
      << " -DEBLEND_NTHRESH 1 -DEBLEND_MINCONT 1 -CLEAN N -BACK_TYPE MANUAL -BACK_VALUE "
      << kBackgroundAdu << " -THRESH_TYPE RELATIVE -DETECT_THRESH " << kDetectSigma
      << " -ANALYSIS_THRESH " << kAnalysisSigma << " -DETECT_MINAREA 3 -GAIN " << kGain
      << " -SATUR_LEVEL " << kSaturAdu << " -MAG_ZEROPOINT " << kZeropoint
      << " -VERBOSE_TYPE QUIET > sex.log 2>&1";
  ASSERT_EQ(std::system(cmd.str().c_str()), 0) << cmd.str();

  const AsciiCatalog cat = readAsciiHead((dir / "r.cat").string());
  ASSERT_GT(cat.rows.size(), 100u);
  // source-extractor's global sigma, from THRESHOLD = DETECT_THRESH * sigma (7 digits).
  const double sigmaAdu = cat.get(0, "THRESHOLD") / kDetectSigma;

  ImageHdu hdu = readImage(image);
  ImageF& measurement = hdu.pixels;
  // source-extractor scales BITPIX 16 data in single precision, float(BSCALE) * i +
  // float(BZERO) (checked: a float copy made that way gives its catalog digit for digit), while
  // the reader scales in double. Redo its arithmetic so the comparison can be tight.
  const double bscale = hdu.header.number("BSCALE").value_or(1.0);
  const double bzero = hdu.header.number("BZERO").value_or(0.0);
  ASSERT_EQ(hdu.bitpix, 16);
  for (float& v : measurement.pixels()) {
    const float stored = float(std::nearbyint((double(v) - bzero) / bscale));
    const float scaled = float(bscale) * stored + float(bzero);
    v = scaled - float(kBackgroundAdu);
  }
  ImageF filtered;
  if (filter) {
    filtered = applyFilter(measurement, test::defaultConvKernel());
  }
  const ImageI32 seg = readIntImage((dir / "seg.fits").string());
  const std::map<int, Segment> segments = segmentsOf(seg);
  ASSERT_EQ(segments.size(), cat.rows.size());

  MeasureContext context;
  context.measurement = &measurement;
  context.detection = filter ? &filtered : &measurement;
  // SATUR_LEVEL applies to raw values: background-subtracted value + the constant background.
  std::vector<std::int64_t> saturated;
  for (std::int64_t p = 0; p < measurement.size(); ++p) {
    if (double(measurement[p]) + kBackgroundAdu >= kSaturAdu) saturated.push_back(p);
  }
  context.saturatedPixels = &saturated;
  context.sigmaAdu = sigmaAdu;
  context.gain = kGain;
  context.magZeropoint = kZeropoint;
  context.levels = {
      ThresholdLevel{1, kDetectSigma * sigmaAdu, kAnalysisSigma * sigmaAdu, kDetectSigma}};

  std::vector<ColumnRequest> request;
  for (const auto& [name, index] : cat.column) request.push_back({name});
  const MeasurementPlan plan = MeasurementPlan::build(request, {}, nullptr);
  ASSERT_EQ(plan.columns().size(), cat.column.size());
  std::map<std::string, int> offset;
  for (int c = 0; c < int(plan.columns().size()); ++c) offset[plan.columns()[c].name] = c;

  // The catalog is printed: each value is SExtractor's rounded to the printf format of its
  // column (the same format octarc declares). octarc's values are SExtractor's to the bit for
  // most columns and within 2 float ulps for the others (tests/integration/
  // test_measure_vs_sextractor.py), so each must lie within half a unit of the last printed
  // digit of the printed value, plus 2 float ulps.
  std::map<std::string, std::string> format;
  for (const ColumnSpec& c : plan.columns()) format[c.name] = c.printfFormat;
  const auto printedTolerance = [](const std::string& fmt, double printed) {
    const char conversion = fmt.back();
    const int precision = std::atoi(fmt.c_str() + fmt.find('.') + 1);
    double unit = 1.0;  // integers (%d)
    if (fmt.find('.') != std::string::npos) {
      const int exponent = printed == 0.0 ? 0 : int(std::floor(std::log10(std::fabs(printed))));
      if (conversion == 'f') unit = std::pow(10.0, -precision);
      if (conversion == 'e' || conversion == 'E') unit = std::pow(10.0, exponent - precision);
      if (conversion == 'g' || conversion == 'G') unit = std::pow(10.0, exponent - precision + 1);
    }
    const double ulp =
        std::nextafter(float(std::fabs(printed)), INFINITY) - float(std::fabs(printed));
    return conversion == 'd' ? 0.0 : 0.5 * unit + 2.0 * ulp;
  };
  std::vector<double> row(std::size_t(plan.rowWidth()));
  int failures = 0;
  for (std::size_t r = 0; r < cat.rows.size(); ++r) {
    const int number = int(cat.get(r, "NUMBER"));
    const auto it = segments.find(number);
    ASSERT_NE(it, segments.end()) << "NUMBER " << number;
    plan.measure(it->second, context, row.data());
    for (const auto& [name, index] : cat.column) {
      if (name == "THETA_IMAGE") continue;
      const double ours = row[std::size_t(offset.at(name))], theirs = cat.get(r, name);
      if (!(std::fabs(ours - theirs) <= printedTolerance(format.at(name), theirs)) &&
          ++failures <= 20) {
        ADD_FAILURE() << "NUMBER " << number << " " << name << ": octarc " << ours
                      << " source-extractor " << theirs << " (" << format.at(name) << ")";
      }
    }
    // THETA printed with 2 decimals; +90 and -90 are the same axis.
    const double dTheta = std::remainder(
        row[std::size_t(offset.at("THETA_IMAGE"))] - cat.get(r, "THETA_IMAGE"), 180.0);
    if (std::fabs(dTheta) > printedTolerance(format.at("THETA_IMAGE"), 90.0) && ++failures <= 20) {
      ADD_FAILURE() << "NUMBER " << number << " THETA_IMAGE differs by " << dTheta;
    }
  }
  EXPECT_EQ(failures, 0);
}

TEST(SExtractorReal, UnfilteredIsophotalColumnsMatch) {
  compareWithSExtractor(false);
}

TEST(SExtractorReal, FilteredDetectionMomentsMatch) {
  compareWithSExtractor(true);
}

}  // namespace
}  // namespace octarc
