#include "host/serve/job_file.h"

#include <algorithm>
#include <cstdint>

#include <fmt/core.h>

#include "geometry/core/text.h"
#include "printer/error.h"
#include "printer/gcode_line.h"

namespace host::serve {

namespace {

using geometry::trim;

// The byte after each command's line, by parse_gcode's own rule for what is a command: the
// text before ';' on a line, trimmed, when not empty.
std::vector<std::uint64_t> command_ends(std::string_view text) {
  std::vector<std::uint64_t> ends;
  std::uint64_t offset = 0;
  while (offset < text.size()) {
    const std::size_t end = text.find('\n', offset);
    const std::size_t line_end = end == std::string_view::npos ? text.size() : end;
    std::string_view line = text.substr(offset, line_end - offset);
    if (const auto semicolon = line.find(';'); semicolon != std::string_view::npos) {
      line = line.substr(0, semicolon);
    }
    offset = end == std::string_view::npos ? text.size() : end + 1;
    if (!trim(line).empty()) ends.push_back(offset);
  }
  return ends;
}

bool is_move(const printer::GcodeCommand& c) {
  return c.letter == 'G' && c.code >= 0 && c.code <= 3;
}

}  // namespace

std::uint64_t JobFile::filepos(std::size_t commands) const {
  if (commands == 0 || command_end.empty()) return 0;
  return command_end[std::min(commands, command_end.size()) - 1];
}

namespace {

// The state at each layer start and the part's extent, from the file's commands.
void add_layer_states(JobFile& file) {
  file.layer_start.reserve(file.gcode.layers.size());
  printer::PrintState state;
  std::size_t next_layer = 0;
  bool any = false;
  for (std::size_t i = 0; i < file.gcode.size(); ++i) {
    while (next_layer < file.gcode.layers.size() && file.gcode.layers[next_layer].first_command == i) {
      file.layer_start.push_back(state);
      ++next_layer;
    }
    const printer::GcodeCommand command = printer::parse_gcode_line(file.gcode.command(i));
    const printer::PrintState before = state;
    printer::apply(state, command);
    // The part's extent: extrusions inside layers (a prime line before the first is not part).
    if (next_layer > 0 && is_move(command) && state.filament_fed > before.filament_fed &&
        (state.x != before.x || state.y != before.y)) {
      if (!any) {
        file.min_x = file.max_x = before.x;
        file.min_y = file.max_y = before.y;
        any = true;
      }
      file.min_x = std::min({file.min_x, before.x, state.x});
      file.max_x = std::max({file.max_x, before.x, state.x});
      file.min_y = std::min({file.min_y, before.y, state.y});
      file.max_y = std::max({file.max_y, before.y, state.y});
    }
  }
  // Layer marks after the last command (an empty last layer) start where the file ends.
  while (file.layer_start.size() < file.gcode.layers.size()) file.layer_start.push_back(state);
}

void check_command_ends(const JobFile& file, const std::string& name) {
  if (file.command_end.size() != file.gcode.size()) {
    // Both count by the same rule; a mismatch would be a bug here, not the user's file.
    throw std::logic_error(fmt::format("{}: {} command lines found for {} commands", name,
                                       file.command_end.size(), file.gcode.size()));
  }
}

}  // namespace

JobFile load_job_file(std::string_view bytes, const std::string& name) {
  JobFile file;
  file.gcode = printer::parse_gcode(bytes, name, kUploadedGcode);
  if (file.gcode.size() == 0) {
    throw printer::ConfigError(fmt::format("{}: the file has no G-code commands", name));
  }
  file.bytes = bytes.size();
  file.command_end = command_ends(bytes);
  check_command_ends(file, name);
  add_layer_states(file);
  return file;
}

JobFile read_job_file(const std::string& path) {
  // Read a piece at a time: the file's bytes are never all in memory, its commands are.
  JobFile file;
  printer::GcodeFile& gcode = file.gcode;
  gcode.path = path;
  gcode.hash = printer::for_each_gcode_piece(path, path, kUploadedGcode, [&](const printer::GcodePiece& piece) {
    gcode.append(piece.gcode);
    for (const std::uint64_t end : command_ends(piece.text)) file.command_end.push_back(piece.offset + end);
    file.bytes = piece.offset + piece.text.size();
  });
  if (gcode.size() == 0) throw printer::ConfigError(fmt::format("{}: the file has no G-code commands", path));
  check_command_ends(file, path);
  add_layer_states(file);
  return file;
}

std::vector<LayerMove> layer_moves(const JobFile& file, int index) {
  std::vector<LayerMove> moves;
  const auto& layers = file.gcode.layers;
  if (index < 0 || static_cast<std::size_t>(index) >= layers.size()) return moves;
  const std::size_t first = layers[static_cast<std::size_t>(index)].first_command;
  const std::size_t end = static_cast<std::size_t>(index) + 1 < layers.size()
                              ? layers[static_cast<std::size_t>(index) + 1].first_command
                              : file.gcode.size();
  printer::PrintState state = file.layer_start[static_cast<std::size_t>(index)];
  for (std::size_t i = first; i < end; ++i) {
    const printer::GcodeCommand command = printer::parse_gcode_line(file.gcode.command(i));
    const printer::PrintState before = state;
    printer::apply(state, command);
    if (!is_move(command) || (state.x == before.x && state.y == before.y)) continue;
    moves.push_back(LayerMove{static_cast<float>(before.x), static_cast<float>(before.y),
                              static_cast<float>(state.x), static_cast<float>(state.y),
                              state.filament_fed > before.filament_fed, static_cast<std::uint32_t>(i)});
  }
  return moves;
}

std::string svg_path(const std::vector<LayerMove>& moves, bool extrudes, std::size_t from_command,
                     std::size_t to_command) {
  std::string d;
  bool open = false;
  float last_x = 0, last_y = 0;
  for (const LayerMove& m : moves) {
    const bool take = m.extrudes == extrudes && m.command >= from_command && m.command < to_command;
    if (!take) {
      open = false;
      continue;
    }
    if (!open || m.x0 != last_x || m.y0 != last_y) d += fmt::format("M{:.2f} {:.2f}", m.x0, m.y0);
    d += fmt::format("L{:.2f} {:.2f}", m.x1, m.y1);
    open = true;
    last_x = m.x1;
    last_y = m.y1;
  }
  return d;
}

}  // namespace host::serve
