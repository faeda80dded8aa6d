// The strong-lens simulation engine (METHOD.md section 3): population draws, rendering with
// octarc::simulation, detection and measurement with the code of `octarc detect`, and the arc
// rules. `octarc simulate lenses` runs it over many systems; the field simulator and the demo
// call it to make single systems.
//
// Reproducibility: everything random about system `index` comes from
// simulation::systemRng(masterSeed, index), in a fixed order (population draw, then noise, then
// the choice of the arc level), so any system can be remade on its own, on any thread. A second
// band's colours and noise come from simulation::secondBandRng(masterSeed, index), so that the
// first band is the same with or without it.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Segment.h"
#include "octarc/core/Table.h"
#include "octarc/detection/Filter.h"
#include "octarc/detection/MultiThresholdDetector.h"
#include "octarc/measure/Colour.h"
#include "octarc/measure/Registry.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/simulation/Cosmology.h"
#include "octarc/simulation/LensSystem.h"
#include "octarc/simulation/Population.h"
#include "octarc/simulation/SourceStamp.h"
#include "octarc/simulation/SyntheticGalaxy.h"

namespace octarc {

// METHOD.md section 3: an arc is an object at least minDistanceArcsec from the lens centre and
// resolved, sqrt(2) * SIZE > minSizeArcsec; a system counts only if the level holding the arc
// has at least minObjects objects (the lens and the arc).
struct ArcRules {
  double minDistanceArcsec = 1.0;
  double minSizeArcsec = 1.0;
  int minObjects = 2;
};

// A colour drawn per system: mean + scatter * N(0, 1), in mag.
struct ColourDraw {
  double meanMag = 0.0;
  double scatterMag = 0.0;  // >= 0; 0: every system gets the mean
};

// A second band (simulate lenses --band): simple colours m_band - m_measurement band, one per
// source and one per lens, Gaussian; not SEDs (no redshift dependence, no K-correction). The
// defaults are g - r for the measurement band r: a blue star-forming source (0.4 +- 0.3) and a
// red early-type lens (1.2 +- 0.1).
struct SecondBand {
  std::string name = "g";  // in column names: MAG_<name>, ARC_COLOUR_<name>, ...
  ColourDraw source{0.4, 0.3};
  ColourDraw lens{1.2, 0.1};
};

// How the systems drawn from the population are chosen for rendering.
//   Plain: every system with theta_E at or above the population's skip limit is rendered
//     (weight 1).
//   Importance: system i is rendered with probability r_i (and weight 1 / r_i), r_i from the
//     drawn lens and source alone (ImportanceSampling), decided with a random stream of its own
//     (simulation::renderRng), so that a rendered system is the same as in a plain run of that
//     seed. Weighted sums over the rendered systems estimate the same sums over every drawn
//     system without bias: a weighted fraction or distribution of the arcs is the plain one.
enum class Sampling { Plain, Importance };

// The render probability of importance sampling: r = clamp(scale * sqrt(p), floor, 1), with p a
// logistic estimate of the probability that the system gives an arc,
//   logit p = c0 + c1 ln(theta_E / d) + c2 (m_s - m_lim) + c3 ln(r_s / FWHM) + c4 (m_l - m_lim),
// d the arc rules' separation limit, m_lim the survey's 5-sigma limiting magnitude in a 2"
// aperture (from the sky sigma and zero point), r_s the source half-light radius, FWHM the
// seeing. sqrt(p) is the proposal that maximises the effective number of arcs per rendered
// system (Kish); the floor keeps every system above the skip limit possible. The coefficients
// were fitted to a plain run of 40 000 `dls` systems (seed 101); for another survey or
// population they remain unbiased, only less efficient. Systems below the skip limit have r = 0.
struct ImportanceSampling {
  double scale = 4.0;
  double floor = 0.005;
  double coefficients[5] = {2.527, 14.751, -2.157, 2.684, 2.857};
};

// Everything fixed for a run: survey, population, lens-light ranges, detection and arc rules.
struct SimulationSetup {
  simulation::ObservingSetup observing;  // stamp grid, PSF, sky sigma, gain, zero point
  simulation::PopulationModel population;
  std::string populationPreset;  // the shipped preset it came from; "" for a file of one's own
  simulation::FlatLambdaCdm cosmology;
  // Lens light (de Vaucouleurs, same position angle as the mass): ellipticity 1 - b/a and
  // half-light radius uniform in these ranges (the population file has no lens-size relation).
  double lensEllipticityMin = 0.0, lensEllipticityMax = 0.5;
  double lensHalfLightMinArcsec = 0.5, lensHalfLightMaxArcsec = 1.5;
  double lensCoreArcsec = 0.0;  // theta_c of the potential
  // Detection levels in ADU, strictly increasing (the survey's thresholds times sky sigma:
  // a stamp has no background to estimate, its noise sigma is known exactly).
  std::vector<double> thresholdsAdu;
  // The same levels as the configuration gives them, in units of the sky sigma (recorded in
  // the output, so that a later run can remake the levels exactly).
  std::vector<double> thresholdsSigma;
  int minAreaPix = 5;                // DETECT_MINAREA
  std::optional<ConvKernel> filter;  // FILTER Y: the .conv kernel; empty for FILTER N
  double saturationAdu = 50000.0;    // SATUR_LEVEL (FLAGS bit 4)
  ArcRules arcRules;
  std::optional<SecondBand> band;  // none: one band, as before
  Sampling sampling = Sampling::Plain;
  ImportanceSampling importance;  // with Sampling::Importance
};

// A source database: noise-free stamps that the population rescales (magnitude, size, rotation).
class SourceDatabase {
 public:
  // `count` built-in synthetic galaxies (types in turn elliptical, spiral, irregular), made from
  // systemRng(seed, i). Their stamps reach stampHalfLightRadii half-light radii (4 by default
  // for speed: the ray tracer's work grows with the stamp's area; a de Vaucouleurs profile holds
  // ~85% of its flux and an exponential disc ~99% inside 4 r_h).
  static SourceDatabase synthetic(int count, std::uint64_t seed,
                                  const simulation::SyntheticGalaxyOptions& options);
  // Every galaxy of a RealGalaxyCatalog file, read once. Throws IoError naming the catalog or
  // the stamp file that is missing or unreadable, or a stamp with no positive flux.
  static SourceDatabase fromRealGalaxyCatalog(const std::string& path);
  // Stamps given directly (tests). Throws ConfigError if empty or a stamp has no positive flux.
  static SourceDatabase fromStamps(std::vector<simulation::SourceStamp> stamps,
                                   std::string description);

