// Hand-made simulate-lenses outputs for the calibration tests: a systems table of float64
// columns filled with the rows a test gives.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "octarc/calibration/SimulationOutput.h"
#include "octarc/core/Table.h"

namespace octarc::test {

inline ColumnSpec column(const char* name) {
  ColumnSpec c;
  c.name = name;
  c.type = ColumnType::Float64;
  return c;
}

// A simulation whose systems table has the columns `names` and one row per entry of `rows`, of
// `drawn` systems drawn from the population (OCTNSYS).
template <std::size_t N>
SimulationOutput simulationOf(const std::array<const char*, N>& names,
                              const std::vector<std::array<double, N>>& rows, std::int64_t drawn) {
  SimulationOutput sim;
  sim.path = "handful.fits";
  std::vector<ColumnSpec> columns;
  for (const char* name : names) columns.push_back(column(name));
  sim.systems = Table(columns);
  for (const auto& r : rows) std::copy(r.begin(), r.end(), sim.systems.appendRow());
  sim.setup.systems = drawn;
  return sim;
}

// A simulation of `rows` systems on the default grid axes: (ARC_FOUND, ARCNESS, ANTIARCNESS,
// SKEW_MAJOR, SKEW_MINOR, E_IMAGE, SNR_ISO, SIM_WEIGHT).
inline SimulationOutput handfulSimulation(const std::vector<std::array<double, 8>>& rows,
                                          std::int64_t drawn) {
  return simulationOf<8>({"ARC_FOUND", "ARCNESS", "ANTIARCNESS", "SKEW_MAJOR", "SKEW_MINOR",
                          "E_IMAGE", "SNR_ISO", "SIM_WEIGHT"},
                         rows, drawn);
}

}  // namespace octarc::test
