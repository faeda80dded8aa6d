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
// the measurements at the survey thresholds (src/app/SimulateLensesCommand.cpp).
int runSimulateLenses(const std::vector<std::string>& args);

// `octarc simulate field ...`: a survey-like image with injected lenses, its weight map and a
// truth list (src/app/SimulateFieldCommand.cpp).
int runSimulateField(const std::vector<std::string>& args);

// `octarc simulate database ...`: a source-galaxy database in RealGalaxyCatalog format cut out
// of a deep image (src/app/SimulateDatabaseCommand.cpp).
int runBuildDatabase(const std::vector<std::string>& args);

// `octarc calibrate SIM.fits ...`: the studies of simulated lenses and the occupation grid of
// their arcs (src/app/CalibrateCommand.cpp).
int runCalibrate(const std::vector<std::string>& args);

// `octarc search IMAGE`: lens candidates with stamps and a vetting page
// (src/app/SearchCommand.cpp).
int runSearch(const std::vector<std::string>& args);
int runBatch(const std::vector<std::string>& args);

// `octarc demo`: simulate a field with lenses, detect, measure, and report
// (src/app/DemoCommand.cpp).
int runDemo(const std::vector<std::string>& args);

// `octarc inject IMAGE`: completeness against spurious candidates per deg2 of the search on
// the user's image, by injected lenses (src/app/InjectCommand.cpp).
int runInject(const std::vector<std::string>& args);

// `octarc grades CATALOG GRADES.csv -o OUT`: a vetting page's grades merged into a copy of the
// candidate catalog as a GRADE column (src/app/GradesCommand.cpp).
int runGrades(const std::vector<std::string>& args);

}  // namespace octarc
