#include "octarc/batch/BatchRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "octarc/batch/BatchConfiguration.h"
#include "octarc/batch/Journal.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/catalog/FitsCard.h"
#include "octarc/catalog/InputCatalog.h"
#include "octarc/catalog/TableCatalog.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Interrupt.h"
#include "octarc/io/Ds9Region.h"
#include "octarc/io/FitsImage.h"
#include "octarc/io/FitsTable.h"
#include "octarc/run/MeasureJob.h"
#include "octarc/search/CandidateTable.h"
#include "octarc/search/VettingPage.h"
#include "octarc/selection/SearchMask.h"

namespace octarc {

namespace fs = std::filesystem;

namespace {

constexpr const char* kAreaFile = "area.fits";
constexpr const char* kClaimsFolder = "claims";
constexpr const char* kConfigurationFile = "configuration.txt";
// The survey outputs, written together once every tile is done or failed: a search's, and a
// measuring batch's (its tiles' catalogs stay in their folders).
constexpr const char* kSurveyOutputFiles[] = {"candidates.fits", "summary.txt",
                                              "index.html",      "candidates.html",
                                              "candidates.reg",  "candidates.cat"};
constexpr const char* kMeasureSurveyOutputFiles[] = {"summary.txt"};
// What RESTART Y sets aside into OUTPUT_DIR/earlier-N: the batch's own files (these and the
// survey outputs), never others. The claims stay, as other runs may hold them (batch/Journal.h).
constexpr const char* kEarlierRunFiles[] = {"journal.txt", "configuration.txt", "tiles"};
// The marker of a measured tile's folder (AtomicDirectory): written last, so a folder holding
// it is complete.
constexpr const char* kMeasureTileMarkerFile = ".octarc-measure";
constexpr const char* kMeasureTileMarkerText = "octarc batch measured tile\n";

bool measuring(const BatchSettings& s) {
  return s.task == BatchTask::Measure;
}

std::vector<std::string> surveyOutputFiles(const BatchSettings& s) {
  if (measuring(s)) {
    return {std::begin(kMeasureSurveyOutputFiles), std::end(kMeasureSurveyOutputFiles)};
  }
  return {std::begin(kSurveyOutputFiles), std::end(kSurveyOutputFiles)};
}

// "candidates.fits, summary.txt, ...", for the messages.
std::string surveyOutputList(const BatchSettings& s) {
  std::string list;
  for (const std::string& name : surveyOutputFiles(s)) list += (list.empty() ? "" : ", ") + name;
  return list;
}

// What the batch does to a tile, for the messages: "search" or "measure".
const char* taskVerb(const BatchSettings& s) {
  return measuring(s) ? "measure" : "search";
}

std::string tileFolder(const BatchSettings& s, const Tile& t) {
  return (fs::path(s.outputDir) / "tiles" / t.name).string();
}

std::string claimFile(const BatchSettings& s, const Tile& t) {
  return (fs::path(s.outputDir) / kClaimsFolder / t.name).string();
}

std::string where(const BatchSettings& s, const Tile& t) {
  return t.line > 0 ? s.manifest + ":" + std::to_string(t.line) + ": " : t.imagePath + ": ";
}

// The search settings of one tile: the configuration's, with the tile's own files.
SearchRunSettings tileSettings(const BatchSettings& s, const Tile& t, int threads) {
  SearchRunSettings tile = s.tile;
  tile.run.imagePaths = {t.imagePath};
  tile.run.weightImagePath = t.weightPath;
  tile.maskPath = t.maskPath;
  tile.inputCatalogPath = t.catalogPath;
  tile.outputDir = tileFolder(s, t);
  tile.run.threads = threads;
  tile.run.quiet = true;
  // The tiles' catalogs stay FITS-LDAC, which the merge reads back; CATALOG_TYPE is the survey
  // catalog's.
  tile.catalogType = CatalogType::FitsLdac;
  return tile;
}

// What can be checked before any tile is searched: weight maps against WEIGHT_TYPE, and every
// mask parsed against its image's header.
void checkTiles(const BatchSettings& s, const std::vector<Tile>& tiles) {
  const bool weighted = s.tile.run.weightType != WeightType::None;
  for (const Tile& t : tiles) {
    if (weighted && t.weightPath.empty()) {
      throw ConfigError(where(s, t) +
                        "no weight map, and WEIGHT_TYPE is not NONE: give one for "
                        "every tile");
    }
    if (!weighted && !t.weightPath.empty()) {
      throw ConfigError(where(s, t) +
                        "a weight map, but WEIGHT_TYPE is NONE: set WEIGHT_TYPE "
                        "MAP_WEIGHT, MAP_RMS or MAP_VAR");
    }
    if (t.maskPath.empty()) continue;
    try {
      (void)readSearchMask(s.tile, t.maskPath, t.imagePath);
    } catch (const Error& e) {
      throw ConfigError(where(s, t) + "mask " + t.maskPath + ": " + e.what());
    }
  }
}

// True while the batch marker at `path` is being written by another batch: there, and its text
// so far a proper beginning of the marker's.
bool markerBeingWritten(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string text(std::strlen(kBatchMarkerText) + 1, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(std::size_t(in.gcount()));
  return text.size() < std::strlen(kBatchMarkerText) &&
         std::string(kBatchMarkerText).compare(0, text.size(), text) == 0;
}

// OUTPUT_DIR is made, or must be a batch's own (or empty). Batches started at once into a new
// directory all take it: the marker is its first entry, made by one of them alone (O_EXCL), and
// the others wait the moment it takes to be written.
void prepareOutputDirectory(const BatchSettings& s) {
  std::error_code ec;
  const fs::path out = s.outputDir;
  const fs::path marker = out / kBatchMarkerFile;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) {
    throw ConfigError("OUTPUT_DIR " + s.outputDir + ": exists and is not a directory");
  }
  fs::create_directories(out, ec);
  if (ec) throw IoError("OUTPUT_DIR " + s.outputDir + ": cannot create (" + ec.message() + ")");
  for (int attempt = 0; !holdsMarker(s.outputDir, kBatchMarkerFile, kBatchMarkerText); ++attempt) {
    // Another batch may have made the marker (and its first folders) since the test above: the
    // directory is then not empty, and the marker being written or complete says whose it is.
    const bool anotherBatch =
        markerBeingWritten(marker) || holdsMarker(s.outputDir, kBatchMarkerFile, kBatchMarkerText);
    if (attempt < 200 && anotherBatch) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      continue;
    }
    if (!fs::is_empty(out, ec)) {
      throw ConfigError("OUTPUT_DIR " + s.outputDir +
                        ": is not the output of an octarc batch (it has no " + kBatchMarkerFile +
                        "); choose a new or empty directory");
    }
    (void)createFileExclusive(marker.string(), kBatchMarkerText);  // or another batch did
  }
  for (const char* folder : {"tiles", kClaimsFolder}) {
    fs::create_directories(out / folder, ec);
    if (ec) {
      throw IoError(s.outputDir + "/" + folder + ": cannot create (" + ec.message() + ")");
    }
  }
}

bool tileFolderComplete(const BatchSettings& s, const Tile& t) {
  std::error_code ec;
  if (measuring(s))
    return holdsMarker(tileFolder(s, t), kMeasureTileMarkerFile, kMeasureTileMarkerText);
  return holdsMarker(tileFolder(s, t), kSearchMarkerFile, kSearchMarkerText) &&
         fs::exists(fs::path(tileFolder(s, t)) / kAreaFile, ec);
}

// The searched area of a tile at block resolution, in its folder.
void writeAreaFile(const std::string& path, const SearchRun& run) {
  FitsTable t;
  t.name = "SEARCHED_AREA";
  std::vector<std::int32_t> bx, by, n;
  const Image<std::int32_t>& blocks = run.searchedBlocks;
  for (std::int64_t y = 0; y < blocks.height(); ++y) {
    for (std::int64_t x = 0; x < blocks.width(); ++x) {
      if (blocks(x, y) == 0) continue;
      bx.push_back(std::int32_t(x));
      by.push_back(std::int32_t(y));
      n.push_back(blocks(x, y));
    }
  }
  t.columns = {{"BLOCK_X", "Block column (0-based)", "", "", 1, bx, "", ""},
               {"BLOCK_Y", "Block row (0-based)", "", "", 1, by, "", ""},
               {"NPIX", "Searched pixels in the block", "pixel", "", 1, n, "", ""}};
  t.keywords = {
      FitsKeyword::integer("BLOCKPIX", SearchMask::kAreaBlockPix, "block side, pixels"),
      FitsKeyword::integer("IMWIDTH", run.image.hdu.pixels.width(), "image width, pixels"),
      FitsKeyword::integer("IMHEIGHT", run.image.hdu.pixels.height(), "image height, pixels"),
      FitsKeyword::real("PIXSCALE", run.pixelScaleArcsec, "pixel scale, arcsec")};
  writeFitsTables(path, {t});
}

TileCandidates loadTile(const BatchSettings& s, const Tile& t) {
  const std::string folder = tileFolder(s, t);
  TileCandidates c;
  c.name = t.name;
  c.candidates = readFitsTable(folder + "/candidates.fits", "LDAC_OBJECTS");
  const FitsTable area = readFitsTable(folder + "/" + kAreaFile, "SEARCHED_AREA");
  // Searched areas are counted in SearchMask's blocks, the only side written.
  c.blockPix = area.integer("BLOCKPIX", SearchMask::kAreaBlockPix, SearchMask::kAreaBlockPix);
  c.widthPix = area.integer("IMWIDTH", 1, kMaxImageSidePix);
  c.heightPix = area.integer("IMHEIGHT", 1, kMaxImageSidePix);
  c.pixelScaleArcsec = area.number(
      "PIXSCALE", [](double v) { return std::isfinite(v) && v > 0.0; }, "a finite number > 0");
  try {
    c.searchedBlocks = Image<std::int32_t>((c.widthPix + c.blockPix - 1) / c.blockPix,
                                           (c.heightPix + c.blockPix - 1) / c.blockPix);
  } catch (const std::bad_alloc&) {
    throw IoError(area.where() + ": the blocks of an image of " + std::to_string(c.widthPix) +
                  " x " + std::to_string(c.heightPix) + " pixels do not fit in memory");
  }
  const std::vector<std::int64_t> bx = area.integers("BLOCK_X"), by = area.integers("BLOCK_Y"),
                                  n = area.integers("NPIX");
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (bx[i] < 0 || by[i] < 0 || bx[i] >= c.searchedBlocks.width() ||
        by[i] >= c.searchedBlocks.height()) {
      throw IoError(folder + "/" + kAreaFile + ": a block outside the image");
    }
    // Only blocks with searched pixels are listed, at most the block's.
    if (n[i] < 1 || n[i] > c.blockPix * c.blockPix) {
      throw IoError(area.where() + ": NPIX = " + std::to_string(n[i]) + " in row " +
                    std::to_string(i + 1) + " is not an integer from 1 to " +
                    std::to_string(c.blockPix * c.blockPix));
    }
    c.searchedBlocks(bx[i], by[i]) = std::int32_t(n[i]);
  }
  // The WCS from the image header the tile's catalog holds: the image is not read again.
  const std::string catalog = folder + "/candidates.fits";
  c.wcs = Wcs::fromHeader(readLdacImageHeader(catalog), catalog);
  return c;
}

