// `mahost profiles list`: the printer and material profiles mahost finds, by name, with the
// folder each comes from (the user's first, then the system's, then the shipped ones).
// `mahost profiles import FILE.ini`: PrusaSlicer's printers as mahost profiles, written to the
// user's folder (printer/prusa_import.h).
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/profile_paths.h"
#include "host/commands.h"
#include "printer/error.h"
#include "printer/profile.h"
#include "printer/prusa_import.h"

namespace host {
namespace {

struct ListedProfile {
  std::string id, name, folder;
};

// Each profile's id, its name as the file says it (or why it cannot be read), its folder.
template <class Load>
std::vector<ListedProfile> listed(const std::string& search_path, std::string_view kind, Load load) {
  std::vector<ListedProfile> rows;
  for (const printer::ProfileFile& file : printer::find_profiles(search_path, kind)) {
    ListedProfile row{file.id, "", file.path.substr(0, file.path.rfind('/'))};
    try {
      row.name = load(file.path).name;
    } catch (const printer::ConfigError& e) {
      row.name = fmt::format("(cannot be used: {})", e.what());
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

void print_table(std::string_view title, const std::vector<ListedProfile>& rows) {
  fmt::print("{} ({}):\n", title, rows.size());
  std::size_t id_width = 2, name_width = 4;
  for (const ListedProfile& r : rows) {
    id_width = std::max(id_width, r.id.size());
    name_width = std::max(name_width, r.name.size());
  }
  name_width = std::min<std::size_t>(name_width, 48);
  for (const ListedProfile& r : rows) {
    fmt::print("  {:<{}}  {:<{}}  {}\n", r.id, id_width, r.name, name_width, r.folder);
  }
}

void run_list() {
  const std::string search_path = app::profile_search_path();
  print_table("printers", listed(search_path, "printers", [&](const std::string& path) {
                return printer::load_printer_profile(path, search_path);
              }));
  print_table("materials", listed(search_path, "materials", [&](const std::string& path) {
                return printer::load_material_profile(path, search_path);
              }));
  std::string folders;
  for (std::string_view rest = search_path; !rest.empty();) {
    const std::size_t colon = rest.find(':');
    folders += fmt::format("\n  {}", rest.substr(0, colon));
    rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
  }
  fmt::print("folders, the first with a name wins:{}\n", folders);
}

struct ImportOptions {
  std::string file;
  std::vector<std::string> printers;
  bool all = false;
  std::string into;  // default: the user's folder
};

// The first line every imported profile starts with, so that importing again replaces what an
// import wrote and never a profile someone wrote by hand.
constexpr std::string_view kImportedMark = "imported from PrusaSlicer's";

bool written_by_import(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  return first.find(kImportedMark) != std::string::npos;
}

// Writes `text` to `path` whole or not at all (beside it, then renamed).
void write_file(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path partial = path.string() + ".part";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
      throw printer::ConfigError(fmt::format("cannot write {}: {}", partial.string(), std::strerror(errno)));
    }
  }
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) throw printer::ConfigError(fmt::format("cannot write {}: {}", path.string(), ec.message()));
}

void run_import(const ImportOptions& options) {
  namespace fs = std::filesystem;
  if (options.all && !options.printers.empty()) {
    throw printer::ConfigError("profiles import: give --printer NAME or --all, not both");
  }
  printer::PrusaImport imported = printer::import_prusa_ini_file(options.file, options.printers);
  if (!options.all && options.printers.empty() && imported.available.size() > 1) {
    throw printer::ConfigError(fmt::format(
        "{} has {} printers: name one with --printer (e.g. --printer \"{}\"), or take them all "
        "with --all", options.file, imported.available.size(), imported.available.front()));
  }
  const fs::path into = options.into.empty() ? printer::user_config_directory() : options.into;
  std::error_code ec;
  for (const char* kind : {"printers", "materials"}) {
    fs::create_directories(into / kind, ec);
    if (ec) {
      throw printer::ConfigError(fmt::format("cannot make {}: {}", (into / kind).string(), ec.message()));
    }
  }
  std::size_t printers = 0;
  std::map<std::string, std::string> materials;  // stem -> name, written
  for (const printer::ImportedPrinter& p : imported.printers) {
    const fs::path printer_path = into / "printers" / (p.printer.stem + ".toml");
    const fs::path material_path = into / "materials" / (p.material.stem + ".toml");
    bool taken = false;
    for (const fs::path& path : {printer_path, material_path}) {
      if (fs::exists(path) && !written_by_import(path) && !materials.count(p.material.stem)) {
        imported.refused.push_back({p.printer.name, fmt::format("{} exists and was not imported; move "
                                                                "it away, or import --into another folder",
                                                                path.string())});
        taken = true;
        break;
      }
    }
    if (taken) continue;
    if (!materials.count(p.material.stem)) {
      write_file(material_path, p.material.toml);
      materials[p.material.stem] = p.material.name;
    }
    write_file(printer_path, p.printer.toml);
    ++printers;
    if (!options.all) {
      fmt::print("imported {} as {} (material {}, speeds and layers of the print profile {})\n",
                 p.printer.name, printer_path.string(), p.material.name, p.print_profile);
    }
  }
  if (printers == 0 && imported.refused.size() == 1) {
    // The one printer asked for (or the file's only one) refused: that reason is the error.
    const printer::ImportRefusal& r = imported.refused.front();
    throw printer::ConfigError(fmt::format("{}: cannot import {}: {}", options.file, r.printer, r.reason));
  }
  if (options.all) {
    fmt::print("imported {} printer{} and {} material{} into {}\n", printers, printers == 1 ? "" : "s",
               materials.size(), materials.size() == 1 ? "" : "s", into.string());
  }
  for (const printer::ImportRefusal& r : imported.refused) {
    fmt::print("refused {}: {}\n", r.printer, r.reason);
  }
  if (printers == 0) {
    throw CommandExit{kExitBadInput, fmt::format("nothing imported from {}: {} printers refused, each "
                                                 "for the reason above", options.file, imported.refused.size())};
  }
  if (!options.all && !imported.refused.empty()) {
    throw CommandExit{kExitBadInput, ""};
  }
  if (options.printers.size() <= 1 && !options.all) {
    fmt::print("slice with: mahost slice MODEL --printer \"{}\"\n", imported.printers.front().printer.name);
  }
}

}  // namespace

void add_profiles_command(CLI::App& app) {
  CLI::App* profiles = app.add_subcommand("profiles", "List printer and material profiles, or import PrusaSlicer's");
  profiles->require_subcommand(1);
  CLI::App* list = profiles->add_subcommand("list", "List the printer and material profiles mahost finds");
  list->footer("Each profile's id (what --printer and --material take; its name works too), its "
               "name and its folder. Folders are searched in order: the user's "
               "($XDG_CONFIG_HOME/mahost, by default ~/.config/mahost), the system's "
               "(/etc/xdg/mahost), then the profiles shipped with mahost; $MAHOST_CONFIG_DIR, "
               "when set, replaces them all.");
  list->callback([] { run_list(); });

  auto options = std::make_shared<ImportOptions>();
  CLI::App* import = profiles->add_subcommand("import", "Import PrusaSlicer's printers as mahost profiles");
  import->footer(
      "FILE is a PrusaSlicer vendor bundle (Debian's prusa-slicer has them in "
      "/usr/share/PrusaSlicer/profiles), a config bundle or a config.ini PrusaSlicer exported. "
      "Each printer becomes a printer profile with its print profile's layers and speeds, and "
      "its filament a material profile; the start and end G-code keep PrusaSlicer's "
      "placeholders, evaluated for each slice. A printer mahost cannot drive or whose G-code "
      "names what mahost does not know is refused, with why. Then: mahost slice MODEL "
      "--printer NAME. Importing again replaces what an import wrote, never a profile written "
      "by hand.");
  import->add_option("FILE", options->file, "the PrusaSlicer .ini file")->required();
  import->add_option("--printer", options->printers,
                     "a printer of the file, by its name in PrusaSlicer; repeatable (default: the "
                     "file's only printer)")
      ->allow_extra_args(false);
  import->add_flag("--all", options->all, "every printer of the file (default: off)");
  import->add_option("--into", options->into,
                     "the folder to write printers/ and materials/ into, e.g. /etc/xdg/mahost for "
                     "every user and the mahost-serve service (default: $XDG_CONFIG_HOME/mahost, "
                     "~/.config/mahost)");
  import->callback([options] { run_import(*options); });
}

}  // namespace host
