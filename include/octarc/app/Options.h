// Boost.Program_options helpers of the commands that take GNU-style options (simulate, demo).
#pragma once

#include <boost/program_options.hpp>
#include <optional>
#include <string>
#include <vector>

namespace octarc {

// An option value stored into `target` when the option is given (at po::notify), left unset
// otherwise: the settings structs keep "not given" apart from any default.
template <typename T>
boost::program_options::typed_value<T>* optionalValue(std::optional<T>& target) {
  return boost::program_options::value<T>()->notifier([&target](const T& v) { target = v; });
}

// Boost would read a negative number after an option as an option of its own: glue the values
// of value-taking options to their names ("--lenses=-1"), so they reach the range checks.
inline std::vector<std::string> glueValues(
    const std::vector<std::string>& args,
    const boost::program_options::options_description& options) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    std::string name;
    if (a.rfind("--", 0) == 0 && a.find('=') == std::string::npos) {
      name = a.substr(2);
    } else if (a.size() == 2 && a[0] == '-' && a[1] != '-') {
      name = a.substr(1);
    }
    const boost::program_options::option_description* d =
        name.empty() ? nullptr : options.find_nothrow(name, false, false, false);
    if (d && d->semantic()->max_tokens() > 0 && i + 1 < args.size()) {
      out.push_back("--" + d->long_name() + "=" + args[i + 1]);
      ++i;
    } else {
      out.push_back(a);
    }
  }
  return out;
}

}  // namespace octarc