// Tiles as bytes for the other ranks: seven fields per tile, each ended by a NUL byte (the
// manifest refuses control characters in its fields).
std::string serialiseTiles(const std::vector<Tile>& tiles) {
  std::string out;
  for (const Tile& t : tiles) {
    for (const std::string* f :
         {&t.name, &t.imagePath, &t.weightPath, &t.maskPath, &t.catalogPath, &t.segmentationPath}) {
      out += *f;
      out += '\0';
    }
    out += std::to_string(t.line);
    out += '\0';
  }
  return out;
}

std::vector<Tile> parseTiles(const std::string& bytes) {
  std::vector<std::string> f;
  for (std::size_t at = 0, end; (end = bytes.find('\0', at)) != std::string::npos; at = end + 1) {
    f.push_back(bytes.substr(at, end - at));
  }
  std::vector<Tile> tiles;
  for (std::size_t k = 0; k + 7 <= f.size(); k += 7) {
    tiles.push_back({f[k], f[k + 1], f[k + 2], f[k + 3], f[k + 4], f[k + 5], std::stoi(f[k + 6])});
  }
  return tiles;
}

std::string shareText(const BatchSettings& s) {
  return s.arrayTasks > 1
             ? "array task " + std::to_string(s.arrayTask) + "/" + std::to_string(s.arrayTasks)
             : std::string("whole manifest");
}

