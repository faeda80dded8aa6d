#include "octarc/simulation/LensSystem.h"

#include <time.h>

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

namespace {

double threadCpuSec() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Adds the CPU time since the last call to one of the timing fields (no-op without timings).
class StepClock {
 public:
  explicit StepClock(RenderTimings* timings)
      : timings_(timings), last_(timings ? threadCpuSec() : 0.0) {}
  void charge(double RenderTimings::*field) {
    if (!timings_) return;
    const double now = threadCpuSec();
    timings_->*field += now - last_;
    last_ = now;
  }

 private:
  RenderTimings* timings_;
  double last_;
};

}  // namespace

RenderedLensSystem renderLensSystem(const LensSystem& system, const SourceStamp& source,
                                    const ObservingSetup& setup, std::mt19937_64& rng,
                                    RenderTimings* timings, const SecondBandColours* band) {
  StepClock clock(timings);
  const double stampFlux = totalFlux(source);
  if (!(stampFlux > 0.0))
    throw ConfigError("lens system: source stamp '" + source.name + "' has no positive flux");
  if (band != nullptr && setup.addNoise && band->noiseRng == nullptr)
    throw ConfigError("lens system: the second band needs its own noise stream");
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
  // The second band's source: the same traced image, fainter or brighter by its colour.
  if (band != nullptr) {
    out.bandImage = out.image;
    const double sourceScale = std::pow(10.0, -0.4 * band->sourceColourMag);
    for (double& v : out.bandImage.pixels()) v *= sourceScale;
  }
  clock.charge(&RenderTimings::rayTraceSec);

  SersicLightParams light = system.light;
  light.totalFlux = fluxFromMagnitude(system.lensMag, setup.magZeroPoint);
  addSersicLight(out.image, setup.grid, light);
  if (band != nullptr) {
    SersicLightParams bandLight = light;
    bandLight.totalFlux = light.totalFlux * std::pow(10.0, -0.4 * band->lensColourMag);
    addSersicLight(out.bandImage, setup.grid, bandLight);
  }
  clock.charge(&RenderTimings::lensLightSec);

  // The traced image and the lens light already hold the flux on each pixel.
  auto seeing = [&setup](const ImageD& image) {
    return setup.userPsf != nullptr
               ? convolve(image, *setup.userPsf)
               : applyGaussianSeeing(image, setup.seeingFwhmArcsec, setup.grid.pixelScaleArcsec);
  };
  out.image = seeing(out.image);
  if (band != nullptr) out.bandImage = seeing(out.bandImage);
  clock.charge(&RenderTimings::psfSec);
  if (setup.addNoise) {
    addPoissonSkyNoise(out.image, setup.skySigmaAdu, setup.gainElectronsPerAdu, rng);
    if (band != nullptr) {
      addPoissonSkyNoise(out.bandImage, setup.skySigmaAdu, setup.gainElectronsPerAdu,
                         *band->noiseRng);
    }
  }
  clock.charge(&RenderTimings::noiseSec);
  return out;
}

}  // namespace octarc::simulation
