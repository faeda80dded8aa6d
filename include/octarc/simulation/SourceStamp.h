// A noise-free source galaxy image used as a surface-brightness model.
#pragma once

#include <string>

#include "octarc/core/Image.h"

namespace octarc::simulation {

// Morphological type, which selects the magnitude-redshift relation (params/simulation/).
enum class GalaxyType { Elliptical, Spiral, Irregular };

// "elliptical", "spiral", "irregular".
const char* galaxyTypeName(GalaxyType type);

struct SourceStamp {
  // Flux per stamp pixel (any linear unit). The stamp centre, the reference point that the
  // simulation places at the source position, is pixel coordinate ((w-1)/2, (h-1)/2), 0-based.
  ImageD fluxPerPixel;
  double pixelScaleArcsec = 0.03;
  GalaxyType type = GalaxyType::Spiral;
  std::string name;  // e.g. "synthetic spiral #3" or "AEGIS 23409"
};

// Sum of all pixels.
double totalFlux(const SourceStamp& stamp);

// Radius (arcsec) of the circle about the flux centroid that holds half the total flux, from the
// pixel centres (linear interpolation between pixels). NaN if the total flux is not positive.
double halfLightRadiusArcsec(const SourceStamp& stamp);

}  // namespace octarc::simulation
