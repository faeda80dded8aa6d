#include "octarc/measure/Registry.h"

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include "octarc/measure/plugins/Footprint.h"
#include "octarc/measure/plugins/Identity.h"
#include "octarc/measure/plugins/IsophotalPhotometry.h"
#include "octarc/measure/plugins/IsophotalShape.h"
#include "octarc/measure/plugins/Octopole.h"
#include "octarc/measure/plugins/QualityFlags.h"
#include "octarc/measure/plugins/WorldCoordinates.h"

namespace octarc {

std::vector<std::unique_ptr<Measurement>> builtinMeasurements() {
  std::vector<std::unique_ptr<Measurement>> list;
  list.push_back(std::make_unique<Identity>());
  list.push_back(std::make_unique<Footprint>());
  list.push_back(std::make_unique<IsophotalShape>());
  list.push_back(std::make_unique<IsophotalPhotometry>());
  list.push_back(std::make_unique<WorldCoordinates>());
  list.push_back(std::make_unique<Octopole>());
  list.push_back(std::make_unique<QualityFlags>());  // last: collects the flags of the others
  return list;
}

std::vector<ColumnSpec> allBuiltinColumns() {
  std::vector<ColumnSpec> all;
  for (const auto& m : builtinMeasurements()) {
    for (OutputColumn& c : m->columns()) all.push_back(std::move(c.spec));
  }
  return all;
}

MeasurementPlan MeasurementPlan::build(const std::vector<ColumnRequest>& requested,
                                       const std::vector<ColumnSpec>& external,
                                       std::vector<std::string>* unknown) {
  std::vector<std::shared_ptr<const Measurement>> all;
  for (auto& m : builtinMeasurements()) all.emplace_back(std::move(m));

  // Column name -> (measurement index, column index); measurement name -> index.
  std::map<std::string, std::pair<std::size_t, int>> provider;
  std::map<std::string, std::size_t> byName;
  std::vector<std::vector<OutputColumn>> outputs(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    byName[all[i]->name()] = i;
    outputs[i] = all[i]->columns();
    for (int c = 0; c < int(outputs[i].size()); ++c) {
      if (outputs[i][c].spec.repeat != 1 || outputs[i][c].value == nullptr) {
        throw std::logic_error(all[i]->name() + ": column " + outputs[i][c].spec.name +
                               " must be a scalar with a value");
      }
      provider.emplace(outputs[i][c].spec.name, std::pair{i, c});
    }
  }

  MeasurementPlan plan;
  std::vector<std::vector<Fill>> fills(all.size());
  std::set<std::string> seen;
  std::vector<bool> needed(all.size(), false);
  for (const ColumnRequest& request : requested) {
    if (!seen.insert(request.name).second) continue;  // duplicates are ignored, as in SExtractor
    if (auto it = provider.find(request.name); it != provider.end()) {
      const auto [m, c] = it->second;
      fills[m].push_back({outputs[m][c].value, plan.rowWidth_});
      plan.rowWidth_ += 1;
      plan.columns_.push_back(outputs[m][c].spec);
      needed[m] = true;
      continue;
    }
    auto ext = std::find_if(external.begin(), external.end(),
                            [&](const ColumnSpec& s) { return s.name == request.name; });
    if (ext != external.end()) {
      ColumnSpec spec = *ext;
      spec.repeat = std::max(1, request.repeat);  // the .param line sizes vectors
      plan.rowWidth_ += spec.repeat;
      plan.columns_.push_back(std::move(spec));
      continue;
    }
    if (unknown) unknown->push_back(request.name);
  }

  // Depth-first dependency order; registration order breaks ties.
  std::vector<int> mark(all.size(), 0);  // 0 = new, 1 = in progress, 2 = done
  std::function<void(std::size_t)> visit = [&](std::size_t i) {
    if (mark[i] == 2) return;
    if (mark[i] == 1) throw std::logic_error("measurement dependency cycle at " + all[i]->name());
    mark[i] = 1;
    for (const std::string& dep : all[i]->dependencies()) {
      auto it = byName.find(dep);
      if (it == byName.end()) {
        throw std::logic_error(all[i]->name() + " depends on unknown measurement " + dep);
      }
      visit(it->second);
    }
    mark[i] = 2;
    plan.steps_.push_back({all[i], fills[i]});
  };
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (needed[i]) visit(i);
  }
  return plan;
}

std::vector<std::string> MeasurementPlan::measurementNames() const {
  std::vector<std::string> names;
  for (const Step& s : steps_) names.push_back(s.measurement->name());
  return names;
}

void MeasurementPlan::measure(const Segment& segment, const MeasureContext& context,
                              double* row) const {
  // One gathering buffer per thread, reused from object to object.
  thread_local ObjectPixels pixels;
  pixels.gather(segment, context);
  ObjectState state;
  state.pixels = &pixels;
  const MeasuredObject object{segment, context, state};
  // Each step's columns are read right after it ran, before later steps add to the state.
  for (const Step& step : steps_) {
    step.measurement->measure(segment, context, state);
    for (const Fill& fill : step.fills) row[fill.offset] = fill.value(object);
  }
}

}  // namespace octarc
