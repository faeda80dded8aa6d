#include "octarc/catalog/RunXml.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>

#include "octarc/core/Format.h"

namespace octarc {

namespace {

// The name, UCD and unit source-extractor 2.25 gives each configuration key in its XML (keys it
// does not write are named by capitalising each word).
struct KeyName {
  const char* key;
  const char* name;
  const char* ucd;
  const char* unit;
};

// clang-format off
constexpr KeyName kKeyNames[] = {
    {"CATALOG_TYPE", "Catalog_Type", "meta.code;meta.table", ""},
    {"CATALOG_NAME", "Catalog_Name", "meta;meta.table;meta.file", ""},
    {"PARAMETERS_NAME", "Parameters_Name", "meta;obs.param", ""},
    {"DETECT_TYPE", "Detect_Type", "meta.code;obs.param;instr.det", ""},
    {"DETECT_MINAREA", "Detect_MinArea", "obs.param;phys.area;stat.min", "pix"},
    {"DETECT_MAXAREA", "Detect_MaxArea", "obs.param;phys.area;stat.max", "pix"},
    {"THRESH_TYPE", "Thresh_Type", "meta.code;obs.param;instr.sensitivity", ""},
    {"DETECT_THRESH", "Detect_Thresh", "obs.param;instr.sensitivity", ""},
    {"ANALYSIS_THRESH", "Analysis_Thresh", "obs.param;instr.sensitivity", ""},
    {"FILTER", "Filter", "meta.code;obs.param", ""},
    {"FILTER_NAME", "Filter_Name", "obs.param;meta.file", ""},
    {"FILTER_THRESH", "Filter_Thresh", "obs.param", ""},
    {"DEBLEND_NTHRESH", "Deblend_NThresh", "meta.number;obs.param", ""},
    {"DEBLEND_MINCONT", "Deblend_MinCont", "obs.param;arith.ratio", ""},
    {"CLEAN", "Clean", "meta.code;obs.param", ""},
    {"CLEAN_PARAM", "Clean_Param", "obs.param;arith.ratio", ""},
    {"MASK_TYPE", "Mask_Type", "meta.code;obs.param", ""},
    {"WEIGHT_TYPE", "Weight_Type", "meta.code;obs.param", ""},
    {"RESCALE_WEIGHTS", "Rescale_Weights", "meta.code;obs.param", ""},
    {"WEIGHT_THRESH", "Weight_Thresh", "obs.param", ""},
    {"WEIGHT_IMAGE", "Weight_Image", "stat.weight;meta.file;meta.fits", ""},
    {"WEIGHT_GAIN", "Weight_Gain", "meta.code;obs.param", ""},
    {"FLAG_IMAGE", "Flag_Image", "meta.code;meta.file;meta.fits", ""},
    {"FLAG_TYPE", "Flag_Type", "meta.code;obs.param", ""},
    {"PHOT_APERTURES", "Phot_Apertures", "obs.param;phys.size.diameter", "pix"},
    {"PHOT_AUTOPARAMS", "Phot_AutoParams", "meta.code;obs.param", ""},
    {"PHOT_PETROPARAMS", "Phot_PetroParams", "meta.code;obs.param", ""},
    {"PHOT_AUTOAPERS", "Phot_AutoApers", "obs.param;phys.size.diameter", "pix"},
    {"PHOT_FLUXFRAC", "Phot_FluxFrac", "obs.param;arith.ratio", ""},
    {"SATUR_LEVEL", "Satur_Level", "obs.param;instr.saturation", "ct"},
    {"GAIN", "Gain", "obs.param;instr.param", ""},
    {"PIXEL_SCALE", "Pixel_Scale", "obs.param;instr.scale", "arcsec/pix"},
    {"XSL_URL", "XSL_URL", "meta.ref.url;meta.file", ""},
    {"SATUR_KEY", "Satur_Key", "meta.code;obs.param;instr.saturation", ""},
    {"MAG_ZEROPOINT", "Mag_ZeroPoint", "obs.param;phot.calib;phot.mag", "mag"},
    {"MAG_GAMMA", "Mag_Gamma", "obs.param;phot.calib;instr.plate.emulsion", ""},
    {"GAIN_KEY", "Gain_Key", "meta.code;obs.param;instr.param", ""},
    {"SEEING_FWHM", "Seeing_FWHM", "obs.param;instr.obsty.seeing", "arcsec"},
    {"STARNNW_NAME", "StarNNW_Name", "obs.param;meta.dataset;meta.file", ""},
    {"BACK_TYPE", "Back_Type", "meta.code;obs.param", ""},
    {"BACK_VALUE", "Back_Value", "obs.param", "ct"},
    {"BACK_SIZE", "Back_Size", "obs.param", "pix"},
    {"BACK_FILTERSIZE", "Back_FilterSize", "obs.param", ""},
    {"BACKPHOTO_TYPE", "BackPhoto_Type", "meta.code;obs.param", ""},
    {"BACKPHOTO_THICK", "BackPhoto_Thick", "obs.param", "pix"},
    {"BACK_FILTTHRESH", "Back_FiltThresh", "obs.param", "ct"},
    {"CHECKIMAGE_TYPE", "CheckImage_Type", "meta.code;obs.param", ""},
    {"CHECKIMAGE_NAME", "CheckImage_Name", "meta.id;meta.file;meta.fits", ""},
    {"MEMORY_OBJSTACK", "Memory_ObjStack", "meta.number;src;obs.param", ""},
    {"MEMORY_PIXSTACK", "Memory_PixStack", "meta.number;obs.param", "pix"},
    {"MEMORY_BUFSIZE", "Memory_BufSize", "meta.number;obs.param", "pix"},
    {"ASSOC_NAME", "Assoc_Name", "meta;meta.table;meta.file", ""},
    {"ASSOC_DATA", "Assoc_Data", "meta;meta.table", ""},
    {"ASSOC_PARAMS", "Assoc_Params", "meta;meta.table", ""},
    {"ASSOCCOORD_TYPE", "AssocCoord_Type", "meta.code", ""},
    {"ASSOC_RADIUS", "Assoc_Radius", "meta;phys.size.radius", "pix"},
    {"ASSOC_TYPE", "Assoc_Type", "meta.code", ""},
    {"ASSOCSELEC_TYPE", "AssocSelec_Type", "meta.code", ""},
    {"VERBOSE_TYPE", "Verbose_Type", "meta.code", ""},
    {"HEADER_SUFFIX", "Header_Suffix", "meta.id;meta.file", ""},
    {"WRITE_XML", "Write_XML", "meta.code", ""},
    {"XML_NAME", "XML_Name", "meta;meta.file", ""},
    {"NTHREADS", "NThreads", "meta.number", ""},
    {"FITS_UNSIGNED", "FITS_Unsigned", "meta.code;obs.param", ""},
    {"PSF_NAME", "PSF_Name", "instr.det.psf;meta.file;meta.fits", ""},
};
// clang-format on

const KeyName* findKey(const std::string& key) {
  for (const KeyName& k : kKeyNames) {
    if (key == k.key) return &k;
  }
  return nullptr;
}

// DETECT_NLEVELS -> Detect_Nlevels.
std::string capitalised(const std::string& key) {
  std::string out = key;
  bool first = true;
  for (char& c : out) {
    if (c == '_') {
      first = true;
      continue;
    }
    c = first ? c : char(std::tolower(static_cast<unsigned char>(c)));
    first = false;
  }
  return out;
}

// XML text and double-quoted attributes: the HTML escapes (core/Format.h), and '?' for the
// control characters XML 1.0 cannot hold (all but tab, newline and carriage return).
std::string escape(const std::string& text) {
  std::string out = escapeHtml(text);
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r') c = '?';
  }
  return out;
}

std::string number(double v) {
  if (!std::isfinite(v)) return "NaN";
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", v);
  return text;
}

const char* datatype(ColumnType type) {
  switch (type) {
    case ColumnType::Int16:
      return "short";
    case ColumnType::Int32:
      return "int";
    case ColumnType::Int64:
      return "long";
    case ColumnType::Float64:
      return "double";
    default:
      return "float";
  }
}

// A catalog unit ("pixel**(-2)", "deg**2", "count") in the spelling SExtractor's XML uses
// ("pix-2", "deg2", "ct"): its units abbreviated, powers written after the unit.
std::string voUnit(const std::string& unit) {
  std::string out;
  for (std::size_t i = 0; i < unit.size();) {
    if (unit.compare(i, 5, "pixel") == 0) {
      out += "pix";
      i += 5;
    } else if (unit.compare(i, 5, "count") == 0) {
      out += "ct";
      i += 5;
    } else if (unit.compare(i, 2, "**") == 0) {
      i += 2;
    } else if (unit[i] == '(' || unit[i] == ')') {
      ++i;
    } else {
      out += unit[i++];
    }
  }
  return out;
}

void param(std::ostringstream& out, const char* indent, const std::string& name,
           const std::string& type, const std::string& ucd, const std::string& value,
           const std::string& unit = "", const std::string& arraysize = "") {
  out << indent << "<PARAM name=\"" << escape(name) << "\"";
  if (!unit.empty()) out << " unit=\"" << escape(unit) << "\"";
  out << " datatype=\"" << type << "\"";
  if (!arraysize.empty()) out << " arraysize=\"" << arraysize << "\"";
  if (!ucd.empty()) out << " ucd=\"" << escape(ucd) << "\"";
  out << " value=\"" << escape(value) << "\"/>\n";
}

void configParam(std::ostringstream& out, const XmlConfigValue& v) {
  const KeyName* known = findKey(v.key);
  const std::string name = known ? known->name : capitalised(v.key);
  const std::string ucd = known ? known->ucd : "obs.param";
  const std::string unit = known ? known->unit : "";
  using Kind = XmlConfigValue::Kind;
  // Numbers and flags as SExtractor writes them: blank-separated, arraysize the count. A key
  // with no value (an empty list) is written as empty text.
  if (v.kind == Kind::Text || v.values.empty()) {
    std::string joined;
    for (std::size_t i = 0; i < v.values.size(); ++i) joined += (i ? "," : "") + v.values[i];
    param(out, "   ", name, "char", ucd, joined, "", "*");
    return;
  }
  std::string joined;
  for (std::size_t i = 0; i < v.values.size(); ++i) {
    const std::string& t = v.values[i];
    joined += (i ? " " : "") + (v.kind == Kind::Bool ? std::string(t == "Y" ? "T" : "F") : t);
  }
  const char* type = v.kind == Kind::Bool ? "boolean" : v.kind == Kind::Int ? "int" : "double";
  param(out, "   ", name, type, ucd, joined, unit,
        v.values.size() > 1 ? std::to_string(v.values.size()) : "");
}

}  // namespace

