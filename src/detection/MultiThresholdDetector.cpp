#include "octarc/detection/MultiThresholdDetector.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"

namespace octarc {
namespace {

constexpr std::int64_t kMaxOffset = std::numeric_limits<std::int32_t>::max();

// A horizontal run of pixels x0..x1 (inclusive) on row y. `offset` is the index of its first
// pixel in the per-pixel buffer of its component (unused for the lowest-level scan).
struct Run {
  std::int32_t y;
  std::int32_t x0;
  std::int32_t x1;
  std::int32_t offset;
};

// Union-find over run indices. The root of a set is always its smallest index (a root is only
// ever attached below a smaller one, and path halving keeps parent[i] <= i), so after
// flattening, sets come out ordered by their first run in raster order whatever the order
// of the unions: this is what makes the output independent of the thread count.
inline std::int32_t findRoot(std::int32_t* parent, std::int32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

inline void unite(std::int32_t* parent, std::int32_t a, std::int32_t b) {
  a = findRoot(parent, a);
  b = findRoot(parent, b);
  if (a < b) {
    parent[b] = a;
  } else if (b < a) {
    parent[a] = b;
  }
}

// Unites the runs of row `cur` [curBegin, curEnd) with the 8-connected runs of the row just
// above it in the scan, `prev` [prevBegin, prevEnd); both sorted by x.
inline void linkRows(const Run* runs, std::int32_t prevBegin, std::int32_t prevEnd,
                     std::int32_t curBegin, std::int32_t curEnd, std::int32_t* parent) {
  std::int32_t p = prevBegin;
  for (std::int32_t r = curBegin; r < curEnd; ++r) {
    // Runs ending left of x0 - 1 touch neither this run nor any later one of the row.
    while (p < prevEnd && runs[p].x1 < runs[r].x0 - 1) ++p;
    for (std::int32_t q = p; q < prevEnd && runs[q].x0 <= runs[r].x1 + 1; ++q) unite(parent, r, q);
  }
}

// Unites the 8-connected runs of runs[begin, end) (sorted by row, then x). parent[i] must be i.
void linkRuns(const Run* runs, std::int32_t begin, std::int32_t end, std::int32_t* parent) {
  std::int32_t prevBegin = begin;
  std::int32_t prevEnd = begin;
  std::int32_t i = begin;
  while (i < end) {
    const std::int32_t y = runs[i].y;
    std::int32_t rowEnd = i;
    while (rowEnd < end && runs[rowEnd].y == y) ++rowEnd;
    if (prevEnd > prevBegin && runs[prevBegin].y == y - 1) {
      linkRows(runs, prevBegin, prevEnd, i, rowEnd, parent);
    }
    prevBegin = i;
    prevEnd = rowEnd;
    i = rowEnd;
  }
}

// After linkRuns: label[i] = component of run i, numbered 0, 1, ... by first run. Returns the
// number of components. Flattening in increasing order needs one step per run because
// parent[i] < i is already flat when i is reached.
std::int32_t labelRuns(std::int32_t count, std::int32_t* parent, std::int32_t* label) {
  std::int32_t components = 0;
  for (std::int32_t i = 0; i < count; ++i) {
    parent[i] = parent[parent[i]];
    label[i] = parent[i] == i ? components++ : label[parent[i]];
  }
  return components;
}

// One component's objects, level by level (level 1 first), before numbering.
struct ComponentObjects {
  std::vector<Segment> segments;
  std::vector<std::int32_t> parentIndex;  // index into segments of the parent, -1 at level 1
};

// Buffers reused from one component to the next by a worker.
struct Scratch {
  std::vector<Run> cur, next;
  std::vector<std::int32_t> curNode, nextNode;  // per run: index of its object in segments
  std::vector<std::int32_t> parent, label, labelNode;
  std::vector<std::int64_t> area;
  std::vector<std::int32_t> firstRun;
};

// Comparisons are in single precision, as in SExtractor (its thresholds and pixels are
// float): pixel f is above threshold t when f > (float)t, or f > (float)t * s with a factor s.
// Comparing in double instead would differ for f between t and (float)t.
struct Detector {
  const ImageF& image;
  const float* scale;  // nullptr without a threshold scale map
  std::vector<float> thresholds;
  int levelCount;
  std::int64_t minArea;
  bool footprintRuns;

  // Pixel above the lowest level. A NaN value or factor fails every comparison.
  bool aboveLowest(std::int64_t i) const {
    const float f = image.data()[i];
    if (!(f < std::numeric_limits<float>::infinity())) return false;
    if (scale == nullptr) return f > thresholds[0];
    const float s = scale[i];
    return s > 0.0f && f > thresholds[0] * s;
  }

  // The runs of one row above the lowest level, appended to `runs`, and the number of levels
  // each of their pixels exceeds, appended to `levels` (run.offset = index of its first pixel).
  void scanRow(std::int64_t y, std::vector<Run>& runs, std::vector<std::uint8_t>& levels) const {
    const std::int64_t width = image.width();
    const std::int64_t base = y * width;
    std::int64_t x = 0;
    if (scale == nullptr) {
      // The common case, kept free of the scale test: a tight compare loop over the row.
      const float* row = image.data() + base;
      const float t0 = thresholds[0];
      constexpr float inf = std::numeric_limits<float>::infinity();
      while (x < width) {
        while (x < width && !(row[x] > t0 && row[x] < inf)) ++x;
        if (x == width) break;
        const std::int64_t start = x;
        while (x < width && row[x] > t0 && row[x] < inf) ++x;
        addRun(y, start, x, runs, levels);
      }
    } else {
      while (x < width) {
        while (x < width && !aboveLowest(base + x)) ++x;
        if (x == width) break;
        const std::int64_t start = x;
        while (x < width && aboveLowest(base + x)) ++x;
        addRun(y, start, x, runs, levels);
      }
    }
  }

  // Records pixels start..end-1 of row y as a run, with their level counts. The counts are
  // taken here, while the row is in cache, rather than when the component is processed.
  void addRun(std::int64_t y, std::int64_t start, std::int64_t end, std::vector<Run>& runs,
              std::vector<std::uint8_t>& levels) const {
    if (levels.size() + (end - start) > static_cast<std::size_t>(kMaxOffset)) {
      throw ConfigError("detection: more than 2^31-1 pixels above the lowest threshold");
    }
    runs.push_back({static_cast<std::int32_t>(y), static_cast<std::int32_t>(start),
                    static_cast<std::int32_t>(end - 1), static_cast<std::int32_t>(levels.size())});
    const std::int64_t base = y * image.width();
    for (std::int64_t x = start; x < end; ++x) levels.push_back(levelOf(base + x));
  }

  // Number of levels pixel i exceeds, knowing it exceeds the lowest.
  std::uint8_t levelOf(std::int64_t i) const {
    const float f = image.data()[i];
    int q = 1;
    if (scale == nullptr) {
      while (q < levelCount && f > thresholds[q]) ++q;
    } else {
      const float s = scale[i];
      while (q < levelCount && f > thresholds[q] * s) ++q;
    }
    return static_cast<std::uint8_t>(q);
  }

  // All objects of one lowest-level component (given by its runs, in raster order, with at
  // least minArea pixels); `levels` holds the level counts of all runs' pixels.
  void objectsOf(const Run* globalRuns, const std::uint8_t* levels, const std::int32_t* runIndex,
                 std::int32_t runCount, Scratch& s, ComponentObjects& out) const {
    const std::int64_t width = image.width();
    out.segments.clear();
    out.parentIndex.clear();

    // Level 1: the component itself.
    s.cur.clear();
    std::int64_t pixelCount = 0;
    for (std::int32_t r = 0; r < runCount; ++r) {
      const Run& run = globalRuns[runIndex[r]];
      pixelCount += run.x1 - run.x0 + 1;
      s.cur.push_back(run);
    }
    out.segments.emplace_back();
    out.parentIndex.push_back(-1);
    if (footprintRuns) {
      Segment& seg = out.segments.back();
      seg.level = 1;
      seg.runs.clear();
      for (const Run& run : s.cur) seg.runs.push_back({run.y, run.x0, run.x1});
    } else {
      Segment& seg = out.segments.back();
      seg.level = 1;
      seg.pixels.resize(static_cast<std::size_t>(pixelCount));
      std::int64_t* dst = seg.pixels.data();
      for (const Run& run : s.cur) {
        const std::int64_t base = static_cast<std::int64_t>(run.y) * width;
        const std::int32_t length = run.x1 - run.x0 + 1;
        for (std::int32_t i = 0; i < length; ++i) dst[i] = base + run.x0 + i;
        dst += length;
      }
    }
    s.curNode.assign(s.cur.size(), 0);

    for (int level = 2; level <= levelCount && !s.cur.empty(); ++level) {
      // Cut the runs of the objects kept at level - 1 into the runs of this level.
      s.next.clear();
      s.nextNode.clear();
      for (std::size_t r = 0; r < s.cur.size(); ++r) {
        const Run& run = s.cur[r];
        const std::uint8_t* q = levels + run.offset;
        const std::int32_t length = run.x1 - run.x0 + 1;
        std::int32_t i = 0;
        while (i < length) {
          while (i < length && q[i] < level) ++i;
          if (i == length) break;
          const std::int32_t start = i;
          while (i < length && q[i] >= level) ++i;
          s.next.push_back({run.y, run.x0 + start, run.x0 + i - 1, run.offset + start});
          s.nextNode.push_back(s.curNode[r]);
        }
      }
      if (s.next.empty()) break;

      const auto n = static_cast<std::int32_t>(s.next.size());
      s.parent.resize(n);
      s.label.resize(n);
      std::iota(s.parent.begin(), s.parent.end(), 0);
      linkRuns(s.next.data(), 0, n, s.parent.data());
      const std::int32_t components = labelRuns(n, s.parent.data(), s.label.data());

      s.area.assign(components, 0);
      s.firstRun.assign(components, -1);
      for (std::int32_t r = 0; r < n; ++r) {
        const std::int32_t c = s.label[r];
        s.area[c] += s.next[r].x1 - s.next[r].x0 + 1;
        if (s.firstRun[c] < 0) s.firstRun[c] = r;
      }
      // Objects of this level, in raster order of their first pixel; too small ones are
      // dropped here, and with them everything above them.
      s.labelNode.assign(components, -1);
      for (std::int32_t c = 0; c < components; ++c) {
        if (s.area[c] < minArea) continue;
        s.labelNode[c] = static_cast<std::int32_t>(out.segments.size());
        out.segments.emplace_back();
        out.parentIndex.push_back(s.nextNode[s.firstRun[c]]);
        Segment& seg = out.segments.back();
        seg.level = level;
        if (!footprintRuns) seg.pixels.resize(static_cast<std::size_t>(s.area[c]));
        s.area[c] = 0;  // from here on: pixels written so far
      }
      s.cur.clear();
      s.curNode.clear();
      for (std::int32_t r = 0; r < n; ++r) {
        const std::int32_t c = s.label[r];
        const std::int32_t node = s.labelNode[c];
        if (node < 0) continue;
        const Run& run = s.next[r];
        s.cur.push_back(run);
        s.curNode.push_back(node);
        if (footprintRuns) {
          out.segments[node].runs.push_back({run.y, run.x0, run.x1});
          continue;
        }
        std::int64_t* dst = out.segments[node].pixels.data() + s.area[c];
        const std::int64_t first = static_cast<std::int64_t>(run.y) * width + run.x0;
        const std::int32_t length = run.x1 - run.x0 + 1;
        for (std::int32_t i = 0; i < length; ++i) dst[i] = first + i;
        s.area[c] += length;
      }
    }
  }
};

void validate(const ImageF& image, const DetectionSettings& settings) {
  const auto& t = settings.thresholdsAdu;
  if (t.empty()) throw ConfigError("DETECT_THRESH: no detection threshold given");
  if (t.size() > static_cast<std::size_t>(kMaxThresholdLevels)) {
    throw ConfigError("DETECT_NLEVELS: " + std::to_string(t.size()) +
                      " detection levels, at most " + std::to_string(kMaxThresholdLevels) +
                      " supported");
  }
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (!std::isfinite(t[k])) {
      throw ConfigError("DETECT_THRESH: level " + std::to_string(k + 1) + " is not finite");
    }
    if (k > 0 && !(t[k] > t[k - 1])) {
      throw ConfigError("DETECT_THRESH: levels must increase strictly, but level " +
                        std::to_string(k + 1) + " (" + std::to_string(t[k]) + " ADU) <= level " +
                        std::to_string(k) + " (" + std::to_string(t[k - 1]) + " ADU)");
    }
  }
  if (settings.minArea < 1) {
    throw ConfigError("DETECT_MINAREA: must be at least 1, got " +
                      std::to_string(settings.minArea));
  }
  if (settings.thresholdScale != nullptr && (settings.thresholdScale->width() != image.width() ||
                                             settings.thresholdScale->height() != image.height())) {
    throw ConfigError(
        "WEIGHT_IMAGE: threshold map is " + std::to_string(settings.thresholdScale->width()) + "x" +
        std::to_string(settings.thresholdScale->height()) + " but the detection image is " +
        std::to_string(image.width()) + "x" + std::to_string(image.height()));
  }
  if (image.width() > kMaxImageSidePix || image.height() > kMaxImageSidePix) {
    throw ConfigError("detection: image side exceeds 2^31-1 pixels");
  }
}

// Step 1: the runs above the lowest level (with their per-pixel levels), scanned by row bands on
// `threads` threads and concatenated in raster order; bandBegin[b] is the first run of band b.
struct ScannedRuns {
  std::vector<Run> runs;
  std::vector<std::uint8_t> levels;
  std::vector<std::int64_t> bandBegin;
};

ScannedRuns scanRuns(const Detector& detector, std::int64_t height, int threads) {
  std::vector<std::vector<Run>> bandRuns(threads);
  std::vector<std::vector<std::uint8_t>> bandLevels(threads);
  parallelFor(threads, threads, [&](std::int64_t band) {
    const std::int64_t y0 = height * band / threads;
    const std::int64_t y1 = height * (band + 1) / threads;
    for (std::int64_t y = y0; y < y1; ++y) detector.scanRow(y, bandRuns[band], bandLevels[band]);
  });
  ScannedRuns out;
  out.bandBegin.assign(threads + 1, 0);
  for (int band = 0; band < threads; ++band) {
    out.bandBegin[band + 1] =
        out.bandBegin[band] + static_cast<std::int64_t>(bandRuns[band].size());
  }
  if (out.bandBegin[threads] > std::numeric_limits<std::int32_t>::max()) {
    throw ConfigError("detection: more than 2^31-1 runs above the lowest threshold");
  }
  std::size_t levelTotal = 0;
  for (const auto& band : bandLevels) levelTotal += band.size();
  if (levelTotal > static_cast<std::size_t>(kMaxOffset)) {
    throw ConfigError("detection: more than 2^31-1 pixels above the lowest threshold");
  }
  out.runs.reserve(static_cast<std::size_t>(out.bandBegin[threads]));
  out.levels.reserve(levelTotal);
  for (int band = 0; band < threads; ++band) {
    const auto shift = static_cast<std::int32_t>(out.levels.size());
    for (Run run : bandRuns[band]) {
      run.offset += shift;
      out.runs.push_back(run);
    }
    out.levels.insert(out.levels.end(), bandLevels[band].begin(), bandLevels[band].end());
    std::vector<Run>().swap(bandRuns[band]);
    std::vector<std::uint8_t>().swap(bandLevels[band]);
  }
  return out;
}

// Step 2: the connected components of the runs, bands in parallel, then the band seams. Fills
// label (one per run) and returns the number of components.
std::int32_t labelComponents(ScannedRuns& scanned, int threads, std::vector<std::int32_t>& label) {
  std::vector<Run>& runs = scanned.runs;
  const std::vector<std::int64_t>& bandBegin = scanned.bandBegin;
  const auto runCount = static_cast<std::int32_t>(runs.size());
  std::vector<std::int32_t> parent(runCount);
  std::iota(parent.begin(), parent.end(), 0);
  parallelFor(threads, threads, [&](std::int64_t band) {
    linkRuns(runs.data(), static_cast<std::int32_t>(bandBegin[band]),
             static_cast<std::int32_t>(bandBegin[band + 1]), parent.data());
  });
  for (int band = 1; band < threads; ++band) {
    // Last row of the previous non-empty band against the first row of this one.
    const auto begin = static_cast<std::int32_t>(bandBegin[band]);
    const auto end = static_cast<std::int32_t>(bandBegin[band + 1]);
    if (begin == end || begin == 0) continue;
    std::int32_t prevBegin = begin - 1;
    while (prevBegin > 0 && runs[prevBegin - 1].y == runs[begin - 1].y) --prevBegin;
    if (runs[begin - 1].y != runs[begin].y - 1) continue;
    std::int32_t curEnd = begin;
    while (curEnd < end && runs[curEnd].y == runs[begin].y) ++curEnd;
    linkRows(runs.data(), prevBegin, begin, begin, curEnd, parent.data());
  }
  label.assign(runCount, 0);
  return labelRuns(runCount, parent.data(), label.data());
}

// Step 3: the runs grouped by component (stable, so each group stays in raster order): group c
// is runOrder[groupBegin[c] .. groupBegin[c + 1]); area[c] its pixels.
struct ComponentGroups {
  std::vector<std::int64_t> area;
  std::vector<std::int32_t> groupBegin;
  std::vector<std::int32_t> runOrder;
};

ComponentGroups groupByComponent(const std::vector<Run>& runs,
                                 const std::vector<std::int32_t>& label,
                                 std::int32_t componentCount) {
  const auto runCount = static_cast<std::int32_t>(runs.size());
  ComponentGroups g;
  g.area.assign(componentCount, 0);
  g.groupBegin.assign(componentCount + 1, 0);
  for (std::int32_t r = 0; r < runCount; ++r) {
    g.area[label[r]] += runs[r].x1 - runs[r].x0 + 1;
    ++g.groupBegin[label[r] + 1];
  }
  for (std::int32_t c = 0; c < componentCount; ++c) g.groupBegin[c + 1] += g.groupBegin[c];
  g.runOrder.resize(runCount);
  std::vector<std::int32_t> fill(g.groupBegin.begin(), g.groupBegin.end() - 1);
  for (std::int32_t r = 0; r < runCount; ++r) g.runOrder[fill[label[r]]++] = r;
  return g;
}

}  // namespace

std::vector<std::int64_t> detectMultiThreshold(
    const ImageF& detection, const DetectionSettings& settings,
    const std::function<void(std::vector<Segment>& objects)>& sink) {
  validate(detection, settings);
  const int levelCount = static_cast<int>(settings.thresholdsAdu.size());
  std::vector<std::int64_t> perLevel(levelCount, 0);
  const std::int64_t width = detection.width();
  const std::int64_t height = detection.height();
  if (width == 0 || height == 0) return perLevel;

  const int threads =
      static_cast<int>(std::min<std::int64_t>(resolveThreads(settings.threads), height));

  const Detector detector{
      detection,
      settings.thresholdScale ? settings.thresholdScale->data() : nullptr,
      std::vector<float>(settings.thresholdsAdu.begin(), settings.thresholdsAdu.end()),
      levelCount,
      settings.minArea,
      settings.footprintRuns};

  // 1-3. Runs above the lowest level, their components, the runs grouped by component;
  //      components below DETECT_MINAREA at the lowest level have no object at any level.
  ScannedRuns scanned = scanRuns(detector, height, threads);
  std::vector<std::int32_t> label;
  const std::int32_t componentCount = labelComponents(scanned, threads, label);
  const std::vector<Run>& runs = scanned.runs;
  const std::vector<std::uint8_t>& levels = scanned.levels;
  ComponentGroups groups = groupByComponent(runs, label, componentCount);
  std::vector<std::int32_t>().swap(label);
  std::vector<std::int64_t>& area = groups.area;
  const std::vector<std::int32_t>& groupBegin = groups.groupBegin;
  const std::vector<std::int32_t>& runOrder = groups.runOrder;

  // 4. Tasks: consecutive kept components, about kTaskPixels pixels each, handled in parallel and
  //    emitted in order.
  constexpr std::int64_t kTaskPixels = 1 << 15;
  std::vector<std::int32_t> kept;
  std::vector<std::size_t> taskBegin{0};
  std::int64_t taskPixels = 0;
  for (std::int32_t c = 0; c < componentCount; ++c) {
    if (area[c] < settings.minArea) continue;
    kept.push_back(c);
    taskPixels += area[c];
    if (taskPixels >= kTaskPixels) {
      taskBegin.push_back(kept.size());
      taskPixels = 0;
    }
  }
  if (taskBegin.back() != kept.size()) taskBegin.push_back(kept.size());
  std::vector<std::int64_t>().swap(area);

  std::vector<std::int32_t> numberOf;  // NUMBER of each object of the component being emitted
  orderedParallel<std::vector<ComponentObjects>, Scratch>(
      taskBegin.size() - 1, threads,
      [&](std::size_t task, Scratch& scratch, std::vector<ComponentObjects>& result) {
        const std::size_t first = taskBegin[task];
        const std::size_t last = taskBegin[task + 1];
        result.resize(last - first);
        for (std::size_t i = first; i < last; ++i) {
          const std::int32_t c = kept[i];
          detector.objectsOf(runs.data(), levels.data(), runOrder.data() + groupBegin[c],
                             groupBegin[c + 1] - groupBegin[c], scratch, result[i - first]);
        }
      },
      [&](std::vector<ComponentObjects>& result) {
        for (ComponentObjects& component : result) {
          std::vector<Segment>& objects = component.segments;
          for (std::size_t i = 0; i < objects.size(); ++i) {
            Segment& seg = objects[i];
            seg.number = static_cast<std::int32_t>(++perLevel[seg.level - 1]);
            const std::int32_t p = component.parentIndex[i];
            seg.parentNumber = p < 0 ? 0 : objects[p].number;
          }
          sink(objects);
        }
      });
  return perLevel;
}

SegmentationRuns::SegmentationRuns(std::int64_t width, std::int64_t height, int levelCount)
    : width_(width), height_(height), levels_(std::max(levelCount, 0)) {}

void SegmentationRuns::add(const std::vector<Segment>& objects) {
  std::vector<std::int64_t> sorted;
  for (const Segment& seg : objects) {
    if (seg.level < 1 || seg.level > levelCount()) {
      throw ConfigError("segmentation: object " + std::to_string(seg.number) + " has level " +
                        std::to_string(seg.level) + " outside 1.." + std::to_string(levelCount()));
    }
    const std::vector<std::int64_t>* pixels = &seg.pixels;
    if (!std::is_sorted(seg.pixels.begin(), seg.pixels.end())) {
      sorted = seg.pixels;
      std::sort(sorted.begin(), sorted.end());
      pixels = &sorted;
    }
    std::vector<Run>& runs = levels_[seg.level - 1];
    if (seg.pixels.empty()) {
      for (const PixelRun& r : seg.runs) {
        runs.push_back({r.y, r.x0, static_cast<std::int32_t>(r.length()), seg.number});
      }
      continue;
    }
    for (std::size_t i = 0; i < pixels->size();) {
      const std::int64_t start = (*pixels)[i];
      const std::int64_t y = start / width_;
      const std::int64_t rowEnd = (y + 1) * width_;
      std::size_t j = i + 1;
      while (j < pixels->size() && (*pixels)[j] == (*pixels)[j - 1] + 1 && (*pixels)[j] < rowEnd) {
        ++j;
      }
      runs.push_back({static_cast<std::int32_t>(y), static_cast<std::int32_t>(start - y * width_),
                      static_cast<std::int32_t>(j - i), seg.number});
      i = j;
    }
  }
}

void SegmentationRuns::render(int level, ImageI32& labels) const {
  if (level < 1 || level > levelCount()) {
    throw ConfigError("segmentation: level " + std::to_string(level) + " outside 1.." +
                      std::to_string(levelCount()));
  }
  if (labels.width() != width_ || labels.height() != height_) {
    labels = ImageI32(width_, height_, 0);
  } else {
    std::fill(labels.pixels().begin(), labels.pixels().end(), 0);
  }
  for (const Run& run : levels_[level - 1]) {
    std::int32_t* row = labels.data() + static_cast<std::int64_t>(run.y) * width_ + run.x0;
    std::fill(row, row + run.length, run.number);
  }
}

std::vector<std::vector<PixelRun>> SegmentationRuns::footprints(
    int level, const std::vector<std::int32_t>& numbers) const {
  std::vector<std::vector<PixelRun>> out(numbers.size());
  if (level < 1 || level > levelCount()) return out;
  std::unordered_map<std::int32_t, std::size_t> slot;
  for (std::size_t i = 0; i < numbers.size(); ++i) slot.emplace(numbers[i], i);
  for (const Run& run : levels_[level - 1]) {
    const auto found = slot.find(run.number);
    if (found != slot.end()) out[found->second].push_back({run.y, run.x0, run.x0 + run.length - 1});
  }
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    if (const auto first = slot.find(numbers[i]); first->second != i) out[i] = out[first->second];
    std::sort(out[i].begin(), out[i].end(), [](const PixelRun& a, const PixelRun& b) {
      return a.y != b.y ? a.y < b.y : a.x0 < b.x0;
    });
  }
  return out;
}

std::size_t SegmentationRuns::runCount(int level) const {
  return level >= 1 && level <= levelCount() ? levels_[level - 1].size() : 0;
}

}  // namespace octarc
