// The vetting page from a hand-made candidate table: the embedded JSON holds each row's values,
// the page fetches nothing, and text from the catalog cannot end the script that holds it.
#include "octarc/search/VettingPage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {
namespace {

FitsTable candidateTable(bool withTiles) {
  FitsTable t;
  t.name = "LDAC_OBJECTS";
  t.columns = {
      {"NUMBER", "", "", "", 1, std::vector<std::int32_t>{1, 2}, "", ""},
      {"NAME", "", "", "", 0, std::vector<std::string>{"OCTARC J1", "evil </script><b>"}, "", ""},
      {"LENS_SCORE", "", "", "", 1, std::vector<double>{0.5, 0.125}, "", ""},
      {"ALPHA_J2000", "", "deg", "", 1, std::vector<double>{150.1234567, std::nan("")}, "", ""},
      {"ARCNESS", "", "", "", 1, std::vector<float>{0.25f, 0.75f}, "", ""},
      {"CAND_FLAGS", "", "", "", 1, std::vector<std::int16_t>{0, 33}, "", ""}};
  if (withTiles) {
    t.columns.push_back({"TILE", "", "", "", 0, std::vector<std::string>{"t1", "t2"}, "", ""});
    t.columns.push_back({"TILE_NUMBER", "", "", "", 1, std::vector<std::int32_t>{4, 1}, "", ""});
  }
  return t;
}

VettingPageInfo pageInfo() {
  VettingPageInfo info;
  info.title = "field <1> & co";
  info.summaryLines = {"2 candidate(s)", "a < b"};
  info.links = {{"Catalog", "candidates.fits"}};
  info.stampFiles = {"stamps/0001.png", ""};
  return info;
}

TEST(VettingPage, EmbedsEachCandidateOnceAsJson) {
  const std::string html = vettingPageHtml(candidateTable(false), pageInfo());
  EXPECT_NE(html.find("<title>field &lt;1&gt; &amp; co</title>"), std::string::npos);
  EXPECT_NE(html.find("a &lt; b<br>"), std::string::npos);
  EXPECT_NE(html.find("Catalog: <a href=\"candidates.fits\">"), std::string::npos);
  EXPECT_NE(html.find("{\"n\":1,\"name\":\"OCTARC J1\",\"ra\":150.1234567,\"dec\":null,"
                      "\"score\":0.5,\"prob\":null,\"arcness\":0.25,"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("\"flags\":33,"), std::string::npos);
  EXPECT_NE(html.find("\"stamp\":\"stamps/0001.png\""), std::string::npos);
  EXPECT_NE(html.find("\"tiles\":false"), std::string::npos);
  EXPECT_EQ(html.find("\"tile\":"), std::string::npos);
  // The name's "</script>" is escaped inside the JSON: the page has exactly its two scripts.
  EXPECT_NE(html.find("evil \\u003c/script\\u003e\\u003cb\\u003e"), std::string::npos);
  std::size_t ends = 0;
  for (std::size_t p = html.find("</script>"); p != std::string::npos;
       p = html.find("</script>", p + 1)) {
    ++ends;
  }
  EXPECT_EQ(ends, 2u);
  // Self-contained: nothing fetched from elsewhere; the page size constant in the script.
  EXPECT_EQ(html.find("http"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_NE(html.find("const perPage = " + std::to_string(kVettingCardsPerPage) + ";"),
            std::string::npos);
  EXPECT_NE(html.find("loading=\"lazy\""), std::string::npos);
}

TEST(VettingPage, SurveyRowsCarryTheirTile) {
  const std::string html = vettingPageHtml(candidateTable(true), pageInfo());
  EXPECT_NE(html.find("\"tiles\":true"), std::string::npos);
  EXPECT_NE(html.find("\"tile\":\"t1\",\"tn\":4,"), std::string::npos);
  EXPECT_NE(html.find("\"tile\":\"t2\",\"tn\":1,"), std::string::npos);
}

TEST(VettingPage, StorageKeyFollowsTheCandidates) {
  const FitsTable a = candidateTable(false);
  FitsTable b = a;
  std::get<std::vector<double>>(b.columns[2].values)[1] = 0.25;
  EXPECT_EQ(vettingStorageKey(a, "x"), vettingStorageKey(candidateTable(false), "x"));
  EXPECT_NE(vettingStorageKey(a, "x"), vettingStorageKey(b, "x"));
  EXPECT_NE(vettingStorageKey(a, "x"), vettingStorageKey(a, "y"));
}

TEST(VettingPage, OneStampNamePerRow) {
  VettingPageInfo info = pageInfo();
  info.stampFiles.pop_back();
  EXPECT_THROW(vettingPageHtml(candidateTable(false), info), IoError);
}

TEST(VettingPage, ColourStampsAreOfferedWhenARowHasOne) {
  EXPECT_EQ(vettingPageHtml(candidateTable(false), pageInfo()).find("\"colour\":"),
            std::string::npos);
  VettingPageInfo info = pageInfo();
  info.colourStampFiles = {"stamps/0001.colour.png", ""};
  const std::string html = vettingPageHtml(candidateTable(false), info);
  EXPECT_NE(html.find("\"stamp\":\"stamps/0001.png\",\"colour\":\"stamps/0001.colour.png\""),
            std::string::npos);
  EXPECT_EQ(html.find("\"colour\":\"\""), std::string::npos);  // none for the second row
  EXPECT_NE(html.find("id=\"colour-toggle\" hidden"), std::string::npos);
}

}  // namespace
}  // namespace octarc
