#include "octarc/sexcompat/ParamFile.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <fstream>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc::sexcompat {

namespace {

// Every catalog parameter `source-extractor -dp` (2.25) lists, sorted.
// clang-format off
constexpr const char* kSextractorParameters[] = {
    "ALPHAMODEL_B1950", "ALPHAMODEL_J2000", "ALPHAMODEL_SKY", "ALPHAPEAK_B1950", "ALPHAPEAK_J2000",
    "ALPHAPEAK_SKY", "ALPHAPSF_B1950", "ALPHAPSF_J2000", "ALPHAPSF_SKY", "ALPHAWIN_B1950",
    "ALPHAWIN_J2000", "ALPHAWIN_SKY", "ALPHA_B1950", "ALPHA_J2000", "ALPHA_SKY", "AMODEL_IMAGE",
    "AMODEL_WORLD", "AWIN_IMAGE", "AWIN_WORLD", "A_IMAGE", "A_WORLD", "BACKGROUND", "BMODEL_IMAGE",
    "BMODEL_WORLD", "BWIN_IMAGE", "BWIN_WORLD", "B_IMAGE", "B_WORLD", "CHI2_DETMODEL",
    "CHI2_MODEL", "CHI2_PSF", "CLASS_STAR", "CXXMODEL_IMAGE", "CXXMODEL_WORLD", "CXXWIN_IMAGE",
    "CXXWIN_WORLD", "CXX_IMAGE", "CXX_WORLD", "CXYMODEL_IMAGE", "CXYMODEL_WORLD", "CXYWIN_IMAGE",
    "CXYWIN_WORLD", "CXY_IMAGE", "CXY_WORLD", "CYYMODEL_IMAGE", "CYYMODEL_WORLD", "CYYWIN_IMAGE",
    "CYYWIN_WORLD", "CYY_IMAGE", "CYY_WORLD", "DELTAMODEL_B1950", "DELTAMODEL_J2000",
    "DELTAMODEL_SKY", "DELTAPEAK_B1950", "DELTAPEAK_J2000", "DELTAPEAK_SKY", "DELTAPSF_B1950",
    "DELTAPSF_J2000", "DELTAPSF_SKY", "DELTAWIN_B1950", "DELTAWIN_J2000", "DELTAWIN_SKY",
    "DELTA_B1950", "DELTA_J2000", "DELTA_SKY", "DGEOXWIN_IMAGE", "DGEOX_IMAGE", "DGEOYWIN_IMAGE",
    "DGEOY_IMAGE", "DISK_ASPECTERR_IMAGE", "DISK_ASPECTERR_WORLD", "DISK_ASPECT_IMAGE",
    "DISK_ASPECT_WORLD", "DISK_INCLINATION", "DISK_INCLINATIONERR", "DISK_SCALEERR_IMAGE",
    "DISK_SCALEERR_WORLD", "DISK_SCALE_IMAGE", "DISK_SCALE_WORLD", "DISK_THETAERR_IMAGE",
    "DISK_THETAERR_WORLD", "DISK_THETA_B1950", "DISK_THETA_IMAGE", "DISK_THETA_J2000",
    "DISK_THETA_SKY", "DISK_THETA_WORLD", "DURATION_ANALYSIS", "ELLIP1ERRMODEL_IMAGE",
    "ELLIP1ERRMODEL_WORLD", "ELLIP1MODEL_IMAGE", "ELLIP1MODEL_WORLD", "ELLIP2ERRMODEL_IMAGE",
    "ELLIP2ERRMODEL_WORLD", "ELLIP2MODEL_IMAGE", "ELLIP2MODEL_WORLD", "ELLIPCORRMODEL_IMAGE",
    "ELLIPCORRMODEL_WORLD", "ELLIPTICITY", "ELONGATION", "ERRAMODEL_IMAGE", "ERRAMODEL_WORLD",
    "ERRAPSF_IMAGE", "ERRAPSF_WORLD", "ERRAWIN_IMAGE", "ERRAWIN_WORLD", "ERRA_IMAGE", "ERRA_WORLD",
    "ERRBMODEL_IMAGE", "ERRBMODEL_WORLD", "ERRBPSF_IMAGE", "ERRBPSF_WORLD", "ERRBWIN_IMAGE",
    "ERRBWIN_WORLD", "ERRB_IMAGE", "ERRB_WORLD", "ERRCXXMODEL_IMAGE", "ERRCXXMODEL_WORLD",
    "ERRCXXPSF_IMAGE", "ERRCXXPSF_WORLD", "ERRCXXWIN_IMAGE", "ERRCXXWIN_WORLD", "ERRCXX_IMAGE",
    "ERRCXX_WORLD", "ERRCXYMODEL_IMAGE", "ERRCXYMODEL_WORLD", "ERRCXYPSF_IMAGE", "ERRCXYPSF_WORLD",
    "ERRCXYWIN_IMAGE", "ERRCXYWIN_WORLD", "ERRCXY_IMAGE", "ERRCXY_WORLD", "ERRCYYMODEL_IMAGE",
    "ERRCYYMODEL_WORLD", "ERRCYYPSF_IMAGE", "ERRCYYPSF_WORLD", "ERRCYYWIN_IMAGE",
    "ERRCYYWIN_WORLD", "ERRCYY_IMAGE", "ERRCYY_WORLD", "ERROR_SOMFIT", "ERRTHETAMODEL_B1950",
    "ERRTHETAMODEL_IMAGE", "ERRTHETAMODEL_J2000", "ERRTHETAMODEL_SKY", "ERRTHETAMODEL_WORLD",
    "ERRTHETAPSF_B1950", "ERRTHETAPSF_IMAGE", "ERRTHETAPSF_J2000", "ERRTHETAPSF_SKY",
    "ERRTHETAPSF_WORLD", "ERRTHETAWIN_B1950", "ERRTHETAWIN_IMAGE", "ERRTHETAWIN_J2000",
    "ERRTHETAWIN_SKY", "ERRTHETAWIN_WORLD", "ERRTHETA_B1950", "ERRTHETA_IMAGE", "ERRTHETA_J2000",
    "ERRTHETA_SKY", "ERRTHETA_WORLD", "ERRX2MODEL_IMAGE", "ERRX2MODEL_WORLD", "ERRX2PSF_IMAGE",
    "ERRX2PSF_WORLD", "ERRX2WIN_IMAGE", "ERRX2WIN_WORLD", "ERRX2_IMAGE", "ERRX2_WORLD",
    "ERRXYMODEL_IMAGE", "ERRXYMODEL_WORLD", "ERRXYPSF_IMAGE", "ERRXYPSF_WORLD", "ERRXYWIN_IMAGE",
    "ERRXYWIN_WORLD", "ERRXY_IMAGE", "ERRXY_WORLD", "ERRY2MODEL_IMAGE", "ERRY2MODEL_WORLD",
    "ERRY2PSF_IMAGE", "ERRY2PSF_WORLD", "ERRY2WIN_IMAGE", "ERRY2WIN_WORLD", "ERRY2_IMAGE",
    "ERRY2_WORLD", "EXT_NUMBER", "FLAGS", "FLAGS_DETMODEL", "FLAGS_MODEL", "FLAGS_WEIGHT",
    "FLAGS_WIN", "FLUXERR_APER", "FLUXERR_AUTO", "FLUXERR_BACKOFFSET", "FLUXERR_BEST",
    "FLUXERR_DETMODEL", "FLUXERR_DISK", "FLUXERR_HYBRID", "FLUXERR_ISO", "FLUXERR_ISOCOR",
    "FLUXERR_MODEL", "FLUXERR_PETRO", "FLUXERR_POINTSOURCE", "FLUXERR_PSF", "FLUXERR_SOMFIT",
    "FLUXERR_SPHEROID", "FLUXERR_WIN", "FLUXRATIOERR_DISK", "FLUXRATIOERR_POINTSOURCE",
    "FLUXRATIOERR_SPHEROID", "FLUXRATIO_DISK", "FLUXRATIO_POINTSOURCE", "FLUXRATIO_SPHEROID",
    "FLUX_APER", "FLUX_AUTO", "FLUX_BACKOFFSET", "FLUX_BEST", "FLUX_DETMODEL", "FLUX_DISK",
    "FLUX_EFF_DISK", "FLUX_EFF_MODEL", "FLUX_EFF_SPHEROID", "FLUX_GROWTH", "FLUX_GROWTHSTEP",
    "FLUX_HYBRID", "FLUX_ISO", "FLUX_ISOCOR", "FLUX_MAX", "FLUX_MAX_DISK", "FLUX_MAX_MODEL",
    "FLUX_MAX_SPHEROID", "FLUX_MEAN_DISK", "FLUX_MEAN_MODEL", "FLUX_MEAN_SPHEROID", "FLUX_MODEL",
    "FLUX_PETRO", "FLUX_POINTSOURCE", "FLUX_PSF", "FLUX_RADIUS", "FLUX_SOMFIT", "FLUX_SPHEROID",
    "FLUX_WIN", "FWHMPSF_IMAGE", "FWHMPSF_WORLD", "FWHM_IMAGE", "FWHM_WORLD", "ID_PARENT",
    "IMAFLAGS_ISO", "ISO0", "ISO1", "ISO2", "ISO3", "ISO4", "ISO5", "ISO6", "ISO7",
    "ISOAREAF_IMAGE", "ISOAREAF_WORLD", "ISOAREA_IMAGE", "ISOAREA_WORLD", "KRON_RADIUS",
    "MAGERR_APER", "MAGERR_AUTO", "MAGERR_BEST", "MAGERR_DETMODEL", "MAGERR_DISK", "MAGERR_HYBRID",
    "MAGERR_ISO", "MAGERR_ISOCOR", "MAGERR_MODEL", "MAGERR_PETRO", "MAGERR_POINTSOURCE",
    "MAGERR_PSF", "MAGERR_SOMFIT", "MAGERR_SPHEROID", "MAGERR_WIN", "MAG_APER", "MAG_AUTO",
    "MAG_BEST", "MAG_DETMODEL", "MAG_DISK", "MAG_GROWTH", "MAG_GROWTHSTEP", "MAG_HYBRID",
    "MAG_ISO", "MAG_ISOCOR", "MAG_MODEL", "MAG_PETRO", "MAG_POINTSOURCE", "MAG_PSF", "MAG_SOMFIT",
    "MAG_SPHEROID", "MAG_WIN", "MATRIX_MODELERR", "MU_EFF_DISK", "MU_EFF_MODEL", "MU_EFF_SPHEROID",
    "MU_MAX", "MU_MAX_DISK", "MU_MAX_MODEL", "MU_MAX_SPHEROID", "MU_MEAN_DISK", "MU_MEAN_MODEL",
    "MU_MEAN_SPHEROID", "MU_THRESHOLD", "NIMAFLAGS_ISO", "NITER_DETMODEL", "NITER_MODEL",
    "NITER_PSF", "NITER_WIN", "NLOWDWEIGHT_ISO", "NLOWWEIGHT_ISO", "NOISEAREA_MODEL", "NUMBER",
    "NUMBER_ASSOC", "PETRO_RADIUS", "POLAR1ERRMODEL_IMAGE", "POLAR1ERRMODEL_WORLD",
    "POLAR1MODEL_IMAGE", "POLAR1MODEL_WORLD", "POLAR2ERRMODEL_IMAGE", "POLAR2ERRMODEL_WORLD",
    "POLAR2MODEL_IMAGE", "POLAR2MODEL_WORLD", "POLARCORRMODEL_IMAGE", "POLARCORRMODEL_WORLD",
    "POLARWIN_IMAGE", "POLARWIN_WORLD", "POLAR_IMAGE", "POLAR_WORLD", "SNR_WIN",
    "SPHEROID_ASPECTERR_IMAGE", "SPHEROID_ASPECTERR_WORLD", "SPHEROID_ASPECT_IMAGE",
    "SPHEROID_ASPECT_WORLD", "SPHEROID_REFFERR_IMAGE", "SPHEROID_REFFERR_WORLD",
    "SPHEROID_REFF_IMAGE", "SPHEROID_REFF_WORLD", "SPHEROID_SERSICN", "SPHEROID_SERSICNERR",
    "SPHEROID_THETAERR_IMAGE", "SPHEROID_THETAERR_WORLD", "SPHEROID_THETA_B1950",
    "SPHEROID_THETA_IMAGE", "SPHEROID_THETA_J2000", "SPHEROID_THETA_SKY", "SPHEROID_THETA_WORLD",
    "SPREADERR_MODEL", "SPREAD_MODEL", "THETAMODEL_B1950", "THETAMODEL_IMAGE", "THETAMODEL_J2000",
    "THETAMODEL_SKY", "THETAMODEL_WORLD", "THETAWIN_B1950", "THETAWIN_IMAGE", "THETAWIN_J2000",
    "THETAWIN_SKY", "THETAWIN_WORLD", "THETA_B1950", "THETA_IMAGE", "THETA_J2000", "THETA_SKY",
    "THETA_WORLD", "THRESHOLD", "THRESHOLDMAX", "VECTOR_ASSOC", "VECTOR_MODEL", "VECTOR_MODELERR",
    "VECTOR_SOMFIT", "VIGNET", "VIGNET_DGEOX", "VIGNET_DGEOY", "VIGNET_SHIFT", "X2MODEL_IMAGE",
    "X2MODEL_WORLD", "X2WIN_IMAGE", "X2WIN_WORLD", "X2_IMAGE", "X2_WORLD", "XFOCAL_WORLD",
    "XMAX_IMAGE", "XMIN_IMAGE", "XMODEL_IMAGE", "XMODEL_WORLD", "XPEAK_FOCAL", "XPEAK_IMAGE",
    "XPEAK_WORLD", "XPSF_IMAGE", "XPSF_WORLD", "XWIN_FOCAL", "XWIN_IMAGE", "XWIN_WORLD",
    "XYMODEL_IMAGE", "XYMODEL_WORLD", "XYWIN_IMAGE", "XYWIN_WORLD", "XY_IMAGE", "XY_WORLD",
    "X_FOCAL", "X_IMAGE", "X_IMAGE_DBL", "X_MAMA", "X_WORLD", "Y2MODEL_IMAGE", "Y2MODEL_WORLD",
    "Y2WIN_IMAGE", "Y2WIN_WORLD", "Y2_IMAGE", "Y2_WORLD", "YFOCAL_WORLD", "YMAX_IMAGE",
    "YMIN_IMAGE", "YMODEL_IMAGE", "YMODEL_WORLD", "YPEAK_FOCAL", "YPEAK_IMAGE", "YPEAK_WORLD",
    "YPSF_IMAGE", "YPSF_WORLD", "YWIN_FOCAL", "YWIN_IMAGE", "YWIN_WORLD", "Y_FOCAL", "Y_IMAGE",
    "Y_IMAGE_DBL", "Y_MAMA", "Y_WORLD",
};
// clang-format on

}  // namespace

