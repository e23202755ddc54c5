#include "host/serve/job_file.h"

#include <algorithm>
#include <cstdint>

#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_line.h"

namespace host::serve {

namespace {

bool is_move(const printer::GcodeCommand& c) {
  return c.letter == 'G' && c.code >= 0 && c.code <= 3;
}

// The state at each layer start and the part's extent, read from the commands in order, a
// piece of the file at a time.
class LayerStates {
 public:
  explicit LayerStates(JobFile& file) : file_(file) {}

  // A held piece's commands and its layers (their first_command counted from the piece's start).
  void add(const printer::GcodeFile& piece) {
    std::size_t next_layer = 0;
    for (std::size_t i = 0; i < piece.size(); ++i) {
      while (next_layer < piece.layers.size() && piece.layers[next_layer].first_command == i) {
        file_.layer_start.push_back(state_);
        ++next_layer;
      }
      const printer::GcodeCommand command = printer::parse_gcode_line(piece.command(i));
      const printer::PrintState before = state_;
      printer::apply(state_, command);
      // The part's extent: extrusions inside layers (a prime line before the first is not part).
      if (!file_.layer_start.empty() && is_move(command) && state_.filament_fed > before.filament_fed &&
          (state_.x != before.x || state_.y != before.y)) {
        if (!any_) {
          file_.min_x = file_.max_x = before.x;
          file_.min_y = file_.max_y = before.y;
          any_ = true;
        }
        file_.min_x = std::min({file_.min_x, before.x, state_.x});
        file_.max_x = std::max({file_.max_x, before.x, state_.x});
        file_.min_y = std::min({file_.min_y, before.y, state_.y});
        file_.max_y = std::max({file_.max_y, before.y, state_.y});
      }
    }
    // Layer marks after the piece's last command: a piece ends before a mark except at the
    // file's end, so these are empty last layers, starting where the file ends.
    for (; next_layer < piece.layers.size(); ++next_layer) file_.layer_start.push_back(state_);
  }

 private:
  JobFile& file_;
  printer::PrintState state_;
  bool any_ = false;
};

}  // namespace

JobFile load_job_file(std::string_view bytes, const std::string& name) {
  JobFile file;
  file.gcode = printer::parse_gcode(bytes, name, kUploadedGcode);
  if (file.gcode.size() == 0) {
    throw printer::ConfigError(fmt::format("{}: the file has no G-code commands", name));
  }
  file.bytes = bytes.size();
  LayerStates(file).add(file.gcode);
  return file;
}

JobFile read_job_file(const std::string& path) {
  JobFile file;
  LayerStates states(file);
  file.gcode = printer::read_gcode_file(path, kUploadedGcode, printer::kGcodeBlock,
                                        [&](const printer::GcodePiece& piece) {
                                          states.add(piece.gcode);
                                          file.bytes = piece.offset + piece.text.size();
                                        });
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
  printer::GcodeReader reader(file.gcode);
  for (std::size_t i = first; i < end; ++i) {
    const printer::GcodeCommand command = printer::parse_gcode_line(reader.command(i));
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