// The tiles a survey still waits for when this run ends: not journaled yet, or done but their
// folder not in place.
struct Waiting {
  std::int64_t searchedElsewhere = 0;  // another run held the claim when this one came to it
  std::int64_t left = 0;               // to other array tasks, or to a rerun
};

// TASK MEASURE: a tile's catalog in its folder: the input catalog's file name when appended
// (its format kept), else NAME.cat (CATALOG_TYPE), as SExtractor names its catalogs.
std::string tileCatalogName(const BatchSettings& s, const Tile& t) {
  if (s.tile.run.appendColumns) return fs::path(t.catalogPath).filename().string();
  return t.name + ".cat";
}

// TASK MEASURE: the summary's lines of each tile done, from the latest `done` line of each in the
// journal (whichever run measured it): rows, seconds, run and rank.
std::vector<std::string> measuredTileLines(const BatchSettings& s, const BatchReport& r,
                                           const std::vector<JournalEntry>& entries) {
  std::map<std::string, const JournalEntry*> done;
  for (const JournalEntry& e : entries) {
    if (e.event == "done") done[e.tile] = &e;
    if (e.event == "failed") done.erase(e.tile);
  }
  std::vector<std::string> lines;
  long long rowsInAll = 0;
  double secondsInAll = 0.0;
  std::int64_t tiles = 0;
  for (const Tile& t : r.tiles) {
    const auto it = done.find(t.name);
    if (it == done.end()) continue;
    long long rows = 0;
    double seconds = 0.0;
    int rank = 0;
    // "N rows, S s, rank R", as recordTile writes it.
    if (std::sscanf(it->second->detail.c_str(), "%lld rows, %lf s, rank %d", &rows, &seconds,
                    &rank) != 3) {
      lines.push_back("  " + t.name + ": " + it->second->detail + " (run " +
                      std::to_string(it->second->run) + ")");
      continue;
    }
    ++tiles;
    rowsInAll += rows;
    secondsInAll += seconds;
    lines.push_back("  " + t.name + ": " + std::to_string(rows) + " rows, " +
                    formatNumber(seconds, "%.2f") + " s (run " + std::to_string(it->second->run) +
                    ", rank " + std::to_string(rank) + "), tiles/" + t.name + "/" +
                    tileCatalogName(s, t));
  }
  lines.insert(lines.begin(), "Catalogs of " + std::to_string(tiles) +
                                  " tile(s): " + std::to_string(rowsInAll) + " rows, " +
                                  formatNumber(secondsInAll, "%.2f") + " s of measuring in all");
  return lines;
}

std::vector<std::string> summaryLines(const BatchSettings& s, const BatchReport& r, int ranks,
                                      const Waiting& waiting,
                                      const std::vector<std::string>& measuredLines) {
  std::int64_t counts[5] = {0, 0, 0, 0, 0};
  for (const TileReport& t : r.reports) ++counts[int(t.state)];
  const std::int64_t elsewhere =
      counts[int(TileState::OtherTask)] + counts[int(TileState::OtherRun)];
  std::vector<std::string> lines;
  lines.push_back("Survey " + s.manifest + ": " + std::to_string(r.tiles.size()) + " tiles" +
                  (measuring(s) ? " (TASK MEASURE)" : ""));
  lines.push_back(
      "Run " + std::to_string(r.run) + " (" + std::to_string(ranks) + " rank(s), " + shareText(s) +
      "): " + std::to_string(counts[0]) + " done, " + std::to_string(counts[1]) + " failed, " +
      std::to_string(counts[2]) + " skipped (done earlier or by other runs)" +
      (elsewhere > 0 ? ", " + std::to_string(elsewhere) + " left to other runs or tasks" : ""));
  for (std::size_t i = 0; i < r.tiles.size(); ++i) {
    if (r.reports[i].state != TileState::Failed) continue;
    lines.push_back("  failed: " + r.tiles[i].name +
                    (r.tiles[i].line > 0 ? " (line " + std::to_string(r.tiles[i].line) + ")" : "") +
                    ": " + r.reports[i].message);
  }
  if (!r.merged) {
    // This run's last line: the survey is not its to write.
    lines.push_back(
        "The survey outputs wait for " + std::to_string(waiting.searchedElsewhere + waiting.left) +
        " tile(s) (" + std::to_string(waiting.searchedElsewhere) +
        " that another run was searching, " + std::to_string(waiting.left) +
        " left to other array tasks or to a rerun): the run that journals the last of them "
        "writes them");
    return lines;
  }
  if (measuring(s)) {
    lines.insert(lines.end(), measuredLines.begin(), measuredLines.end());
    return lines;
  }
  const SurveyCandidates& sv = r.survey;
  lines.push_back("Searched area " + formatNumber(sv.areaDeg2, "%.5f") +
                  " deg2 (the union of the tiles' searched areas)");
  std::string candidates = std::to_string(sv.table.rows()) + " candidate(s)";
  if (sv.areaDeg2 > 0) {
    candidates += ", " + formatNumber(double(sv.table.rows()) / sv.areaDeg2, "%.1f") + " per deg2";
  }
  lines.push_back(candidates + "; " + std::to_string(sv.tileCandidates) + " in the tiles, " +
                  std::to_string(sv.duplicatesRemoved) + " duplicate(s) in overlaps removed");
  for (const SpaceTotal& space : sv.spaces) {
    lines.push_back(reportSpaceLine(space.name, space.expression, space.candidates, sv.areaDeg2));
  }
  return lines;
}

