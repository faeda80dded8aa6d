#include "octarc/io/Wcs.h"

#include <wcslib/wcs.h>
#include <wcslib/wcserr.h>
#include <wcslib/wcshdr.h>
#include <wcslib/wcsmath.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "octarc/core/Conventions.h"
#include "octarc/core/Error.h"

namespace octarc {

namespace {

constexpr double kJ2000Jd = 2451545.0;
constexpr double kDaysPerJulianCentury = 36525.0;
constexpr double kArcsecPerRad = 180.0 * 3600.0 / std::numbers::pi;

// wcslib's detailed message when it recorded one, else its short text for the status code.
std::string wcsMessage(int status, const wcsprm* wcs = nullptr) {
  if (wcs != nullptr && wcs->err != nullptr && wcs->err->msg[0] != '\0') {
    std::string text = wcs->err->msg;
    std::replace(text.begin(), text.end(), '\n', ' ');  // errors are reported on one line
    return text;
  }
  if (status > 0 && status <= WCSERR_NON_SEPARABLE) return wcs_errmsg[status];
  return "wcslib status " + std::to_string(status);
}

// Detailed error messages are off by default in wcslib; switch them on once.
void enableWcsErrors() {
  static std::once_flag once;
  std::call_once(once, [] { wcserr_enable(1); });
}

// Julian date of a Julian epoch (FK5 EQUINOX values) or a Besselian epoch (FK4).
double julianEpochToJd(double epochYears) {
  return kJ2000Jd + (epochYears - 2000.0) * 365.25;
}
double besselianEpochToJd(double epochYears) {
  return 2415020.31352 + (epochYears - 1900.0) * 365.242198781;
}

// IAU 1976 precession (Lieske et al. 1977, A&A 58, 1) of mean equatorial coordinates from the
// mean equator and equinox of date jdFrom to that of J2000.0. The three Euler angles are the
// published polynomials in the start epoch T (centuries from J2000) and the interval t.
std::array<double, 2> precessToJ2000(double raDeg, double decDeg, double jdFrom) {
  const double bigT = (jdFrom - kJ2000Jd) / kDaysPerJulianCentury;
  const double t = (kJ2000Jd - jdFrom) / kDaysPerJulianCentury;
  const double base = 2306.2181 + 1.39656 * bigT - 0.000139 * bigT * bigT;
  const double zetaRad =
      (base * t + (0.30188 - 0.000344 * bigT) * t * t + 0.017998 * t * t * t) / kArcsecPerRad;
  const double zRad =
      (base * t + (1.09468 + 0.000066 * bigT) * t * t + 0.018203 * t * t * t) / kArcsecPerRad;
  const double thetaRad = ((2004.3109 - 0.85330 * bigT - 0.000217 * bigT * bigT) * t -
                           (0.42665 + 0.000217 * bigT) * t * t - 0.041833 * t * t * t) /
                          kArcsecPerRad;
  const double ra0 = raDeg * kRadPerDeg + zetaRad;
  const double dec0 = decDeg * kRadPerDeg;
  const double a = std::cos(dec0) * std::sin(ra0);
  const double b =
      std::cos(thetaRad) * std::cos(dec0) * std::cos(ra0) - std::sin(thetaRad) * std::sin(dec0);
  const double c =
      std::sin(thetaRad) * std::cos(dec0) * std::cos(ra0) + std::cos(thetaRad) * std::sin(dec0);
  double raOutDeg = (std::atan2(a, b) + zRad) * kDegPerRad;
  raOutDeg = std::fmod(raOutDeg, 360.0);
  if (raOutDeg < 0.0) raOutDeg += 360.0;
  // asin loses precision near the poles; use the cos part there.
  const double decOutRad = std::atan2(c, std::sqrt(a * a + b * b));
  return {raOutDeg, decOutRad * kDegPerRad};
}

// Galactic (l, b) to FK5 J2000 (RA, Dec): the IAU 1958 galactic system expressed in J2000
// (north galactic pole at RA 192.85948, Dec 27.12825; the north celestial pole at l 122.93192).
std::array<double, 2> galacticToJ2000(double lDeg, double bDeg) {
  constexpr double kPoleRaDeg = 192.85948;
  constexpr double kPoleDecDeg = 27.12825;
  constexpr double kNcpLonDeg = 122.93192;
  const double b = bDeg * kRadPerDeg;
  const double dl = (kNcpLonDeg - lDeg) * kRadPerDeg;
  const double decP = kPoleDecDeg * kRadPerDeg;
  const double sinDec = std::sin(decP) * std::sin(b) + std::cos(decP) * std::cos(b) * std::cos(dl);
  const double y = std::cos(b) * std::sin(dl);
  const double x = std::cos(decP) * std::sin(b) - std::sin(decP) * std::cos(b) * std::cos(dl);
  double raDeg = kPoleRaDeg + std::atan2(y, x) * kDegPerRad;
  raDeg = std::fmod(raDeg, 360.0);
  if (raDeg < 0.0) raDeg += 360.0;
  return {raDeg, std::atan2(sinDec, std::hypot(x, y)) * kDegPerRad};
}

}  // namespace

struct Wcs::Impl {
  wcsprm wcs{};
  // wcsset() runs once, at construction, so the transforms never redo the set-up. They still
  // write into the struct: scratch arrays (linprm::tmpcrd, disprm::tmpmem for SIP/TPV) and the
  // error record on failure. Concurrent transforms on one struct are therefore serialised.
  mutable std::mutex mutex;

