#include "host/serve/api_key.h"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <fmt/core.h>

#include "printer/error.h"

namespace host::serve {

namespace fs = std::filesystem;

namespace {

bool key_characters_ok(std::string_view key) {
  for (char c : key) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '-' || c == '_';
    if (!ok) return false;
  }
  return true;
}

void check_key(std::string_view key, const std::string& source) {
  if (key.size() < 16 || key.size() > 256 || !key_characters_ok(key)) {
    throw printer::ConfigError(fmt::format(
        "{}: an API key is 16 to 256 characters of A-Z, a-z, 0-9, - and _; {}", source,
        source == "MAHOST_API_KEY" ? "set another" : "delete the file to have a new one made"));
  }
}

std::string config_home() {
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg != nullptr && xdg[0] == '/') return xdg;
  const char* home = std::getenv("HOME");
  if (home == nullptr || home[0] != '/') {
    throw printer::ConfigError(
        "neither XDG_CONFIG_HOME nor HOME is set: set MAHOST_API_KEY, or HOME, so mahost serve "
        "can keep its API key");
  }
  return std::string(home) + "/.config";
}

std::string read_key_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) {
    throw printer::ConfigError(fmt::format("{}: cannot read the API key: {}", path, std::strerror(errno)));
  }
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    ::close(fd);
    throw printer::ConfigError(fmt::format("{}: the API key file is not a regular file", path));
  }
  if ((info.st_mode & 077) != 0) {
    ::close(fd);
    throw printer::ConfigError(fmt::format(
        "{}: the API key file may be read by others (mode {:o}): chmod 600 it, or delete it to "
        "have a new key made",
        path, info.st_mode & 0777));
  }
  char buffer[512];
  const ssize_t n = ::read(fd, buffer, sizeof buffer);
  ::close(fd);
  if (n < 0) throw printer::ConfigError(fmt::format("{}: cannot read the API key", path));
  std::string key(buffer, static_cast<std::size_t>(n));
  while (!key.empty() && (key.back() == '\n' || key.back() == '\r' || key.back() == ' ')) key.pop_back();
  check_key(key, path);
  return key;
}

}  // namespace

std::string api_key_path() { return config_home() + "/mahost/api-key"; }

std::string make_api_key() {
  unsigned char bytes[16];
  std::size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = ::getrandom(bytes + got, sizeof bytes - got, 0);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw printer::ConfigError(fmt::format("cannot draw a random API key: {}", std::strerror(errno)));
    }
    got += static_cast<std::size_t>(n);
  }
  std::string key;
  for (unsigned char b : bytes) key += fmt::format("{:02x}", b);
  return key;
}

ApiKey load_api_key() {
  if (const char* env = std::getenv("MAHOST_API_KEY"); env != nullptr && env[0] != '\0') {
    check_key(env, "MAHOST_API_KEY");
    return ApiKey{env, "MAHOST_API_KEY", false};
  }
  const std::string path = api_key_path();
  std::error_code error;
  if (fs::exists(fs::symlink_status(path, error))) return ApiKey{read_key_file(path), path, false};

  const fs::path folder = fs::path(path).parent_path();
  fs::create_directories(folder, error);
  if (error) {
    throw printer::ConfigError(fmt::format("{}: cannot create the folder for the API key: {}",
                                           folder.string(), error.message()));
  }
  ::chmod(folder.c_str(), 0700);
  const std::string key = make_api_key();
  // O_EXCL: two servers starting at once do not overwrite each other's key.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) {
    if (errno == EEXIST) return ApiKey{read_key_file(path), path, false};
    throw printer::ConfigError(fmt::format("{}: cannot write the API key: {}", path, std::strerror(errno)));
  }
  const std::string line = key + "\n";
  const bool written = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!written || !synced) {
    ::unlink(path.c_str());
    throw printer::ConfigError(fmt::format("{}: cannot write the API key", path));
  }
  return ApiKey{key, path, true};
}

bool same_key(std::string_view given, std::string_view expected) {
  // The length is not secret (a key is 32 hex digits by default); the contents are.
  unsigned char differ = given.size() == expected.size() ? 0 : 1;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const char g = i < given.size() ? given[i] : 0;
    differ |= static_cast<unsigned char>(g ^ expected[i]);
  }
  return differ == 0;
}

}  // namespace host::serve
