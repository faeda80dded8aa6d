#include "octarc/run/CatalogAssembly.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <optional>
#include <thread>

#include "octarc/catalog/FitsCard.h"
#include "octarc/catalog/RunXml.h"
#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/core/Version.h"
#include "octarc/io/Wcs.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/ParamFile.h"

namespace octarc {

std::string runXmlText(const RunSettings& s, const sexcompat::Config& config,
                       const std::vector<sexcompat::KeySpec>& schema,
                       const std::vector<ColumnSpec>& columns, const XmlRunFacts& facts) {
  RunXml x;
  x.xslUrl = s.xslUrl;
  for (std::size_t i = 0; i < s.imagePaths.size(); ++i) {
    x.imageName += (i ? "," : "") + s.imagePaths[i];
  }
  x.columns = columns;
  x.version = kVersion;
  const std::vector<std::string> now = xmlDateTimeNow();
  x.date = now[0];
  x.time = now[1];
  x.durationSec = facts.durationSec;
  x.threads = resolveThreads(s.threads);
  if (const char* user = std::getenv("USER")) x.user = user;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) == 0) x.host = host;
  std::error_code ec;
  x.path = std::filesystem::current_path(ec).string();
  x.extensions = facts.extensions;
  x.levelCounts = facts.levelCounts;
  for (const std::string& w : facts.warnings) x.warnings.push_back({x.date, x.time, w});
  x.commandLine = facts.commandLine;
  x.configFile = s.configPath;
  using Kind = sexcompat::KeySpec::Kind;
  for (const sexcompat::KeySpec& k : schema) {
    XmlConfigValue v;
    v.key = k.name;
    v.kind = k.kind == Kind::Bool    ? XmlConfigValue::Kind::Bool
             : k.kind == Kind::Int   ? XmlConfigValue::Kind::Int
             : k.kind == Kind::Float ? XmlConfigValue::Kind::Float
                                     : XmlConfigValue::Kind::Text;
    v.values = config.getStrings(k.name);
    x.config.push_back(std::move(v));
  }
  return formatRunXml(x);
}

MeasureContext withOwnWcs(const MeasureContext& context, std::optional<Wcs>& storage) {
  MeasureContext local = context;
  if (local.wcs != nullptr) {
    storage.emplace(*local.wcs);
    local.wcs = &*storage;
  }
  return local;
}

ColumnPlan planColumns(const RunSettings& settings, bool quiet, int levelCount) {
  ColumnPlan out;
  std::vector<sexcompat::ParamRequest> params = sexcompat::readParamFile(settings.parametersPath);
  auto has = [&](const char* name) {
    return std::any_of(params.begin(), params.end(),
                       [&](const sexcompat::ParamRequest& p) { return p.name == name; });
  };
  if (levelCount > 1 && !has("THRESH_LEVEL")) {
    auto number = std::find_if(params.begin(), params.end(),
                               [](const sexcompat::ParamRequest& p) { return p.name == "NUMBER"; });
    params.insert(number == params.end() ? params.begin() : number + 1, {"THRESH_LEVEL", {}, 0});
    if (!quiet) {
      std::cerr << "WARNING: " << settings.parametersPath
                << ": THRESH_LEVEL added to the catalog columns: the rows of the " << levelCount
                << " levels could not be told apart without it\n";
    }
  }
  std::vector<ColumnRequest> requests;
  std::vector<ColumnSpec> external;
  for (const sexcompat::ParamRequest& p : params) {
    int repeat = 1;
    for (int size : p.sizes) repeat *= size;
    if (p.name == "VECTOR_ASSOC") {
      // Every row holds the whole vector: a size from a hostile .param file must not cost
      // gigabytes per object. No ASSOC_DATA list is longer than this.
      constexpr int kMaxAssocVector = 2048;
      if (repeat > kMaxAssocVector) {
        throw ConfigError(settings.parametersPath + ":" + std::to_string(p.line) +
                          ": VECTOR_ASSOC(" + std::to_string(repeat) + "): at most " +
                          std::to_string(kMaxAssocVector) + " elements (the longest ASSOC_DATA)");
      }
      out.assoc = true;
      out.assocVectorSize = repeat;
      external.push_back(sexcompat::vectorAssocColumn(repeat));
    } else if (p.name == "NUMBER_ASSOC") {
      out.assoc = true;
      external.push_back(sexcompat::numberAssocColumn());
    }
    requests.push_back({p.name, repeat});
  }
  std::vector<std::string> unknown;
  // ASSOC matches on the isophotal centroid, which the user may not have asked for.
  std::vector<ColumnRequest> measured = requests;
  auto requested = [&](const char* name) {
    return std::any_of(requests.begin(), requests.end(),
                       [&](const ColumnRequest& r) { return r.name == name; });
  };
  if (out.assoc) {
    if (!requested("X_IMAGE")) measured.push_back({"X_IMAGE", 1});
    if (!requested("Y_IMAGE")) measured.push_back({"Y_IMAGE", 1});
  }
  out.plan = MeasurementPlan::build(measured, external, &unknown);
  for (const std::string& name : unknown) {
    if (!quiet) {
      // A SExtractor column octarc leaves out is not a typo: say why it is missing.
      std::cerr << "WARNING: " << settings.parametersPath << ": catalog parameter " << name
                << (sexcompat::isSextractorParameter(name)
                        ? " not measured by octarc (isophotal only), skipped"
                        : " unknown, skipped")
                << "\n";
    }
  }
  for (const ColumnRequest& r : requests) {
    const bool seen = std::any_of(out.outputColumns.begin(), out.outputColumns.end(),
                                  [&](const ColumnSpec& c) { return c.name == r.name; });
    if (seen) continue;  // SExtractor ignores a repeated parameter
    for (const ColumnSpec& c : out.plan.columns()) {
      if (c.name == r.name) {
        out.outputColumns.push_back(c);
        break;
      }
    }
  }
  if (out.outputColumns.empty()) {
    throw ConfigError(settings.parametersPath + ": no known catalog parameter");
  }
  return out;
}