std::string surveyIndexHtml(const BatchSettings& s, const BatchReport& r) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">\n<title>octarc batch: "
       << escapeHtml(fs::path(s.manifest).filename().string()) << "</title>\n"
       << "<style>body{font-family:sans-serif;margin:1em}table{border-collapse:collapse}"
          "td,th{border:1px solid #bbb;padding:2px 8px;text-align:left}"
          ".failed{color:#b00}</style></head><body>\n"
       << "<h1>octarc batch: " << escapeHtml(fs::path(s.manifest).filename().string())
       << "</h1>\n<pre>";
  for (const std::string& l : r.summaryLines) html << escapeHtml(l) << "\n";
  html << "</pre>\n<p><a href=\"candidates.html\">candidates.html</a>: the survey's vetting page "
          "(its candidates, duplicates removed); <a href=\"candidates.fits\">candidates.fits</a>, "
          "<a href=\"candidates.cat\">candidates.cat</a>, <a href=\"candidates.reg\">"
          "candidates.reg</a></p>\n"
       << "<table id=\"tiles\">\n<tr><th>tile</th><th>status</th><th>candidates kept</th>"
       << "<th>vetting page</th><th>regions</th></tr>\n";
  for (std::size_t i = 0; i < r.tiles.size(); ++i) {
    const Tile& t = r.tiles[i];
    const TileReport& tr = r.reports[i];
    const std::string folder = "tiles/" + t.name + "/";
    const bool failed = tr.state == TileState::Failed;
    const bool elsewhere = tr.state == TileState::OtherTask || tr.state == TileState::OtherRun;
    const char* status = failed ? "failed" : elsewhere ? "not done" : "done";
    html << "<tr class=\"" << status << "\"><td>" << escapeHtml(t.name) << "</td><td>" << status;
    if (failed) html << ": " << escapeHtml(tr.message);
    html << "</td><td>" << (failed ? 0 : r.survey.keptPerTile.at(i)) << "</td><td>";
    if (!failed) {
      html << "<a href=\"" << escapeHtml(folder) << "index.html\">index.html</a></td><td><a href=\""
           << escapeHtml(folder) << "candidates.reg\">candidates.reg</a>";
    } else {
      html << "</td><td>";
    }
    html << "</td></tr>\n";
  }
  html << "</table>\n</body></html>\n";
  return html.str();
}

// The survey's candidates for DS9: a circle of 2" at each RA, Dec, labelled with NUMBER (the
// tiles' own region files hold the arcs' shapes, in their pixels).
std::string surveyRegionText(const FitsTable& objects) {
  const std::vector<std::int64_t> number = objects.integers("NUMBER");
  const std::vector<double> ra = objects.doubles("ALPHA_J2000"),
                            dec = objects.doubles("DELTA_J2000");
  std::ostringstream out;
  out << "# Region file format: DS9 version 4.1\n"
      << "global color=green width=1 font=\"helvetica 10 normal roman\"\nfk5\n";
  for (std::size_t i = 0; i < number.size(); ++i) {
    if (!std::isfinite(ra[i]) || !std::isfinite(dec[i])) {
      out << "# NUMBER " << number[i] << ": no RA, Dec (its tile has no WCS)\n";
      continue;
    }
    out << "circle(" << formatNumber(ra[i], "%.7f") << "," << formatNumber(dec[i], "%+.7f")
        << ",2\") # text={" << number[i] << "}\n";
  }
  return out.str();
}

// The summary as the vetting page shows it: the manifest by its name, and without the failed
// tiles' errors, which quote their files' paths (index.html and summary.txt list them).
std::vector<std::string> pageSummaryLines(const BatchSettings& s, const BatchReport& r) {
  std::vector<std::string> lines;
  const std::string name = fs::path(s.manifest).filename().string();
  for (std::string line : r.summaryLines) {
    if (line.starts_with("  failed: ")) continue;
    for (std::size_t at;
         !s.manifest.empty() && (at = line.find(s.manifest)) != std::string::npos;) {
      line.replace(at, s.manifest.size(), name);
    }
    lines.push_back(line);
  }
  return lines;
}

void writeSurveyOutputs(const BatchSettings& s, const BatchReport& r) {
  std::string summary;
  for (const std::string& l : r.summaryLines) summary += l + "\n";
  if (measuring(s)) {
    OutputFiles outputs;
    outputs.add((fs::path(s.outputDir) / "summary.txt").string());
    outputs.write(0, [&](const std::string& path) { writeTextFile(path, summary); });
    outputs.commit();
    return;
  }
  OutputFiles outputs;
  for (const char* name : kSurveyOutputFiles) outputs.add((fs::path(s.outputDir) / name).string());
  FitsTable objects = r.survey.table;
  const SurveyCandidates& sv = r.survey;
  objects.keywords = {
      FitsKeyword::integer("NTILES", std::int64_t(r.tiles.size()), "tiles in the manifest"),
      FitsKeyword::integer("NCANDID", sv.table.rows(), "candidates in the survey"),
      FitsKeyword::integer("NTILECND", sv.tileCandidates, "candidates in the tiles"),
      FitsKeyword::integer("NDUPLIC", sv.duplicatesRemoved, "duplicates in overlaps removed"),
      FitsKeyword::real("SRCHAREA", sv.areaDeg2, "[deg2] union of searched areas"),
      FitsKeyword::real("MATCHRAD", s.matchRadiusArcsec, "[arcsec] duplicate match radius")};
  for (std::size_t i = 0; i < sv.spaces.size(); ++i) {
    const std::string n = std::to_string(i + 1);
    objects.keywords.push_back(FitsKeyword::text("SPNAME" + n, sv.spaces[i].name));
    objects.keywords.push_back(FitsKeyword::text("SPEXPR" + n, sv.spaces[i].expression));
    objects.keywords.push_back(
        FitsKeyword::integer("SPCAND" + n, sv.spaces[i].candidates, "candidates in the space"));
  }
  const std::vector<std::string> cards = {
      formatCard("OCTBATCH", std::string(fs::path(s.manifest).filename().string()),
                 "manifest of the survey"),
      formatCard("NTILES", std::int64_t(r.tiles.size()), "tiles")};
  // The UCDs of the tiles' columns (which their FITS files do not hold), and of the survey's.
  std::map<std::string, std::string> ucds = candidateColumnUcds(s.tile.search.colourBands);
  ucds["TILE"] = "meta.id;obs.field";
  ucds["TILE_NUMBER"] = "meta.id.cross";
  outputs.write(0, [&](const std::string& path) {
    writeTableCatalog(path, s.tile.catalogType, objects, ldacImheadTable(FitsHeader(), cards),
                      ucds);
  });
  outputs.write(1, [&](const std::string& path) { writeTextFile(path, summary); });
  outputs.write(2, [&](const std::string& path) { writeTextFile(path, surveyIndexHtml(s, r)); });
  VettingPageInfo page;
  page.title = "octarc batch: " + fs::path(s.manifest).filename().string();
  page.summaryLines = pageSummaryLines(s, r);
  page.links = {{"Catalog", "candidates.fits"},
                {"ASCII catalog", "candidates.cat"},
                {"DS9 regions", "candidates.reg"},
                {"Tiles", "index.html"}};
  page.stampFiles = catalogStampFiles(objects);
  if (!s.tile.writeStamps) page.stampFiles.assign(page.stampFiles.size(), "");
  for (const std::string& stamp : page.stampFiles) {
    // The tiles' FITS cut-outs lie beside their stamps (STAMP_CUTOUTS).
    page.cutoutFiles.push_back(stamp.empty() || !s.tile.writeCutouts
                                   ? std::string()
                                   : stamp.substr(0, stamp.size() - 4) + ".fits");
  }
  outputs.write(
      3, [&](const std::string& path) { writeTextFile(path, vettingPageHtml(objects, page)); });
  outputs.write(4,
                [&](const std::string& path) { writeTextFile(path, surveyRegionText(objects)); });
  outputs.write(5, [&](const std::string& path) {
    writeTableCatalog(path, CatalogType::AsciiHead, objects, FitsTable(), ucds);
  });
  outputs.commit();
}

