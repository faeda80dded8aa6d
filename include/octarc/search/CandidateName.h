// Positions of candidates as astronomers write them: sexagesimal RA (hours) and Dec (degrees),
// and an IAU-style designation "PREFIX Jhhmmss.ss+ddmmss.s" (J2000).
//
// Sexagesimal strings are rounded to the requested decimals, with the carry into minutes,
// degrees and hours ("59.999" seconds at two decimals is the next minute). Designations are
// truncated, not rounded, as the IAU recommends, so a name never points past the object.
#pragma once

#include <string>

namespace octarc {

// "hh:mm:ss.ss" for secondDecimals = 2; RA taken modulo 360 degrees. "NaN" for a non-finite
// position; secondDecimals outside 0..9 is a programming error (std::invalid_argument).
std::string formatRaSexagesimal(double raDeg, int secondDecimals = 2);
// "+dd:mm:ss.s" for secondDecimals = 1 (always signed; "-00:30:00.0" for -0.5 degrees).
std::string formatDecSexagesimal(double decDeg, int secondDecimals = 1);
// "PREFIX Jhhmmss.ss+ddmmss.s", truncated; an empty prefix gives "Jhhmmss.ss+ddmmss.s";
// "PREFIX NaN" for a non-finite position.
std::string iauDesignation(const std::string& prefix, double raDeg, double decDeg);

}  // namespace octarc
