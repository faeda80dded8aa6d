// Morphological type of a galaxy stamp from its light alone, for source databases whose catalog
// has no type column (GalSim's RealGalaxyCatalog format has none). The type selects the
// magnitude-redshift relation of the source (params/simulation/population.txt).
//
// Measures (about the flux centroid, circular apertures on pixel centres):
//   concentration C = 5 log10(r80 / r20), r20 and r80 the radii holding 20 % and 80 % of the
//     total flux (Bershady, Jangren & Conselice 2000, AJ 119, 2645);
//   rotational asymmetry A = (sum |I - I_180| - noise term) / sum I over the pixels within
//     1.5 r80, I_180 the stamp rotated by 180 degrees about the centre that minimises A
//     (Conselice, Bershady & Jangren 2000, ApJ 529, 886). Their noise term is measured on a sky
//     patch; here it is its expectation, 2 sigma / sqrt(pi) per pixel, with sigma from the
//     stamp's outer frame, and the flux replaces sum |I| in the denominator (which would count
//     the noise as well).
// Rule (classifyMorphology):
//   A >= 0.35 -> irregular (Conselice 2003, ApJS 147, 1: the asymmetry of mergers and
//     irregulars); otherwise
//   C >= 4.22 -> elliptical (the concentration of a Sersic profile of index n = 2.5, the usual
//     division between discs and spheroids: 2.80 for n = 1, 5.27 for n = 4); otherwise spiral.
// The PSF of the stamp lowers C of small galaxies, so the rule errs towards spirals.
#pragma once

#include <string>

#include "octarc/simulation/SourceStamp.h"

namespace octarc::simulation {

struct MorphologyMeasures {
  double concentration = 0.0;  // C = 5 log10(r80 / r20)
  double asymmetry = 0.0;      // A, 0 for a stamp symmetric under a half turn
};

inline constexpr double kIrregularAsymmetryMin = 0.35;
inline constexpr double kEllipticalConcentrationMin = 4.22;

// NaN measures when the stamp has no positive flux.
MorphologyMeasures measureMorphology(const SourceStamp& stamp);

// The rule above; spiral for NaN measures.
GalaxyType classifyMorphology(const MorphologyMeasures& measures);

// Parses "elliptical", "spiral" or "irregular" (any case, surrounding blanks ignored); false
// for anything else.
bool parseGalaxyType(const std::string& text, GalaxyType* type);

}  // namespace octarc::simulation
