// Exceptions for configuration and I/O trouble. Per-object trouble is never an exception: it is
// a flag bit plus NaN values (see core/Flags.h).
#pragma once

#include <stdexcept>
#include <string>

namespace octarc {

// Base of every error octarc reports to the user. what() is one line, and names the file or the
// option concerned, e.g. "seg.fits: segmentation image is 512x512 but the image is 1024x1024".
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file could not be read or written, or is not what it should be.
class IoError : public Error {
 public:
  using Error::Error;
};

// A configuration key, .param line, command-line option or value is wrong.
class ConfigError : public Error {
 public:
  using Error::Error;
};

}  // namespace octarc
