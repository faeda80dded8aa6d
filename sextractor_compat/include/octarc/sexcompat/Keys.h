// Key tables: SExtractor 2.25's configuration keys and the keys of `octarc measure`.
#pragma once

#include <vector>

#include "octarc/sexcompat/Config.h"

namespace octarc::sexcompat {

// Every key `source-extractor -dd` (2.25) prints, in its order, with its default, list length,
// range (as in SExtractor's key table) or allowed keywords. Keys octarc does not act on say
// "(ignored by octarc)" in their comment; they are accepted so that existing .sex files load.
const std::vector<KeySpec>& sextractorKeys();

// sextractorKeys() plus the keys of `octarc measure`: SEGMENTATION_NAME, INPUT_CATALOG,
// BACKGROUND_NAME, BACKGROUND_RMS_NAME, DETECT_THRESH_MAX, DETECT_NLEVELS, DETECT_LEVELS; with
// BACK_TYPE extended by GLOBAL and NTHREADS meaning "0 = all cores".
std::vector<KeySpec> octarcMeasureKeys();

}  // namespace octarc::sexcompat
