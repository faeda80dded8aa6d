#include "octarc/search/CandidateName.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace octarc {

namespace {

struct Sexagesimal {
  std::int64_t whole = 0;  // hours or degrees
  std::int64_t minutes = 0;
  std::int64_t secondUnits = 0;  // seconds in units of 10^-decimals
};

// |value| (hours or degrees) split into whole, minutes and seconds, rounded or truncated to
// `decimals` second decimals, with the carry.
Sexagesimal split(double value, int decimals, bool round) {
  // 9 decimals keep the count of second units of 360 degrees far inside 64 bits.
  if (decimals < 0 || decimals > 9) {
    throw std::invalid_argument("sexagesimal seconds need 0 to 9 decimals, not " +
                                std::to_string(decimals));
  }
  const double unitsPerSecond = std::pow(10.0, decimals);
  const double units = std::fabs(value) * 3600.0 * unitsPerSecond;
  // A tiny tolerance keeps values such as 12.2 hours, not exact in binary, from truncating to
  // 12:11:59.99.
  const auto total =
      static_cast<std::int64_t>(round ? std::llround(units) : std::floor(units * (1.0 + 1e-12)));
  const auto perMinute = static_cast<std::int64_t>(60.0 * unitsPerSecond);
  Sexagesimal s;
  s.secondUnits = total % perMinute;
  s.minutes = (total / perMinute) % 60;
  s.whole = total / (perMinute * 60);
  return s;
}

std::string seconds(const Sexagesimal& s, int decimals) {
  char text[32];
  const double unitsPerSecond = std::pow(10.0, decimals);
  std::snprintf(text, sizeof text, "%0*.*f", decimals > 0 ? decimals + 3 : 2, decimals,
                double(s.secondUnits) / unitsPerSecond);
  return text;
}

double normalisedRaHours(double raDeg) {
  double ra = std::fmod(raDeg, 360.0);
  if (ra < 0.0) ra += 360.0;
  return ra / 15.0;
}

}  // namespace

std::string formatRaSexagesimal(double raDeg, int secondDecimals) {
  if (!std::isfinite(raDeg)) return "NaN";
  Sexagesimal s = split(normalisedRaHours(raDeg), secondDecimals, true);
  s.whole %= 24;
  char text[48];
  std::snprintf(text, sizeof text, "%02lld:%02lld:%s", static_cast<long long>(s.whole),
                static_cast<long long>(s.minutes), seconds(s, secondDecimals).c_str());
  return text;
}

std::string formatDecSexagesimal(double decDeg, int secondDecimals) {
  if (!std::isfinite(decDeg)) return "NaN";
  const Sexagesimal s = split(decDeg, secondDecimals, true);
  char text[48];
  std::snprintf(text, sizeof text, "%c%02lld:%02lld:%s", decDeg < 0.0 ? '-' : '+',
                static_cast<long long>(s.whole), static_cast<long long>(s.minutes),
                seconds(s, secondDecimals).c_str());
  return text;
}

std::string iauDesignation(const std::string& prefix, double raDeg, double decDeg) {
  if (!std::isfinite(raDeg) || !std::isfinite(decDeg))
    return prefix.empty() ? "NaN" : prefix + " NaN";
  const Sexagesimal ra = split(normalisedRaHours(raDeg), 2, false);
  const Sexagesimal dec = split(decDeg, 1, false);
  char text[64];
  std::snprintf(text, sizeof text, "J%02lld%02lld%s%c%02lld%02lld%s",
                static_cast<long long>(ra.whole % 24), static_cast<long long>(ra.minutes),
                seconds(ra, 2).c_str(), decDeg < 0.0 ? '-' : '+', static_cast<long long>(dec.whole),
                static_cast<long long>(dec.minutes), seconds(dec, 1).c_str());
  return prefix.empty() ? std::string(text) : prefix + " " + text;
}

}  // namespace octarc
