// The octarc commands, each one readable top to bottom as the data flow it runs:
// read image -> background/noise -> segmentation (read or detect) -> measure -> catalog.
#pragma once

#include <string>
#include <vector>

namespace octarc {

// `octarc measure IMAGE [-c file.sex] [-KEY value ...]`: measures the objects of external
// SExtractor segmentation check-images (one per threshold). Returns the process exit code.
int runMeasure(const std::vector<std::string>& args);

// `octarc detect IMAGE [-c file.sex] [-KEY value ...]`: detects at every threshold in one pass
// and measures every object of every level. Returns the process exit code.
int runDetect(const std::vector<std::string>& args);

}  // namespace octarc