// A tile's report as it crosses between ranks: "done\tN\tSECONDS\tRANK" or "failed\tMESSAGE";
// N is the candidates of a search, the catalog rows of a measured tile.
TileReport parseReport(const std::string& text, BatchTask task) {
  std::vector<std::string> f;
  std::stringstream in(text);
  for (std::string field; std::getline(in, field, '\t');) f.push_back(field);
  TileReport r;
  if (f.size() == 4 && f[0] == "done") {
    r.state = TileState::Done;
    (task == BatchTask::Measure ? r.catalogRows : r.candidates) = std::stoll(f[1]);
    r.seconds = std::stod(f[2]);
    r.rank = std::stoi(f[3]);
  } else {
    r.state = TileState::Failed;
    r.message = f.size() >= 2 ? text.substr(text.find('\t') + 1) : text;
  }
  return r;
}

}  // namespace

std::int64_t BatchReport::failed() const {
  return std::count_if(reports.begin(), reports.end(),
                       [](const TileReport& r) { return r.state == TileState::Failed; });
}

namespace {

// A configuration without TASK (recorded before batches had it) is a search's.
std::vector<ConfigurationItem> withTask(std::vector<ConfigurationItem> items) {
  if (std::none_of(items.begin(), items.end(),
                   [](const ConfigurationItem& i) { return i.key == "TASK"; })) {
    items.push_back({"TASK", "SEARCH", "SEARCH"});
  }
  return items;
}

// This run's configuration (batch/BatchConfiguration.h), the files the search reads hashed.
std::vector<ConfigurationItem> currentConfiguration(const BatchSettings& s) {
  std::vector<ConfigurationItem> items = s.configuration;
  for (const auto& [key, path] : s.configurationFiles) {
    const auto it = std::find_if(items.begin(), items.end(),
                                 [&](const ConfigurationItem& i) { return i.key == key; });
    if (it != items.end()) {
      *it = fileItem(key, path);
    } else {
      items.push_back(fileItem(key, path));
    }
  }
  return withTask(std::move(items));
}

std::string readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot read");
  std::stringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(path + ": cannot read");
  return text.str();
}

// The configuration recorded in OUTPUT_DIR. A key it lacks that this run leaves at its default
// (a key added to octarc after the recording run) is taken as this run's, so that a survey
// started with an earlier octarc resumes.
std::vector<ConfigurationItem> recordedConfiguration(const std::string& path,
                                                     const std::vector<ConfigurationItem>& current,
                                                     const std::vector<std::string>& atDefault) {
  std::vector<ConfigurationItem> recorded = withTask(parseConfiguration(readWholeFile(path), path));
  for (const ConfigurationItem& item : current) {
    const bool missing =
        std::none_of(recorded.begin(), recorded.end(),
                     [&](const ConfigurationItem& r) { return r.key == item.key; });
    if (missing && std::find(atDefault.begin(), atDefault.end(), item.key) != atDefault.end()) {
      recorded.push_back(item);
    }
  }
  return recorded;
}

void writeConfiguration(const std::string& path, const std::string& text) {
  OutputFiles out;
  out.add(path);
  out.write(0, [&](const std::string& temp) { writeTextFile(temp, text); });
  out.commit();
}

// Moves the earlier runs' files into OUTPUT_DIR/earlier-N, the first N free, and makes tiles/
// again. Returns the folder.
std::string setEarlierRunsAside(const BatchSettings& s) {
  const fs::path out = s.outputDir;
  fs::path aside;
  std::error_code ec;
  for (int n = 1;; ++n) {
    aside = out / ("earlier-" + std::to_string(n));
    if (fs::create_directory(aside, ec)) break;
    if (ec) throw IoError(aside.string() + ": cannot create (" + ec.message() + ")");
  }
  std::vector<std::string> names(std::begin(kEarlierRunFiles), std::end(kEarlierRunFiles));
  names.insert(names.end(), std::begin(kSurveyOutputFiles), std::end(kSurveyOutputFiles));
  for (const std::string& name : names) {
    if (!fs::exists(out / name, ec)) continue;
    fs::rename(out / name, aside / name, ec);
    if (ec) {
      throw IoError((out / name).string() + ": cannot move to " + aside.string() + " (" +
                    ec.message() + ")");
    }
  }
  fs::create_directories(out / "tiles", ec);
  if (ec) throw IoError(s.outputDir + "/tiles: cannot create (" + ec.message() + ")");
  return aside.string();
}

