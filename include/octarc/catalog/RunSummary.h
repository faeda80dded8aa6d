// The values SExtractor records about a run in LDAC_IMHEAD (SEx* keywords) and in the primary
// header of a FITS_1.0 catalog, and their cards.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace octarc {

struct RunSummary {
  // LDAC_IMHEAD block (same order as the cards).
  std::string fitsFile;                      // FITSFILE: name of the analysed image, no directory
  std::int64_t fitsExt = 1;                  // FITSEXT: extension number
  std::int64_t fitsNext = 1;                 // FITSNEXT: number of image extensions in the file
  std::string version;                       // SEXVERS, e.g. "octarc 0.1.0"
  std::string date;                          // SEXDATE, dd/mm/yyyy
  std::string time;                          // SEXTIME, hh:mm:ss
  double elapsedSec = 0.0;                   // SEXELAPS
  double backgroundAdu = 0.0;                // SEXBKGND: median background level
  double backgroundRmsAdu = 0.0;             // SEXBKDEV: median background RMS
  double thresholdAdu = 0.0;                 // SEXTHLD: detection threshold
  double analysisThresholdAdu = 0.0;         // SEXATHLD
  std::int64_t detections = 0;               // SEXNDET: raw detections
  std::int64_t finalObjects = 0;             // SEXNFIN: catalog rows
  std::int64_t parameters = 0;               // SEXNPARA: parameters per source
  double pixelScaleArcsec = 0.0;             // SEXPXSCL
  double seeingFwhmArcsec = 0.0;             // SEXSFWHM
  std::string nnwFile;                       // SEXNNWF: S/G network file name, no directory
  double gainEPerAdu = 0.0;                  // SEXGAIN (0 = infinite)
  bool filtering = false;                    // SEXFLTR
  std::string filterFile;                    // SEXFILTN: no directory
  std::int64_t minAreaPix = 0;               // SEXMINAR
  std::int64_t deblendThresholds = 0;        // SEXDBLDN
  double deblendContrast = 0.0;              // SEXDBLDC
  bool cleaning = false;                     // SEXCLN
  double cleanParam = 0.0;                   // SEXCLNPA
  std::int64_t cleanStack = 0;               // SEXCLNST
  double apertureDiamPix[4] = {0, 0, 0, 0};  // SEXAPED1..4 (unused apertures 0)
  double autoParams[2] = {0, 0};             // SEXAUTP1/2: Kron factor and minimum radius
  double petroParams[2] = {0, 0};            // SEXPETP1/2
  double saturationAdu = 0.0;                // SEXSATLV
  double magZeropoint = 0.0;                 // SEXMGZPT
  double magGamma = 0.0;                     // SEXMGGAM
  std::int64_t backMeshPix[2] = {0, 0};      // SEXBKGSX/Y
  std::int64_t backFilterMesh[2] = {0, 0};   // SEXBKGFX/Y
  std::int64_t photBackThicknessPix = 0;     // SEXPBKGS
  std::int64_t pixelStack = 0;               // SEXPIXSK
  std::int64_t frameBufferLines = 0;         // SEXFBUFS
  double measureWeightScale = 0.0;           // SEXMWSCL
  double detectWeightScale = 0.0;            // SEXDWSCL

  // Extra values of the FITS_1.0 primary header.
  double epoch = 0.0;                   // EPOCH
  std::string object;                   // OBJECT
  std::string origin = "octarc";        // ORIGIN
  double kronAnalysisRadius = 0.0;      // SEXAPEK2
  std::int64_t imageWidthPix = 0;       // SEXIMASX
  std::int64_t imageHeightPix = 0;      // SEXIMASY
  std::int64_t stripHeightLines = 0;    // SEXSTRSY
  std::int64_t imageBitpix = 0;         // SEXIMABP
  std::string configFile;               // SEXCONFF
  std::string detectionType = "CCD";    // SEXDETT
  std::string thresholdType = "SIGMA";  // SEXTHLDT
  double thresholdSetting = 0.0;        // SEXTHLD of FITS_1.0: DETECT_THRESH as configured
  bool filterNorm = false;              // SEXCONVN
  std::string photBackType = "GLOBAL";  // SEXPBKGT
  double isoAperRatio = 0.0;            // SEXISAPR
};

// The 46 LDAC_IMHEAD cards, FITSFILE..SEXDWSCL, with SExtractor's names, types, value formats,
// comments and order.
std::vector<std::string> sexRunCards(const RunSummary& run);

// The FITS_1.0 primary-header cards that follow SIMPLE/BITPIX/NAXIS/EXTEND (EPOCH, OBJECT,
// ORIGIN, FITSFILE.., SEXIMASX.., SEXNDET, SEXNFIN, SEXNPARA), in SExtractor's order.
std::vector<std::string> sexFits10Cards(const RunSummary& run);

}  // namespace octarc
