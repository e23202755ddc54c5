// A model file's bytes, read whole (every reader parses them in place).
#pragma once

#include <string>

namespace geometry {

// The file's bytes, or InputError naming `path` in one line: "no such file (check the path)",
// "permission denied: cannot read the file", "is a directory, not a model file", ...
std::string read_file_bytes(const std::string& path);

}  // namespace geometry