// With the journal locked, before this run's start line: the configuration OUTPUT_DIR's tiles
// are searched with is this run's (the first run records it), else ConfigError naming the keys
// that differ, or with RESTART Y the earlier runs' files set aside (returns true: a new
// journal). Then every later line of this run checks that it still is (another run may set
// them aside).
bool checkConfiguration(const BatchSettings& s, Journal& journal,
                        const std::vector<JournalEntry>& entries, const RunLog& log) {
  const std::string path = (fs::path(s.outputDir) / kConfigurationFile).string();
  const std::vector<ConfigurationItem> current = currentConfiguration(s);
  const std::string text = formatConfiguration(current);
  journal.guardAppends([path, current, atDefault = s.keysAtDefault, dir = s.outputDir] {
    std::error_code ec;
    if (!fs::exists(path, ec) ||
        !configurationDifferences(recordedConfiguration(path, current, atDefault), current)
             .empty()) {
      throw ConfigError("OUTPUT_DIR " + dir +
                        ": another run set this run's tiles aside (RESTART Y, another "
                        "configuration); this run stops");
    }
  });
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    // A new OUTPUT_DIR, or one of an octarc that kept no configuration: this one's.
    const std::size_t earlier = completedTiles(entries).size();
    if (earlier > 0 && log) {
      log("WARNING: octarc batch: OUTPUT_DIR " + s.outputDir + " holds " + std::to_string(earlier) +
          " tile(s) done by runs that recorded no configuration (an earlier octarc): they are "
          "kept as if searched with this run's");
    }
    writeConfiguration(path, text);
    return false;
  }
  const std::vector<std::string> differences =
      configurationDifferences(recordedConfiguration(path, current, s.keysAtDefault), current);
  if (differences.empty()) return false;
  std::string list;
  for (const std::string& d : differences) list += (list.empty() ? "" : "; ") + d;
  // Another TASK: every other key differs too, and says nothing more.
  const auto task = std::find_if(differences.begin(), differences.end(),
                                 [](const std::string& d) { return d.rfind("TASK ", 0) == 0; });
  if (task != differences.end()) list = *task;
  const std::string mixed = task != differences.end() ? "tasks"
                            : measuring(s)            ? "measurements"
                                                      : "searches";
  if (!s.restart) {
    throw ConfigError("OUTPUT_DIR " + s.outputDir + " was made with " + list +
                      ": its tiles would mix two " + mixed +
                      "; give -RESTART Y to set them aside "
                      "(into " +
                      s.outputDir + "/earlier-N) and start over, or another OUTPUT_DIR");
  }
  const std::string aside = setEarlierRunsAside(s);
  writeConfiguration(path, text);
  if (log) log("> RESTART Y: the earlier runs' files, of " + list + ", set aside into " + aside);
  return true;
}