  std::size_t size() const { return stamps_.size(); }
  const simulation::SourceStamp& stamp(std::size_t i) const { return stamps_.at(i); }
  // Measured half-light radius of stamp i at its own pixel scale (arcsec).
  double halfLightArcsec(std::size_t i) const { return halfLight_.at(i); }
  const std::string& description() const { return description_; }
  // The synthetic sources' stamp extent in half-light radii; 0 for a RealGalaxyCatalog.
  double syntheticExtentHalfLightRadii() const { return syntheticExtent_; }

 private:
  void add(simulation::SourceStamp stamp);
  std::vector<simulation::SourceStamp> stamps_;
  std::vector<double> halfLight_;
  std::string description_;
  double syntheticExtent_ = 0.0;
};

// One system's drawn parameters (the truth columns of the output).
struct LensSystemDraw {
  std::int64_t index = 0;
  simulation::LensDraw lens;      // magnitude, redshift, absolute magnitude, sigma_v
  simulation::SourceDraw source;  // magnitude, half-light radius, redshift
  std::size_t sourceIndex = 0;    // row of the source database
  double lensEllipticity = 0.0;   // light, 1 - b/a
  double einsteinRadiusArcsec = 0.0;
  simulation::LensSystem system;  // ready for simulation::renderLensSystem
  int redraws = 0;                // pairs drawn again: no source redshift in the range
  // Draws the sampling itself turned down: a lens outside the magnitude window, or a pair not
  // kept by the cross-section weight (D_ls/D_s)^2.
  std::int64_t rejections = 0;
  bool skipped = false;  // theta_E below the population's skip limit: drawn, not rendered
  // The probability that the system is rendered (Sampling) and whether it was; a rendered
  // system has the weight 1 / renderProbability. A system not rendered has no source position,
  // rotation or size on the sky (NaN).
  double renderProbability = 1.0;
  bool rendered = true;
  double weight() const { return rendered ? 1.0 / renderProbability : 0.0; }
};

// The seed stream of the synthetic source database of `simulate lenses`: its own, so that the
// same sources serve every master seed.
constexpr std::uint64_t kSyntheticSourceSeed = 0x5EEDDA7AULL;

// CPU seconds spent per stage (summed over systems and threads).
struct StageTimings {
  double drawSec = 0, rayTraceSec = 0, lensLightSec = 0, psfSec = 0, noiseSec = 0;
  double detectionSec = 0;  // filter, detection and measurement (one pass, run/ImageRun.h)
  double arcRulesSec = 0;
  void add(const StageTimings& other);
  double totalSec() const;
};

// The population draw of system `index`, as a rejection sampler of the joint distribution
// VDF x dV/dz x source counts x cross-section (simulation/Population.h): a lens (sigma_v from the
// VDF times sigma^4, z from the volume, magnitude from Faber-Jackson, kept inside the magnitude
// window), a source (database pick, magnitude, size, redshift for its type), the pair kept with
// probability (D_ls/D_s)^2; anything turned down is drawn again from the same stream (counted in
// `redraws` when the source relation gave no redshift, in `rejections` otherwise), ConfigError
// after the population's max_attempts. Then the lens light shape, Einstein radius, source
// position uniform inside the multiply-imaged region of the lens
// (simulation/MultipleImageRegion.h), random rotation; `skipped` when theta_E is below the
// population's skip limit.
// With Sampling::Importance the render decision takes `renderUniform`, a uniform deviate in
// [0, 1) from simulation::renderRng(masterSeed, index) (ConfigError without one); a system not
// rendered is returned before its source is placed.
// Reads the first values of `rng`, which must be systemRng(masterSeed, index).
LensSystemDraw drawLensSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                              std::int64_t index, std::mt19937_64& rng,
                              std::optional<double> renderUniform = std::nullopt);
