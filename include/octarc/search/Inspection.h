// What an inspector looks at (METHOD.md section 4): a DS9 region file of the candidates, one
// postage stamp per candidate (without text: the vetting page, search/VettingPage.h, captions it),
// made from a search's result.
// Nothing here writes files: the caller writes the texts and stamps (atomically, together).
//
// Marks: the arc's ellipse at 3 A_IMAGE x 3 B_IMAGE along THETA_IMAGE (about the isophotal
// extent; green), labelled with the candidate number; the lens as a circle of 1" (red), or
// nothing for a possible dark lens.
#pragma once

#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Table.h"
#include "octarc/io/Ds9Region.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/io/Wcs.h"
#include "octarc/plot/Stamp.h"
#include "octarc/search/Search.h"

namespace octarc {

struct StampSettings {
  double sideArcsec = 26.0;  // STAMP_SIZE
  int sizePix = 400;         // of the PNG
  double scaleBarArcsec = 5.0;
};

// The marks of every candidate (arc ellipse, lens circle).
std::vector<RegionMark> candidateRegionMarks(const Table& catalog, const SearchResult& result,
                                             double pixelScaleArcsec);

// The stamp of candidate `index` (0-based) cut from `image` (background-subtracted), with the
// display range from the cut-out's own pixels: black at the median minus one robust sigma,
// white at the 99.7th percentile. Marks, North / East and the scale bar only: no title.
Stamp candidateStamp(const ImageF& image, const Table& catalog, const SearchResult& result,
                     std::size_t index, const Wcs* wcs, double pixelScaleArcsec,
                     const StampSettings& settings);

// One band of a colour stamp: its background-subtracted image (on the searched image's pixel
// grid) and its magnitude zero point.
struct ColourStampBand {
  const ImageF* pixels = nullptr;
  double magZeropoint = 0.0;
};

// The colour stretch (plot/LuptonColour.h): Q, and the softening in sky sigmas of the searched
// band. White (a channel at 1) is then at an intensity of about 15 sinh(5) / 5 = 220 sigma, the
// sky noise dark, an arc of ten sigma per pixel in the middle of the range.
constexpr double kColourStampQ = 5.0;
constexpr double kColourStampSofteningSigmas = 15.0;

// The colour composite of the candidate whose grey stamp is `grey` (its cut-out, North / East
// and scale bar; no marks, which would hide the colours), with the stretch of Lupton et al.
// (2004): with one other band, red the searched band, blue the other, green their mean; with
// more, blue the first other band, green the second, red the searched band (later ones unused).
// Every band is scaled to the searched band's flux scale by 10^(-0.4 (ZP_band - ZP_searched)),
// the softening is kColourStampSofteningSigmas x `skySigmaAdu` (the searched band's). A pixel
// without data in any band is black. ConfigError without another band.
Stamp candidateColourStamp(const Stamp& grey, const ColourStampBand& searched,
                           const std::vector<ColourStampBand>& others, double skySigmaAdu);

// The file name of candidate `index`'s stamp inside the output directory ("stamps/0001.png").
std::string stampFileName(std::size_t index);

// Its colour composite beside it ("stamps/0001.colour.png").
std::string colourStampFileName(std::size_t index);

// Its FITS cut-out beside it ("stamps/0001.fits"): the stamp's pixels with `imageHeader`'s cards,
// CRPIX1/2 shifted so that the WCS holds on the cut-out, and LTV1/2 (with LTM1_1, LTM2_2) so
// that DS9's physical coordinates are the whole image's pixels.
std::string cutoutFileName(std::size_t index);
FitsHeader cutoutHeader(const FitsHeader& imageHeader, const Stamp& stamp);

}  // namespace octarc
