// The registry: one explicit list, column metadata as source-extractor 2.25 writes it, and plans
// that run only what the requested columns need.
#include "octarc/measure/Registry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace octarc {
namespace {

const ColumnSpec* findSpec(const std::vector<ColumnSpec>& specs, const std::string& name) {
  for (const ColumnSpec& s : specs)
    if (s.name == name) return &s;
  return nullptr;
}

TEST(Registry, EveryColumnOnceWithDescription) {
  const std::vector<ColumnSpec> all = allBuiltinColumns();
  std::set<std::string> names;
  for (const ColumnSpec& c : all) {
    EXPECT_TRUE(names.insert(c.name).second) << "duplicate " << c.name;
    EXPECT_FALSE(c.description.empty()) << c.name;
    EXPECT_FALSE(c.ucd.empty()) << c.name;
    EXPECT_EQ(c.printfFormat.front(), '%') << c.name;
  }
  for (const char* n :
       {"NUMBER",      "THRESH_LEVEL", "PARENT_NUMBER", "X_IMAGE",        "Y_IMAGE",
        "XMIN_IMAGE",  "YMIN_IMAGE",   "XMAX_IMAGE",    "YMAX_IMAGE",     "XPEAK_IMAGE",
        "YPEAK_IMAGE", "X2_IMAGE",     "Y2_IMAGE",      "XY_IMAGE",       "A_IMAGE",
        "B_IMAGE",     "THETA_IMAGE",  "CXX_IMAGE",     "CYY_IMAGE",      "CXY_IMAGE",
        "ELONGATION",  "ELLIPTICITY",  "ISOAREA_IMAGE", "ISOAREAF_IMAGE", "FLUX_ISO",
        "FLUXERR_ISO", "MAG_ISO",      "MAGERR_ISO",    "FLUX_MAX",       "THRESHOLD",
        "X_WORLD",     "Y_WORLD",      "ALPHA_J2000",   "DELTA_J2000",    "X2_WORLD",
        "Y2_WORLD",    "XY_WORLD",     "A_WORLD",       "B_WORLD",        "THETA_WORLD",
        "FLAGS",       "ARCNESS",      "ANTIARCNESS",   "SKEW_MAJOR",     "SKEW_MINOR",
        "I_AAB_IMAGE", "I_ABB_IMAGE",  "I_AAA_IMAGE",   "I_BBB_IMAGE",    "ARC_SIDE",
        "E1_IMAGE",    "E2_IMAGE",     "E_IMAGE",       "SIZE_IMAGE",     "SNR_ISO",
        "OCT_FLAGS"}) {
    EXPECT_TRUE(names.count(n)) << n;
  }
}

// octarc's own descriptions fit whole in the comment of an LDAC TTYPE card (80 columns, the
// comment starting at column 34 after a name of up to 18 characters), so that astropy, TOPCAT
// and `octarc measure -dp` show the same text.
TEST(Registry, OctarcDescriptionsFitInATtypeCard) {
  const std::set<std::string> own = {
      "THRESH_LEVEL", "PARENT_NUMBER", "ARCNESS",     "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR",
      "I_AAB_IMAGE",  "I_ABB_IMAGE",   "I_AAA_IMAGE", "I_BBB_IMAGE", "ARC_SIDE",   "E1_IMAGE",
      "E2_IMAGE",     "E_IMAGE",       "SIZE_IMAGE",  "SNR_ISO",     "OCT_FLAGS"};
  for (const ColumnSpec& c : allBuiltinColumns()) {
    if (own.count(c.name)) {
      EXPECT_LE(c.description.size(), 47u) << c.name;
    }
  }
}

TEST(Registry, MetadataMatchesSourceExtractor) {
  // TFORM/TUNIT/TDISP of a source-extractor 2.25 FITS_LDAC catalog and the UCDs of its
  // ASCII_VOTABLE output (same .param).
  struct Expect {
    const char* name;
    ColumnType type;
    const char* unit;
    const char* format;
    const char* ucd;
    const char* description;
  };
  const Expect expected[] = {
      {"NUMBER", ColumnType::Int32, "", "%10d", "meta.record", "Running object number"},
      {"X_IMAGE", ColumnType::Float32, "pixel", "%11.4f",
       "pos.cartesian.x;pos.barycenter;instr.det;meta.main", "Object position along x"},
      {"X2_IMAGE", ColumnType::Float64, "pixel**2", "%18.10e", "src.impactParam;instr.det",
       "Variance along x"},
      {"A_IMAGE", ColumnType::Float32, "pixel", "%9.3f", "phys.size.smajAxis;instr.det;meta.main",
       "Profile RMS along major axis"},
      {"THETA_IMAGE", ColumnType::Float32, "deg", "%6.2f", "pos.posAng;instr.det;meta.main",
       "Position angle (CCW/x)"},
      {"CXX_IMAGE", ColumnType::Float32, "pixel**(-2)", "%15.7e", "src.impactParam;instr.det",
       "Cxx object ellipse parameter"},
      {"ELONGATION", ColumnType::Float32, "", "%8.3f", "src.ellipticity;arith.ratio;instr.det",
       "A_IMAGE/B_IMAGE"},
      {"ISOAREA_IMAGE", ColumnType::Int32, "pixel**2", "%9d", "phys.area",
       "Isophotal area above Analysis threshold"},
      {"FLUX_ISO", ColumnType::Float32, "count", "%12.7g", "phot.flux", "Isophotal flux"},
      {"MAG_ISO", ColumnType::Float32, "mag", "%8.4f", "phot.mag", "Isophotal magnitude"},
      {"XMIN_IMAGE", ColumnType::Int32, "pixel", "%10d", "pos.cartesian.x;stat.min",
       "Minimum x-coordinate among detected pixels"},
      {"X_WORLD", ColumnType::Float64, "deg", "%18.10e", "pos.eq.ra",
       "Barycenter position along world x axis"},
      {"ALPHA_J2000", ColumnType::Float64, "deg", "%11.7f", "pos.eq.ra;pos.barycenter;meta.main",
       "Right ascension of barycenter (J2000)"},
      {"DELTA_J2000", ColumnType::Float64, "deg", "%+11.7f", "pos.eq.dec;pos.barycenter;meta.main",
       "Declination of barycenter (J2000)"},
      {"X2_WORLD", ColumnType::Float64, "deg**2", "%18.10e", "src.impactParam",
       "Variance along X-WORLD (alpha)"},
      {"A_WORLD", ColumnType::Float32, "deg", "%12.7g", "phys.size.smajAxis;meta.main",
       "Profile RMS along major axis (world units)"},
      {"THETA_WORLD", ColumnType::Float32, "deg", "%6.2f", "pos.posAng",
       "Position angle (CCW/world-x)"},
      {"FLAGS", ColumnType::Int16, "", "%3d", "meta.code.qual", "Extraction flags"},
      {"THRESHOLD", ColumnType::Float32, "count", "%12.7g", "instr.sensitivity;phot.flux.sb",
       "Detection threshold above background"},
  };
  const std::vector<ColumnSpec> all = allBuiltinColumns();
  for (const Expect& e : expected) {
    const ColumnSpec* s = findSpec(all, e.name);
    ASSERT_NE(s, nullptr) << e.name;
    EXPECT_EQ(s->type, e.type) << e.name;
    EXPECT_EQ(s->unit, e.unit) << e.name;
    EXPECT_EQ(s->printfFormat, e.format) << e.name;
    EXPECT_EQ(s->ucd, e.ucd) << e.name;
    EXPECT_EQ(s->description, e.description) << e.name;
    EXPECT_EQ(s->repeat, 1) << e.name;
  }
  EXPECT_EQ(findSpec(all, "I_AAB_IMAGE")->unit, "pixel**3");
  EXPECT_EQ(findSpec(all, "SIZE_IMAGE")->unit, "pixel");
}

TEST(Registry, PlanKeepsRequestedOrderAndReportsUnknown) {
  std::vector<std::string> unknown;
  const std::vector<ColumnSpec> external = {
      {"VECTOR_ASSOC", "ASSOCiated parameter vector", "", "src", ColumnType::Float64, "%12.7g"},
      {"NUMBER_ASSOC", "Number of ASSOCiated IDs", "", "meta.number", ColumnType::Int32, "%10d"}};
  const MeasurementPlan plan = MeasurementPlan::build(
      {{"ARCNESS"}, {"FOO_BAR"}, {"VECTOR_ASSOC", 3}, {"X_IMAGE"}, {"ARCNESS"}, {"NUMBER"}},
      external, &unknown);
  ASSERT_EQ(plan.columns().size(), 4u);
  EXPECT_EQ(plan.columns()[0].name, "ARCNESS");
  EXPECT_EQ(plan.columns()[1].name, "VECTOR_ASSOC");
  EXPECT_EQ(plan.columns()[1].repeat, 3);
  EXPECT_EQ(plan.columns()[2].name, "X_IMAGE");
  EXPECT_EQ(plan.columns()[3].name, "NUMBER");
  EXPECT_EQ(plan.rowWidth(), 6);
  EXPECT_EQ(unknown, std::vector<std::string>{"FOO_BAR"});

  // External columns are left alone; built-in ones are written.
  ImageF img(4, 4, 0.0f);
  img(1, 1) = 2.0f;
  img(2, 1) = 1.0f;
  Segment s{5, 1, 0, {img.index(1, 1), img.index(2, 1)}, {}};
  MeasureContext c;
  c.measurement = &img;
  c.detection = &img;
  std::vector<double> row(6, -7.0);
  plan.measure(s, c, row.data());
  EXPECT_EQ(row[1], -7.0);
  EXPECT_EQ(row[2], -7.0);
  EXPECT_EQ(row[3], -7.0);
  EXPECT_NEAR(row[4], 1.0 + (1 * 2.0 + 2 * 1.0) / 3.0, 1e-12);
  EXPECT_EQ(row[5], 5.0);
}

TEST(Registry, OnlyNeededMeasurementsRunInDependencyOrder) {
  using Names = std::vector<std::string>;
  EXPECT_EQ(MeasurementPlan::build({{"ARCNESS"}}, {}, nullptr).measurementNames(),
            Names{"Octopole"});
  EXPECT_EQ(MeasurementPlan::build({{"X_WORLD"}}, {}, nullptr).measurementNames(),
            (Names{"Footprint", "IsophotalShape", "WorldCoordinates"}));
  EXPECT_EQ(MeasurementPlan::build({{"OCT_FLAGS"}, {"NUMBER"}}, {}, nullptr).measurementNames(),
            (Names{"Identity", "Footprint", "IsophotalShape", "IsophotalPhotometry", "Octopole",
                   "QualityFlags"}));
  EXPECT_TRUE(MeasurementPlan::build({}, {}, nullptr).measurementNames().empty());

  // Every declared dependency exists and comes earlier in the registration list.
  const auto list = builtinMeasurements();
  for (std::size_t i = 0; i < list.size(); ++i) {
    for (const std::string& dep : list[i]->dependencies()) {
      const auto it = std::find_if(list.begin(), list.begin() + std::ptrdiff_t(i),
                                   [&](const auto& m) { return m->name() == dep; });
      EXPECT_NE(it, list.begin() + std::ptrdiff_t(i)) << list[i]->name() << " -> " << dep;
    }
  }
}

}  // namespace
}  // namespace octarc