LensSystemDraw drawLensSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                              std::uint64_t masterSeed, std::int64_t index);

// The render probability of a drawn system (lens, source magnitude and size, theta_E known):
// 0 below the skip limit, else 1 (Plain) or ImportanceSampling's r (Importance).
double renderProbability(const SimulationSetup& setup, const LensSystemDraw& draw);
// The survey's 5-sigma limiting magnitude in a 2" aperture, from the sky sigma and zero point.
double limitingMagnitude(const simulation::ObservingSetup& observing);

// The measured columns of every detected object (one table row per object per level).
const std::vector<ColumnSpec>& measuredColumns();
// The plan measuring measuredColumns().
const MeasurementPlan& measuredPlan();

// Which rows of `objects` (columns measuredColumns()) are arcs, and the chosen one.
struct ArcSelection {
  std::vector<std::int64_t> arcRows;   // every arc row at a qualifying level, in table order
  std::int64_t chosenRow = -1;         // -1: no arc (ARC_FOUND = 0)
  std::vector<double> distanceArcsec;  // distance to the lens of every row of `objects`
};

// Applies `rules` to measured objects. A level qualifies when it holds at least
// rules.minObjects objects and at least one arc. One qualifying level is drawn uniformly with
// `rng` (seeded per system); the arc of that level with the largest FLUX_ISO is chosen.
// lensXPix/lensYPix are 0-based (X_IMAGE/Y_IMAGE are 1-based, as in SExtractor).
ArcSelection selectArcs(const Table& objects, double lensXPix, double lensYPix,
                        double pixelScaleArcsec, const ArcRules& rules, std::mt19937_64& rng);

// One object's isophotal magnitudes in the measurement band and in the second band, in the same
// footprint (measure/Colour.h).
struct BandPair {
  BandMagnitude measurement, band;
};