  Impl() { wcs.flag = -1; }
  Impl(const Impl& other) {
    wcs.flag = -1;
    int status = wcssub(1, &other.wcs, nullptr, nullptr, &wcs);
    if (status == 0) status = wcsset(&wcs);
    // The source was set up successfully, so only memory exhaustion can fail here.
    if (status != 0) {
      const std::string message = "cannot copy WCS (" + wcsMessage(status, &wcs) + ")";
      wcsfree(&wcs);  // the destructor does not run when the constructor throws
      throw IoError(message);
    }
  }
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    clearErrors();
    wcsfree(&wcs);
  }

  // A failed transform records its message in the struct and its sub-structures; the next
  // failure would write over (and lose) them, and wcsfree() does not free them all. Called
  // after every failed transform, under the mutex, and on destruction.
  void clearErrors() {
    wcserr_clear(&wcs.err);
    wcserr_clear(&wcs.lin.err);
    wcserr_clear(&wcs.cel.err);
    wcserr_clear(&wcs.cel.prj.err);
    wcserr_clear(&wcs.spc.err);
  }

  bool equatorial() const {
    return wcs.lng >= 0 && std::string(wcs.ctype[wcs.lng]).compare(0, 2, "RA") == 0;
  }
  bool hasEquinox() const { return !undefined(wcs.equinox); }
};

namespace {

// True for a keyword card whose value is a string that never closes ('' is an embedded quote),
// or a card holding a byte outside printable ASCII: wcslib 7.12's header parser (wcspih)
// overflows a buffer on the first ("CTYPE2  = 'DEC-CD1_1   =" aborts the process) and has no
// use for the second.
bool unsafeForWcslib(const std::string& card) {
  for (const char c : card) {
    if (c < 0x20 || c > 0x7E) return true;
  }
  if (card.size() < 10 || card.compare(8, 2, "= ") != 0) return false;
  const std::size_t open = card.find_first_not_of(' ', 10);
  if (open == std::string::npos || card[open] != '\'') return false;
  for (std::size_t i = open + 1; i < card.size(); ++i) {
    if (card[i] != '\'') continue;
    if (i + 1 < card.size() && card[i + 1] == '\'') {
      ++i;  // an embedded quote
      continue;
    }
    return false;  // closed
  }
  return true;
}

}  // namespace

