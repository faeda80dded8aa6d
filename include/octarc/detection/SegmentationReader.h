// Objects from SExtractor SEGMENTATION check-images, one image per threshold, so that a survey's
// existing single-threshold SExtractor runs (deblending off) feed the measurement stage unchanged.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/core/Segment.h"

namespace octarc {

// Every object of every level of a stack of label images, lowest threshold first.
// levels[k] is the label image of THRESH_LEVEL k + 1 (0 = no object, > 0 = NUMBER); names[k]
// names it in error messages (usually its file name). Label numbers need not be contiguous.
//
// Returns the objects ordered by level, then by label: number = label, level = k + 1,
// parentNumber = the label of level k that holds all of the object's pixels (0 at level 1),
// pixels = linear indices y * width + x in ascending order.
//
// Throws IoError (one line naming the file) when a level's size differs from the first level's,
// a label is negative, or the levels do not nest: a label of level k + 1 with a pixel on the
// background of level k, or with pixels in several labels of level k. Throws ConfigError when
// names and levels differ in length. O(pixels) time per level.
std::vector<Segment> segmentsFromLabels(const std::vector<ImageI32>& levels,
                                        const std::vector<std::string>& names);

// The same from SEGMENTATION files (paths[k] = level k + 1; cfitsio's extended syntax allowed).
// Throws IoError naming the file when one cannot be read, is not an integer image, or is not
// width x height (the measured image's size); then the checks of segmentsFromLabels.
std::vector<Segment> readSegmentation(const std::vector<std::string>& paths, std::int64_t width,
                                      std::int64_t height);

}  // namespace octarc
