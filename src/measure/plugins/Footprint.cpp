#include "octarc/measure/plugins/Footprint.h"

#include <algorithm>

#include "octarc/core/Flags.h"

namespace octarc {

std::vector<OutputColumn> Footprint::columns() const {
  // Bounds are 1-based, as SExtractor writes them; 0 for an empty footprint.
  return {
      {{"XMIN_IMAGE", "Minimum x-coordinate among detected pixels", "pixel",
        "pos.cartesian.x;stat.min", ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) {
         return o.state.haveFootprint ? double(o.state.xMin) + 1.0 : 0.0;
       }},
      {{"YMIN_IMAGE", "Minimum y-coordinate among detected pixels", "pixel",
        "pos.cartesian.y;stat.min", ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) {
         return o.state.haveFootprint ? double(o.state.yMin) + 1.0 : 0.0;
       }},
      {{"XMAX_IMAGE", "Maximum x-coordinate among detected pixels", "pixel",
        "pos.cartesian.x;stat.max", ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) {
         return o.state.haveFootprint ? double(o.state.xMax) + 1.0 : 0.0;
       }},
      {{"YMAX_IMAGE", "Maximum y-coordinate among detected pixels", "pixel",
        "pos.cartesian.y;stat.max", ColumnType::Int32, "%10d"},
       [](const MeasuredObject& o) {
         return o.state.haveFootprint ? double(o.state.yMax) + 1.0 : 0.0;
       }},
      {{"ISOAREAF_IMAGE", "Isophotal area (filtered) above Detection threshold", "pixel**2",
        "phys.area", ColumnType::Int32, "%9d"},
       [](const MeasuredObject& o) { return double(o.state.footprintPixels); }},
      {{"FLAGS", "Extraction flags", "", "meta.code.qual", ColumnType::Int16, "%3d"},
       [](const MeasuredObject& o) { return double(o.state.sexFlags); }},
  };
}

void Footprint::measure(const Segment& segment, const MeasureContext& context,
                        ObjectState& state) const {
  const ImageF& image = *context.measurement;
  const std::int64_t width = image.width();
  const ObjectPixels& pixels = *state.pixels;
  double xMinPix = double(width), xMaxPix = -1.0, yMinPix = double(image.height()), yMaxPix = -1.0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    xMinPix = std::min(xMinPix, pixels.x[i]);
    xMaxPix = std::max(xMaxPix, pixels.x[i]);
    yMinPix = std::min(yMinPix, pixels.y[i]);
    yMaxPix = std::max(yMaxPix, pixels.y[i]);
  }
  const auto xMin = std::int64_t(xMinPix), xMax = std::int64_t(xMaxPix);
  const auto yMin = std::int64_t(yMinPix), yMax = std::int64_t(yMaxPix);
  bool saturated = false;
  if (context.saturatedPixels != nullptr && !context.saturatedPixels->empty()) {
    const std::vector<std::int64_t>& sat = *context.saturatedPixels;
    if (segment.pixels.empty()) {
      // A run holds a saturated pixel when the first saturated index at or after its start
      // is not beyond its end.
      for (const PixelRun& r : segment.runs) {
        const std::int64_t first = std::int64_t(r.y) * width + r.x0;
        const auto it = std::lower_bound(sat.begin(), sat.end(), first);
        if (it != sat.end() && *it < first + r.length()) {
          saturated = true;
          break;
        }
      }
    } else {
      for (const std::int64_t p : segment.pixels) {
        if (std::binary_search(sat.begin(), sat.end(), p)) {
          saturated = true;
          break;
        }
      }
    }
  }
  state.footprintPixels = static_cast<std::int64_t>(pixels.size());
  if (pixels.size() == 0) return;
  state.haveFootprint = true;
  state.xMin = xMin;
  state.xMax = xMax;
  state.yMin = yMin;
  state.yMax = yMax;
  if (saturated) state.sexFlags |= sexflag::kSaturated;
  if (xMin == 0 || yMin == 0 || xMax == width - 1 || yMax == image.height() - 1) {
    state.sexFlags |= sexflag::kTouchesBorder;
  }
}

}  // namespace octarc
