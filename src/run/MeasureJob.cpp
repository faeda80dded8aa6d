#include "octarc/run/MeasureJob.h"

#include <optional>

#include "octarc/catalog/AppendedCatalog.h"
#include "octarc/catalog/Catalog.h"
#include "octarc/core/Error.h"
#include "octarc/run/CatalogAssembly.h"
#include "octarc/run/MeasurementRun.h"
#include "octarc/run/RunKeys.h"

namespace octarc {

int addXmlOutput(const RunSettings& s, OutputFiles& outputs,
                 const std::vector<NamedInput>& inputs) {
  if (!s.writeXml) return -1;
  const int index = int(outputs.size());
  outputs.add(s.xmlName);
  for (const NamedInput& in : inputs) refuseOutputOverInput(s.xmlName, "XML_NAME", in.path, in.key);
  return index;
}

MeasureJobReport runMeasureJob(const RunSettings& s, const sexcompat::Config& config,
                               const MeasureJobFacts& facts, const RunLog& log) {
  if (s.segmentationPaths.empty()) {
    throw ConfigError("SEGMENTATION_NAME is required: the SExtractor segmentation check-image(s)");
  }
  const std::size_t levelCount = s.segmentationPaths.size();
  const bool withCatalogs = !s.inputCatalogPaths.empty();
  const bool appendMode = withCatalogs && s.appendColumns;
  if (withCatalogs && s.inputCatalogPaths.size() != levelCount) {
    throw ConfigError("INPUT_CATALOG lists " + std::to_string(s.inputCatalogPaths.size()) +
                      " catalogs but SEGMENTATION_NAME has " + std::to_string(levelCount) +
                      " images: give one catalog per segmentation image");
  }
  if (appendMode && s.catalogNames.size() != levelCount) {
    throw ConfigError("CATALOG_NAME must list one output per INPUT_CATALOG (" +
                      std::to_string(levelCount) + ")");
  }
  if (!appendMode && s.catalogNames.size() != 1) {
    throw ConfigError("CATALOG_NAME must be one file name");
  }
  // Appending keeps each input catalog's own format; CATALOG_TYPE is for new catalogs.
  const CatalogType catalogType = parseCatalogType(s.catalogType);
  if (appendMode && config.isExplicit("CATALOG_TYPE") && log) {
    log("WARNING: CATALOG_TYPE " + s.catalogType +
        " is not used with APPEND_COLUMNS Y: each output keeps the format of its INPUT_CATALOG");
  }

  // Appended catalogs hold one level each; a new catalog holds every level.
  const ColumnPlan columns = planColumns(s, s.quiet, appendMode ? 1 : int(levelCount));
  std::optional<sexcompat::AssocSettings> assocSettings;
  if (columns.assoc) assocSettings = sexcompat::AssocSettings::fromConfig(config);
  if (appendMode && assocSettings && log &&
      assocSettings->selection != sexcompat::AssocSelection::All) {
    log("WARNING: ASSOCSELEC_TYPE " + config.getString("ASSOCSELEC_TYPE") +
        " does not remove rows with APPEND_COLUMNS Y: every row of the input catalogs is kept, "
        "with its VECTOR_ASSOC/NUMBER_ASSOC (APPEND_COLUMNS N selects rows)");
  }

  // The outputs, checked before anything is read; renamed into place together at the end.
  OutputFiles outputs;
  if (appendMode || catalogType != CatalogType::None) {
    for (const std::string& name : s.catalogNames) outputs.add(name);
  }
  const std::size_t catalogCount = outputs.size();
  const std::vector<NamedInput> inputs =
      runInputs(s, assocSettings ? assocSettings->listPath : std::string());
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (const NamedInput& in : inputs) {
      // Only with REPLACE_INPUT_CATALOG Y may an appended catalog take its own input's name.
      if (appendMode && s.replaceInputCatalog && in.key == "INPUT_CATALOG" &&
          in.path == s.inputCatalogPaths[i]) {
        continue;
      }
      refuseOutputOverInput(outputs[i].finalPath(), "CATALOG_NAME", in.path,
                            in.key == "INPUT_CATALOG" && appendMode
                                ? "INPUT_CATALOG (REPLACE_INPUT_CATALOG Y replaces it)"
                                : in.key);
    }
  }
  const int xmlOutput = addXmlOutput(s, outputs, inputs);

  // Every catalog and its run values are checked before any image is read.
  const InputCatalogs catalogs = readInputCatalogs(s);
  const MeasurementRunResult result = runMeasurement(s, columns, assocSettings, catalogs, log);
  MeasureJobReport report;
  if (appendMode) {
    for (std::size_t k = 0; k < levelCount; ++k) {
      const std::vector<AppendedColumns> appended = result.appendedColumns(k, columns, catalogs);
      outputs.write(k, [&](const std::string& path) {
        writeAppendedCatalog(s.inputCatalogPaths[k], catalogs.parts[k], path, appended);
      });
      for (const AppendedColumns& a : appended) report.catalogRows += std::int64_t(a.rows->size());
    }
  } else if (catalogType != CatalogType::None) {
    outputs.write(0, [&](const std::string& path) {
      writeCatalog(path, catalogType, result.parts(), result.fits10Cards);
    });
    for (const MeasuredExtension& x : result.extensions) report.catalogRows += x.table.rows();
  }
  if (xmlOutput >= 0) {
    XmlRunFacts xml;
    for (const MeasuredExtension& x : result.extensions) {
      xml.extensions.push_back(x.summary);
      xml.levelCounts.push_back(x.levelCount);
    }
    xml.commandLine = facts.commandLine;
    xml.warnings = facts.warnings;
    xml.durationSec =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - facts.start).count();
    outputs.write(std::size_t(xmlOutput), [&](const std::string& path) {
      writeTextFile(path, runXmlText(s, config, octarcKeys(), columns.outputColumns, xml));
    });
  }
  // Every output is complete: they appear together.
  outputs.commit();
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (i < catalogCount) report.catalogPaths.push_back(outputs[i].finalPath());
    if (log) log("> Wrote " + outputs[i].finalPath());
  }
  return report;
}

}  // namespace octarc
