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

// `octarc simulate lenses ...`: simulated galaxy-galaxy lenses pushed through the detector and
// the measurements at the survey thresholds (src/pipeline/SimulateLenses.cpp).
int runSimulateLenses(const std::vector<std::string>& args);

// `octarc simulate field ...`: a survey-like image with injected lenses, its weight map and a
// truth list (src/pipeline/SimulateField.cpp).
int runSimulateField(const std::vector<std::string>& args);

// `octarc simulate database ...`: a source-galaxy database in RealGalaxyCatalog format cut out
// of a deep image (src/pipeline/BuildDatabase.cpp).
int runBuildDatabase(const std::vector<std::string>& args);

// `octarc demo`: simulate a field with lenses, detect, measure, and report (src/pipeline/Demo.cpp).
int runDemo(const std::vector<std::string>& args);

}  // namespace octarc
