#include "octarc/calibration/NoiseThreshold.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "octarc/core/Error.h"
#include "octarc/core/Parallel.h"
#include "octarc/run/ImageRun.h"
#include "octarc/simulation/Seeds.h"

namespace octarc {

namespace {

constexpr std::size_t kMaxLevelsPerPass = 255;

}  // namespace

void checkNoiseThresholdSettings(const NoiseThresholdSettings& s) {
  if (s.sizePix < 16) throw ConfigError("NOISE_SIZE: must be at least 16 pixels");
  if (s.realisations < 1) throw ConfigError("NOISE_REALISATIONS: must be at least 1");
  if (s.minAreaPix < 1) throw ConfigError("DETECT_MINAREA: must be at least 1");
  if (!(s.stepSigma > 0) || !(s.hiSigma > s.loSigma) || !(s.loSigma > 0)) {
    throw ConfigError("NOISE_THRESH: give 0 < lowest < highest and a positive step");
  }
}

NoiseThresholdResult noiseOnlyThreshold(const NoiseThresholdSettings& s) {
  checkNoiseThresholdSettings(s);
  NoiseThresholdResult out;
  for (int k = 0;; ++k) {
    const double t = s.loSigma + k * s.stepSigma;
    if (t > s.hiSigma + 1e-9 * s.stepSigma) break;
    out.thresholdsSigma.push_back(t);
  }
  if (out.thresholdsSigma.size() > 100000) {
    throw ConfigError("NOISE_THRESH: more than 100000 thresholds (raise the step)");
  }
  DetectionRequest request;
  for (std::size_t k = 0; k < out.thresholdsSigma.size(); ++k) {
    ThresholdLevel l;
    l.level = int(k) + 1;
    l.thresholdAdu = out.thresholdsSigma[k];  // sigma = 1
    l.analysisThresholdAdu = l.thresholdAdu;
    l.thresholdSigma = l.thresholdAdu;
    request.levels.push_back(l);
  }
  request.minAreaPix = s.minAreaPix;
  request.threads = 1;

  const std::size_t rungs = out.thresholdsSigma.size();
  std::vector<std::vector<std::int64_t>> counts(std::size_t(s.realisations));
  parallelForDynamic(s.realisations, resolveThreads(s.threads), [&](std::size_t r) {
    std::mt19937_64 rng = simulation::systemRng(s.seed, r);
    std::normal_distribution<double> noise(0.0, 1.0);
    ImageF pixels(s.sizePix, s.sizePix);
    for (float& v : pixels.pixels()) v = float(noise(rng));
    InMemoryImage description;
    description.sigmaAdu = 1.0;
    description.filter = s.filter ? &*s.filter : nullptr;
    const PreparedImage image = prepareInMemory(std::move(pixels), description);
    // The detector takes at most 255 levels at a time: the ladder in pieces.
    for (std::size_t first = 0; first < request.levels.size(); first += kMaxLevelsPerPass) {
      DetectionRequest piece = request;
      piece.levels.assign(
          request.levels.begin() + std::ptrdiff_t(first),
          request.levels.begin() +
              std::ptrdiff_t(std::min(request.levels.size(), first + kMaxLevelsPerPass)));
      const std::vector<std::int64_t> n = countObjects(image.detectionImage(), piece);
      counts[r].insert(counts[r].end(), n.begin(), n.end());
    }
  });
  out.realisationsWithObjects.assign(rungs, 0);
  out.meanObjects.assign(rungs, 0.0);
  for (const std::vector<std::int64_t>& c : counts) {
    for (std::size_t k = 0; k < rungs; ++k) {
      if (c[k] > 0) ++out.realisationsWithObjects[k];
      out.meanObjects[k] += double(c[k]) / s.realisations;
    }
  }
  out.noiseOnlyThresholdSigma = std::nan("");
  for (std::size_t k = rungs; k-- > 0;) {
    if (out.realisationsWithObjects[k] > 0) break;
    out.noiseOnlyThresholdSigma = out.thresholdsSigma[k];
  }
  out.atLowestRung = out.realisationsWithObjects.front() == 0;
  return out;
}

}  // namespace octarc
