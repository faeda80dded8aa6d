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
  // Thread-safe: wcslib keeps scratch arrays inside its struct even after set-up, so the
  // transforms of one Wcs are serialised by a mutex (copy the Wcs per thread to avoid waiting).
  std::array<double, 2> pixelToWorld(double xFits, double yFits) const;
  // The same for `count` positions at once (pixelXY: x0, y0, x1, y1, ...; worldLngLat likewise,
  // NaN, NaN for a position that fails): one transform call for all of them.
  void pixelsToWorld(const double* pixelXY, int count, double* worldLngLat) const;
  // Inverse; NaN, NaN on failure. Thread-safe like pixelToWorld.
  std::array<double, 2> worldToPixel(double lngDeg, double latDeg) const;
  // (RA, Dec) in degrees referred to the mean equator and equinox J2000 (ALPHA_J2000,
  // DELTA_J2000): the world position unchanged for ICRS or an equinox of 2000, else precessed
  // to J2000 with the IAU 1976 model. FK4 frames are precessed from their Besselian equinox
  // without the E-terms or the FK4 -> FK5 correction (error below about 1 arcsec). Galactic
  // (GLON/GLAT) positions are rotated to J2000; other frames (ecliptic, ...) and failures give
  // NaN, NaN.
  std::array<double, 2> pixelToJ2000(double xFits, double yFits) const;
  // The same from a world position of this WCS (as pixelToWorld gives it).
  std::array<double, 2> worldToJ2000(double lngDeg, double latDeg) const;
  // EQUINOX of the header (or EPOCH); if absent 1950 for FK4, else 2000.
  double equinox() const;
  // RADESYS: "ICRS", "FK5", "FK4", ...; if absent, the FITS default for an equatorial frame
  // (ICRS without EQUINOX, FK4 for EQUINOX < 1984, else FK5); "" for non-equatorial frames.
  std::string radesys() const;
  // True when world coordinates are J2000 RA and Dec already: ICRS, or FK5 at equinox 2000
  // (DS9's fk5 and icrs, SExtractor's ALPHA_J2000 without precession).
  bool isJ2000Equatorial() const;
  // The sky area of one pixel at a 1-based position, in square degrees: the determinant of the
  // pixel-to-world Jacobian (longitude steps shrunk by cos latitude, wrapped at 0/360); NaN
  // where the transform fails.
  double pixelAreaDeg2(double xFits, double yFits) const;

 private:
  struct Impl;
  explicit Wcs(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace octarc