void measureSegments(const MeasurementPlan& plan, const std::vector<Segment>& segments,
                     const MeasureContext& context, Table& table, int threads) {
  const std::int64_t first = table.rows();
  const std::int64_t count = std::int64_t(segments.size());
  for (std::int64_t i = 0; i < count; ++i) table.appendRow();
  // Rows are preallocated, so each worker writes only its own rows: the output does not depend
  // on the number of threads.
  const int workers = std::max(1, std::min<int>(threads, int(count / 64) + 1));
  parallelBlocks(workers, workers, [&](std::int64_t w0, std::int64_t w1) {
    for (std::int64_t w = w0; w < w1; ++w) {
      std::optional<Wcs> wcs;
      const MeasureContext local = workers > 1 ? withOwnWcs(context, wcs) : context;
      for (std::int64_t i = w; i < count; i += workers) {
        plan.measure(segments[std::size_t(i)], local, table.row(first + i));
      }
    }
  });
}

void applyAssoc(const sexcompat::AssocSettings& settings, int vectorSize,
                const PreparedImage& image, Table& table, bool quiet, bool keepAllRows) {
  const Wcs* wcs = image.wcs ? &*image.wcs : nullptr;
  std::vector<std::string> warnings;
  const sexcompat::AssocList list = sexcompat::AssocList::load(
      settings, vectorSize, image.hdu.pixels.height(),
      [wcs](double lng, double lat) {
        return wcs ? wcs->worldToPixel(lng, lat)
                   : std::array<double, 2>{std::nan(""), std::nan("")};
      },
      &warnings);
  if (!quiet) {
    for (const std::string& w : warnings) std::cerr << "WARNING: " << w << "\n";
  }
  const int xCol = table.findColumn("X_IMAGE");
  const int yCol = table.findColumn("Y_IMAGE");
  const int vecCol = table.findColumn("VECTOR_ASSOC");
  const int numCol = table.findColumn("NUMBER_ASSOC");
  std::vector<bool> keep(std::size_t(table.rows()), true);
  for (std::int64_t r = 0; r < table.rows(); ++r) {
    const sexcompat::AssocList::Match m = list.match(table.value(r, xCol), table.value(r, yCol));
    if (vecCol >= 0) {
      const int n = table.columns()[std::size_t(vecCol)].repeat;
      for (int e = 0; e < n; ++e) {
        table.setValue(r, vecCol, e < int(m.values.size()) ? m.values[std::size_t(e)] : 0.0, e);
      }
    }
    if (numCol >= 0) table.setValue(r, numCol, m.count);
    keep[std::size_t(r)] = keepAllRows || list.keeps(m);
  }
  if (!keepAllRows) table.filterRows(keep);
}

Table outputTable(const ColumnPlan& plan, Table&& full) {
  // Usually the catalog is the plan itself: hand it over rather than copy it.
  if (full.columnCount() == int(plan.outputColumns.size())) return std::move(full);
  return outputTable(plan, static_cast<const Table&>(full));
}

Table outputTable(const ColumnPlan& plan, const Table& full) {
  Table out(plan.outputColumns);
  std::vector<int> source;
  for (const ColumnSpec& c : plan.outputColumns) source.push_back(full.findColumn(c.name));
  for (std::int64_t r = 0; r < full.rows(); ++r) {
    double* row = out.appendRow();
    const double* in = full.row(r);
    for (int c = 0; c < out.columnCount(); ++c) {
      std::copy_n(in + full.offset(source[std::size_t(c)]), out.columns()[std::size_t(c)].repeat,
                  row + out.offset(c));
    }
  }
  return out;
}

