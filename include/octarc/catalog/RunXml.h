// SExtractor's XML run summary (WRITE_XML Y, XML_NAME): a VOTable 1.1 laid out as
// source-extractor 2.25 writes it. One RESOURCE named after the image holds the table
// "Source_List" (the catalog's columns as FIELDs, no rows) and the RESOURCE "MetaData": the
// software, date, duration and image, the table "Extension_Data" (one row per image extension:
// counts, background, threshold, pixel scale, gain...), the table "Warnings" and the RESOURCE
// "Config" (the command line, the configuration file and every key's value).
#pragma once

#include <string>
#include <vector>

#include "octarc/catalog/RunSummary.h"
#include "octarc/core/Column.h"

namespace octarc {

// One configuration key as a PARAM of the "Config" resource.
struct XmlConfigValue {
  enum class Kind { Bool, Int, Float, Text };
  std::string key;  // upper case, e.g. "DETECT_MINAREA"; named as SExtractor names it
  Kind kind = Kind::Text;
  std::vector<std::string> values;  // canonical text (booleans "Y"/"N")
};

struct XmlWarning {
  std::string date, time;  // yyyy-mm-dd, hh:mm:ss
  std::string message;
};

struct RunXml {
  std::string xslUrl;     // XSL_URL: the style sheet named in the prologue
  std::string imageName;  // the image(s) as given ("a.fits" or "a.fits,b.fits")
  std::vector<ColumnSpec> columns;
  std::string version;     // e.g. "0.1.0"
  std::string date, time;  // end of the run, yyyy-mm-dd and hh:mm:ss (UTC)
  double durationSec = 0.0;
  int threads = 1;
  std::string user, host, path;           // who ran it, where, and the working directory
  std::vector<RunSummary> extensions;     // one per image extension, in order
  std::vector<std::int64_t> levelCounts;  // thresholds per extension (octarc's own field)
  std::vector<XmlWarning> warnings;
  std::string commandLine;  // as typed (arguments joined by blanks)
  std::string configFile;   // -c file, "" for none
  std::vector<XmlConfigValue> config;
};

// The XML text. Every value is escaped; non-finite numbers are written as NaN.
std::string formatRunXml(const RunXml& run);

// XML text or a double-quoted attribute value: &, <, >, " and ' escaped, and the control
// characters XML 1.0 cannot hold (all but tab, newline, carriage return) replaced by '?'.
std::string xmlEscaped(const std::string& text);

// A catalog unit ("pixel**(-2)", "deg**2", "count") in the VO spelling SExtractor's XML uses
// ("pix-2", "deg2", "ct").
std::string votableUnit(const std::string& catalogUnit);

// The VOTable datatype of a column's storage type: "short", "int", "long", "float", "double".
const char* votableDatatype(ColumnType type);

// The current date and time in UTC, as the XML writes them: {"yyyy-mm-dd", "hh:mm:ss"}.
std::vector<std::string> xmlDateTimeNow();

}  // namespace octarc
