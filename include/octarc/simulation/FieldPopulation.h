// The objects of a simulated survey field (`octarc simulate field`): field galaxies with number
// counts, sizes and a morphology mix, stars with power-law counts, and injected galaxy-galaxy
// lens systems, each rendered into its own small stamp so that no profile is evaluated over the
// whole image.
//
// Coordinates: 0-based survey pixel indices (core/Conventions.h); the truth list converts them to
// 1-based FITS pixels. Galaxy and lens stamps are drawn before the PSF (the field is convolved
// once as a whole); star stamps are drawn already convolved (pixel-integrated Gaussian PSF).
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/simulation/LensModel.h"
#include "octarc/simulation/LensSystem.h"
#include "octarc/simulation/Population.h"
#include "octarc/simulation/SourceStamp.h"

namespace octarc::simulation {

// The kind column of the truth list.
enum class FieldObjectKind { LensGalaxy = 1, LensedSource = 2, Galaxy = 3, Star = 4 };

// Differential number counts dN/dm = densityAtRef 10^(slope (m - magRef)) per deg^2 per mag on
// [magMin, magMax].
struct NumberCounts {
  double magMin = 17.0;
  double magMax = 26.5;
  double slopePerMag = 0.35;
  double magRef = 24.0;
  double densityAtRefPerDeg2PerMag = 3.0e4;

