// FITS headers the tests make in memory.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "octarc/io/FitsHeader.h"

namespace octarc::test {

using Cards = std::vector<std::pair<std::string, std::string>>;

// The header of a width x height float image (SIMPLE, BITPIX -32, NAXIS, NAXIS1, NAXIS2), then
// `cards` (keyword, value as written), in order.
inline FitsHeader imageHeader(int width, int height, const Cards& cards = {}) {
  FitsHeader h;
  h.set("SIMPLE", "T");
  h.set("BITPIX", "-32");
  h.set("NAXIS", "2");
  h.set("NAXIS1", std::to_string(width));
  h.set("NAXIS2", std::to_string(height));
  for (const auto& [key, value] : cards) h.set(key, value);
  return h;
}

}  // namespace octarc::test
