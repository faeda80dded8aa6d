#include "octarc/catalog/RunSummary.h"

#include "octarc/catalog/FitsCard.h"

namespace octarc {

namespace {

// Small builder so that the card lists below read as tables.
class Cards {
 public:
  void text(const char* key, const std::string& v, const char* comment) {
    cards_.push_back(formatCard(key, v, comment));
  }
  void integer(const char* key, std::int64_t v, const char* comment) {
    cards_.push_back(formatCard(key, v, comment));
  }
  void logical(const char* key, bool v, const char* comment) {
    cards_.push_back(formatCard(key, v, comment));
  }
  void expo(const char* key, double v, const char* comment) {
    cards_.push_back(formatCard(key, RealValue(v, RealFormat::Exponential), comment));
  }
  void fixed(const char* key, double v, const char* comment) {
    cards_.push_back(formatCard(key, RealValue(v, RealFormat::Fixed), comment));
  }
  std::vector<std::string> take() { return std::move(cards_); }

 private:
  std::vector<std::string> cards_;
};

}  // namespace

std::vector<std::string> sexRunCards(const RunSummary& r) {
  Cards c;
  c.text("FITSFILE", r.fitsFile, "File name of the analysed image");
  c.integer("FITSEXT", r.fitsExt, "FITS Extension number");
  c.integer("FITSNEXT", r.fitsNext, "Number of FITS image extensions in file");
  c.text("SEXVERS", r.version, "Extraction software");
  c.text("SEXDATE", r.date, "Extraction date");
  c.text("SEXTIME", r.time, "Extraction time");
  c.fixed("SEXELAPS", r.elapsedSec, "Elapsed time during extraction (s)");
  c.expo("SEXBKGND", r.backgroundAdu, "Median background level (ADU)");
  c.expo("SEXBKDEV", r.backgroundRmsAdu, "Median background RMS (ADU)");
  c.expo("SEXTHLD", r.thresholdAdu, "Extraction threshold (ADU)");
  c.expo("SEXATHLD", r.analysisThresholdAdu, "Analysis threshold (ADU)");
  c.integer("SEXNDET", r.detections, "Number of raw detections");
  c.integer("SEXNFIN", r.finalObjects, "Final number of extracted sources");
  c.integer("SEXNPARA", r.parameters, "Number of parameters per source");
  c.expo("SEXPXSCL", r.pixelScaleArcsec, "Pixel scale used for measurements (arcsec)");
  c.expo("SEXSFWHM", r.seeingFwhmArcsec, "Source FWHM used for measurements (arcsec)");
  c.text("SEXNNWF", r.nnwFile, "S/G classification NNW filename");
  c.expo("SEXGAIN", r.gainEPerAdu, "Gain used (e-/ADU)");
  c.logical("SEXFLTR", r.filtering, "Detection filtering activated (flag)");
  c.text("SEXFILTN", r.filterFile, "Filter filename");
  c.integer("SEXMINAR", r.minAreaPix, "Minimum area used for detection (pixels)");
  c.integer("SEXDBLDN", r.deblendThresholds, "Number of deblending thresholds");
  c.fixed("SEXDBLDC", r.deblendContrast, "Minimum contrast used for deblending");
  c.logical("SEXCLN", r.cleaning, "Cleaning activated (flag)");
  c.fixed("SEXCLNPA", r.cleanParam, "Cleaning parameter");
  c.integer("SEXCLNST", r.cleanStack, "Cleaning stack-size");
  const char* apertureKeys[4] = {"SEXAPED1", "SEXAPED2", "SEXAPED3", "SEXAPED4"};
  const char* apertureComments[4] = {
      "Fixed photometric aperture #1 (pixels)", "Fixed photometric aperture #2 (pixels)",
      "Fixed photometric aperture #3 (pixels)", "Fixed photometric aperture #4 (pixels)"};
  for (int i = 0; i < 4; ++i) c.fixed(apertureKeys[i], r.apertureDiamPix[i], apertureComments[i]);
  c.fixed("SEXAUTP1", r.autoParams[0], "Parameter #1 used for automatic magnitudes");
  c.fixed("SEXAUTP2", r.autoParams[1], "Parameter #2 used for automatic magnitudes");
  // "Petronsian" is SExtractor's own spelling; kept so the headers compare equal.
  c.fixed("SEXPETP1", r.petroParams[0], "Parameter #1 used for Petronsian magnitudes");
  c.fixed("SEXPETP2", r.petroParams[1], "Parameter #2 used for Petrosian magnitudes");
  c.expo("SEXSATLV", r.saturationAdu, "Saturation level used for flagging (ADU)");
  c.fixed("SEXMGZPT", r.magZeropoint, "Zero-point used for magnitudes");
  c.fixed("SEXMGGAM", r.magGamma, "Gamma used for photographic photometry");
  c.integer("SEXBKGSX", r.backMeshPix[0], "Mesh width used for background mapping (pixels)");
  c.integer("SEXBKGSY", r.backMeshPix[1], "Mesh height used for background mapping (pixels)");
  c.integer("SEXBKGFX", r.backFilterMesh[0], "Mask width used for background map filtering");
  c.integer("SEXBKGFY", r.backFilterMesh[1], "Mask height used for background map filtering");
  c.integer("SEXPBKGS", r.photBackThicknessPix, "Thickness used for local background (pixels)");
  c.integer("SEXPIXSK", r.pixelStack, "Pixel stack-size (pixels)");
  c.integer("SEXFBUFS", r.frameBufferLines, "Image-buffer height (scanlines)");
  c.expo("SEXMWSCL", r.measureWeightScale, "Measurement-weight re-scaling factor");
  c.expo("SEXDWSCL", r.detectWeightScale, "Detection-weight re-scaling factor");
  return c.take();
}

std::vector<std::string> sexFits10Cards(const RunSummary& r) {
  Cards c;
  c.fixed("EPOCH", r.epoch, "");
  c.text("OBJECT", r.object, "");
  c.text("ORIGIN", r.origin, "");
  c.text("FITSFILE", r.fitsFile, "File name of the analysed image");
  c.integer("FITSEXT", r.fitsExt, "FITS Extension number");
  c.integer("FITSNEXT", r.fitsNext, "Number of FITS image extensions in file");
  c.integer("SEXIMASX", r.imageWidthPix, "IMAGE WIDTH (PIXELS)");
  c.integer("SEXIMASY", r.imageHeightPix, "IMAGE HEIGHT (PIXELS)");
  c.integer("SEXSTRSY", r.stripHeightLines, "STRIP HEIGHT (LINES)");
  c.integer("SEXIMABP", r.imageBitpix, "FITS IMAGE BITPIX");
  c.expo("SEXPIXS", r.pixelScaleArcsec, "PIXEL SCALE (ARCSEC)");
  c.expo("SEXSFWHM", r.seeingFwhmArcsec, "SEEING FWHM (ARCSEC)");
  c.text("SEXNNWF", r.nnwFile, "CLASSIFICATION NNW FILENAME");
  c.expo("SEXGAIN", r.gainEPerAdu, "GAIN (IN E- PER ADU)");
  c.expo("SEXBKGND", r.backgroundAdu, "MEDIAN BACKGROUND (ADU)");
  c.expo("SEXBKDEV", r.backgroundRmsAdu, "MEDIAN RMS (ADU)");
  c.expo("SEXBKTHD", r.thresholdAdu, "EXTRACTION THRESHOLD (ADU)");
  c.text("SEXCONFF", r.configFile, "CONFIGURATION FILENAME");
  c.text("SEXDETT", r.detectionType, "DETECTION TYPE");
  c.text("SEXTHLDT", r.thresholdType, "THRESHOLD TYPE");
  c.expo("SEXTHLD", r.thresholdSetting, "THRESHOLD");
  c.integer("SEXMINAR", r.minAreaPix, "EXTRACTION MINIMUM AREA (PIXELS)");
  c.logical("SEXCONV", r.filtering, "CONVOLUTION FLAG");
  c.logical("SEXCONVN", r.filterNorm, "CONVOLUTION NORM. FLAG");
  c.text("SEXCONVF", r.filterFile, "CONVOLUTION FILENAME");
  c.integer("SEXDBLDN", r.deblendThresholds, "NUMBER OF SUB-THRESHOLDS");
  c.fixed("SEXDBLDC", r.deblendContrast, "CONTRAST PARAMETER");
  c.logical("SEXCLN", r.cleaning, "CLEANING FLAG");
  c.fixed("SEXCLNPA", r.cleanParam, "CLEANING PARAMETER");
  c.integer("SEXCLNST", r.cleanStack, "CLEANING OBJECT-STACK");
  c.fixed("SEXAPERD", r.apertureDiamPix[0], "1ST APERTURE DIAMETER (PIXELS)");
  c.fixed("SEXAPEK1", r.autoParams[0], "KRON PARAMETER");
  c.fixed("SEXAPEK2", r.kronAnalysisRadius, "KRON ANALYSIS RADIUS");
  c.fixed("SEXAPEK3", r.autoParams[1], "KRON MINIMUM RADIUS");
  c.expo("SEXSATLV", r.saturationAdu, "SATURATION LEVEL (ADU)");
  c.fixed("SEXMGZPT", r.magZeropoint, "MAGNITUDE ZERO-POINT");
  c.fixed("SEXMGGAM", r.magGamma, "MAGNITUDE GAMMA");
  c.integer("SEXBKGSX", r.backMeshPix[0], "BACKGROUND MESH WIDTH (PIXELS)");
  c.integer("SEXBKGSY", r.backMeshPix[1], "BACKGROUND MESH HEIGHT (PIXELS)");
  c.integer("SEXBKGFX", r.backFilterMesh[0], "BACKGROUND FILTER WIDTH");
  c.integer("SEXBKGFY", r.backFilterMesh[1], "BACKGROUND FILTER HEIGHT");
  c.text("SEXPBKGT", r.photBackType, "PHOTOM BACKGROUND TYPE");
  c.integer("SEXPBKGS", r.photBackThicknessPix, "LOCAL AREA THICKNESS (PIXELS)");
  c.integer("SEXPIXSK", r.pixelStack, "PIXEL STACKSIZE (PIXELS)");
  c.integer("SEXFBUFS", r.frameBufferLines, "FRAME-BUFFER SIZE (LINES)");
  c.fixed("SEXISAPR", r.isoAperRatio, "ISO-APER RATIO");
  c.integer("SEXNDET", r.detections, "NB OF DETECTIONS");
  c.integer("SEXNFIN", r.finalObjects, "NB OF FINAL EXTRACTED OBJECTS");
  c.integer("SEXNPARA", r.parameters, "NB OF PARAMETERS PER OBJECT");
  return c.take();
}

}  // namespace octarc
