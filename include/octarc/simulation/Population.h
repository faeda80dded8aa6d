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

// The velocity dispersion function of early-type galaxies as a modified Schechter function
// (Sheth et al. 2003, ApJ 594, 225):
//   phi(sigma) dsigma = phi* (sigma/sigma*)^alpha exp(-(sigma/sigma*)^beta) beta/Gamma(alpha/beta)
//                       dsigma/sigma,
// with the SDSS early-type fit of Choi, Park & Vogeley 2007 (ApJ 658, 884) as default.
struct VelocityDispersionFunction {
  double phiStarH3PerMpc3 = 8.0e-3;  // phi*, in h^3 Mpc^-3
  double sigmaStarKmPerS = 161.0;
  double alpha = 2.32;
  double beta = 2.67;
  // phi(sigma), h^3 Mpc^-3 (km/s)^-1.
  double density(double sigmaKmPerS) const;
  // A sigma with density proportional to phi(sigma) sigma^power on (lo, hi): x =
  // (sigma/sigma*)^beta then follows a Gamma((alpha + power)/beta) law, drawn until sigma falls
  // inside (at most maxDraws times; nullopt after that).
  std::optional<double> sampleWeighted(double power, double loKmPerS, double hiKmPerS, int maxDraws,
                                       std::mt19937_64& rng) const;
};

// Redshifts with density proportional to the comoving volume element dV_C/dz on [zMin, zMax]
// (a non-evolving comoving density): inverse of the CDF tabulated on `nodes` redshifts, linear
// between them.
class ComovingVolumeRedshifts {
 public:
  ComovingVolumeRedshifts() = default;
  ComovingVolumeRedshifts(const FlatLambdaCdm& cosmology, double zMin, double zMax,
                          int nodes = 2048);
  double sample(std::mt19937_64& rng) const;
  bool empty() const { return z_.empty(); }
  const CosmologyParams& cosmology() const { return cosmology_; }

 private:
  CosmologyParams cosmology_;
  std::vector<double> z_;
  std::vector<double> cdf_;
};

struct PopulationModel {
  std::string sourcePath;  // the file read, for messages
  std::string name;        // the file name without extension, e.g. "population-dls"

  MagnitudePowerLaw sourceMagnitude;
  MagnitudeSizeRelation sourceSize;
  std::map<GalaxyType, MagnitudeRedshiftRelation> sourceRedshift;
  double sourceZMin = 0.2;
  double sourceZMax = 3.0;
  double sourceMinDzBehindLens = 0.1;

  VelocityDispersionFunction lensVdf;
  double sigmaMinKmPerS = 250.0;
  double sigmaMaxKmPerS = 400.0;
  double lensZMin = 0.05;
  double lensZMax = 1.5;
  // Apparent magnitude window of the lenses (a selection on the drawn population).
  double lensMagMin = 21.0;
  double lensMagMax = 23.0;
  // Faber-Jackson: M = absMagStar - 10 log10(sigma / sigmaStar) + N(0, scatter), i.e. L
  // proportional to sigma^4, then m = M + DM(z) + K(z).
  double fjAbsMagStar = -21.6;
  double fjSigmaStarKmPerS = 225.0;
  double fjScatterMag = 0.0;
  LinearTable lensKCorrectionMag;  // K(z) for ellipticals in the survey band
  // Systems with theta_E below this are drawn (and counted) but not rendered: they cannot give
  // an arc beyond the separation limit. 0 renders everything.
  double skipEinsteinRadiusBelowArcsec = 0.0;
  int maxLensAttempts = 100000;
  ComovingVolumeRedshifts lensRedshifts;  // for the cosmology of tabulate()

  // (Re)builds the redshift table for `cosmology`; readPopulationModel calls it for the default
  // flat LambdaCDM.
  void tabulate(const FlatLambdaCdm& cosmology);

  // One lens draw: sigma_v from the VDF weighted by sigma^4 (the SIS cross-section
  // pi theta_E^2 is proportional to sigma^4 (D_ls/D_s)^2; the distance factor is the caller's,
  // see lensingWeight), z from dV_C/dz, M from Faber-Jackson and m = M + DM + K; nullopt when m
  // falls outside the magnitude window (the caller draws again). ConfigError naming the file
  // and the sigma keys when the sigma range gives no draws at all.
  std::optional<LensDraw> drawLens(const FlatLambdaCdm& cosmology, std::mt19937_64& rng) const;
  // Source magnitude, size and redshift (in [sourceZMin, sourceZMax]; type picks the relation);
  // nullopt when the relation gives no redshift in the range at the drawn magnitude.
  // ConfigError naming the file when the type has no relation.
  std::optional<SourceDraw> drawSource(GalaxyType type, std::mt19937_64& rng) const;
  // The distance part of the cross-section, (D_ls/D_s)^2 in [0, 1): the probability of keeping
  // a lens-source pair; 0 unless the source lies sourceMinDzBehindLens behind the lens.
  double lensingWeight(double zLens, double zSource, const FlatLambdaCdm& cosmology) const;
};

// Reads and validates a population file. Throws IoError if it cannot be read, ConfigError
// ("<file>: line N: ..." or "<file>: key <k>: ...") for bad content.
PopulationModel readPopulationModel(const std::string& path);

// The parameter file octarc ships (simulation/population.txt of its data directory, see
// core/DataFiles.h; params/simulation/population.txt in the sources). IoError naming where it
// looked when it is missing.
std::string defaultPopulationModelPath();

// The shipped presets: "physical" (population.txt, the default) and "dls" (population-dls.txt,
// the Deep Lens Survey setup of Kubo & Dell'Antonio 2008).
std::vector<std::string> populationPresetNames();
// The file of a preset; ConfigError naming the known presets for another name.
std::string populationPresetPath(const std::string& preset);

}  // namespace octarc::simulation
