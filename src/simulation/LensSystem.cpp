#include "octarc/simulation/LensSystem.h"

#include <cmath>
#include <numbers>

#include "octarc/core/Error.h"
#include "octarc/simulation/Noise.h"
#include "octarc/simulation/Psf.h"

namespace octarc::simulation {

Vec2 drawUniformInDisc(double radiusArcsec, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // sqrt of a uniform deviate makes the density uniform in area.
  const double r = radiusArcsec * std::sqrt(unit(rng));
  const double phi = 2.0 * std::numbers::pi * unit(rng);
  return {r * std::cos(phi), r * std::sin(phi)};
}

RenderedLensSystem renderLensSystem(const LensSystem& system, const SourceStamp& source,
                                    const ObservingSetup& setup, std::mt19937_64& rng) {
  const double stampFlux = totalFlux(source);
  if (!(stampFlux > 0.0))
    throw ConfigError("lens system: source stamp '" + source.name + "' has no positive flux");
  const EllipticalPotentialLens lens(system.mass);
  RenderedLensSystem out;
  out.image =
      traceLensedImage(lens, source, system.source, setup.grid, setup.rayTrace, &out.rayTrace);
  const double scale = fluxFromMagnitude(system.sourceMag, setup.magZeroPoint) / stampFlux;
  double traced = 0.0;
  for (double& v : out.image.pixels()) {
    v *= scale;
    traced += v;
  }
  out.lensedSourceFlux = traced;
  out.magnification = traced / fluxFromMagnitude(system.sourceMag, setup.magZeroPoint);

  SersicLightParams light = system.light;
  light.totalFlux = fluxFromMagnitude(system.lensMag, setup.magZeroPoint);
  addSersicLight(out.image, setup.grid, light);

  out.image = setup.userPsf != nullptr
                  ? convolve(out.image, *setup.userPsf)
                  : convolveSeparable(out.image, gaussianPsfKernel1d(setup.seeingFwhmArcsec,
                                                                     setup.grid.pixelScaleArcsec));
  if (setup.addNoise)
    addPoissonSkyNoise(out.image, setup.skySigmaAdu, setup.gainElectronsPerAdu, rng);
  return out;
}

}  // namespace octarc::simulation
