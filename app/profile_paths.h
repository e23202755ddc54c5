// Where this mahost finds the profiles it ships with, and the search path every command reads
// profiles from (printer::config_directory: the user's folder first).
#pragma once

#include <string>

namespace app {

// The shipped profiles: share/mahost beside the bin/ folder this executable is installed in
// (the layout `cmake --install` and the Debian package make), else, run from its build
// tree, the build tree's share/mahost (links to the source tree's configs/). Found from the
// executable's own location, so no path of the machine it was built on is compiled in.
// Empty when neither exists.
std::string installed_profiles_dir();

// printer::config_directory(installed_profiles_dir()).
std::string profile_search_path();

}  // namespace app
