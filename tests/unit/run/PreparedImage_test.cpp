// Values octarc takes from headers it did not write: an input catalog's LDAC_IMHEAD and the
// image's GAIN / SATURATE keywords.
#include "octarc/run/PreparedImage.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

std::string card(const std::string& key, const std::string& value) {
  std::string c = key;
  c.resize(8, ' ');
  c += "= " + value;
  c.resize(80, ' ');
  return c;
}

InputCatalogPart partWith(const std::vector<std::string>& cards) {
  InputCatalogPart part;
  part.objectsHdu = 3;  // cfitsio's numbering: HDU 2 from 0
  part.imageHeader.cards = cards;
  return part;
}

TEST(CatalogRunValues, ReadsWhatSExtractorWrote) {
  const CatalogRunValues v =
      catalogRunValues(partWith({card("SEXBKGND", "1.004398345947E+02"),
                                 card("SEXBKDEV", "5.1E+00"), card("SEXGAIN", "0.000000000000E+00"),
                                 card("SEXTHLD", "1.53E+01"), card("SEXATHLD", "1.53E+01")}),
                       "cat.ldac");
  EXPECT_EQ(v.backgroundAdu, 100.4398345947);
  EXPECT_EQ(v.sigmaAdu, 5.1);
  EXPECT_EQ(v.gain, 0.0);  // SExtractor's "infinite gain"
  EXPECT_EQ(v.thresholdAdu, 15.3);
  EXPECT_EQ(v.analysisThresholdAdu, 15.3);
  // Absent keywords (a FITS_1.0 catalog has no LDAC_IMHEAD) leave the values unset.
  const CatalogRunValues none = catalogRunValues(partWith({}), "cat.fits");
  EXPECT_FALSE(none.backgroundAdu || none.sigmaAdu || none.gain || none.thresholdAdu ||
               none.analysisThresholdAdu);
  // A negative background is a legal level.
  EXPECT_EQ(catalogRunValues(partWith({card("SEXBKGND", "-2.5")}), "c").backgroundAdu, -2.5);
}

// Accepted with exit 0 before: SEXBKGND = NaN (every row NaN), SEXGAIN < 0 (wrong FLUXERR).
TEST(CatalogRunValues, ImpossibleValuesAreAnIoErrorNamingCatalogAndKeyword) {
  struct Case {
    const char* key;
    const char* value;
    const char* shown;
  };
  const std::vector<Case> cases = {
      {"SEXBKGND", "NaN", "SEXBKGND = 'NaN'"}, {"SEXBKGND", "'x'", "SEXBKGND = 'x'"},
      {"SEXBKDEV", "0.0", "SEXBKDEV = '0.0'"}, {"SEXBKDEV", "-1", "SEXBKDEV = '-1'"},
      {"SEXBKDEV", "Inf", "SEXBKDEV = 'Inf'"}, {"SEXGAIN", "-1.0", "SEXGAIN = '-1.0'"},
      {"SEXGAIN", "T", "SEXGAIN = 'T'"},       {"SEXTHLD", "0", "SEXTHLD = '0'"},
      {"SEXTHLD", "-3", "SEXTHLD = '-3'"},     {"SEXATHLD", "NaN", "SEXATHLD = 'NaN'"},
      {"SEXATHLD", "0.0", "SEXATHLD = '0.0'"},
  };
  for (const Case& c : cases) {
    try {
      catalogRunValues(partWith({card(c.key, c.value)}), "run3.ldac");
      ADD_FAILURE() << "no IoError for " << c.key << " = " << c.value;
    } catch (const IoError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find("run3.ldac: LDAC_IMHEAD for the objects table in HDU 2: "), 0u) << what;
      EXPECT_NE(what.find(c.shown), std::string::npos) << what;
    }
  }
}

TEST(HeaderNonNegative, UsableValuesAreTakenSilently) {
  FitsHeader header;
  header.cards = {card("GAIN", "4.0"), card("SATURATE", "0"), card("EGAIN", "1.5D0")};
  std::vector<std::string> warnings;
  EXPECT_EQ(headerNonNegative(header, "GAIN", "im.fits", "GAIN 2", warnings), 4.0);
  EXPECT_EQ(headerNonNegative(header, "SATURATE", "im.fits", "SATUR_LEVEL 1", warnings), 0.0);
  EXPECT_EQ(headerNonNegative(header, "EGAIN", "im.fits", "GAIN 2", warnings), 1.5);
  EXPECT_FALSE(headerNonNegative(header, "ABSENT", "im.fits", "GAIN 2", warnings).has_value());
  EXPECT_TRUE(warnings.empty());
}

// Header GAIN -1, NaN or 'x' were silently dropped or used.
TEST(HeaderNonNegative, OtherValuesAreIgnoredWithAWarningSayingWhatIsUsed) {
  for (const std::string value : {"-1", "NaN", "'x'", "Inf", "(1.0, 2.0)"}) {
    FitsHeader header;
    header.cards = {card("GAIN", value)};
    std::vector<std::string> warnings;
    EXPECT_FALSE(
        headerNonNegative(header, "GAIN", "im.fits", "GAIN 4 of the configuration", warnings)
            .has_value());
    ASSERT_EQ(warnings.size(), 1u) << value;
    const std::string shown = value.front() == '\'' ? "'x'" : "'" + value + "'";
    EXPECT_EQ(warnings[0], "im.fits: header GAIN = " + shown +
                               " is not a finite number >= 0: ignored, using GAIN 4 of the "
                               "configuration instead");
  }
}

}  // namespace
}  // namespace octarc
