// The files folder of `mahost serve`: the G-code and STL files it holds, as OctoPrint's
// "local" storage. Flat (no subfolders), and never left: every name is checked before it
// meets the file system, uploads are written to a hidden temporary file inside the folder and
// renamed into place only once complete and checked, and only regular files (not links) are
// listed, read or deleted.
//
// A name from a client is cleaned: refused when it holds a '/' or '\', a control character,
// starts with '.', or is longer than 200 bytes; otherwise spaces and characters outside
// [A-Za-z0-9._+-()] become '_' (OctoPrint also keeps names ASCII). Its extension says what it
// is: .gcode, .gco, .g (machine code) or .stl (a model).
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "printer/motion_model.h"

namespace host::serve {

enum class FileKind { gcode, model };
std::string_view to_string(FileKind kind);  // "machinecode", "model" (OctoPrint's types)

// What a G-code file will do, for the file list and the job: the motion model's estimate
// (heating not counted), the filament fed, the layers, and what the slicer wrote about itself.
struct GcodeAnalysis {
  std::size_t commands = 0, layers = 0;
  double estimated_seconds = 0;
  double filament_mm = 0;
  double filament_cm3 = 0;   // for the serving printer's filament diameter
  std::string contour;       // mahost's "; contour: ma" header, "" from other slicers
  std::string error;         // set when the file is not G-code the printer can take
};

struct StoredFile {
  std::string name;
  FileKind kind = FileKind::gcode;
  std::uint64_t size = 0;
  std::int64_t date = 0;     // modification time, Unix seconds
  std::optional<GcodeAnalysis> analysis;  // G-code only
};

// A client's name checked and cleaned, or why it is refused (with the HTTP status to answer).
struct CleanName {
  std::string name;   // set when accepted
  int status = 0;     // 400 (a path, a dot file, control characters, too long), 415 (not G-code or STL)
  std::string error;
};
CleanName clean_file_name(std::string_view given);
// True for a name clean_file_name leaves as it is: a name that may be looked up.
bool is_clean_name(std::string_view name);
std::optional<FileKind> kind_of(std::string_view name);

class FileStore {
 public:
  // Creates the folder (mode 0700) when missing and removes upload leftovers. Throws
  // printer::ConfigError naming the folder when it cannot be made or is not a folder.
  FileStore(std::string folder, printer::MotionLimits motion, double filament_diameter);

  const std::string& folder() const { return folder_; }

  // Every stored G-code and STL file, by name. G-code files are analysed the first time they
  // are listed (a few ms per MiB) and remembered while unchanged.
  std::vector<StoredFile> list();
  // A clean name's file, analysed; nullopt when there is none.
  std::optional<StoredFile> find(const std::string& name);
  // The path of a clean name in the folder (which need not exist); throws std::invalid_argument
  // for a name that is not clean (a bug in the caller: names are checked on the way in).
  std::string path_of(const std::string& name) const;
  bool remove(const std::string& name);
  std::uint64_t free_bytes() const;

  // An upload in progress: a temporary file in the folder, removed unless committed.
  class Upload {
   public:
    explicit Upload(FileStore& store);
    ~Upload();
    Upload(const Upload&) = delete;
    Upload& operator=(const Upload&) = delete;
    bool write(const char* data, std::size_t size);  // false once the disk is full or broken
    std::uint64_t size() const { return size_; }
    const std::string& temporary_path() const { return temp_; }
    // Writes the bytes through to the disk and closes the file: the slow part of storing it,
    // done before the rename (which the session makes under its lock). False when it cannot.
    bool finish();
    // Renames the finished upload to `name` (replacing a file of that name), finishing it
    // first if need be. False when it cannot; the temporary file is removed either way.
    bool commit(const std::string& name);

   private:
    FileStore& store_;
    std::string temp_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
    bool ok_ = true;
  };

  // Analyses G-code bytes (as the upload check and list() do).
  GcodeAnalysis analyse(const std::string& path) const;
  // Keeps the analysis of a file just stored, so it is not read again.
  void remember(const std::string& name, const GcodeAnalysis& analysis);

 private:
  struct Cached {
    std::uint64_t size = 0;
    std::int64_t mtime_ns = 0;
    GcodeAnalysis analysis;
  };
  std::optional<StoredFile> stat_file(const std::string& name);

  std::string folder_;
  printer::MotionLimits motion_;
  double filament_diameter_ = 1.75;
  std::mutex mutex_;  // guards cache_
  std::map<std::string, Cached> cache_;
};

}  // namespace host::serve
