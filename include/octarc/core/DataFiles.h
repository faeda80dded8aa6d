// Where octarc finds the data files it ships (octarc.sex, octarc.param, default.conv, the lens
// population file): in the data directory of the installation, found relative to the octarc
// executable, so that an installed or moved tree works without any path of the build.
//
//   $OCTARC_DATA_DIR                      when set (unusual layouts, tests of the libraries)
//   setDataDirectory's                    when a program embedding the libraries set one (the
//                                         Python module, whose executable is python3)
//   <executable's directory>/<relative>   otherwise; <relative> is ../share/octarc for the
//                                         standard layout (bin/octarc, share/octarc/), the same
//                                         in the build tree as in an installed tree
#pragma once

#include <string>
#include <string_view>

namespace octarc {

// The data directory, without checking that it exists.
std::string dataDirectory();

// For a program that embeds the libraries and does not sit in the installation's bin/: the data
// directory to use when OCTARC_DATA_DIR is unset (empty: beside the executable again).
void setDataDirectory(std::string directory);

// The path of the shipped data file `name` (e.g. "octarc.sex", "simulation/population.txt").
// IoError naming the file and the directory searched when it is not there.
std::string dataFile(std::string_view name);

// A file named by the user that may also be one of the shipped files: `path` itself when it
// exists or names a directory ("./x.conv", "dir/x.conv"); otherwise the shipped file of that
// name when there is one; otherwise `path` unchanged (the caller's open then fails naming it).
std::string userOrDataFile(const std::string& path);

// userOrDataFile for a file that must exist: IoError when it is in neither place, naming the
// file, `what` names it (e.g. "PARAMETERS_NAME file", "configuration file (-c)") and, for a name
// without a directory, both places searched.
std::string existingUserOrDataFile(const std::string& path, const std::string& what);

}  // namespace octarc
