// Per-system cost of simulated lens stamps: 26" x 26" at 0.257"/px (101 x 101 px), source
// ray-traced at 0.03"/px with 4x4 sub-pixels, de Vaucouleurs lens light, 0.9" Gaussian PSF,
// Poisson sky noise with gain 54.
// Usage: octarc_simulation_benchmark [systems] [master seed] [source stamp radius / r_half].
#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <vector>

#include "octarc/simulation/Cosmology.h"
#include "octarc/simulation/LensLight.h"
#include "octarc/simulation/LensModel.h"
#include "octarc/simulation/LensSystem.h"
#include "octarc/simulation/MultipleImageRegion.h"
#include "octarc/simulation/Noise.h"
#include "octarc/simulation/Population.h"
#include "octarc/simulation/Psf.h"
#include "octarc/simulation/RayTracer.h"
#include "octarc/simulation/Seeds.h"
#include "octarc/simulation/SyntheticGalaxy.h"

using namespace octarc;
using namespace octarc::simulation;
using Clock = std::chrono::steady_clock;

namespace {
// CPU time of this thread in ms: the machine is shared, so wall time overstates the cost.
double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
}  // namespace

int main(int argc, char** argv) {
  const int systems = argc > 1 ? std::atoi(argv[1]) : 200;
  const std::uint64_t master = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  SyntheticGalaxyOptions galaxyOptions;  // third argument: stamp radius in half-light radii
  if (argc > 3) galaxyOptions.stampHalfLightRadii = std::atof(argv[3]);
  const ObservingSetup setup;  // 101 x 101 px at 0.257", 0.9" seeing, gain 54, sigma 1 ADU
  const FlatLambdaCdm cosmo;
  // The population file of the source tree (this program is not installed).
  const PopulationModel population =
      readPopulationModel(OCTARC_SOURCE_DIR "/params/simulation/population.txt");
  const std::vector<double> psf = gaussianPsfKernel1d(0.9, 0.257, PsfSampling::PointSampled);

  // A database of 30 synthetic sources, made once (like reading a catalog).
  std::vector<SourceStamp> database;
  for (int i = 0; i < 30; ++i) {
    auto rng = systemRng(master ^ 0xDA7ABA5EULL, i);
    database.push_back(makeSyntheticGalaxy(static_cast<GalaxyType>(i % 3), rng, galaxyOptions));
  }
  std::vector<double> databaseRh;
  for (const SourceStamp& s : database) databaseRh.push_back(halfLightRadiusArcsec(s));

  const auto wallStart = Clock::now();
  double tDraw = 0, tTrace = 0, tLight = 0, tPsf = 0, tNoise = 0, tRender = 0;
  long long rays = 0, skipped = 0, total = 0;
  double checksum = 0.0;
  for (int i = 0; i < systems; ++i) {
    const double t0 = threadCpuMs();
    auto rng = systemRng(master, i);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::optional<LensDraw> lensDrawn = population.drawLens(cosmo, rng);
    if (!lensDrawn) continue;  // outside the lens magnitude window: the engine draws again
    const LensDraw& lensDraw = *lensDrawn;
    const std::size_t pick = std::uniform_int_distribution<std::size_t>(0, 29)(rng);
    const SourceStamp& src = database[pick];
    const std::optional<SourceDraw> drawn = population.drawSource(src.type, rng);
    // No source redshift, or a source not behind the lens: the engine draws the pair again.
    if (!drawn || population.lensingWeight(lensDraw.redshift, drawn->redshift, cosmo) <= 0.0)
      continue;
    const SourceDraw& srcDraw = *drawn;
    const double b =
        sisEinsteinRadiusArcsec(lensDraw.sigmaKmPerS, lensDraw.redshift, srcDraw.redshift, cosmo);
    // Lens light: ellipticity 0-0.5 and r_e 0.5-1.5" here (placeholders for the engine's draw).
    const double lightE = 0.5 * unit(rng);
    const double pa = std::numbers::pi * unit(rng);
    LensSystem sys;
    sys.mass = {b, potentialEllipticityFromLight(lightE), 0.0, pa};
    sys.light = {4.0, 0.5 + unit(rng), 1.0 - lightE, pa, 0.0};
    sys.lensMag = lensDraw.mag;
    sys.source.betaArcsec = MultipleImageRegion(sys.mass).drawUniform(rng);
    sys.source.rotationRad = 2.0 * std::numbers::pi * unit(rng);
    sys.source.pixelScaleArcsec = src.pixelScaleArcsec * srcDraw.halfLightArcsec / databaseRh[pick];
    sys.sourceMag = srcDraw.mag;
    const EllipticalPotentialLens lens(sys.mass);
    const double t1 = threadCpuMs();
    // The stages of renderLensSystem, timed one by one.
    RayTraceStats stats;
    ImageD img = traceLensedImage(lens, src, sys.source, setup.grid, setup.rayTrace, &stats);
    const double sourceFlux = fluxFromMagnitude(sys.sourceMag, setup.magZeroPoint);
    for (double& v : img.pixels()) v *= sourceFlux;
    const double t2 = threadCpuMs();
    SersicLightParams light = sys.light;
    light.totalFlux = fluxFromMagnitude(sys.lensMag, setup.magZeroPoint);
    addSersicLight(img, setup.grid, light);
    const double t3 = threadCpuMs();
    img = convolveSeparable(img, psf);
    const double t4 = threadCpuMs();
    addPoissonSkyNoise(img, setup.skySigmaAdu, setup.gainElectronsPerAdu, rng);
    const double t5 = threadCpuMs();
    // The same system through renderLensSystem, for the end-to-end figure.
    auto rngCopy = systemRng(master, i);
    const RenderedLensSystem rendered = renderLensSystem(sys, src, setup, rngCopy);
    const double t6 = threadCpuMs();
    tRender += t6 - t5;
    checksum += rendered.magnification;
    auto ms = [](double a, double z) { return z - a; };
    tDraw += ms(t0, t1);
    tTrace += ms(t1, t2);
    tLight += ms(t2, t3);
    tPsf += ms(t3, t4);
    tNoise += ms(t4, t5);
    rays += stats.raysTraced;
    skipped += stats.finePixelsSkipped;
    total += stats.finePixelsTotal;
  }
  const double n = systems;
  const double wallMs = std::chrono::duration<double, std::milli>(Clock::now() - wallStart).count();
  std::printf("systems %d (101 x 101 px at 0.257\"/px, 0.03\"/px x 4x4 rays)\n", systems);
  std::printf(
      "per system, CPU ms: draw %.3f  ray trace %.3f  lens light %.3f  PSF %.3f  noise %.3f"
      "  total %.3f\n",
      tDraw / n, tTrace / n, tLight / n, tPsf / n, tNoise / n,
      (tDraw + tTrace + tLight + tPsf + tNoise) / n);
  std::printf("per system, CPU ms: renderLensSystem (trace + light + PSF + noise) %.3f\n",
              tRender / n);
  std::printf("per system, wall ms for all of the above, both passes (shared machine): %.3f\n",
              wallMs / n);
  std::printf("rays per system %.0f, fine pixels skipped %.1f%%  (checksum %.6g)\n", rays / n,
              100.0 * skipped / total, checksum);
  return 0;
}
