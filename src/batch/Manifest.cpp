#include "octarc/batch/Manifest.h"

#include <glob.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc {

namespace fs = std::filesystem;

namespace {

constexpr const char* kWeightSuffix = ".weight";

bool endsWith(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

bool isGlobPattern(const std::string& s) {
  return s.find_first_of("*?[") != std::string::npos;
}

std::string tileNameOf(const std::string& imagePath) {
  std::string name = fs::path(imagePath).filename().string();
  const auto strip = [&](const char* suffix) {
    const std::size_t n = std::char_traits<char>::length(suffix);
    if (name.size() > n && name.compare(name.size() - n, n, suffix) == 0) {
      name.resize(name.size() - n);
      return true;
    }
    return false;
  };
  strip(".fz") || strip(".gz");
  strip(".fits") || strip(".fit") || strip(".fts");
  return name;
}

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

// Fields of one line: commas separate when there is one outside quotes, else blanks. A field
// may be quoted (RFC 4180): "a, b#1.fits" holds its commas, blanks and '#', and "" in it is a
// quote. `at` starts the error messages ("survey.csv:4: ").
std::vector<std::string> splitFields(const std::string& line, const std::string& at) {
  bool csv = false, quoted = false;
  for (const char c : line) {
    if (c == '"') quoted = !quoted;  // "" inside a quote toggles twice
    if (c == ',' && !quoted) csv = true;
  }
  if (quoted) throw ConfigError(at + "a quote (\") is not closed");
  const auto separator = [&](char c) { return csv ? c == ',' : isBlank(c); };
  std::vector<std::string> fields;
  std::size_t i = 0;
  const std::size_t n = line.size();
  const auto skipBlanks = [&] {
    while (i < n && isBlank(line[i])) ++i;
  };
  for (;;) {
    skipBlanks();
    if (i == n && !csv) break;  // blanks separate: no field after the last blank
    std::string field;
    if (i < n && line[i] == '"') {
      for (++i;; ++i) {
        if (line[i] == '"' && i + 1 < n && line[i + 1] == '"') {
          field += '"';
          ++i;
        } else if (line[i] == '"') {
          ++i;
          break;
        } else {
          field += line[i];
        }
      }
      const std::size_t closed = i;
      skipBlanks();
      // Then the line's end, or a separator: a comma, or (blank-separated) the blanks skipped.
      if (i < n && !(csv ? line[i] == ',' : i > closed)) {
        throw ConfigError(at + "text after a closing quote: quote the whole field");
      }
    } else {
      while (i < n && !separator(line[i])) {
        if (line[i] == '"') {
          throw ConfigError(at +
                            "a quote inside a field: quote the whole "
                            "field, \"\" for a quote");
        }
        field += line[i++];
      }
      while (!field.empty() && isBlank(field.back())) field.pop_back();
    }
    fields.push_back(field);
    if (i == n) break;
    if (csv) ++i;  // past the comma
  }
  return fields;
}

bool readable(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  return bool(in);
}

}  // namespace

std::vector<Tile> readManifest(const std::string& manifestOrGlob, bool globWeights,
                               ManifestRows rows) {
  std::vector<Tile> tiles;
  std::error_code ec;
  const bool measure = rows == ManifestRows::Measure;
  if (!fs::exists(manifestOrGlob, ec) && isGlobPattern(manifestOrGlob)) {
    if (measure) {
      throw ConfigError(manifestOrGlob +
                        ": TASK MEASURE takes a manifest of IMAGE SEGMENTATION CATALOG [WEIGHT] "
                        "rows, not a glob of images (each image needs its SExtractor outputs)");
    }
    glob_t found{};
    const int status = ::glob(manifestOrGlob.c_str(), 0, nullptr, &found);
    const std::size_t matched = status == 0 ? found.gl_pathc : 0;
    for (std::size_t i = 0; status == 0 && i < found.gl_pathc; ++i) {
      Tile t;
      t.imagePath = found.gl_pathv[i];
      t.name = tileNameOf(t.imagePath);
      // NAME.weight.fits is NAME.fits's weight map (as `simulate field` writes them), not a tile.
      if (endsWith(t.name, kWeightSuffix)) continue;
      if (globWeights) {
        t.weightPath =
            (fs::path(t.imagePath).parent_path() / (t.name + kWeightSuffix + std::string(".fits")))
                .string();
      }
      tiles.push_back(std::move(t));
    }
    ::globfree(&found);
    for (const Tile& t : tiles) {
      // Names go into the journal's fields and the other ranks' tile lists whole.
      if (hasControlCharacter(t.imagePath)) {
        throw ConfigError(manifestOrGlob + ": " + quoteForMessage(t.imagePath) +
                          " holds a control character");
      }
      if (!readable(t.imagePath)) throw ConfigError(t.imagePath + ": cannot be read");
      if (t.weightPath.empty()) continue;
      if (!fs::exists(t.weightPath, ec)) {
        throw ConfigError(manifestOrGlob + ": " + t.imagePath + " has no weight map " +
                          t.weightPath + " beside it, and WEIGHT_TYPE is not NONE");
      }
      if (!readable(t.weightPath)) throw ConfigError(t.weightPath + ": cannot be read");
    }
    std::sort(tiles.begin(), tiles.end(),
              [](const Tile& a, const Tile& b) { return a.imagePath < b.imagePath; });
    if (tiles.empty() && matched > 0) {
      throw ConfigError(manifestOrGlob +
                        ": only weight maps (NAME.weight.fits) match the pattern, no image");
    }
    if (tiles.empty()) throw ConfigError(manifestOrGlob + ": no file matches the pattern");
  } else {
    std::ifstream in(manifestOrGlob);
    if (!in) throw IoError(manifestOrGlob + ": cannot read the manifest");
    const fs::path base = fs::path(manifestOrGlob).parent_path();
    auto resolve = [&](const std::string& p) {
      if (p.empty() || p == "-") return std::string();
      return fs::path(p).is_absolute() || base.empty() ? p : (base / p).string();
    };
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      // A comment is a line of its own: elsewhere '#' may be part of a path.
      const std::size_t first = line.find_first_not_of(" \t\r");
      if (first == std::string::npos || line[first] == '#') continue;
      const std::string at = manifestOrGlob + ":" + std::to_string(n) + ": ";
      const std::vector<std::string> f = splitFields(line, at);
      if (f.empty() || (f.size() == 1 && f[0].empty())) continue;
      for (const std::string& field : f) {
        if (hasControlCharacter(field)) throw ConfigError(at + "holds a control character");
      }
      if (tiles.empty() && lowercase(f[0]) == "image") continue;  // a CSV header
      if (measure && (f.size() < 3 || f.size() > 4)) {
        throw ConfigError(at + std::to_string(f.size()) + " field(s): give IMAGE SEGMENTATION " +
                          "CATALOG [WEIGHT] (TASK MEASURE)");
      }
      if (f.size() > 4) {
        throw ConfigError(at + "too many fields (" + std::to_string(f.size()) +
                          "): give IMAGE [WEIGHT [MASK [CATALOG]]]");
      }
      if (f[0].empty() || f[0] == "-") throw ConfigError(at + "no image");
      Tile t;
      t.line = n;
      t.imagePath = resolve(f[0]);
      if (measure) {
        t.segmentationPath = resolve(f[1]);
        t.catalogPath = resolve(f[2]);
        t.weightPath = f.size() > 3 ? resolve(f[3]) : "";
        if (t.segmentationPath.empty()) throw ConfigError(at + "no segmentation image");
        if (t.catalogPath.empty()) throw ConfigError(at + "no catalog");
      } else {
        t.weightPath = f.size() > 1 ? resolve(f[1]) : "";
        t.maskPath = f.size() > 2 ? resolve(f[2]) : "";
        t.catalogPath = f.size() > 3 ? resolve(f[3]) : "";
      }
      t.name = tileNameOf(t.imagePath);
      const std::pair<const char*, const std::string*> files[] = {
          {"image", &t.imagePath},
          {"segmentation image", &t.segmentationPath},
          {"weight map", &t.weightPath},
          {"mask", &t.maskPath},
          {"catalog", &t.catalogPath}};
      for (const auto& [what, path] : files) {
        if (path->empty()) continue;
        if (!fs::exists(*path, ec)) throw ConfigError(at + what + " " + *path + ": no such file");
        if (!readable(*path)) throw ConfigError(at + what + " " + *path + ": cannot be read");
      }
      tiles.push_back(std::move(t));
    }
    if (tiles.empty()) throw ConfigError(manifestOrGlob + ": the manifest lists no tile");
  }
  // Tiles are told apart by name (their output folders) and must not repeat.
  std::map<std::string, const Tile*> byName, byImage;
  for (const Tile& t : tiles) {
    const std::string at =
        t.line > 0 ? manifestOrGlob + ":" + std::to_string(t.line) + ": " : manifestOrGlob + ": ";
    const auto lineOf = [&](const Tile* other) {
      return other->line > 0 ? "line " + std::to_string(other->line) : other->imagePath;
    };
    const fs::path canonical = fs::weakly_canonical(t.imagePath, ec);
    const std::string key = ec ? t.imagePath : canonical.string();
    if (const auto it = byImage.find(key); it != byImage.end()) {
      throw ConfigError(at + "duplicate tile: " + t.imagePath + " is already " +
                        lineOf(it->second));
    }
    if (const auto it = byName.find(t.name); it != byName.end()) {
      throw ConfigError(at + "duplicate tile name " + t.name + " (" + lineOf(it->second) +
                        "): tiles are named by their image file, which must differ");
    }
    byImage[key] = &t;
    byName[t.name] = &t;
  }
  return tiles;
}

}  // namespace octarc
