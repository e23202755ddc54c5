// mahost as installed: `cmake --install` into a scratch prefix, run from another folder with the
// source tree's profiles out of reach (no MAHOST_CONFIG_DIR, a user folder of its own): it
// slices with the shipped profiles found beside it, says where it looked, carries no path of
// the source tree, and brings its man page and systemd unit; the Debian package holds the same.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "geometry/mesh/stl_io.h"
#include "support/build_kind.h"
#include "support/run_command.h"
#include "support/solids.h"

namespace install_test {

namespace {

namespace fs = std::filesystem;
using test_support::run_command;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("installed_mahost_slices_with_its_shipped_profiles_from_anywhere") {
  const std::string dir = test_support::scratch_dir("install_prefix");
  const std::string prefix = dir + "/prefix";
  auto r = run_command({MAHOST_CMAKE, "--install", MAHOST_BUILD_DIR, "--prefix", prefix});
  INFO(r.out, r.err);
  REQUIRE(r.exit_code == 0);
  const std::string mahost = prefix + "/bin/mahost";
  REQUIRE(fs::exists(mahost));
  CHECK(fs::exists(prefix + "/share/mahost/printers/up-plus-2.toml"));
  CHECK(fs::exists(prefix + "/share/mahost/materials/pla.toml"));
  // No path of the source tree or the build tree in the binary. A sanitizer build is never
  // installed for users and carries its sources' names by design (its reports and debug
  // information name the file and line), so only the release build is held to this.
  if (!test_support::kSanitizedBuild) {
    const std::string binary = read_file(mahost);
    CHECK(binary.find(MAHOST_SOURCE_DIR) == std::string::npos);
    CHECK(binary.find(MAHOST_BUILD_DIR) == std::string::npos);
  }

  // Another folder, a user of its own, nothing pointing at the source tree.
  const std::string elsewhere = dir + "/elsewhere";
  fs::create_directories(elsewhere);
  geometry::write_stl_binary(elsewhere + "/cube.stl", solids::cube(10).mesh);
  const std::vector<std::string> env{"env", "-u", "MAHOST_CONFIG_DIR", "-u", "XDG_CONFIG_HOME", "-C", elsewhere,
                                     "HOME=" + dir + "/home", "XDG_CONFIG_DIRS=" + dir + "/system"};
  auto run = [&](std::vector<std::string> args) {
    std::vector<std::string> argv = env;
    argv.push_back(mahost);
    argv.insert(argv.end(), args.begin(), args.end());
    return run_command(argv);
  };
  r = run({"slice", "cube.stl", "-o", "cube.gcode", "--contour", "mid"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string gcode = read_file(elsewhere + "/cube.gcode");
  CHECK(gcode.find("; printer: UP Plus 2 (" + prefix + "/share/mahost/printers/up-plus-2.toml)") != std::string::npos);
  r = run({"slice", "cube.stl", "-o", "cube.gcode", "--printer", "prusa-mk4"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "mahost: printer profile 'prusa-mk4' not found in " + dir + "/home/.config/mahost/printers, " + dir +
                     "/system/mahost/printers, " + prefix + "/share/mahost/printers (available: generic-marlin, "
                     "up-plus-2); give one of these names or a path to a .toml file\n");

  // The help: `mahost help slice` is `mahost slice --help`, and the man page has every command's.
  const auto help = run({"help", "slice"});
  CHECK(help.exit_code == 0);
  CHECK(help.out == run({"slice", "--help"}).out);
  const std::string man = read_file(prefix + "/share/man/man1/mahost.1");
  CHECK(man.find(".TH MAHOST \"1\"") != std::string::npos);
  for (const char* command : {"slice", "print", "serve", "profiles import", "info"}) {
    CAPTURE(command);
    CHECK(man.find(".SS \"mahost " + std::string(command) + ":\"") != std::string::npos);
  }
  CHECK(man.find("Usage: mahost slice [OPTIONS] MODEL") != std::string::npos);
  // The service runs the installed binary.
  const std::string unit = read_file(prefix + "/lib/systemd/system/mahost-serve.service");
  CHECK(unit.find("ExecStart=" + mahost + " serve ") != std::string::npos);
  if (std::system("command -v systemd-analyze >/dev/null 2>&1") == 0) {
    r = run_command({"systemd-analyze", "verify", prefix + "/lib/systemd/system/mahost-serve.service"});
    // Nothing said about the unit, but that man cannot find mahost(1) outside MANPATH.
    std::istringstream said(r.err);
    for (std::string line; std::getline(said, line);) {
      if (line.find("mahost-serve.service") == std::string::npos || line.find("Command 'man ") != std::string::npos) continue;
      CHECK(line == "");
    }
  }
}

TEST_CASE("the_debian_package_holds_what_the_install_does") {
  if (std::system("command -v dpkg-deb >/dev/null 2>&1") != 0) {
    MESSAGE("dpkg-deb is not installed: skipped");
    return;
  }
  const std::string dir = test_support::scratch_dir("install_deb");
  auto r = run_command({MAHOST_CPACK, "-G", "DEB", "-B", dir, "--config", std::string(MAHOST_BUILD_DIR) + "/CPackConfig.cmake"});
  INFO(r.out, r.err);
  REQUIRE(r.exit_code == 0);
  std::string deb;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".deb") deb = entry.path().string();
  }
  REQUIRE(!deb.empty());
  r = run_command({"dpkg-deb", "--contents", deb});
  for (const char* file : {"./usr/bin/mahost", "./usr/share/mahost/printers/up-plus-2.toml",
                           "./usr/share/mahost/materials/abs.toml", "./usr/share/man/man1/mahost.1",
                           "./usr/lib/systemd/system/mahost-serve.service"}) {
    CAPTURE(file);
    CHECK(r.out.find(file) != std::string::npos);
  }
  r = run_command({"dpkg-deb", "--field", deb, "Package", "Depends"});
  CHECK(r.out.rfind("Package: mahost\n", 0) == 0);
  CHECK(r.out.find("libzip") != std::string::npos);  // found by dpkg-shlibdeps
  r = run_command({"dpkg-deb", "--fsys-tarfile", deb});
  CHECK(r.out.find("ExecStart=/usr/bin/mahost serve ") != std::string::npos);
}

}  // namespace install_test