// The root alone reads the manifest, checks the tiles' files and OUTPUT_DIR, and picks the tiles
// to do: this task's share, less those complete (a `done` line and the folder in place), largest
// images first (the ranks then end together). Returns the plan: the run number, then the tiles'
// indices; journalRead: the journal's bytes it read.
std::string planRun(const BatchSettings& s, const Cluster& cluster, Journal& journal,
                    BatchReport& report, std::uint64_t& journalRead, const RunLog& log) {
  report.tiles = readManifest(s.manifest, s.tile.run.weightType != WeightType::None,
                              measuring(s) ? ManifestRows::Measure : ManifestRows::Search);
  checkTiles(s, report.tiles);
  prepareOutputDirectory(s);
  report.run = journal.startRun(std::to_string(report.tiles.size()) + " tiles, " +
                                    std::to_string(cluster.size()) + " rank(s), " + shareText(s),
                                [&](const std::vector<JournalEntry>& entries) {
                                  return checkConfiguration(s, journal, entries, log);
                                });
  // Read once the configuration is checked (RESTART Y may start a new journal); the claims
  // follow the lines appended after these.
  const std::set<std::string> done = completedTiles(journal.readFrom(journalRead));
  report.reports.assign(report.tiles.size(), TileReport());
  std::vector<std::pair<std::uintmax_t, std::size_t>> bySize;
  for (std::size_t i = 0; i < report.tiles.size(); ++i) {
    if (int(i % std::size_t(s.arrayTasks)) != s.arrayTask) continue;
    if (done.count(report.tiles[i].name) && tileFolderComplete(s, report.tiles[i])) {
      report.reports[i].state = TileState::DoneEarlier;
      continue;
    }
    std::error_code ec;
    const std::uintmax_t bytes = fs::file_size(report.tiles[i].imagePath, ec);
    bySize.push_back({ec ? 0 : bytes, i});
  }
  std::stable_sort(bySize.begin(), bySize.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string plan = std::to_string(report.run);
  for (const auto& [bytes, i] : bySize) plan += " " + std::to_string(i);
  return plan;
}

// The plan on every rank: made by the root (a failure there stops every rank), then sent with
// the tiles to the others. Returns the indices of the tiles to search.
std::vector<std::size_t> shareRunPlan(const BatchSettings& s, const Cluster& cluster,
                                      Journal& journal, BatchReport& report,
                                      std::uint64_t& journalRead, const RunLog& log) {
  std::exception_ptr error;
  std::string plan;
  if (cluster.isRoot()) {
    try {
      plan = planRun(s, cluster, journal, report, journalRead, log);
    } catch (const Error&) {
      error = std::current_exception();
    }
  }
  cluster.raiseIfAnyFailed(error);
  if (cluster.size() > 1) {
    const std::string tiles = cluster.broadcast(serialiseTiles(report.tiles));
    if (!cluster.isRoot()) report.tiles = parseTiles(tiles);
    plan = cluster.broadcast(plan);
  }
  std::vector<std::size_t> todo;
  std::istringstream in(plan);
  in >> report.run;
  for (std::size_t i; in >> i;) todo.push_back(i);
  return todo;
}

// Searches one tile into its folder; its report as it crosses between ranks (parseReport).
std::string searchTile(const BatchSettings& s, const Tile& tile, int threads, int rank,
                       const RunLog& log) {
  const auto start = std::chrono::steady_clock::now();
  try {
    const SearchRunSettings settings = tileSettings(s, tile, threads);
    const RunLog tileLog = [&](const std::string& line) {
      if (log && line.rfind("WARNING", 0) == 0) log("tile " + tile.name + ": " + line);
    };
    const SearchRun run = searchImage(settings, tileLog);
    writeSearchOutputs(run, settings, {}, {},
                       [&](const std::string& dir) { writeAreaFile(dir + "/" + kAreaFile, run); });
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return "done\t" + std::to_string(run.result.candidates.size()) + "\t" +
           formatNumber(seconds, "%.2f") + "\t" + std::to_string(rank);
  } catch (const std::exception& e) {
    // A tile's trouble is its own: reported and journaled, the others go on.
    return "failed\t" + printableMessage(e.what());
  }
}

// TASK MEASURE: the measure run of one tile, as `octarc measure` runs it on the configuration's
// settings with the tile's files, its catalog written into `folder`.
RunSettings measureTileSettings(const BatchSettings& s, const Tile& t, const std::string& folder,
                                int threads) {
  RunSettings run = s.tile.run;
  run.imagePaths = {t.imagePath};
  run.segmentationPaths = {t.segmentationPath};
  run.inputCatalogPaths = {t.catalogPath};
  run.weightImagePath = t.weightPath;
  run.measurement.weightImagePath = t.weightPath;
  run.catalogNames = {(fs::path(folder) / tileCatalogName(s, t)).string()};
  run.replaceInputCatalog = false;
  run.writeXml = false;  // a batch reports in its journal and summary.txt
  run.threads = threads;
  run.quiet = true;
  return run;
}

// Measures one tile into its folder, written whole (AtomicDirectory); its report as it crosses
// between ranks (parseReport).
std::string measureTile(const BatchSettings& s, const Tile& tile, int threads, int rank,
                        const RunLog& log) {
  const auto start = std::chrono::steady_clock::now();
  try {
    const std::string folder = tileFolder(s, tile);
    AtomicDirectory dir(folder, kMeasureTileMarkerFile, kMeasureTileMarkerText);
    // The tiles' runs share one configuration, so its warnings (CATALOG_TYPE not used with
    // APPEND_COLUMNS Y, say) would repeat for every tile: each is said once, with its tile.
    static std::mutex warnedMutex;
    static std::set<std::string> warned;
    const RunLog tileLog = [&](const std::string& line) {
      if (!log || line.rfind("WARNING", 0) != 0) return;
      const std::lock_guard lock(warnedMutex);
      if (warned.insert(line).second) log("tile " + tile.name + ": " + line);
    };
    MeasureJobReport measured;
    try {
      measured = runMeasureJob(measureTileSettings(s, tile, dir.tempPath(), threads), *s.config,
                               MeasureJobFacts(), tileLog);
      writeTextFile(dir.tempPath() + "/" + kMeasureTileMarkerFile, kMeasureTileMarkerText);
    } catch (const Error& e) {
      // Messages name the folder the user knows, not its temporary name.
      std::string message = e.what();
      for (std::size_t at; (at = message.find(dir.tempPath())) != std::string::npos;) {
        message.replace(at, dir.tempPath().size(), folder);
      }
      throw Error(message);
    }
    dir.commit();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return "done\t" + std::to_string(measured.catalogRows) + "\t" + formatNumber(seconds, "%.2f") +
           "\t" + std::to_string(rank);
  } catch (const std::exception& e) {
    // A tile's trouble is its own: reported and journaled, the others go on.
    return "failed\t" + printableMessage(e.what());
  }
}

// The claims of the tiles this run searches, on the root: taken as a tile is handed out, let go
// once it is journaled. Its methods may run on both of the root's threads.
class TileClaims {
 public:
  TileClaims(const BatchSettings& s, const Journal& journal, std::uint64_t journalRead,
             BatchReport& report)
      : s_(s), journal_(journal), journalRead_(journalRead), report_(report) {}

  // Claims tile i for this run. False, with the tile's report set, when another run holds its
  // claim or has journaled it since this run read the journal (checked once the claim is held:
  // the other journals a tile before it lets go of it).
  bool take(std::size_t i) {
    const std::lock_guard lock(mutex_);
    const Tile& tile = report_.tiles[i];
    std::optional<TileClaim> claim = TileClaim::tryTake(claimFile(s_, tile));
    if (!claim) {
      report_.reports[i].state = TileState::OtherRun;
      return false;
    }
    for (const JournalEntry& e : journal_.readFrom(journalRead_)) {
      if (e.event == "done" || e.event == "failed") latest_[e.tile] = e.event;
    }
    const auto it = latest_.find(tile.name);
    if (it != latest_.end() && it->second == "failed") {
      report_.reports[i].state = TileState::Failed;
      report_.reports[i].message = "(failed in another run; see journal.txt)";
      return false;
    }
    if (it != latest_.end() && tileFolderComplete(s_, tile)) {
      report_.reports[i].state = TileState::DoneEarlier;
      return false;
    }
    held_.emplace(i, std::move(*claim));
    return true;
  }
  void release(std::size_t i) {
    const std::lock_guard lock(mutex_);
    held_.erase(i);
  }

 private:
  const BatchSettings& s_;
  const Journal& journal_;
  std::uint64_t journalRead_;
  BatchReport& report_;
  std::mutex mutex_;
  std::map<std::string, std::string> latest_;  // tile: its last done/failed since the plan
  std::map<std::size_t, TileClaim> held_;
};

// A searched tile's report, on the root: journaled, logged as the `finished`-th of `total`.
void recordTile(const Journal& journal, BatchReport& report, std::size_t i, TileReport r,
                std::int64_t finished, std::size_t total, BatchTask task, const RunLog& log) {
  const Tile& tile = report.tiles[i];
  const std::string count = "[" + std::to_string(finished) + "/" + std::to_string(total) + "] ";
  if (r.state == TileState::Done) {
    const bool rows = task == BatchTask::Measure;
    const std::string counted = rows ? std::to_string(r.catalogRows) + " rows"
                                     : std::to_string(r.candidates) + " candidates";
    {
      // The count a signal reports is that of the `done` lines: both or neither.
      const DeferInterrupts hold;
      journal.append(
          report.run, "done", tile.name,
          counted + ", " + formatNumber(r.seconds, "%.2f") + " s, rank " + std::to_string(r.rank));
      notePieceKept();
    }
    if (log) {
      log(count + tile.name + ": " +
          (rows ? counted : std::to_string(r.candidates) + " candidate(s)") + ", " +
          formatNumber(r.seconds, "%.1f") + " s (rank " + std::to_string(r.rank) + ")");
    }
  } else {
    journal.append(report.run, "failed", tile.name, r.message);
    if (log) log(count + tile.name + " FAILED: " + r.message);
  }
  report.reports[i] = std::move(r);
}

// With the journal's lines of every run and task: each tile's latest state, and, when every
// tile is done or failed and every done folder is in place, the survey's candidates, summary
// and index.
void mergeSurvey(const BatchSettings& s, BatchReport& report,
                 const std::vector<JournalEntry>& entries, int ranks, const RunLog& log) {
  const std::vector<Tile>& tiles = report.tiles;
  std::map<std::string, std::string> latest;
  for (const JournalEntry& e : entries) {
    if (e.event == "done" || e.event == "failed") latest[e.tile] = e.event;
  }
  report.merged = true;
  Waiting waiting;
  std::vector<TileCandidates> merged;
  std::vector<std::size_t> mergedIndex;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const auto it = latest.find(tiles[i].name);
    TileReport& r = report.reports[i];
    if (it == latest.end()) {
      report.merged = false;
      ++(r.state == TileState::OtherRun ? waiting.searchedElsewhere : waiting.left);
      continue;
    }
    if (r.state == TileState::OtherTask || r.state == TileState::OtherRun) {
      r.state = it->second == "done" ? TileState::DoneEarlier : TileState::Failed;
      if (r.state == TileState::Failed) r.message = "(failed in another run; see journal.txt)";
    }
    if (it->second == "done" && r.state != TileState::Failed) {
      // A folder that another run is redoing is not there yet: the survey waits for it.
      if (!tileFolderComplete(s, tiles[i])) {
        report.merged = false;
        ++waiting.left;
      }
      mergedIndex.push_back(i);
    }
  }
  if (report.merged && !measuring(s)) {
    const auto start = std::chrono::steady_clock::now();
    for (const std::size_t i : mergedIndex) merged.push_back(loadTile(s, tiles[i]));
    report.survey = mergeTiles(merged, s.matchRadiusArcsec);
    if (log) {
      log("> Merged " + std::to_string(mergedIndex.size()) + " tiles in " +
          formatNumber(
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              "%.2f") +
          " s");
    }
    std::vector<std::int64_t> kept(tiles.size(), 0);
    for (std::size_t k = 0; k < mergedIndex.size(); ++k) {
      kept[mergedIndex[k]] = report.survey.keptPerTile[k];
    }
    report.survey.keptPerTile = kept;
  }
  report.summaryLines = summaryLines(
      s, report, ranks, waiting,
      measuring(s) ? measuredTileLines(s, report, entries) : std::vector<std::string>());
  if (report.merged) {
    markNextOutputsFinal();
    writeSurveyOutputs(s, report);
    if (log) log("> Wrote " + s.outputDir);
  }
}