namespace {

std::string baseName(const std::string& path) {
  return path.empty() ? std::string() : std::filesystem::path(path).filename().string();
}

}  // namespace

RunSummary runSummary(const RunSettings& settings, const PreparedImage& image,
                      const std::vector<ThresholdLevel>& levels, const RunFacts& facts) {
  RunSummary r;
  std::string file = facts.imagePath;
  if (auto bracket = file.find('['); bracket != std::string::npos) file.resize(bracket);
  r.fitsFile = baseName(file);
  r.fitsExt = facts.extension + 1;
  r.fitsNext = facts.extensionCount;
  r.version = std::string("octarc ") + kVersion;
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char date[16], time[16];
  std::strftime(date, sizeof date, "%d/%m/%Y", &utc);
  std::strftime(time, sizeof time, "%H:%M:%S", &utc);
  r.date = date;
  r.time = time;
  r.elapsedSec = facts.elapsedSec;
  r.backgroundAdu = image.backgroundAdu;
  r.backgroundRmsAdu = image.sigmaAdu;
  // SEXTHLD/SEXATHLD describe the lowest level; OCTTHnnn cards list every level.
  if (!levels.empty()) {
    r.thresholdAdu = levels.front().thresholdAdu;
    r.analysisThresholdAdu = levels.front().analysisThresholdAdu;
  }
  r.detections = facts.detectedCount;
  r.finalObjects = facts.finalCount;
  r.parameters = facts.parameterCount;
  r.pixelScaleArcsec = settings.pixelScaleArcsec;
  r.seeingFwhmArcsec = settings.seeingFwhmArcsec;
  r.gainEPerAdu = image.gain;
  r.filtering = settings.filter;
  r.filterFile = settings.filter ? baseName(settings.filterPath) : "";
  r.minAreaPix = settings.minAreaPix;
  r.deblendThresholds = 1;  // octarc never deblends
  r.deblendContrast = 1.0;
  r.cleaning = false;
  r.saturationAdu = image.saturationAdu;
  r.magZeropoint = settings.magZeropoint;
  r.backMeshPix[0] = settings.backMeshWidthPix;
  r.backMeshPix[1] = settings.backMeshHeightPix;
  r.backFilterMesh[0] = settings.backFilterWidth;
  r.backFilterMesh[1] = settings.backFilterHeight;
  r.imageWidthPix = image.hdu.pixels.width();
  r.imageHeightPix = image.hdu.pixels.height();
  r.imageBitpix = image.hdu.bitpix;
  r.configFile = baseName(settings.configPath);
  r.thresholdType = settings.detectThresholdType == ThresholdType::Relative ? "SIGMA" : "ABSOLUTE";
  r.thresholdSetting = settings.detectThreshold;
  if (auto object = image.hdu.header.value("OBJECT")) r.object = *object;
  return r;
}

std::vector<std::string> runHeaderCards(const RunSummary& summary, const PreparedImage& image,
                                        const std::vector<ThresholdLevel>& levels) {
  std::vector<std::string> cards = sexRunCards(summary);
  const std::vector<std::string> own = octarcRunCards(image, levels);
  cards.insert(cards.end(), own.begin(), own.end());
  return cards;
}

std::vector<std::string> appendedRunCards(const RunSummary& summary, const PreparedImage& image,
                                          const std::vector<ThresholdLevel>& levels) {
  std::vector<std::string> cards;
  for (const std::string& card : runHeaderCards(summary, image, levels)) {
    const std::string key = card.substr(0, 8);
    if (key == "SEXGAIN " || key == "SEXBKGND" || key == "SEXBKDEV" || key.rfind("OCT", 0) == 0) {
      cards.push_back(card);
    }
  }
  return cards;
}

std::vector<std::string> octarcRunCards(const PreparedImage& image,
                                        const std::vector<ThresholdLevel>& levels) {
  std::vector<std::string> cards;
  cards.push_back(formatCard("OCTNLEV", std::int64_t(levels.size()), "Number of threshold levels"));
  for (const ThresholdLevel& l : levels) {
    const std::string n = std::to_string(l.level);
    cards.push_back(formatCard("OCTTH" + n, RealValue(l.thresholdAdu),
                               "Detection threshold of level " + n + " (ADU)"));
  }
  cards.push_back(
      formatCard("OCTBKSRC", image.origin.background, "Origin of the background level"));
  cards.push_back(formatCard("OCTSGSRC", image.origin.sigma, "Origin of the noise sigma SEXBKDEV"));
  if (image.separateDetection) {
    // Dual-image mode: SEXBKDEV is the measurement image's noise, the thresholds follow this one.
    cards.push_back(formatCard("OCTDTDEV", RealValue(image.detectionSigmaAdu),
                               "Noise sigma of the detection image (ADU)"));
  }
  return cards;
}

}  // namespace octarc