// A system's magnitudes in both bands: of every arc row (ArcSelection::arcRows order) and of
// its lens, the object holding the lens centre, found as the search finds an arc's lens among
// the objects of level 1 and of the arc's level that are not the arc or below it: at level 1
// when that object there does not also hold the arc row, else at the arc row's level when it is
// another object there; NaN when neither (the lens is not detected apart from the arc). A system
// without an arc row has its lens at level 1 (levelOneLens; NaN without an object there).
struct SecondBandMagnitudes {
  std::vector<BandPair> arcs, lenses;  // per arc row
  BandPair levelOneLens;
};

struct SimulatedSystem {
  LensSystemDraw draw;
  // The second band (setup.band): the colours drawn (NaN without a band) and the magnitudes.
  double sourceColourMag = std::numeric_limits<double>::quiet_NaN();
  double lensColourMag = std::numeric_limits<double>::quiet_NaN();
  SecondBandMagnitudes band;
  double magnification = 0.0;             // traced source flux / unlensed flux (before the PSF)
  std::vector<std::int64_t> levelCounts;  // objects per level
  Table objects;                          // every detected object, measuredColumns()
  ArcSelection arcs;
  ImageF image;  // the stamp (kept only when asked)
};

// The first half of simulateSystem: the draw and the rendered stamp with its noise (empty when
// the draw is skipped), and the system's random stream where the second half continues it (the
// choice of the arc level). The stamp does not depend on the detection levels, so studies that
// vary only those render each system once.
struct RenderedSystem {
  LensSystemDraw draw;
  double magnification = 0.0;
  ImageF image;  // empty when skipped
  std::mt19937_64 rng;
  // With setup.band: its colours (drawn even for a skipped system) and its stamp (empty when
  // skipped).
  double sourceColourMag = std::numeric_limits<double>::quiet_NaN();
  double lensColourMag = std::numeric_limits<double>::quiet_NaN();
  ImageF bandImage;
};
RenderedSystem renderSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                            std::uint64_t masterSeed, std::int64_t index,
                            StageTimings* timings = nullptr);

// The second half: detection at setup.thresholdsAdu, measurement and the arc rules (the level
// drawn from `rng`); with setup.band the footprints are kept for the second band's magnitudes.
struct DetectedSystem {
  PreparedImage prepared;
  std::vector<std::int64_t> levelCounts;
  Table objects;
  ArcSelection arcs;
  std::optional<SegmentationRuns> footprints;
};
DetectedSystem detectSystem(ImageF image, const SimulationSetup& setup, std::mt19937_64& rng,
                            StageTimings* timings = nullptr);

// The magnitudes of `detected` (its footprints kept) in its measurement image and in `bandImage`
// (the second band's stamp, same grid, noise and zero point). Error without footprints.
SecondBandMagnitudes measureSecondBand(const DetectedSystem& detected, const ImageF& bandImage,
                                       const SimulationSetup& setup);

// Draws, renders, detects at setup.thresholdsAdu (the stamp is background-free with known
// sigma: no background is estimated), measures every object with measuredPlan() and applies
// the arc rules. A draw not rendered (skipped, or left out by importance sampling) has no
// objects, a NaN magnification and a blank stamp.
// Adds the time of each stage to *timings when given.
SimulatedSystem simulateSystem(const SimulationSetup& setup, const SourceDatabase& sources,
                               std::uint64_t masterSeed, std::int64_t index, bool keepImage,
                               StageTimings* timings = nullptr);

// A simulated stamp (background-free, noise sigma known: no background is estimated) as a
// PreparedImage: filtered with setup.filter, saturated pixels at setup.saturationAdu.
PreparedImage prepareStamp(ImageF pixels, const SimulationSetup& setup);

// Detection and measurement of a prepared stamp through the run API (run/ImageRun.h), as
// `octarc detect` does it, one thread. Returns the objects (measuredColumns(), ordered by level
// then NUMBER) and fills levelCounts, and *footprints when given (every object's footprint).
Table detectAndMeasure(PreparedImage& image, const SimulationSetup& setup,
                       std::vector<std::int64_t>* levelCounts, StageTimings* timings = nullptr,
                       std::optional<SegmentationRuns>* footprints = nullptr);

}  // namespace octarc
