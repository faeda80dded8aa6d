// PLplot keeps global state: every plot of the process is drawn under this one lock.
#pragma once

#include <mutex>

namespace octarc::detail {

std::mutex& plplotMutex();

}  // namespace octarc::detail
