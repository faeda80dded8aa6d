// Card formatting, SEx* run cards, catalog-type keywords and value formatting.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "CatalogTestSupport.h"
#include "TestPaths.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/catalog/RunSummary.h"
#include "octarc/core/Error.h"

namespace octarc {
namespace {

std::string pad(std::string s) {
  s.resize(80, ' ');
  return s;
}

TEST(FitsCard, FormatsEachValueTypeInTheFixedFormat) {
  // Expected strings are cards of a source-extractor 2.25 LDAC_IMHEAD.
  EXPECT_EQ(formatCard("SEXBKGND", RealValue(0.0), "Median background level (ADU)"),
            pad("SEXBKGND=   0.000000000000E+00 / Median background level (ADU)"));
  EXPECT_EQ(formatCard("SEXSFWHM", RealValue(double(1.2f)), "x"),
            pad("SEXSFWHM=   1.200000047684E+00 / x"));
  EXPECT_EQ(
      formatCard("SEXMGZPT", RealValue(25.0, RealFormat::Fixed), "Zero-point used for magnitudes"),
      pad("SEXMGZPT=          25.00000000 / Zero-point used for magnitudes"));
  EXPECT_EQ(formatCard("SEXNDET", std::int64_t(3), "Number of raw detections"),
            pad("SEXNDET =                    3 / Number of raw detections"));
  EXPECT_EQ(formatCard("SEXFLTR", false, "Detection filtering activated (flag)"),
            pad("SEXFLTR =                    F / Detection filtering activated (flag)"));
  EXPECT_EQ(formatCard("FITSFILE", std::string("small.fits"), "File name of the analysed image"),
            pad("FITSFILE= 'small.fits'         / File name of the analysed image"));
  EXPECT_EQ(formatCard("SEXVERS", std::string("Source Extractor 2.25.0"), "Extraction software"),
            pad("SEXVERS = 'Source Extractor 2.25.0' / Extraction software"));
  // Short strings get at least 8 characters inside the quotes; no comment, no slash.
  EXPECT_EQ(formatCard("TTYPE1", std::string("NUMBER")), pad("TTYPE1  = 'NUMBER  '"));
  // Quotes are doubled.
  EXPECT_EQ(formatCard("OBJECT", std::string("O'Neil")), pad("OBJECT  = 'O''Neil '"));
}

TEST(FitsCard, CutsLongCommentsAtColumn80) {
  const std::string card =
      formatCard("SEXBKGSY", std::int64_t(48), "Mesh height used for background mapping (pixels)");
  EXPECT_EQ(card.size(), 80u);
  EXPECT_EQ(card,
            "SEXBKGSY=                   48 / Mesh height used for background mapping (pixels");
}

TEST(FitsCard, RejectsBadKeywords) {
  EXPECT_THROW(formatCard("TOOLONGKEY", std::int64_t(1)), ConfigError);
  EXPECT_THROW(formatCard("lower", std::int64_t(1)), ConfigError);
  EXPECT_THROW(formatCard("", std::int64_t(1)), ConfigError);
}

TEST(CatalogType, ParsesSExtractorKeywords) {
  EXPECT_EQ(parseCatalogType("FITS_LDAC"), CatalogType::FitsLdac);
  EXPECT_EQ(parseCatalogType("fits_1.0"), CatalogType::Fits10);
  EXPECT_EQ(parseCatalogType("ASCII_HEAD"), CatalogType::AsciiHead);
  EXPECT_EQ(parseCatalogType("ascii"), CatalogType::Ascii);
  EXPECT_EQ(parseCatalogType("ascii_votable"), CatalogType::AsciiVotable);
  EXPECT_EQ(parseCatalogType("NONE"), CatalogType::None);
  for (const char* bad : {"ASCII_SKYCAT", "FITS_TPX"}) {
    try {
      parseCatalogType(bad);
      ADD_FAILURE() << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("not supported"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parseCatalogType("FITS"), ConfigError);
  EXPECT_EQ(catalogTypeName(CatalogType::Fits10), "FITS_1.0");
  EXPECT_EQ(catalogTypeName(CatalogType::AsciiVotable), "ASCII_VOTABLE");
}

TEST(ColumnFormat, TdispFromPrintf) {
  EXPECT_EQ(tdispFromPrintf("%10d"), "I10");
  EXPECT_EQ(tdispFromPrintf("%11.4f"), "F11.4");
  EXPECT_EQ(tdispFromPrintf("%18.10e"), "E18.10");
  EXPECT_EQ(tdispFromPrintf("%12.7g"), "G12.7");
  EXPECT_EQ(tdispFromPrintf("%+6.2f"), "F6.2");
  EXPECT_EQ(tdispFromPrintf("%3d"), "I3");
  EXPECT_EQ(tdispFromPrintf("%15.7E"), "E15.7");
  EXPECT_EQ(tdispFromPrintf("%d"), "");
  EXPECT_EQ(tdispFromPrintf("%s"), "");
}

TEST(ColumnFormat, TformCarriesTheRepeatCount) {
  ColumnSpec c;
  c.type = ColumnType::Float32;
  EXPECT_EQ(tformOf(c), "1E");
  c.type = ColumnType::Float64;
  c.repeat = 3;
  EXPECT_EQ(tformOf(c), "3D");
  c.type = ColumnType::Int16;
  c.repeat = 1;
  EXPECT_EQ(tformOf(c), "1I");
  c.type = ColumnType::Int32;
  EXPECT_EQ(tformOf(c), "1J");
  c.type = ColumnType::Int64;
  EXPECT_EQ(tformOf(c), "1K");
}

TEST(ColumnFormat, AsciiValuesFollowTheStorageType) {
  ColumnSpec number{"NUMBER", "Running object number", "", "", ColumnType::Int32, "%10d", 1};
  EXPECT_EQ(formatAsciiValue(number, 7.0), "         7");
  EXPECT_EQ(formatAsciiValue(number, std::nan("")), "         0");
  ColumnSpec flags{"FLAGS", "Extraction flags", "", "", ColumnType::Int16, "%3d", 1};
  EXPECT_EQ(formatAsciiValue(flags, 40000.0), "32767");  // clamped to the int16 range
  ColumnSpec x{"X_IMAGE", "x", "pixel", "", ColumnType::Float32, "%11.4f", 1};
  EXPECT_EQ(formatAsciiValue(x, 46.30196), "    46.3020");
  EXPECT_EQ(formatAsciiValue(x, std::nan("")), "        nan");
  EXPECT_EQ(formatAsciiValue(x, -std::nan("")), "        nan");  // never "-nan"
  ColumnSpec theta{"THETA", "t", "deg", "", ColumnType::Float32, "%+6.2f", 1};
  EXPECT_EQ(formatAsciiValue(theta, 45.0), "+45.00");
  EXPECT_EQ(formatAsciiValue(theta, std::nan("")), "   nan");  // never "+nan"
  ColumnSpec left{"L", "l", "", "", ColumnType::Float64, "%-9.3f", 1};
  EXPECT_EQ(formatAsciiValue(left, std::nan("")), "nan      ");
  // A float column is printed as the float it is stored as: 0.1f = 0.100000001490116...
  ColumnSpec g{"F", "f", "", "", ColumnType::Float32, "%18.10e", 1};
  EXPECT_EQ(formatAsciiValue(g, 0.1), "  1.0000000149e-01");
  ColumnSpec d{"D", "d", "", "", ColumnType::Float64, "%18.10e", 1};
  EXPECT_EQ(formatAsciiValue(d, 0.1), "  1.0000000000e-01");
  ColumnSpec bad{"B", "b", "", "", ColumnType::Float64, "%s", 1};
  EXPECT_THROW(formatAsciiValue(bad, 1.0), ConfigError);
}

// The SEx* cards of source-extractor's own LDAC_IMHEAD, rebuilt from the same run values.
TEST(RunSummary, CardsMatchSourceExtractor) {
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const auto dir = test::scratchDir();
  test::writeSmallImage(dir / "small.fits");
  {
    std::FILE* f = std::fopen((dir / "t.param").c_str(), "w");
    std::fputs("NUMBER\nX_IMAGE\nFLUX_APER(3)\n", f);
    std::fclose(f);
  }
  const auto cat = test::runSourceExtractor(dir, "small.fits", "t.param", "FITS_LDAC", "c.ldac");
  const std::vector<std::string> cell = test::imheadCards(cat, 2);
  // 8 image cards (SIMPLE, BITPIX, NAXIS, NAXIS1, NAXIS2, EXTEND, GAIN, OBJECT), the run cards, END
  ASSERT_EQ(cell.size(), 8u + 46u + 1u);
  auto valueOf = [&](const std::string& key) {
    for (const std::string& c : cell) {
      if (c.compare(0, 8, (key + "        ").substr(0, 8)) == 0) return c.substr(10, 20);
    }
    return std::string();
  };
  RunSummary run;
  run.fitsFile = "small.fits";
  run.fitsExt = 1;
  run.fitsNext = 1;
  run.version = "Source Extractor 2.25.0";
  const std::string date = valueOf("SEXDATE");  // the run's own date and time
  run.date = date.substr(1, 10);
  run.time = valueOf("SEXTIME").substr(1, 8);
  run.elapsedSec = std::stod(valueOf("SEXELAPS"));
  run.backgroundAdu = 0.0;
  run.backgroundRmsAdu = 1.0;  // MANUAL background with a constant image: RMS 1
  run.thresholdAdu = 1.0;
  run.analysisThresholdAdu = 1.0;
  run.detections = 3;
  run.finalObjects = 3;
  run.parameters = 3;
  run.pixelScaleArcsec = 1.0;
  run.seeingFwhmArcsec = double(1.2f);
  run.nnwFile = "default.nnw";
  run.gainEPerAdu = 2.0;  // the header GAIN wins over -GAIN 0
  run.filtering = false;
  run.filterFile = "default.conv";
  run.minAreaPix = 1;
  run.deblendThresholds = 1;
  run.deblendContrast = 1.0;
  run.cleaning = false;
  run.cleanParam = 1.0;
  run.cleanStack = 3000;
  run.apertureDiamPix[0] = 3;
  run.apertureDiamPix[1] = 5;
  run.apertureDiamPix[2] = 7;
  run.autoParams[0] = 2.5;
  run.autoParams[1] = 3.5;
  run.petroParams[0] = 2.5;
  run.petroParams[1] = 3.5;
  run.saturationAdu = 50000.0;
  run.magZeropoint = 25.0;
  run.magGamma = 4.0;
  run.backMeshPix[0] = 64;
  run.backMeshPix[1] = 48;
  run.backFilterMesh[0] = 1;
  run.backFilterMesh[1] = 1;
  run.photBackThicknessPix = 24;
  run.pixelStack = 300000;
  run.frameBufferLines = 1024;
  const std::vector<std::string> cards = sexRunCards(run);
  ASSERT_EQ(cards.size(), 46u);
  for (std::size_t i = 0; i < cards.size(); ++i) EXPECT_EQ(cards[i], cell[8 + i]) << i;
}

TEST(RunSummary, Fits10CardsHaveSExtractorsKeywordsInOrder) {
  if (!test::haveProgram("source-extractor"))
    OCTARC_SKIP_MISSING() << "source-extractor not installed";
  const auto dir = test::scratchDir();
  test::writeSmallImage(dir / "small.fits");
  {
    std::FILE* f = std::fopen((dir / "t.param").c_str(), "w");
    std::fputs("NUMBER\nX_IMAGE\n", f);
    std::fclose(f);
  }
  const auto cat = test::runSourceExtractor(dir, "small.fits", "t.param", "FITS_1.0", "c.fits");
  const std::vector<test::Card> theirs = test::headerCards(cat, 1);
  RunSummary run;
  run.fitsFile = "small.fits";
  run.detections = 3;
  run.finalObjects = 3;
  run.parameters = 2;
  const std::vector<std::string> ours = sexFits10Cards(run);
  ASSERT_EQ(theirs.size(), 4 + ours.size());  // after SIMPLE, BITPIX, NAXIS, EXTEND
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(ours[i].substr(0, 8), theirs[4 + i].image.substr(0, 8)) << i;
    // Comments are SExtractor's (the value field is 20 wide, so they start at column 33 when
    // the value fits).
    EXPECT_EQ(ours[i].substr(30), theirs[4 + i].image.substr(30)) << theirs[4 + i].image;
  }
  EXPECT_EQ(ours.back(),
            theirs.back().image);  // SEXNPARA = 2 / NB OF PARAMETERS PER OBJECT, byte for byte
}

}  // namespace
}  // namespace octarc
