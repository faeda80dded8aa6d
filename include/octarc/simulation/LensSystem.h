// One simulated galaxy-galaxy lens stamp (METHOD.md section 3, "Imaging"): the source
// ray-traced through the lens, rebinned to survey pixels, plus the lens light, convolved with the
// PSF, plus sky noise. Choosing the parameters (population draws, source pick) is the caller's
// job; this only renders them.
#pragma once

#include <random>

#include "octarc/core/Image.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/LensModel.h"
#include "octarc/simulation/RayTracer.h"
#include "octarc/simulation/SourceStamp.h"

namespace octarc::simulation {

// The survey: stamp geometry, PSF, noise and photometric zero point (Deep Lens Survey defaults).
struct ObservingSetup {
  SurveyGrid grid;                  // default 101 x 101 px of 0.257" (26" x 26")
  double seeingFwhmArcsec = 0.9;    // Gaussian PSF, used when userPsf is null
  const ImageD* userPsf = nullptr;  // normalised PSF image at the survey scale, or null
  double skySigmaAdu = 1.0;         // per-pixel sky noise
  double gainElectronsPerAdu = 54.0;
  double magZeroPoint = 30.0;  // flux (ADU) = 10^(-0.4 (m - zp))
  bool addNoise = true;        // false: the noise-free stamp (truth images, tests)
  RayTraceOptions rayTrace;
};

struct LensSystem {
  EllipticalPotentialParams mass;  // lens potential (b, eps, core, position angle)
  SersicLightParams light;         // lens light; totalFlux is set from lensMag
  double lensMag = 21.0;
  SourcePlacement source;   // position (multiply imaged), rotation, size
  double sourceMag = 23.0;  // magnitude of the unlensed source
};

// A second band of the same system, as simple colours (no SED, no redshift): colour = m_band -
// m_first band, so the lensed source is scaled by 10^(-0.4 sourceColourMag) and the lens light by
// 10^(-0.4 lensColourMag); the same geometry, zero point and PSF, the same sky noise level with
// draws of its own.
struct SecondBandColours {
  double sourceColourMag = 0.0;
  double lensColourMag = 0.0;
  std::mt19937_64* noiseRng = nullptr;  // the band's noise draws; required with noise
};

struct RenderedLensSystem {
  ImageD image;                   // ADU per survey pixel
  ImageD bandImage;               // the second band's stamp; empty without one
  double lensedSourceFlux = 0.0;  // traced source flux before the PSF (ADU)
  double magnification = 0.0;     // lensedSourceFlux / unlensed source flux
  RayTraceStats rayTrace;
};

// CPU seconds (of the calling thread) spent in each rendering step, for profiling.
struct RenderTimings {
  double rayTraceSec = 0.0;  // ray tracing and rebinning
  double lensLightSec = 0.0;
  double psfSec = 0.0;
  double noiseSec = 0.0;
};

// A point drawn uniformly inside a disc of radiusArcsec about the origin.
Vec2 drawUniformInDisc(double radiusArcsec, std::mt19937_64& rng);

// Renders the stamp. The source stamp's flux is rescaled to sourceMag (its pixel sum is taken as
// its total flux); the lens light is centred on the grid's lens position. Noise draws come from
// rng. Throws ConfigError for invalid parameters and for a source with non-positive flux.
// Adds the CPU time of each step to *timings when given. With `band`, also renders bandImage
// from the same ray trace (the first band's image and draws are the same as without it).
RenderedLensSystem renderLensSystem(const LensSystem& system, const SourceStamp& source,
                                    const ObservingSetup& setup, std::mt19937_64& rng,
                                    RenderTimings* timings = nullptr,
                                    const SecondBandColours* band = nullptr);

}  // namespace octarc::simulation
