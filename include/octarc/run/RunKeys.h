// The configuration keys of `octarc detect` and `octarc measure`: SExtractor's key table
// (sexcompat/Keys.h) with octarc's changes (BACK_TYPE GLOBAL, one CATALOG_NAME per
// INPUT_CATALOG, NTHREADS 0 = all cores, the CATALOG_TYPE / CHECKIMAGE_TYPE / WEIGHT_TYPE values
// octarc writes) and octarc's own keys: SEGMENTATION_NAME, INPUT_CATALOG, APPEND_COLUMNS,
// REPLACE_INPUT_CATALOG, BACKGROUND_NAME, BACKGROUND_RMS_NAME, DETECT_THRESH_MAX,
// DETECT_NLEVELS, DETECT_LEVELS.
#pragma once

#include <vector>

#include "octarc/sexcompat/Config.h"

namespace octarc {

std::vector<sexcompat::KeySpec> octarcKeys();

}  // namespace octarc