std::string xmlEscaped(const std::string& text) {
  return escape(text);
}

std::string votableUnit(const std::string& catalogUnit) {
  return voUnit(catalogUnit);
}

const char* votableDatatype(ColumnType type) {
  return datatype(type);
}

std::vector<std::string> xmlDateTimeNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char date[16], time[16];
  std::strftime(date, sizeof date, "%Y-%m-%d", &utc);
  std::strftime(time, sizeof time, "%H:%M:%S", &utc);
  return {date, time};
}

std::string formatRunXml(const RunXml& r) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  if (!r.xslUrl.empty()) {
    out << "<?xml-stylesheet type=\"text/xsl\" href=\"" << escape(r.xslUrl) << "\"?>\n";
  }
  // SExtractor's root element, with the VOTable namespace it leaves out (astropy warns of it).
  out << "<VOTABLE version=\"1.1\" xmlns=\"http://www.ivoa.net/xml/VOTable/v1.1\" "
         "xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" "
         "xsi:noNamespaceSchemaLocation=\"http://www.ivoa.net/xml/VOTable/v1.1\">\n"
      << "<DESCRIPTION>produced by octarc</DESCRIPTION>\n"
      << "<!-- VOTable description at http://www.ivoa.net/Documents/latest/VOT.html -->\n"
      << "<RESOURCE ID=\"octarc\" name=\"" << escape(r.imageName) << "\">\n"
      << " <DESCRIPTION>Catalog of sources extracted with octarc</DESCRIPTION>\n"
      << " <INFO name=\"QUERY_STATUS\" value=\"OK\" />\n"
      << " <COOSYS ID=\"J2000\" equinox=\"J2000\" epoch=\"J2000\" system=\"ICRS\"/>\n"
      << " <TABLE ID=\"Source_List\" name=\"" << escape(r.imageName) << "/out\">\n"
      << "  <DESCRIPTION>Table of sources detected in image</DESCRIPTION>\n";
  for (const ColumnSpec& c : r.columns) {
    out << "  <FIELD name=\"" << escape(c.name) << "\"";
    if (!c.ucd.empty()) out << " ucd=\"" << escape(c.ucd) << "\"";
    out << " datatype=\"" << datatype(c.type) << "\"";
    if (c.repeat > 1) out << " arraysize=\"" << c.repeat << "\"";
    out << " unit=\"" << escape(voUnit(c.unit)) << "\">\n"
        << "   <DESCRIPTION>" << escape(c.description) << "</DESCRIPTION>\n"
        << "  </FIELD>\n";
  }
  out << "  <DATA><TABLEDATA>\n  </TABLEDATA></DATA>\n"
      << " </TABLE>\n"
      << " <RESOURCE ID=\"MetaData\" name=\"MetaData\">\n"
      << "  <DESCRIPTION>octarc meta-data</DESCRIPTION>\n"
      << "  <INFO name=\"QUERY_STATUS\" value=\"OK\" />\n";
  param(out, "  ", "Software", "char", "meta.title;meta.software", "octarc", "", "*");
  param(out, "  ", "Version", "char", "meta.version;meta.software", r.version, "", "*");
  param(out, "  ", "NThreads", "int", "meta.number;meta.software", std::to_string(r.threads));
  param(out, "  ", "Date", "char", "time.event.end;meta.software", r.date, "", "*");
  param(out, "  ", "Time", "char", "time.event.end;meta.software", r.time, "", "*");
  param(out, "  ", "Duration", "float", "time.event;meta.software", number(r.durationSec), "s");
  param(out, "  ", "User", "char", "meta.curation", r.user, "", "*");
  param(out, "  ", "Host", "char", "meta.curation", r.host, "", "*");
  param(out, "  ", "Path", "char", "meta.dataset", r.path, "", "*");
  param(out, "  ", "Image_Name", "char", "obs.image;meta.fits", r.imageName, "", "*");
  out << "  <TABLE ID=\"Extension_Data\" name=\"Extension_Data\">\n"
      << "   <DESCRIPTION>Data gathered by octarc for every FITS extension</DESCRIPTION>\n";
  param(out, "   ", "NExtensions", "int", "meta.number;meta.dataset",
        std::to_string(r.extensions.size()));
  param(out, "   ", "CurrExtension", "int", "meta.number;meta.dataset",
        std::to_string(r.extensions.size()));
  out << "   <FIELD name=\"Extension\" datatype=\"int\" ucd=\"meta.record\"/>\n"
         "   <FIELD name=\"External_Header\" datatype=\"boolean\" arraysize=\"1\" "
         "ucd=\"meta.code\"/>\n"
         "   <FIELD name=\"Date\" datatype=\"char\" arraysize=\"*\" "
         "ucd=\"meta.record;time.event.end\"/>\n"
         "   <FIELD name=\"Time\" datatype=\"char\" arraysize=\"*\" "
         "ucd=\"meta.record;time.event.end\"/>\n"
         "   <FIELD name=\"Duration\" datatype=\"float\" ucd=\"meta.record;time.event.end\" "
         "unit=\"s\"/>\n"
         "   <FIELD name=\"NDetect\" datatype=\"int\" ucd=\"meta.number;src.sample\"/>\n"
         "   <FIELD name=\"NSextracted\" datatype=\"int\" ucd=\"meta.number;src.sample\"/>\n"
         "   <FIELD name=\"NLevels\" datatype=\"int\" ucd=\"meta.number;obs.param\"/>\n"
         "   <FIELD name=\"Image_Ident\" datatype=\"char\" arraysize=\"*\" ucd=\"meta.id;obs\"/>\n"
         "   <FIELD name=\"Background_Mean\" datatype=\"float\" arraysize=\"1\" "
         "ucd=\"instr.skyLevel;obs.image;stat.median\" unit=\"ct\"/>\n"
         "   <FIELD name=\"Background_StDev\" datatype=\"float\" arraysize=\"1\" "
         "ucd=\"stat.stdev;obs.image;stat.median\" unit=\"ct\"/>\n"
         "   <FIELD name=\"Threshold\" datatype=\"float\" arraysize=\"1\" "
         "ucd=\"instr.sensitivity;obs.image;stat.median\" unit=\"ct\"/>\n"
         "   <FIELD name=\"Weight_Scaling\" datatype=\"float\" arraysize=\"1\" "
         "ucd=\"arith.factor;obs.image;stat.median\"/>\n"
         "   <FIELD name=\"Pixel_Scale\" datatype=\"float\" arraysize=\"1\" "
         "ucd=\"instr.scale;obs.image;stat.mean\" unit=\"arcsec\"/>\n"
         "   <FIELD name=\"Epoch\" datatype=\"float\" arraysize=\"1\" ucd=\"time.epoch;obs\" "
         "unit=\"yr\"/>\n"
         "   <FIELD name=\"Gain\" datatype=\"float\" arraysize=\"1\" "
         "ucd=\"instr.param;obs.param\"/>\n"
         "   <FIELD name=\"Satur_Level\" datatype=\"float\" arraysize=\"1\" "
         "ucd=\"instr.saturation;phot.count\" unit=\"ct\"/>\n"
         "   <DATA><TABLEDATA>\n";
  for (std::size_t i = 0; i < r.extensions.size(); ++i) {
    const RunSummary& e = r.extensions[i];
    const std::int64_t levels = i < r.levelCounts.size() ? r.levelCounts[i] : 1;
    out << "    <TR>\n     <TD>" << e.fitsExt << "</TD><TD>F</TD><TD>" << escape(e.date)
        << "</TD><TD>" << escape(e.time) << "</TD><TD>" << number(e.elapsedSec) << "</TD><TD>"
        << e.detections << "</TD><TD>" << e.finalObjects << "</TD><TD>" << levels
        << "</TD>\n     <TD>" << escape(e.object) << "</TD><TD>" << number(e.backgroundAdu)
        << "</TD><TD>" << number(e.backgroundRmsAdu) << "</TD><TD>" << number(e.thresholdAdu)
        << "</TD><TD>" << number(e.measureWeightScale) << "</TD><TD>" << number(e.pixelScaleArcsec)
        << "</TD><TD>" << number(e.epoch) << "</TD><TD>" << number(e.gainEPerAdu) << "</TD><TD>"
        << number(e.saturationAdu) << "</TD>\n    </TR>\n";
  }
  out << "   </TABLEDATA></DATA>\n"
      << "  </TABLE>\n"
      << "  <TABLE ID=\"Warnings\" name=\"Warnings\">\n"
      << "   <DESCRIPTION>octarc warnings</DESCRIPTION>\n"
      << "   <FIELD name=\"Date\" datatype=\"char\" arraysize=\"*\" "
         "ucd=\"meta;time.event.end\"/>\n"
      << "   <FIELD name=\"Time\" datatype=\"char\" arraysize=\"*\" "
         "ucd=\"meta;time.event.end\"/>\n"
      << "   <FIELD name=\"Msg\" datatype=\"char\" arraysize=\"*\" ucd=\"meta\"/>\n"
      << "   <DATA><TABLEDATA>\n";
  for (const XmlWarning& w : r.warnings) {
    out << "    <TR><TD>" << escape(w.date) << "</TD><TD>" << escape(w.time) << "</TD><TD>"
        << escape(w.message) << "</TD></TR>\n";
  }
  out << "   </TABLEDATA></DATA>\n"
      << "  </TABLE>\n"
      << "  <RESOURCE ID=\"Config\" name=\"Config\">\n"
      << "   <DESCRIPTION>octarc configuration</DESCRIPTION>\n";
  param(out, "   ", "Command_Line", "char", "obs.param", r.commandLine, "", "*");
  param(out, "   ", "Prefs_Name", "char", "obs.param;meta.file", r.configFile, "", "*");
  for (const XmlConfigValue& v : r.config) configParam(out, v);
  out << "  </RESOURCE>\n"
      << " </RESOURCE>\n"
      << "</RESOURCE>\n"
      << "</VOTABLE>\n";
  return out.str();
}

}  // namespace octarc
