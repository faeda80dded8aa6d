// World coordinates through wcslib (wcslib stays inside src/io).
//
// All pixel arguments are 1-based FITS pixel coordinates (core/Conventions.h); world
// coordinates are degrees. Supports every projection wcslib reads from a header, including
// SIP and TPV distortions.
#pragma once

#include <array>
#include <memory>
#include <optional>

#include "octarc/io/FitsHeader.h"

namespace octarc {

class Wcs {
 public:
  // The celestial WCS of a header, or nullopt if the header has none (no CTYPE with a
  // celestial axis pair). Throws IoError if the WCS cards are present but invalid.
  static std::optional<Wcs> fromHeader(const FitsHeader& header, const std::string& fileForErrors);

  Wcs(const Wcs&);
  Wcs& operator=(const Wcs&);
  Wcs(Wcs&&) noexcept;
  Wcs& operator=(Wcs&&) noexcept;
  ~Wcs();

  // (longitude, latitude) in degrees of a 1-based pixel position; NaN, NaN on failure.
  // Thread-safe (each call works on its own copy of the wcslib state if needed).
  std::array<double, 2> pixelToWorld(double xFits, double yFits) const;
  // Inverse; NaN, NaN on failure.
  std::array<double, 2> worldToPixel(double lngDeg, double latDeg) const;
  // EQUINOX of the header (2000 if absent); used for ALPHA_J2000 precession.
  double equinox() const;
  // RADESYS: "ICRS", "FK5", "FK4", ... ("" if unknown).
  std::string radesys() const;

 private:
  struct Impl;
  explicit Wcs(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace octarc
