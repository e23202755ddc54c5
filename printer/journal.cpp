#include "printer/journal.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "printer/error.h"

namespace printer {

namespace {

using nlohmann::json;

json to_json(const PrintState& s) {
  return json{{"x", s.x}, {"y", s.y}, {"z", s.z}, {"e", s.e}, {"feedrate", s.feedrate},
              {"relative_xyz", s.relative_xyz}, {"relative_e", s.relative_e},
              {"units", s.unit == 1 ? "mm" : "inches"}, {"hotend_target", s.hotend_target},
              {"bed_target", s.bed_target}, {"fan", s.fan}, {"filament_fed", s.filament_fed}};
}

PrintState state_from_json(const json& j) {
  PrintState s;
  s.x = j.at("x").get<double>();
  s.y = j.at("y").get<double>();
  s.z = j.at("z").get<double>();
  s.e = j.at("e").get<double>();
  s.feedrate = j.at("feedrate").get<double>();
  s.relative_xyz = j.at("relative_xyz").get<bool>();
  s.relative_e = j.at("relative_e").get<bool>();
  s.unit = j.value("units", std::string("mm")) == "inches" ? 25.4 : 1;  // G20; else G21
  s.hotend_target = j.at("hotend_target").get<double>();
  s.bed_target = j.at("bed_target").get<double>();
  s.fan = j.at("fan").get<int>();
  s.filament_fed = j.value("filament_fed", 0.0);
  return s;
}

void write_all(int fd, const std::string& bytes, const std::string& path) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      throw ConfigError(fmt::format("{}: cannot write the journal: {}", path, std::strerror(errno)));
    }
    done += static_cast<std::size_t>(n);
  }
}

std::string local_time_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  return text;
}

}  // namespace

void write_journal(const std::string& path, const JournalRecord& r, bool durable) {
  json j{{"version", 1},
         {"job", r.job},
         {"gcode", {{"path", r.gcode_path}, {"hash", r.gcode_hash}, {"commands", r.commands},
                    {"layers", r.layers}}},
         {"printer_profile", r.printer},
         {"firmware", r.firmware},
         {"port", r.port},
         {"baud", r.baud},
         {"state", to_string(r.state)},
         {"reason", r.reason},
         {"resume", {{"layer_index", r.layer_index}, {"command", r.resume_command},
                     {"printer", to_json(r.state_at_resume)}}},
         {"updated", r.updated.empty() ? local_time_now() : r.updated},
         {"pid", r.pid != 0 ? r.pid : static_cast<int>(::getpid())}};
  const std::string bytes = j.dump(2) + "\n";
  const std::string temp = path + ".tmp";
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) {
    throw ConfigError(fmt::format("{}: cannot write the journal: {}", temp, std::strerror(errno)));
  }
  try {
    write_all(fd, bytes, temp);
    if (durable && ::fsync(fd) != 0) {
      throw ConfigError(fmt::format("{}: cannot sync the journal: {}", temp, std::strerror(errno)));
    }
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    throw ConfigError(fmt::format("{}: cannot replace the journal: {}", path, std::strerror(errno)));
  }
  // The rename is durable only once the directory entry is.
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const int dir_fd =
      durable ? ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC) : -1;
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

JournalRecord read_journal(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    throw ConfigError(fmt::format("{}: cannot open the job journal: check the path", path));
  }
  std::ostringstream text;
  text << in.rdbuf();
  json j;
  try {
    j = json::parse(text.str());
  } catch (const json::exception&) {
    throw ConfigError(fmt::format("{}: is not a mahost job journal (not JSON)", path));
  }
  try {
    if (j.at("version").get<int>() != 1) {
      throw ConfigError(fmt::format("{}: journal version {} is not one this mahost reads", path,
                                    j.at("version").dump()));
    }
    JournalRecord r;
    r.job = j.at("job").get<std::string>();
    r.gcode_path = j.at("gcode").at("path").get<std::string>();
    r.gcode_hash = j.at("gcode").at("hash").get<std::string>();
    r.commands = j.at("gcode").at("commands").get<std::size_t>();
    r.layers = j.at("gcode").at("layers").get<std::size_t>();
    r.printer = j.value("printer_profile", std::string());
    r.firmware = j.value("firmware", std::string());
    r.port = j.at("port").get<std::string>();
    r.baud = j.at("baud").get<int>();
    const std::string state = j.at("state").get<std::string>();
    const std::optional<JobState> parsed = parse_job_state(state);
    if (!parsed) {
      throw ConfigError(fmt::format("{}: the journal's state \"{}\" is not one a job records", path, state));
    }
    r.state = *parsed;
    r.reason = j.at("reason").get<std::string>();
    r.layer_index = j.at("resume").at("layer_index").get<int>();
    r.resume_command = j.at("resume").at("command").get<std::size_t>();
    r.state_at_resume = state_from_json(j.at("resume").at("printer"));
    if (const std::string units = j.at("resume").at("printer").value("units", std::string("mm"));
        units != "mm" && units != "inches") {
      throw ConfigError(fmt::format(
          "{}: the journal's units \"{}\" are neither \"mm\" nor \"inches\"", path, units));
    }
    r.updated = j.at("updated").get<std::string>();
    r.pid = j.value("pid", 0);
    return r;
  } catch (const json::exception& e) {
    throw ConfigError(fmt::format("{}: is not a complete mahost job journal ({})", path, e.what()));
  }
}

std::string resume_command(std::string_view journal_path, std::string_view port) {
  if (port.empty()) return fmt::format("mahost resume {} --dry-run", journal_path);
  return fmt::format("mahost resume {} --port {}", journal_path, port);
}

std::string job_directory() {
  std::filesystem::path dir;
  if (const char* runtime = std::getenv("XDG_RUNTIME_DIR"); runtime != nullptr && *runtime) {
    dir = std::filesystem::path(runtime) / "mahost";
  } else {
    dir = fmt::format("/tmp/mahost-{}", ::getuid());
  }
  if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) {
    throw ConfigError(fmt::format("{}: cannot create the job directory: {}", dir.string(),
                                  std::strerror(errno)));
  }
  struct stat info{};
  if (::lstat(dir.c_str(), &info) != 0 || !S_ISDIR(info.st_mode) || info.st_uid != ::getuid()) {
    throw ConfigError(fmt::format(
        "{}: is not a directory of yours; remove it or set XDG_RUNTIME_DIR", dir.string()));
  }
  if ((info.st_mode & 0077) != 0) ::chmod(dir.c_str(), 0700);
  return dir.string();
}

}  // namespace printer