// What a signal leaves on disk, said on the line it prints (core/Interrupt.h): the tiles this run
// journaled, the survey outputs or not. Only the root knows them; the other ranks point to the
// journal.
void accountOnInterrupt(const BatchSettings& s, const Cluster& cluster) {
  PiecesAccount account;
  if (!cluster.isRoot()) {
    // Said whole here: mpirun may kill the first rank before it prints its own line.
    account.before =
        " (rank " + std::to_string(cluster.rank()) +
        "): its tile in progress is left to a rerun; the tiles with a `done` line in " +
        s.outputDir +
        "/journal.txt are kept (run the same command again to resume "
        "from them)";
    account.counted = false;
  } else {
    account.before =
        std::string("; this run ") + (measuring(s) ? "measured" : "searched") + " and journaled ";
    account.after = " tile(s), kept in " + s.outputDir +
                    "/tiles (run the same command again to resume from them); ";
    account.finalWritten = "it wrote the survey outputs (" + surveyOutputList(s) +
                           "), complete; nothing half-written is left";
    account.finalNotWritten =
        "it wrote no survey output (" + surveyOutputList(s) + "); nothing half-written is left";
  }
  accountPiecesOnInterrupt(account);
}

}  // namespace

BatchReport runBatch(const BatchSettings& s, const Cluster& cluster, const RunLog& log) {
  accountOnInterrupt(s, cluster);
  BatchReport report;
  Journal journal((fs::path(s.outputDir) / "journal.txt").string());
  std::uint64_t journalRead = 0;
  const std::vector<std::size_t> todo = shareRunPlan(s, cluster, journal, report, journalRead, log);
  const int threads = cluster.threadsPerRank(s.requestedThreads);
  if (log && cluster.isRoot()) {
    log("> Batch run " + std::to_string(report.run) + ": " + std::to_string(report.tiles.size()) +
        " tiles, " + std::to_string(todo.size()) + " to " + taskVerb(s) + " (" + shareText(s) +
        ") on " + std::to_string(cluster.size()) + " rank(s) of " + std::to_string(threads) +
        " thread(s)");
    if (!s.arrayShareNote.empty()) log("> " + s.arrayShareNote);
    const std::string launch =
        slurmLaunchWarning(std::getenv("SLURM_STEP_NUM_TASKS"), std::getenv("SLURM_NTASKS"),
                           std::getenv("SLURM_STEP_ID"), cluster.size());
    if (!launch.empty()) log("WARNING: octarc batch: " + launch);
  }
  // The ranks take the tiles as they become free, each once the root holds its claim; the root
  // records each, then lets go of its claim.
  TileClaims claims(s, journal, journalRead, report);
  std::int64_t finished = 0;
  cluster.distribute(
      std::int64_t(todo.size()),
      [&](std::int64_t k) {
        const Tile& tile = report.tiles[todo[std::size_t(k)]];
        return measuring(s) ? measureTile(s, tile, threads, cluster.rank(), log)
                            : searchTile(s, tile, threads, cluster.rank(), log);
      },
      [&](std::int64_t k, const std::string& text) {
        recordTile(journal, report, todo[std::size_t(k)], parseReport(text, s.task), ++finished,
                   todo.size(), s.task, log);
        claims.release(todo[std::size_t(k)]);
      },
      [&](std::int64_t k) { return claims.take(todo[std::size_t(k)]); });
  if (!cluster.isRoot()) return report;

  // The survey outputs, once every tile is done or failed. The journal stays locked from this
  // run's last line to the survey's last file: of a job array's tasks, the one that appends
  // last sees every other task's lines, and two tasks never write the survey at once.
  journal.appendWhileLocked(report.run, "finished", "-", shareText(s),
                            [&](const std::vector<JournalEntry>& entries) {
                              mergeSurvey(s, report, entries, cluster.size(), log);
                            });
  return report;
}

}  // namespace octarc
