// Sky noise for simulated stamps (METHOD.md section 3).
#pragma once

#include <random>

#include "octarc/core/Image.h"

namespace octarc::simulation {

// Adds a background of B = (sigma g)^2 / g ADU (so (sigma g)^2 electrons, whose Poisson noise is
// sigma ADU per pixel), draws each pixel's electron count from a Poisson distribution of mean
// (value + B) g (negative values clipped to 0), converts back to ADU and subtracts B. Counts
// above kGaussianNoiseThresholdElectrons are drawn from the Gaussian approximation N(mean, mean)
// (relative skewness error 1/sqrt(mean) < 3%), which is much faster for the usual sky levels.
// Throws ConfigError unless sigmaAdu > 0 and gain > 0.
void addPoissonSkyNoise(ImageD& image, double sigmaAdu, double gainElectronsPerAdu,
                        std::mt19937_64& rng);

constexpr double kGaussianNoiseThresholdElectrons = 1000.0;

// Per-pixel sky sigma (ADU) of a survey whose 5-sigma limiting magnitude in a circular aperture
// of diameter apertureArcsec is limitingMag: the aperture flux 10^(-0.4 (m - zp)) equals
// nSigma sigma sqrt(N_pix), N_pix = pi (d/2)^2 / pixelScale^2.
double skySigmaFromLimitingMagnitude(double limitingMag, double magZeroPoint, double apertureArcsec,
                                     double pixelScaleArcsec, double nSigma = 5.0);

}  // namespace octarc::simulation