std::optional<Wcs> Wcs::fromHeader(const FitsHeader& header, const std::string& fileForErrors) {
  enableWcsErrors();
  // Cards wcslib cannot parse safely are left out, as if absent (the WCS they would describe is
  // then incomplete or missing, which every caller handles).
  std::string text;
  text.reserve(header.cards.size() * 80);
  for (const std::string& card : header.cards) {
    text += unsafeForWcslib(card) ? std::string(80, ' ') : card;
  }
  const int nCards = static_cast<int>(header.cards.size());
  if (nCards == 0) return std::nullopt;
  int nReject = 0;
  int nWcs = 0;
  wcsprm* all = nullptr;
  // WCSHDR_all accepts the common non-standard forms (e.g. EPOCH for EQUINOX); SIP and TPV
  // are translated into wcslib distortions.
  int status = wcspih(text.data(), nCards, WCSHDR_all, 0, &nReject, &nWcs, &all);
  if (status != 0) {
    throw IoError(fileForErrors + ": cannot parse WCS header (" + wcsMessage(status) + ")");
  }
  struct Guard {
    int& n;
    wcsprm*& p;
    ~Guard() { wcsvfree(&n, &p); }
  } guard{nWcs, all};

  const wcsprm* primary = nullptr;
  for (int i = 0; i < nWcs; ++i) {
    if (all[i].alt[0] == ' ' || all[i].alt[0] == '\0') primary = &all[i];
  }
  if (primary == nullptr || primary->naxis < 2) return std::nullopt;

  auto impl = std::make_unique<Impl>();
  // Keep image axes 1 and 2 only, so that degenerate third axes (NAXIS3 = 1) drop out.
  int nSub = 2;
  int axes[2] = {1, 2};
  status = wcssub(1, primary, &nSub, axes, &impl->wcs);
  if (status != 0) {
    throw IoError(fileForErrors + ": cannot use WCS (" + wcsMessage(status, &impl->wcs) + ")");
  }
  status = wcsset(&impl->wcs);
  if (status != 0) {
    throw IoError(fileForErrors + ": invalid WCS (" + wcsMessage(status, &impl->wcs) + ")");
  }
  if (impl->wcs.lng < 0 || impl->wcs.lat < 0) return std::nullopt;
  return Wcs(std::move(impl));
}

