// Where the shipped profiles are; see profile_paths.h.
#include "app/profile_paths.h"

#include <filesystem>
#include <system_error>

#include "printer/profile.h"

namespace app {

std::string installed_profiles_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path executable = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path bin = executable.parent_path();
  // MAHOST_DATA_FROM_BIN: the install layout's share/mahost relative to its bin/
  // ("../share/mahost"), from app/CMakeLists.txt.
  for (const fs::path& candidate : {bin / MAHOST_DATA_FROM_BIN, bin / "share" / "mahost"}) {
    if (fs::is_directory(candidate / "printers", ec)) return candidate.lexically_normal().string();
  }
  return {};
}

std::string profile_search_path() { return printer::config_directory(installed_profiles_dir()); }

}  // namespace app
