#include "host/serve/file_store.h"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include <fmt/core.h>

#include "app/model.h"
#include "host/serve/job_file.h"
#include "printer/error.h"
#include "printer/gcode_file.h"
#include "printer/print_state.h"
#include "printer/print_time.h"

namespace host::serve {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kLongestName = 200;
constexpr const char* kUploadPrefix = ".upload-";

bool allowed_character(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '-' || c == '+' || c == '(' || c == ')';
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string random_suffix() {
  unsigned char bytes[8];
  if (::getrandom(bytes, sizeof bytes, 0) != static_cast<ssize_t>(sizeof bytes)) {
    for (unsigned char& b : bytes) b = static_cast<unsigned char>(std::rand());
  }
  std::string s;
  for (unsigned char b : bytes) s += fmt::format("{:02x}", b);
  return s;
}

std::string header_value(std::string_view text, std::string_view key) {
  const std::string_view head = text.substr(0, std::min<std::size_t>(text.size(), 8192));
  const std::size_t at = head.find(key);
  if (at == std::string_view::npos) return {};
  std::string_view rest = head.substr(at + key.size());
  rest = rest.substr(0, rest.find_first_of("\r\n"));
  while (!rest.empty() && rest.back() == ' ') rest.remove_suffix(1);
  return std::string(rest);
}

}  // namespace

std::string_view to_string(FileKind kind) { return kind == FileKind::gcode ? "machinecode" : "model"; }

std::optional<FileKind> kind_of(std::string_view name) {
  const std::string extension = lower(fs::path(std::string(name)).extension().string());
  if (extension == ".gcode" || extension == ".gco" || extension == ".g") return FileKind::gcode;
  if (app::is_model_name(name)) return FileKind::model;
  return std::nullopt;
}

CleanName clean_file_name(std::string_view given) {
  CleanName result;
  auto refuse = [&](int status, std::string error) {
    result.status = status;
    result.error = std::move(error);
    return result;
  };
  if (given.empty()) return refuse(400, "the file has no name");
  if (given.size() > kLongestName) {
    return refuse(400, fmt::format("the file name is {} bytes long; {} at most", given.size(), kLongestName));
  }
  for (char c : given) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return refuse(400, "the file name contains control characters");
    if (c == '/' || c == '\\') {
      return refuse(400, "the file name contains a path: give a plain name (folders are not supported)");
    }
  }
  if (given.front() == '.') return refuse(400, "the file name starts with '.'");
  std::string name;
  for (char c : given) {
    const char kept = allowed_character(c) ? c : '_';
    if (kept == '_' && !name.empty() && name.back() == '_' && !allowed_character(c)) continue;
    name += kept;
  }
  if (!kind_of(name)) {
    return refuse(415, fmt::format("{}: only G-code (.gcode, .gco, .g) and models (.stl, .3mf, .obj) are taken", name));
  }
  result.name = name;
  return result;
}

bool is_clean_name(std::string_view name) {
  const CleanName clean = clean_file_name(name);
  return clean.status == 0 && clean.name == name;
}

FileStore::FileStore(std::string folder, printer::MotionLimits motion, double filament_diameter)
    : folder_(std::move(folder)), motion_(motion), filament_diameter_(filament_diameter) {
  std::error_code error;
  fs::create_directories(folder_, error);
  if (error || !fs::is_directory(folder_)) {
    throw printer::ConfigError(fmt::format("{}: cannot use it as the files folder{}{}", folder_,
                                           error ? ": " : "", error ? error.message() : ""));
  }
  folder_ = fs::canonical(folder_).string();
  // Uploads cut short by a crash.
  for (const fs::directory_entry& entry : fs::directory_iterator(folder_, error)) {
    if (entry.path().filename().string().rfind(kUploadPrefix, 0) == 0) fs::remove(entry.path(), error);
  }
}

std::string FileStore::path_of(const std::string& name) const {
  if (!is_clean_name(name)) throw std::invalid_argument("not a clean file name: " + name);
  return folder_ + "/" + name;
}

GcodeAnalysis FileStore::analyse(const std::string& path) const {
  // A piece at a time, as a job reads it: a file of any size analysed in a few MiB.
  GcodeAnalysis a;
  const std::string name = fs::path(path).filename().string();
  try {
    printer::PrintClock clock(motion_);
    printer::PrintState state;
    printer::for_each_gcode_piece(path, name, kUploadedGcode, [&](const printer::GcodePiece& piece) {
      if (piece.offset == 0) a.contour = header_value(piece.text, "; contour: ");
      for (std::size_t i = 0; i < piece.gcode.size(); ++i) {
        clock.line(piece.gcode.command(i));
        printer::apply(state, piece.gcode.command(i));
      }
      a.commands += piece.gcode.size();
      a.layers += piece.gcode.layers.size();
    });
    if (a.commands == 0) throw printer::ConfigError(fmt::format("{}: the file has no G-code commands", name));
    // The motion model's time, as the job's estimate reads it (printer::PrintEta).
    a.estimated_seconds = clock.finish();
    a.filament_mm = state.filament_fed;
    const double radius = filament_diameter_ / 2;
    a.filament_cm3 = a.filament_mm * std::acos(-1.0) * radius * radius / 1000.0;
  } catch (const printer::ConfigError& e) {
    a = GcodeAnalysis{};
    a.error = e.what();
  }
  return a;
}

