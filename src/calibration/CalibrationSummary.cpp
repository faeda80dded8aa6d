#include "octarc/calibration/CalibrationSummary.h"

#include <cmath>
#include <cstdio>
#include <iostream>

#include "octarc/calibration/Weights.h"
#include "octarc/core/Format.h"

namespace octarc {

namespace {

// The colour cut study: the MAX for each completeness level, then the table every 0.25 mag.
void printColourCut(const ColourCutStudy& c) {
  std::printf("Colour cut COLOUR_CUT %s,MAX on %s (%s; %lld with both colours):\n", c.band.c_str(),
              countWithEffective(c.arcs.count, c.arcs.effective()).c_str(), c.arcSelection.c_str(),
              static_cast<long long>(c.withColours));
  for (const ColourCutLevel& l : c.levels) {
    std::printf("  %3.0f%% of the arcs kept from MAX = %s\n", 100.0 * l.completeness,
                std::isinf(l.maxMag) ? "any" : formatNumber(l.maxMag, "%.3f", true).c_str());
  }
  std::printf("  MAX [mag]  kept\n");
  for (const ColourCutRow& row : c.rows) {
    const double quarters = row.maxMag / 0.25;
    if (std::abs(quarters - std::round(quarters)) > 1e-6) continue;
    std::printf("  %9.2f  %.4f %s\n", row.maxMag, row.fraction.fraction,
                intervalText(row.fraction).c_str());
  }
}

}  // namespace

void printCalibrationSummary(const CalibrationRun& run, const CalibrationResult& r) {
  std::printf("%lld simulated systems, %s with an arc >= 1\" from the lens\n",
              static_cast<long long>(r.simulatedSystems),
              countWithEffective(r.arcSystems.count, r.arcSystems.effective(), "systems").c_str());
  std::printf(
      "Lensing fraction (of the systems with an arc, 68%% intervals):\n  ARCNESS      all         "
      "                e > %g, S/N > %g\n",
      run.settings.fractionCuts.ellipticityMin, run.settings.fractionCuts.snrMin);
  for (std::size_t i = 0; i + 1 < r.fractions.rows.size(); i += 2) {
    const FractionRow& a = r.fractions.rows[i];
    const FractionRow& d = r.fractions.rows[i + 1];
    const std::string range = std::isfinite(a.arcnessHi) ? formatNumber(a.arcnessLo, "%.2f") + "-" +
                                                               formatNumber(a.arcnessHi, "%.2f")
                                                         : "> " + formatNumber(a.arcnessLo, "%.2f");
    std::printf("  %-10s  %.4f %s      %.4f %s\n", range.c_str(), a.fraction.fraction,
                intervalText(a.fraction).c_str(), d.fraction.fraction,
                intervalText(d.fraction).c_str());
  }
  for (const Distribution& d : r.distributions) {
    if (!d.gaussian) continue;
    std::printf("%s of the arcs with %s: Gaussian fit FWHM %s (mean %s)%s\n", d.name.c_str(),
                d.selection.c_str(), formatNumber(d.gaussian->fwhm, "%.3f", true).c_str(),
                formatNumber(d.gaussian->mean, "%.3f", true).c_str(),
                d.gaussian->converged ? "" : ", not converged");
  }
  if (r.noise) {
    std::printf(
        "Noise-only threshold: %s%s sigma (%d realisations of %d^2 pixels, "
        "DETECT_MINAREA %d)\n",
        r.noise->atLowestRung ? "<= " : "",
        formatNumber(r.noise->noiseOnlyThresholdSigma, "%.2f", true).c_str(),
        run.settings.noise->realisations, run.settings.noise->sizePix,
        run.settings.noise->minAreaPix);
  }
  if (r.thresholdCount) {
    std::printf("Arcs with ARCNESS > 0.10 against the number of thresholds (%lld systems each",
                static_cast<long long>(run.settings.thresholdCount->systems));
    if (!r.thresholdCount->rows.empty()) {
      std::printf(", %lld rendered", static_cast<long long>(r.thresholdCount->rows[0].rendered));
    }
    std::printf("):\n");
    for (const ThresholdCountRow& row : r.thresholdCount->rows) {
      std::printf("  %3d levels  %.4f %s  (%s)\n", row.levels, row.fraction.fraction,
                  intervalText(row.fraction).c_str(),
                  countWithEffective(row.withArcness.count, row.withArcness.effective()).c_str());
    }
    std::printf("  flat (within 1 sigma of the most levels) from %d levels\n",
                r.thresholdCount->flattensAtLevels);
  }
  if (r.snrFloor) {
    std::fflush(stdout);
    printSnrFloor(std::cout, *r.snrFloor, *run.settings.snrFloor);
    std::cout.flush();
  }
  if (r.colourCut) printColourCut(*r.colourCut);
  const GridOutcome& g = r.grid;
  const std::string arcs = countWithEffective(g.samples.count, g.samples.effective());
  if (g.skipped) {
    std::printf("Occupation grid: none (GRID_NAME NONE)\n");
  } else if (g.grid) {
    std::printf(
        "Occupation grid: %s, %zu axes, %d bins per axis (finest connected at P = %g), %lld of "
        "%lld occupied bins selected\n",
        arcs.c_str(), g.usedAxes.size(), g.searches.back().result.finestConnected, g.options.level,
        static_cast<long long>(g.grid->contour.selectedBins),
        static_cast<long long>(g.grid->grid.occupiedBins()));
  } else {
    std::printf("Occupation grid: none (%s)\n", arcs.c_str());
  }
}

}  // namespace octarc