bool isSextractorParameter(std::string_view name) {
  return std::binary_search(std::begin(kSextractorParameters), std::end(kSextractorParameters),
                            name, [](std::string_view a, std::string_view b) { return a < b; });
}

std::vector<ParamRequest> readParamFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open parameter file");
  std::vector<ParamRequest> requests;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    const std::size_t nameEnd = line.find_first_of(" \t\r([{#", start);
    ParamRequest request;
    request.name =
        line.substr(start, nameEnd == std::string::npos ? std::string::npos : nameEnd - start);
    request.line = lineNo;
    if (nameEnd != std::string::npos) {
      const std::string rest = line.substr(nameEnd);
      constexpr const char* kSizeSeparators = " \t\r,;.([{)]}";
      std::size_t pos = 0;
      long elements = 1;
      while ((pos = rest.find_first_not_of(kSizeSeparators, pos)) != std::string::npos) {
        const std::size_t end = rest.find_first_of(kSizeSeparators, pos);
        const std::string token =
            rest.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
        if (token[0] == '#') break;
        errno = 0;
        char* tail = nullptr;
        const long size = std::strtol(token.c_str(), &tail, 10);
        const std::string where =
            path + ":" + std::to_string(lineNo) + ": " + quoteForMessage(request.name);
        if (tail == token.c_str() || *tail != '\0' || errno == ERANGE || size > INT_MAX)
          throw ConfigError(where + ": vector size " + quoteForMessage(token) +
                            " is not an integer");
        if (size <= 0)
          throw ConfigError(where + ": vector size must be positive, got " +
                            quoteForMessage(token));
        // The column holds the product of the sizes: it must be an int, like each size.
        if (elements > INT_MAX / size)
          throw ConfigError(where + ": vector of more than " + std::to_string(INT_MAX) +
                            " elements");
        elements *= size;
        request.sizes.push_back(static_cast<int>(size));
        pos = end;
      }
    }
    bool duplicate = false;
    for (const auto& r : requests) duplicate = duplicate || r.name == request.name;
    if (!duplicate) requests.push_back(std::move(request));
  }
  if (in.bad()) throw IoError(path + ": read error");
  return requests;
}

}  // namespace octarc::sexcompat
