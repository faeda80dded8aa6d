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

// The file name of candidate `index`'s stamp inside the output directory ("stamps/0001.png").
std::string stampFileName(std::size_t index);

// Its FITS cut-out beside it ("stamps/0001.fits"): the stamp's pixels with `imageHeader`'s cards,
// CRPIX1/2 shifted so that the WCS holds on the cut-out, and LTV1/2 (with LTM1_1, LTM2_2) so
// that DS9's physical coordinates are the whole image's pixels.
std::string cutoutFileName(std::size_t index);
FitsHeader cutoutHeader(const FitsHeader& imageHeader, const Stamp& stamp);

}  // namespace octarc
