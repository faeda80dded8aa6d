// Population relations for simulated lens systems (METHOD.md section 3), read from a documented,
// user-replaceable text file (default: params/simulation/population.txt).
//
// File format: one "key = value" per line; '#' starts a comment; keys are listed in
// params/simulation/population.txt, which also says which published relation each default
// follows. Unknown or repeated keys, missing keys and nonsense ranges are ConfigErrors naming the
// file and the key.
#pragma once

#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "octarc/simulation/Cosmology.h"
#include "octarc/simulation/SourceStamp.h"

namespace octarc::simulation {

// Number counts dN/dm proportional to 10^(slope m) on [magMin, magMax].
struct MagnitudePowerLaw {
  double magMin = 22.0;
  double magMax = 25.0;
  double slopePerMag = 0.3;
  double sample(std::mt19937_64& rng) const;
};

// log10(r_h / arcsec) = log10(r_h at magRef) + slope (m - magRef) + N(0, scatterDex).
struct MagnitudeSizeRelation {
  double magRef = 22.0;
  double halfLightArcsecAtRef = 0.45;
  double log10SlopePerMag = -0.1;
  double scatterDex = 0.15;
  double sample(double mag, std::mt19937_64& rng) const;
};

// z = z0 + slope (m - magRef) + N(0, scatter), redrawn until zMin <= z <= zMax and z >= zFloor
// (the lens redshift plus a margin, for sources). nullopt when the range is empty or 1000 draws
// all fail: an unlucky combination (e.g. a faint source behind a distant lens), which the caller
// redraws, not an error.
struct MagnitudeRedshiftRelation {
  double magRef = 22.0;
  double zAtRef = 0.7;
  double slopePerMag = 0.15;
  double scatter = 0.25;
  std::optional<double> sample(double mag, double zFloor, double zMin, double zMax,
                               std::mt19937_64& rng) const;
};

// Piecewise-linear table, clamped at both ends.
struct LinearTable {
  std::vector<double> x;
  std::vector<double> y;
  double operator()(double xValue) const;
};

struct SourceDraw {
  double mag = 0.0;
  double halfLightArcsec = 0.0;
  double redshift = 0.0;
};

struct LensDraw {
  double mag = 0.0;
  double redshift = 0.0;
  double absoluteMag = 0.0;
  double sigmaKmPerS = 0.0;
};

struct PopulationModel {
  std::string sourcePath;  // the file read, for messages

  MagnitudePowerLaw sourceMagnitude;
  MagnitudeSizeRelation sourceSize;
  std::map<GalaxyType, MagnitudeRedshiftRelation> sourceRedshift;
  double sourceZMin = 0.2;
  double sourceZMax = 3.0;
  double sourceMinDzBehindLens = 0.1;

  MagnitudePowerLaw lensMagnitude{21.0, 23.0, 0.3};
  MagnitudeRedshiftRelation lensRedshift;
  double lensZMin = 0.05;
  double lensZMax = 1.5;
  // Faber-Jackson: M = absMagStar - 10 log10(sigma / sigmaStar), i.e. L proportional to sigma^4.
  double fjAbsMagStar = -21.6;
  double fjSigmaStarKmPerS = 225.0;
  double fjScatterMag = 0.0;
  LinearTable lensKCorrectionMag;  // K(z) for ellipticals in the survey band
  double sigmaMinKmPerS = 250.0;
  double sigmaMaxKmPerS = 400.0;
  int maxLensAttempts = 100000;

  // Source magnitude, size and a redshift behind zLens (type picks the redshift relation);
  // nullopt when the relation gives no redshift behind this lens at the drawn magnitude (the
  // caller redraws the system). ConfigError naming the file when the type has no relation.
  std::optional<SourceDraw> drawSource(GalaxyType type, double zLens, std::mt19937_64& rng) const;
  // Lens magnitude, redshift and sigma_v from Faber-Jackson (M = m - DM(z) - K(z)), redrawn until
  // sigmaMin < sigma < sigmaMax (and until the redshift relation gives a redshift). Throws
  // ConfigError naming the file and the sigma keys if maxLensAttempts draws all fail (a range that
  // gives no lenses).
  LensDraw drawLens(const FlatLambdaCdm& cosmology, std::mt19937_64& rng) const;
};

// Reads and validates a population file. Throws IoError if it cannot be read, ConfigError
// ("<file>: line N: ..." or "<file>: key <k>: ...") for bad content.
PopulationModel readPopulationModel(const std::string& path);

// The parameter file octarc ships (simulation/population.txt of its data directory, see
// core/DataFiles.h; params/simulation/population.txt in the sources). IoError naming where it
// looked when it is missing.
std::string defaultPopulationModelPath();

}  // namespace octarc::simulation
