#include "octarc/sexcompat/Keys.h"

#include <algorithm>
#include <string>

#include "octarc/sexcompat/KeyRow.h"

namespace octarc::sexcompat {
namespace {

using Kind = KeySpec::Kind;

constexpr double kBig = KeyRow::kBig;    // SExtractor's "BIG"
constexpr int kMaxList = 2048;           // longest list SExtractor accepts
constexpr int kMaxApertures = 32;        // MAG_APER / FLUX_RADIUS list length
constexpr int kMaxCheckImages = 17;      // CHECKIMAGE_TYPE / CHECKIMAGE_NAME
constexpr int kMaxFlagImages = 4;        // FLAG_IMAGE / FLAG_TYPE
constexpr int kMaxImages = 2;            // detection + measurement image
constexpr double kMaxPicSize = 1048576;  // largest image side

using Row = KeyRow;

std::vector<KeySpec> buildSextractorKeys() {
  // clang-format off
  return {
    // Catalog
    Row("CATALOG_NAME", Kind::String, {"test.cat"}, "output catalog file name"),
    Row("CATALOG_TYPE", Kind::Keyword, {"ASCII_HEAD"},
        "NONE, ASCII, ASCII_HEAD, ASCII_SKYCAT, ASCII_VOTABLE,\nFITS_1.0, FITS_LDAC or FITS_TPX")
        .keywords({"NONE", "ASCII", "ASCII_HEAD", "ASCII_SKYCAT", "ASCII_VOTABLE", "FITS_LDAC",
                   "FITS_TPX", "FITS_1.0"}),
    Row("PARAMETERS_NAME", Kind::String, {"default.param"}, "file listing the catalog columns"),
    // Extraction
    Row("DETECT_TYPE", Kind::Keyword, {"CCD"}, "CCD (linear response) or PHOTO (photographic)")
        .keywords({"CCD", "PHOTO"}).ignored(),
    Row("DETECT_MINAREA", Kind::Int, {"5"}, "smallest object, in pixels above the threshold")
        .range(1, 1e6),
    Row("DETECT_MAXAREA", Kind::Int, {"0"}, "largest object, in pixels (0 = no limit)")
        .range(0, 1e9).expert().ignored(),
    Row("THRESH_TYPE", Kind::Keyword, {"RELATIVE"},
        "RELATIVE (thresholds in units of the background sigma)\nor ABSOLUTE (in ADU)")
        .keywords({"RELATIVE", "ABSOLUTE"}).list(1, 2).expert(),
    Row("DETECT_THRESH", Kind::Float, {"1.5"}, "detection threshold, or <mu>,<ZP> in mag.arcsec-2")
        .list(1, 2),
    Row("ANALYSIS_THRESH", Kind::Float, {"1.5"}, "analysis threshold, or <mu>,<ZP> in mag.arcsec-2")
        .list(1, 2),
    Row("FILTER", Kind::Bool, {"Y"}, "filter the image before detection (Y/N)"),
    Row("FILTER_NAME", Kind::String, {"default.conv"}, "convolution mask (.conv file)"),
    Row("FILTER_THRESH", Kind::Float, {}, "thresholds of neural (retina) filters")
        .list(0, 2).expert().ignored(),
    Row("DEBLEND_NTHRESH", Kind::Int, {"32"}, "number of deblending sub-thresholds")
        .range(1, 64).ignored(),
    Row("DEBLEND_MINCONT", Kind::Float, {"0.005"}, "minimum contrast for deblending")
        .range(0, 1).ignored(),
    Row("CLEAN", Kind::Bool, {"Y"}, "remove spurious detections near bright objects (Y/N)")
        .ignored(),
    Row("CLEAN_PARAM", Kind::Float, {"1.0"}, "cleaning efficiency").range(0.1, 10).ignored(),
    Row("MASK_TYPE", Kind::Keyword, {"CORRECT"}, "masking of neighbours: NONE, BLANK or CORRECT")
        .keywords({"NONE", "BLANK", "CORRECT"}).ignored(),
    // Weighting
    Row("WEIGHT_TYPE", Kind::Keyword, {"NONE"},
        "NONE, BACKGROUND, MAP_RMS, MAP_VAR or MAP_WEIGHT")
        .keywords({"NONE", "BACKGROUND", "MAP_RMS", "MAP_VAR", "MAP_WEIGHT"})
        .list(0, kMaxImages).expert(),
    Row("RESCALE_WEIGHTS", Kind::Bool, {"Y"}, "rescale the weight maps (Y/N)")
        .list(1, kMaxImages).expert(),
    Row("WEIGHT_IMAGE", Kind::String, {"weight.fits"}, "weight map file name(s)")
        .list(0, kMaxImages).expert(),
    Row("WEIGHT_GAIN", Kind::Bool, {"Y"}, "scale the gain with the weights (Y/N)")
        .expert(),
    Row("WEIGHT_THRESH", Kind::Float, {}, "weight threshold(s) for bad pixels")
        .range(0, kBig).list(0, kMaxImages).expert(),
    // Flagging
    Row("FLAG_IMAGE", Kind::String, {"flag.fits"}, "flag image file name(s)")
        .list(0, kMaxFlagImages).expert().ignored(),
    Row("FLAG_TYPE", Kind::Keyword, {"OR"}, "combination of flag pixels: OR, AND, MIN, MAX or MOST")
        .keywords({"OR", "AND", "MIN", "MAX", "MOST"}).list(0, kMaxFlagImages).expert().ignored(),
    // Differential geometry
    Row("DGEO_TYPE", Kind::Keyword, {"NONE"}, "differential geometry map: NONE or PIXEL")
        .keywords({"NONE", "PIXEL"}).expert().ignored(),
    Row("DGEO_IMAGE", Kind::String, {"dgeo.fits"}, "differential geometry map file name")
        .expert().ignored(),
    // Photometry
    Row("PHOT_APERTURES", Kind::Float, {"5"}, "MAG_APER aperture diameter(s), pixels")
        .range(0, 2 * kMaxPicSize).list(1, kMaxApertures).ignored(),
    Row("PHOT_AUTOPARAMS", Kind::Float, {"2.5", "3.5"}, "MAG_AUTO: <Kron factor>,<minimum radius>")
        .range(0, 10).list(2, 2).ignored(),
    Row("PHOT_PETROPARAMS", Kind::Float, {"2.0", "3.5"},
        "MAG_PETRO: <Petrosian factor>,<minimum radius>").range(0, 10).list(2, 2).ignored(),
    Row("PHOT_AUTOAPERS", Kind::Float, {"0.0", "0.0"},
        "smallest MAG_AUTO/MAG_PETRO apertures:\n<estimation>,<measurement>")
        .range(0, 1e6).list(2, 2).expert().ignored(),
    Row("PHOT_FLUXFRAC", Kind::Float, {"0.5"}, "flux fraction(s) for FLUX_RADIUS")
        .range(1e-6, 1).list(1, kMaxApertures).expert().ignored(),
    Row("SATUR_LEVEL", Kind::Float, {"50000.0"}, "saturation level, ADU").range(-kBig, kBig),
    Row("SATUR_KEY", Kind::String, {"SATURATE"}, "header keyword holding the saturation level"),
    Row("MAG_ZEROPOINT", Kind::Float, {"0.0"}, "magnitude zero-point").range(-100, 100),
    Row("MAG_GAMMA", Kind::Float, {"4.0"}, "emulsion gamma (photographic scans)")
        .range(1e-10, kBig).ignored(),
    Row("GAIN", Kind::Float, {"0.0"}, "detector gain, e-/ADU (0 = infinite)").range(0, kBig),
    Row("GAIN_KEY", Kind::String, {"GAIN"}, "header keyword holding the gain (wins over GAIN)"),
    Row("PIXEL_SCALE", Kind::Float, {"1.0"}, "pixel size, arcsec (0 = from the WCS)")
        .range(0, 1e10),
    // Star/galaxy separation
    Row("SEEING_FWHM", Kind::Float, {"1.2"}, "stellar FWHM, arcsec (recorded as SEXSFWHM)")
        .range(0, 1e10),
    Row("STARNNW_NAME", Kind::String, {"default.nnw"}, "neural network weights for CLASS_STAR")
        .ignored(),
    // Background
    Row("BACK_TYPE", Kind::Keyword, {"AUTO"}, "AUTO (mesh map) or MANUAL (BACK_VALUE)")
        .keywords({"AUTO", "MANUAL"}).list(1, 2).expert(),
    Row("BACK_VALUE", Kind::Float, {"0.0"}, "constant background of the MANUAL mode, ADU")
        .list(1, 2).expert(),
    Row("BACK_SIZE", Kind::Int, {"64"}, "background mesh: <size> or <width>,<height>")
        .range(1, 2e9).list(1, 2),
    Row("BACK_FILTERSIZE", Kind::Int, {"3"}, "mesh filter: <size> or <width>,<height>")
        .range(1, 11).list(1, 2),
    Row("BACKPHOTO_TYPE", Kind::Keyword, {"GLOBAL"}, "photometry background: GLOBAL or LOCAL")
        .keywords({"GLOBAL", "LOCAL"}).ignored(),
    Row("BACKPHOTO_THICK", Kind::Int, {"24"}, "width of the LOCAL background annulus, pixels")
        .range(1, 256).expert().ignored(),
    Row("BACK_FILTTHRESH", Kind::Float, {"0.0"}, "mesh filter acts only above this\ndifference, ADU")
        .range(0, kBig).expert(),
    // Check images
    Row("CHECKIMAGE_TYPE", Kind::Keyword, {"NONE"},
        "NONE, BACKGROUND, BACKGROUND_RMS, MINIBACKGROUND,\nMINIBACK_RMS, -BACKGROUND, FILTERED,"
        " OBJECTS,\n-OBJECTS, SEGMENTATION or APERTURES")
        .keywords({"NONE", "IDENTICAL", "BACKGROUND", "BACKGROUND_RMS", "MINIBACKGROUND",
                   "MINIBACK_RMS", "-BACKGROUND", "FILTERED", "OBJECTS", "APERTURES",
                   "SEGMENTATION", "MASK", "-MASK", "ASSOC", "-OBJECTS", "PSFS", "-PSFS",
                   "PC_CONVPROTOS", "-PC_CONVPROTOS", "PC_PROTOS", "MAP_SOM", "MODELS", "-MODELS",
                   "SPHEROIDS", "-SPHEROIDS", "DISKS", "-DISKS", "PATTERNS", "OTHER"})
        .list(0, kMaxCheckImages),
    Row("CHECKIMAGE_NAME", Kind::String, {"check.fits"}, "check-image file name(s)")
        .list(0, kMaxCheckImages),
    // Memory
    Row("MEMORY_OBJSTACK", Kind::Int, {"3000"}, "objects in the stack").range(16, 65536).ignored(),
    Row("MEMORY_PIXSTACK", Kind::Int, {"300000"}, "pixels in the stack").range(1000, 1e8).ignored(),
    Row("MEMORY_BUFSIZE", Kind::Int, {"1024"}, "image lines in the buffer").range(8, 65534)
        .ignored(),
    // Association
    Row("ASSOC_NAME", Kind::String, {"sky.list"}, "ASCII list to associate with the objects")
        .expert(),
    Row("ASSOC_DATA", Kind::Int, {"2", "3", "4"}, "list columns copied to VECTOR_ASSOC (0 = all)")
        .range(0, 1e6).list(1, kMaxList).expert(),
    Row("ASSOC_PARAMS", Kind::Int, {"2", "3", "4"}, "list columns of x, y[, weight or magnitude]")
        .range(1, 1e6).list(2, 3).expert(),
    Row("ASSOCCOORD_TYPE", Kind::Keyword, {"PIXEL"}, "list coordinates: PIXEL or WORLD")
        .keywords({"PIXEL", "WORLD"}).expert(),
    Row("ASSOC_RADIUS", Kind::Float, {"2.0"}, "matching radius, pixels").range(1e-10, 1e10)
        .expert(),
    Row("ASSOC_TYPE", Kind::Keyword, {"NEAREST"},
        "FIRST, NEAREST, MEAN, MAG_MEAN, SUM, MAG_SUM,\nMIN or MAX")
        .keywords({"FIRST", "NEAREST", "MEAN", "MAG_MEAN", "SUM", "MAG_SUM", "MIN", "MAX"})
        .expert(),
    Row("ASSOCSELEC_TYPE", Kind::Keyword, {"MATCHED"}, "objects kept: ALL, MATCHED or -MATCHED")
        .keywords({"ALL", "MATCHED", "-MATCHED"}).expert(),
    // Miscellaneous
    Row("VERBOSE_TYPE", Kind::Keyword, {"NORMAL"}, "QUIET, NORMAL, EXTRA_WARNINGS or FULL")
        .keywords({"QUIET", "NORMAL", "EXTRA_WARNINGS", "FULL"}),
    Row("HEADER_SUFFIX", Kind::String, {".head"}, "suffix of external header files").ignored(),
    Row("WRITE_XML", Kind::Bool, {"N"}, "write an XML summary (Y/N)"),
    Row("XML_NAME", Kind::String, {"sex.xml"}, "XML summary file name"),
    Row("XSL_URL", Kind::String, {"file:///usr/share/source-extractor/source-extractor.xsl"},
        "XSL style sheet of the XML summary").expert(),
    Row("NTHREADS", Kind::Int, {"1"}, "number of threads").range(-65535, 65535).expert(),
    Row("FITS_UNSIGNED", Kind::Bool, {"N"}, "read FITS integers as unsigned (Y/N)").expert(),
    Row("INTERP_MAXXLAG", Kind::Int, {"16"}, "largest x gap filled for zero weights")
        .range(1, 1e6).list(1, 2).expert().ignored(),
    Row("INTERP_MAXYLAG", Kind::Int, {"16"}, "largest y gap filled for zero weights")
        .range(1, 1e6).list(1, 2).expert().ignored(),
    Row("INTERP_TYPE", Kind::Keyword, {"ALL"}, "zero-weight interpolation: NONE, VAR_ONLY or ALL")
        .keywords({"NONE", "VAR_ONLY", "ALL"}).list(1, 2).expert().ignored(),
    // Experimental
    Row("PSF_NAME", Kind::String, {"default.psf"}, "PSF model file(s)").list(1, 2).expert()
        .ignored(),
    Row("PSF_NMAX", Kind::Int, {"1"}, "PSFs fitted at once").range(1, 9).expert().ignored(),
    Row("PATTERN_TYPE", Kind::Keyword, {"RINGS-HARMONIC"},
        "RINGS-QUADPOLE, RINGS-OCTOPOLE, RINGS-HARMONIC\nor GAUSS-LAGUERRE")
        .keywords({"RINGS-QUADPOLE", "RINGS-OCTOPOLE", "RINGS-HARMONIC", "GAUSS-LAGUERRE"})
        .expert().ignored(),
    Row("SOM_NAME", Kind::String, {"default.som"}, "self-organising map file").expert().ignored(),
  };
  // clang-format on
}

}  // namespace

const std::vector<KeySpec>& sextractorKeys() {
  static const std::vector<KeySpec> keys = buildSextractorKeys();
  return keys;
}

}  // namespace octarc::sexcompat
