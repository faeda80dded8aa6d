// Built-in synthetic source galaxies, so that simulations run without any external data.
//
// Each galaxy is a noise-free stamp (default 0.03"/px) normalised to unit total flux, zero outside
// the stamp's inscribed circle (radius stampHalfLightRadii half-light radii), built from
//   - elliptical: a de Vaucouleurs bulge (n = 4) with a faint n = 1 envelope;
//   - spiral: a small n = 4 bulge plus an exponential disc modulated by two logarithmic spiral
//     arms, with star-forming clumps (compact Gaussians) placed along the arms;
//   - irregular: a lopsided exponential disc plus several bright clumps scattered at random.
// The inclination, position angle, bulge fraction, arm pitch and clump positions and fluxes are
// random, drawn from the generator passed in.
#pragma once

#include <random>

#include "octarc/simulation/SourceStamp.h"

namespace octarc::simulation {

struct SyntheticGalaxyOptions {
  double pixelScaleArcsec = 0.03;
  double halfLightRadiusArcsec = 0.3;  // of the main component (disc or bulge); sets the size
  double stampHalfLightRadii = 6.0;    // stamp half-width in units of the half-light radius
};

// Throws ConfigError for non-positive scale or radius.
SourceStamp makeSyntheticGalaxy(GalaxyType type, std::mt19937_64& rng,
                                const SyntheticGalaxyOptions& options = {});

}  // namespace octarc::simulation
