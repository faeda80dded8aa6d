#include "octarc/simulation/Noise.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "octarc/core/Error.h"

namespace octarc::simulation {

void addPoissonSkyNoise(ImageD& image, double sigmaAdu, double gainElectronsPerAdu,
                        std::mt19937_64& rng) {
  if (!(sigmaAdu > 0.0) || !(gainElectronsPerAdu > 0.0))
    throw ConfigError("noise: sigma and gain must be positive, got sigma " +
                      std::to_string(sigmaAdu) + " ADU, gain " +
                      std::to_string(gainElectronsPerAdu) + " e-/ADU");
  const double g = gainElectronsPerAdu;
  const double backgroundAdu = (sigmaAdu * g) * (sigmaAdu * g) / g;
  std::normal_distribution<double> unitNormal(0.0, 1.0);
  for (double& v : image.pixels()) {
    const double meanElectrons = std::max(0.0, (v + backgroundAdu) * g);
    double electrons = 0.0;
    if (meanElectrons > kGaussianNoiseThresholdElectrons) {
      electrons = meanElectrons + std::sqrt(meanElectrons) * unitNormal(rng);
    } else if (meanElectrons > 0.0) {
      electrons = static_cast<double>(std::poisson_distribution<long long>(meanElectrons)(rng));
    }
    v = electrons / g - backgroundAdu;
  }
}

double skySigmaFromLimitingMagnitude(double limitingMag, double magZeroPoint, double apertureArcsec,
                                     double pixelScaleArcsec, double nSigma) {
  if (!(apertureArcsec > 0.0) || !(pixelScaleArcsec > 0.0) || !(nSigma > 0.0))
    throw ConfigError("noise: aperture, pixel scale and n-sigma must be positive");
  const double flux = std::pow(10.0, -0.4 * (limitingMag - magZeroPoint));
  const double nPix = std::numbers::pi * 0.25 * apertureArcsec * apertureArcsec /
                      (pixelScaleArcsec * pixelScaleArcsec);
  return flux / (nSigma * std::sqrt(nPix));
}

}  // namespace octarc::simulation