  // Expected number in an area of areaDeg2 (the integral of dN/dm over [magMin, magMax]).
  double expectedCount(double areaDeg2) const;
  // The magnitude distribution, for drawing.
  MagnitudePowerLaw magnitudes() const { return {magMin, magMax, slopePerMag}; }
};

// The field population. Defaults: a high-latitude R-band field.
//  - Galaxies: slope 0.35 dex/mag and about 3e4 per deg^2 per mag at R = 24, roughly the faint
//    R-band counts of deep surveys (e.g. Metcalfe et al. 2001, MNRAS 323, 795), drawn to
//    half a magnitude below the default 5-sigma limit so that the faintest ones add to the noise.
//  - Sizes: the source magnitude-size relation of params/simulation/population.txt
//    (0.45" at R = 22, -0.1 dex/mag, 0.15 dex scatter); ellipticals follow their own, more
//    compact-at-faint-magnitudes relation (1.2" at R = 18, -0.12 dex/mag).
//  - Morphology: the elliptical fraction falls from 40% at R < 19 to 15% at the faint end, the
//    rest being spirals, with 30% irregulars among the faint ones; ellipticals brighter than
//    haloMagLimit get an extended de Vaucouleurs halo drawn out to haloRadiusInHalfLight r_e.
//  - Stars: slope 0.12 dex/mag and about 170 per deg^2 per mag at R = 20 (a few hundred
//    stars brighter than R = 20 per deg^2, as at high Galactic latitude), R = 14 to 25.
struct FieldPopulationParams {
  NumberCounts galaxies;
  NumberCounts stars{14.0, 25.0, 0.12, 20.0, 170.0};
  MagnitudeSizeRelation diskSize{22.0, 0.45, -0.10, 0.15};
  MagnitudeSizeRelation ellipticalSize{18.0, 1.2, -0.12, 0.10};
  double brightMag = 19.0;                 // "bright" for the morphology mix
  double ellipticalFractionBright = 0.40;  // m < brightMag
  double ellipticalFractionFaint = 0.15;   // m >= brightMag
  double irregularFractionFaint = 0.30;    // among faint non-ellipticals
  double haloMagLimit = 20.0;              // ellipticals brighter than this get a halo
  double stampHalfLightRadii = 6.0;        // galaxy stamp half-width, in r_e
  // Fainter galaxies (most of them, too faint for their outskirts to matter) get smaller stamps.
  double faintStampMag = 24.0;
  double faintStampHalfLightRadii = 4.0;
  double haloRadiusInHalfLight = 15.0;  // halo stamp half-width, in r_e
  double maxHalfLightArcsec = 6.0;      // sizes are capped here
};

// One field galaxy or star (its own random stream renders it: index seeds systemRng).
struct FieldObject {
  FieldObjectKind kind = FieldObjectKind::Galaxy;
  double xPix = 0.0, yPix = 0.0;  // 0-based centre
  double mag = 0.0;
  GalaxyType type = GalaxyType::Spiral;
  double halfLightArcsec = 0.0;  // galaxies
  double axisRatio = 1.0;        // ellipticals: b/a
  double positionAngleRad = 0.0;
  bool halo = false;
};

// Draws the galaxies, then the stars, of a width x height field of pixelScaleArcsec pixels:
// Poisson numbers with the expected counts, uniform positions, magnitudes from the counts.
// Positions of objects brighter than keepOutMag within keepOutRadiusPix of any keepOut point
// are redrawn (so injected lenses are not buried under a bright star or galaxy).
std::vector<FieldObject> drawFieldObjects(const FieldPopulationParams& params, int width,
                                          int height, double pixelScaleArcsec, std::mt19937_64& rng,
                                          const std::vector<Vec2>& keepOutPix = {},
                                          double keepOutRadiusPix = 0.0, double keepOutMag = 0.0);

// A rectangle of pixels to be added to the field with its lower-left pixel at (x0, y0).
struct Stamp {
  ImageD pixels;
  std::int64_t x0 = 0, y0 = 0;
};

// Adds the stamp to the image; the parts outside the image are dropped.
void addStamp(ImageD& image, const Stamp& stamp);

// A galaxy before the PSF. Ellipticals: a de Vaucouleurs profile integrated over each pixel, out
// to stampHalfLightRadii (haloRadiusInHalfLight with a halo) half-light radii, so the stamp holds
// the profile's flux inside that square. Spirals and irregulars: a synthetic galaxy
// (makeSyntheticGalaxy, drawn from rng, out to stampHalfLightRadii or, fainter than
// faintStampMag, faintStampHalfLightRadii) made at a third of the pixel scale and summed in 3x3
// blocks, so the stamp holds exactly the total flux; its centre is placed to a third of a pixel,
// and the centre actually used is returned in xUsedPix / yUsedPix (may be null).
Stamp renderGalaxyStamp(const FieldObject& galaxy, const FieldPopulationParams& params,
                        double pixelScaleArcsec, double magZeroPoint, std::mt19937_64& rng,
                        double* xUsedPix = nullptr, double* yUsedPix = nullptr);

// A point source through a Gaussian PSF of seeingFwhmArcsec, each pixel the PSF integrated over
// it; the stamp reaches out to where the profile falls below minValueAdu (at least 5 sigma).
Stamp renderStarStamp(double xPix, double yPix, double fluxAdu, double seeingFwhmArcsec,
                      double pixelScaleArcsec, double minValueAdu);

// Sets every pixel above saturationAdu to saturationAdu; returns how many were clipped.
std::int64_t clipSaturation(ImageF& image, float saturationAdu);

// An injected galaxy-galaxy lens system, rendered.
struct FieldLens {
  double xPix = 0.0, yPix = 0.0;  // lens centre, 0-based
  LensSystem system;              // what was rendered
  double magnification = 0.0;     // traced source flux / unlensed source flux
  // The separate images of the lensed source: flux centroid (0-based) and magnitude.
  struct LensedImage {
    double xPix = 0.0, yPix = 0.0, mag = 0.0;
  };
  std::vector<LensedImage> images;
  Stamp stamp;  // lens light + lensed source, before the PSF
};

// How far from its lens centre (arcsec) a system's lensed light can reach: no ray from farther
// out lands on the source (|beta| + the source stamp's half-diagonal + the largest deflection).
double lensedLightReachArcsec(const LensSystem& system, const SourceStamp& source);

// Renders a drawn lens system noise-free and before the PSF, with the lens centre at
// (xPix, yPix): the source stamp, rescaled to system.sourceMag (its pixel sum taken as its total
// flux), traced through the elliptical potential (system.source gives its position, rotation and
// size), plus the de Vaucouleurs lens light of system.lensMag. The stamp reaches every pixel whose
// ray can land on the source and eight lens half-light radii. The separate images are the
// 8-connected parts of the traced light above 2% of its peak that hold at least 5% of its flux.
// Throws ConfigError for invalid parameters or a source without positive flux.
FieldLens renderFieldLens(const LensSystem& system, const SourceStamp& source, double xPix,
                          double yPix, double pixelScaleArcsec, double magZeroPoint);

// Header cards of a TAN projection centred on the image: CRPIX at the image centre, CRVAL =
// (raDeg, decDeg), north up and east left (CD1_1 = -scale, CD2_2 = +scale), ICRS.
FitsHeader tanWcsHeader(int width, int height, double pixelScaleArcsec, double raDeg,
                        double decDeg);

}  // namespace octarc::simulation
