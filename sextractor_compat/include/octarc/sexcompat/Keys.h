// SExtractor 2.25's configuration key table (octarc's own keys: run/RunKeys.h).
#pragma once

#include <vector>

#include "octarc/sexcompat/Config.h"

namespace octarc::sexcompat {

// Every key `source-extractor -dd` (2.25) prints, in its order, with its default, list length,
// range (as in SExtractor's key table) or allowed keywords. Keys octarc does not act on say
// "(ignored by octarc)" in their comment; they are accepted so that existing .sex files load.
const std::vector<KeySpec>& sextractorKeys();

}  // namespace octarc::sexcompat
