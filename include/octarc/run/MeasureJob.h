// `octarc measure` as one library call: the measurement run of a configured image on SExtractor's
// segmentation check-images (run/MeasurementRun.h), written. The settings are checked and the
// outputs named before anything is read; the catalog(s) (each INPUT_CATALOG with octarc's
// columns appended, APPEND_COLUMNS Y, or one new catalog of every level) and the XML run summary
// (WRITE_XML) then appear together or not at all (core/AtomicFile.h). `octarc measure` calls it
// for its image, `octarc batch -TASK MEASURE` for each tile.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/AtomicFile.h"
#include "octarc/run/DetectionRun.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"

namespace octarc {

// What the XML run summary (WRITE_XML) records of the command that started the run.
struct MeasureJobFacts {
  std::string commandLine;            // as typed, e.g. "octarc measure a.fits -c x.sex"
  std::vector<std::string> warnings;  // the configuration's warnings
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
};

struct MeasureJobReport {
  std::vector<std::string> catalogPaths;  // the catalogs written (none for CATALOG_TYPE NONE)
  std::int64_t catalogRows = 0;           // their rows, over every catalog and extension
};

// Runs `settings` (one image in imagePaths, SEGMENTATION_NAME, optionally INPUT_CATALOG) and
// writes its outputs. `config` is the loaded configuration the settings come from (its ASSOC
// keys, whether CATALOG_TYPE was given, the XML summary's values). Warnings ("WARNING: ...")
// and a "> Wrote PATH" line per output go to `log` (none when empty). ConfigError / IoError
// naming the file for bad settings or input; nothing is then written.
MeasureJobReport runMeasureJob(const RunSettings& settings, const sexcompat::Config& config,
                               const MeasureJobFacts& facts, const RunLog& log);

// WRITE_XML: registers XML_NAME with `outputs` (after the run's other outputs), refusing it over
// any of `inputs`; returns its index, or -1 without WRITE_XML.
int addXmlOutput(const RunSettings& settings, OutputFiles& outputs,
                 const std::vector<NamedInput>& inputs);

}  // namespace octarc
