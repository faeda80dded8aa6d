// Postage stamps for visual inspection (METHOD.md section 4): a cut-out of the image drawn in
// grey levels, each pixel a square, marks on it (the arc's ellipse, the lens), North and East
// arrows and a scale bar, written as PNG with cairo (wrapped here only). cairo rather than
// PLplot, which draws the check-plots: PLplot's global state allows one plot at a time, about
// 18 ms each, too slow for the thousands of stamps of a survey tile; cairo draws one surface per
// thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Image.h"

namespace octarc {

struct StampMark {
  bool ellipse = true;  // else a circle of radius semiAxis1Pix
  double xFits = 0.0;   // 1-based pixel coordinates of the full image
  double yFits = 0.0;
  double semiAxis1Pix = 0.0;
  double semiAxis2Pix = 0.0;
  double angleRad = 0.0;  // counter-clockwise from +x
  int red = 0, green = 255, blue = 0;
  std::string label;  // drawn beside the mark; "" for none
};

struct Stamp {
  ImageF pixels;  // the cut-out (NaN: no data, drawn black)
  // A colour stamp's pixels as 0xRRGGBB (plot/LuptonColour.h), the size of `pixels`: when not
  // empty, drawn instead of the grey levels (the display range is then unused).
  Image<std::uint32_t> rgbPixels;
  double xFirstFits = 1;  // 1-based coordinates of the cut-out's pixel (0, 0) in the image
  double yFirstFits = 1;
  double displayLowAdu = 0;   // black
  double displayHighAdu = 1;  // white; values between go through an asinh stretch
  // North and East as unit vectors in pixel coordinates (+x right, +y up), from the WCS.
  bool hasSkyDirections = false;
  double northX = 0, northY = 1, eastX = -1, eastY = 0;
  double pixelScaleArcsec = 0;  // > 0: a scale bar of scaleBarArcsec is drawn
  double scaleBarArcsec = 5;
  std::vector<StampMark> marks;
  std::string title;     // above the image ("" with subtitle "": a thin frame, no text band)
  std::string subtitle;  // below it
  int sizePix = 400;     // the PNG is sizePix x sizePix
};

// Writes `stamp` as a PNG at `path`; safe to call from several threads at once.
// ConfigError for an empty cut-out, rgbPixels of another size than pixels or a display range
// that is not increasing; IoError naming
// the file when it cannot be written.
void writeStampPng(const std::string& path, const Stamp& stamp);

}  // namespace octarc