std::optional<StoredFile> FileStore::stat_file(const std::string& name) {
  struct stat info {};
  const std::string path = path_of(name);
  if (::lstat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return std::nullopt;
  StoredFile file;
  file.name = name;
  file.kind = *kind_of(name);
  file.size = static_cast<std::uint64_t>(info.st_size);
  file.date = info.st_mtim.tv_sec;
  if (file.kind == FileKind::gcode) {
    const std::int64_t mtime_ns = info.st_mtim.tv_sec * 1'000'000'000LL + info.st_mtim.tv_nsec;
    {
      std::lock_guard lock(mutex_);
      const auto it = cache_.find(name);
      if (it != cache_.end() && it->second.size == file.size && it->second.mtime_ns == mtime_ns) {
        file.analysis = it->second.analysis;
        return file;
      }
    }
    GcodeAnalysis analysis = analyse(path);
    std::lock_guard lock(mutex_);
    cache_[name] = Cached{file.size, mtime_ns, analysis};
    file.analysis = std::move(analysis);
  }
  return file;
}

void FileStore::remember(const std::string& name, const GcodeAnalysis& analysis) {
  struct stat info {};
  if (!is_clean_name(name) || ::lstat(path_of(name).c_str(), &info) != 0) return;
  const std::int64_t mtime_ns = info.st_mtim.tv_sec * 1'000'000'000LL + info.st_mtim.tv_nsec;
  std::lock_guard lock(mutex_);
  cache_[name] = Cached{static_cast<std::uint64_t>(info.st_size), mtime_ns, analysis};
}

std::vector<StoredFile> FileStore::list() {
  std::vector<std::string> names;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder_, error)) {
    const std::string name = entry.path().filename().string();
    if (is_clean_name(name)) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  std::vector<StoredFile> files;
  for (const std::string& name : names) {
    if (auto file = stat_file(name)) files.push_back(std::move(*file));
  }
  return files;
}

std::optional<StoredFile> FileStore::find(const std::string& name) {
  if (!is_clean_name(name)) return std::nullopt;
  return stat_file(name);
}

bool FileStore::remove(const std::string& name) {
  if (!is_clean_name(name)) return false;
  struct stat info {};
  const std::string path = path_of(name);
  if (::lstat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return false;
  {
    std::lock_guard lock(mutex_);
    cache_.erase(name);
  }
  return ::unlink(path.c_str()) == 0;
}

std::uint64_t FileStore::free_bytes() const {
  struct statvfs info {};
  if (::statvfs(folder_.c_str(), &info) != 0) return 0;
  return static_cast<std::uint64_t>(info.f_bavail) * info.f_frsize;
}

FileStore::Upload::Upload(FileStore& store) : store_(store) {
  for (int attempt = 0; attempt < 8 && fd_ < 0; ++attempt) {
    temp_ = store_.folder_ + "/" + kUploadPrefix + random_suffix() + ".part";
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0600);
  }
  ok_ = fd_ >= 0;
}

FileStore::Upload::~Upload() {
  if (fd_ >= 0) ::close(fd_);
  if (!temp_.empty()) ::unlink(temp_.c_str());
}

bool FileStore::Upload::write(const char* data, std::size_t size) {
  while (ok_ && size > 0) {
    const ssize_t n = ::write(fd_, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      ok_ = false;
      break;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
    size_ += static_cast<std::uint64_t>(n);
  }
  return ok_;
}

bool FileStore::Upload::finish() {
  if (fd_ >= 0) {
    ok_ = ok_ && ::fsync(fd_) == 0;
    ::close(fd_);
    fd_ = -1;
  }
  return ok_;
}

bool FileStore::Upload::commit(const std::string& name) {
  if (!finish() || temp_.empty()) return false;
  const std::string target = store_.path_of(name);
  {
    std::lock_guard lock(store_.mutex_);
    store_.cache_.erase(name);
  }
  if (::rename(temp_.c_str(), target.c_str()) != 0) return false;
  temp_.clear();
  return true;
}

}  // namespace host::serve
