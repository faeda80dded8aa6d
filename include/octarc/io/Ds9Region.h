// SAOImage DS9 region files (format version 4.1): the area shapes (circle, box, ellipse,
// polygon) in image, physical and fk5 / icrs (J2000) coordinates, read into shapes in 1-based
// image pixel coordinates (core/Conventions.h) of one image.
//
// Written here because no Debian package offers a C or C++ reader: cfitsio's fits_read_rgnfile
// exists in the library, but Debian ships no region.h for it, and it handles neither DS9's
// sexagesimal units nor its include / exclude rules as DS9 draws them.
//
// Conventions, as DS9 and astropy regions read a file:
//   - Positions in image coordinates are 1-based pixels; in fk5 / icrs, degrees or sexagesimal
//     (RA hh:mm:ss.s or 12h34m56.7s in hours; Dec +dd:mm:ss or 12d34m56s in degrees).
//   - Sizes are pixels in image and physical coordinates; in fk5 / icrs, degrees unless marked
//     " (arcsec), ' (arcmin), d (degrees) or r (radians).
//   - Angles are degrees counter-clockwise: from +x in image coordinates; in fk5 / icrs from the
//     longitude axis (angle 0 lays a box's width or an ellipse's r1 along RA), i.e. the pixel
//     angle is the sky angle plus the North angle (from +x) minus 90 degrees.
//   - fk5 (J2000) and icrs are taken as one frame (they differ by about 0.02 arcsec), as
//     SExtractor's ALPHA_J2000 is; the image's WCS must be ICRS or FK5 J2000.
//   - A sky shape becomes a pixel shape through the local pixel scale and North angle at its
//     centre (a circle stays a circle); polygon vertices go through the WCS one by one.
//   - box(x, y, width, height, angle); ellipse(x, y, r1, r2, angle), r1 along the angle;
//     circle(x, y, r); polygon(x1, y1, x2, y2, ...), even-odd rule.
//   - annulus(x, y, r_inner, r_outer): the ring between the two circles (one annulus per
//     shape; more radii are an error).
//   - point(x, y) (also "circle point(x, y)" etc.) has no area: with a point radius it is that
//     circle, without one an error (never silently dropped).
//   - A leading '-' marks an exclude shape. The other area-less shapes (line, text, vector,
//     ruler, compass, projection, segment) are skipped; panda and the other multi-radius
//     shapes, and galactic / ecliptic coordinates, are an error.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "octarc/io/FitsHeader.h"
#include "octarc/io/Wcs.h"

namespace octarc {

enum class RegionShapeKind { Circle, Box, Ellipse, Polygon, Annulus };

// One area shape in 1-based image pixel coordinates.
struct RegionShape {
  RegionShapeKind kind = RegionShapeKind::Circle;
  bool exclude = false;
  int lineNumber = 0;  // 1-based line of the region file
  double xCentre = 0.0;
  double yCentre = 0.0;
  // Circle: both the radius. Box: half the width and half the height. Ellipse: the semi-axes
  // along the angle and across it. Annulus: the outer and the inner radius.
  double semiAxis1Pix = 0.0;
  double semiAxis2Pix = 0.0;
  double angleRad = 0.0;                        // counter-clockwise from +x
  std::vector<std::array<double, 2>> vertices;  // polygon only

  // Whether the point (1-based pixel coordinates) lies inside; points on the edge count as
  // inside for circle, box, ellipse and annulus.
  bool contains(double xFits, double yFits) const;
  // The pixel-coordinate bounding box: xMin, xMax, yMin, yMax.
  std::array<double, 4> bounds() const;
};

// Reads the area shapes of a region file for the image whose header is given (its WCS for
// fk5 / icrs shapes; LTV1, LTV2, LTM1_1, LTM2_2 for physical ones, the identity when absent).
// `pointRadiusPix` > 0 makes each point shape a circle of that radius (pixels); with 0 a point
// is an error. Throws ConfigError naming the file and line for a malformed or unsupported line,
// and for sky shapes on an image without a celestial WCS; IoError if the file cannot be read.
std::vector<RegionShape> readDs9Regions(const std::filesystem::path& regionFile,
                                        const FitsHeader& imageHeader,
                                        const std::string& imageNameForErrors,
                                        double pointRadiusPix = 0.0);

// The same from text (regionFileForErrors names it in messages).
std::vector<RegionShape> parseDs9Regions(const std::string& text,
                                         const std::string& regionFileForErrors,
                                         const FitsHeader& imageHeader,
                                         const std::string& imageNameForErrors,
                                         double pointRadiusPix = 0.0);

// A mark to draw: a circle or an ellipse (1-based pixel coordinates, as RegionShape) with its
// colour and an optional text label shown with it.
struct RegionMark {
  RegionShapeKind kind = RegionShapeKind::Circle;  // Circle or Ellipse
  double xCentre = 0.0;
  double yCentre = 0.0;
  double semiAxis1Pix = 0.0;
  double semiAxis2Pix = 0.0;
  double angleRad = 0.0;
  std::string colour = "green";  // a DS9 colour name
  std::string text;              // "" for none; '{' and '}' are dropped
};

// A DS9 region file (version 4.1) of the marks: in fk5 (degrees, sizes in arcsec, sky angles)
// through the local frame of `wcs` at each centre (the inverse of what readDs9Regions does),
// or in image coordinates when `wcs` is null or not J2000 equatorial (Wcs::isJ2000Equatorial:
// a galactic or B1950 WCS would put its own coordinates under the fk5 label). ConfigError for a
// box or polygon mark, or a centre the WCS cannot place on the sky.
std::string formatDs9Regions(const std::vector<RegionMark>& marks, const Wcs* wcs);

// DS9's rule for a set of shapes: a point is in the region when it lies inside at least one
// include shape (or there is no include shape at all) and inside no exclude shape.
bool regionContains(const std::vector<RegionShape>& shapes, double xFits, double yFits);

}  // namespace octarc