Wcs::Wcs(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Wcs::Wcs(const Wcs& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
Wcs& Wcs::operator=(const Wcs& other) {
  if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
  return *this;
}
Wcs::Wcs(Wcs&&) noexcept = default;
Wcs& Wcs::operator=(Wcs&&) noexcept = default;
Wcs::~Wcs() = default;

std::array<double, 2> Wcs::pixelToWorld(double xFits, double yFits) const {
  // wcslib pixel coordinates are 1-based, like xFits/yFits.
  const double pixel[2] = {xFits, yFits};
  std::array<double, 2> world{};
  pixelsToWorld(pixel, 1, world.data());
  return world;
}

void Wcs::pixelsToWorld(const double* pixelXY, int count, double* worldLngLat) const {
  if (count <= 0) return;
  constexpr int kMaxBatch = 8;  // per call: the scratch arrays live on the stack
  for (int first = 0; first < count; first += kMaxBatch) {
    const int n = std::min(kMaxBatch, count - first);
    double intermediate[2 * kMaxBatch];
    double world[2 * kMaxBatch];
    double phi[kMaxBatch], theta[kMaxBatch];
    int stat[kMaxBatch] = {0};
    int status = 0;
    {
      std::lock_guard<std::mutex> lock(impl_->mutex);
      status =
          wcsp2s(&impl_->wcs, n, 2, pixelXY + 2 * first, intermediate, phi, theta, world, stat);
      if (status != 0) impl_->clearErrors();
    }
    for (int i = 0; i < n; ++i) {
      // wcslib flags the failing positions in stat (status 8 when only some fail).
      const bool ok = status == 0 || (status == 8 && stat[i] == 0);
      double* out = worldLngLat + 2 * (first + i);
      out[0] = ok ? world[2 * i + impl_->wcs.lng] : kNaN;
      out[1] = ok ? world[2 * i + impl_->wcs.lat] : kNaN;
    }
  }
}

std::array<double, 2> Wcs::worldToPixel(double lngDeg, double latDeg) const {
  double world[2];
  world[impl_->wcs.lng] = lngDeg;
  world[impl_->wcs.lat] = latDeg;
  double intermediate[2];
  double pixel[2];
  double phi = 0.0;
  double theta = 0.0;
  int stat[1] = {0};
  int status = 0;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    status = wcss2p(&impl_->wcs, 1, 2, world, &phi, &theta, intermediate, pixel, stat);
    if (status != 0) impl_->clearErrors();
  }
  if (status != 0) return {kNaN, kNaN};
  return {pixel[0], pixel[1]};
}

double Wcs::equinox() const {
  if (impl_->hasEquinox()) return impl_->wcs.equinox;
  // FITS WCS paper II: FK4 defaults to B1950, every other frame to 2000.
  return radesys() == "FK4" ? 1950.0 : 2000.0;
}

std::string Wcs::radesys() const {
  std::string frame(impl_->wcs.radesys);
  while (!frame.empty() && frame.back() == ' ') frame.pop_back();
  if (!frame.empty() || !impl_->equatorial()) return frame;
  // FITS WCS paper II defaults: ICRS without EQUINOX, else FK4 before 1984 and FK5 after.
  if (!impl_->hasEquinox()) return "ICRS";
  return impl_->wcs.equinox < 1984.0 ? "FK4" : "FK5";
}

bool Wcs::isJ2000Equatorial() const {
  const std::string frame = radesys();
  return frame == "ICRS" || (frame == "FK5" && equinox() == 2000.0);
}

double Wcs::pixelAreaDeg2(double xFits, double yFits) const {
  const double xy[6] = {xFits, yFits, xFits + 1.0, yFits, xFits, yFits + 1.0};
  double world[6];
  pixelsToWorld(xy, 3, world);
  const auto dLng = [](double a, double b) { return std::remainder(a - b, 360.0); };
  const double cosLat = std::cos(world[1] * kRadPerDeg);
  const double j11 = dLng(world[2], world[0]) * cosLat;
  const double j12 = dLng(world[4], world[0]) * cosLat;
  const double j21 = world[3] - world[1];
  const double j22 = world[5] - world[1];
  return std::fabs(j11 * j22 - j12 * j21);
}

std::array<double, 2> Wcs::pixelToJ2000(double xFits, double yFits) const {
  const std::array<double, 2> world = pixelToWorld(xFits, yFits);
  return worldToJ2000(world[0], world[1]);
}

std::array<double, 2> Wcs::worldToJ2000(double lngDeg, double latDeg) const {
  const std::array<double, 2> world = {lngDeg, latDeg};
  if (std::isnan(world[0]) || std::isnan(world[1])) return world;
  if (!impl_->equatorial()) {
    if (std::string(impl_->wcs.ctype[impl_->wcs.lng]).compare(0, 4, "GLON") == 0) {
      return galacticToJ2000(world[0], world[1]);
    }
    return {kNaN, kNaN};  // ecliptic and other frames are not converted
  }
  const std::string frame = radesys();
  const double equinoxYears = equinox();
  if (frame == "ICRS" || equinoxYears == 2000.0) return world;
  if (frame == "FK4" || frame == "FK4-NO-E") {
    // Precession only, from the Besselian equinox; the E-terms and the FK4 -> FK5 frame
    // rotation are not applied (an error below about 1 arcsec).
    return precessToJ2000(world[0], world[1], besselianEpochToJd(equinoxYears));
  }
  return precessToJ2000(world[0], world[1], julianEpochToJd(equinoxYears));
}

}  // namespace octarc
