// Reproducible random streams: every simulated system gets its own std::mt19937_64 whose seed is
// derived from the run's master seed and the system index, so results do not depend on the
// order or thread in which systems are made.
#pragma once

#include <cstdint>
#include <random>

namespace octarc::simulation {

// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mixer.
constexpr std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// Seed of system `index` in a run with `masterSeed`.
constexpr std::uint64_t systemSeed(std::uint64_t masterSeed, std::uint64_t index) {
  return splitMix64(splitMix64(masterSeed) ^ splitMix64(index + 0x632BE59BD9B4E019ULL));
}

inline std::mt19937_64 systemRng(std::uint64_t masterSeed, std::uint64_t index) {
  return std::mt19937_64(systemSeed(masterSeed, index));
}

// The stream of system `index`'s second band (its colours and its own noise): apart from the
// system's own stream, so that asking for a second band leaves every draw of the first band
// as it was.
inline std::mt19937_64 secondBandRng(std::uint64_t masterSeed, std::uint64_t index) {
  return systemRng(splitMix64(masterSeed ^ 0xB5AD4ECE0C0102ULL), index);
}

// The stream of system `index`'s render decision (importance sampling): apart from the system's
// own stream, so that a rendered system is drawn and rendered exactly as in a plain run.
inline std::mt19937_64 renderRng(std::uint64_t masterSeed, std::uint64_t index) {
  return systemRng(splitMix64(masterSeed ^ 0x4E4DE2C0FFEE51ULL), index);
}

}  // namespace octarc::simulation
