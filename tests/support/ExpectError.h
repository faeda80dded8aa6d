// Checks of the one-line error messages the library throws.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc::test {

// Expects an exception of type E whose one-line message contains every fragment.
template <typename E, typename Fn>
void expectError(Fn&& fn, const std::vector<std::string>& fragments) {
  try {
    fn();
    ADD_FAILURE() << "no exception (expected '" << fragments.front() << "')";
  } catch (const E& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    for (const std::string& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << what;
  }
}

template <typename Fn>
void expectIoError(Fn&& fn, const std::vector<std::string>& fragments) {
  expectError<IoError>(fn, fragments);
}

}  // namespace octarc::test
