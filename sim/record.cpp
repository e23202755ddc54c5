#include "sim/record.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "geometry/mesh/stl_io.h"
#include "printer/error.h"
#include "sim/printed_part.h"

namespace sim {

namespace {

std::string_view state_name(PrinterState state) {
  switch (state) {
    case PrinterState::running: return "running";
    case PrinterState::booting: return "booting";
    case PrinterState::halted: return "halted";
    case PrinterState::disconnected: return "disconnected";
  }
  return "running";
}

std::string json_string(std::string_view text) { return nlohmann::json(std::string(text)).dump(); }

}  // namespace

void write_record_json(const Printer& printer, const std::string& path) {
  // Streamed rather than built as one nlohmann::json: a long print has a million moves.
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!file) {
    throw printer::ConfigError(fmt::format("cannot write the record {}: {}; check the folder exists "
                                           "and is writable", path, std::strerror(errno)));
  }
  std::FILE* f = file.get();
  const Config& c = printer.config();
  const Counters& n = printer.counters();
  fmt::print(f, "{{\n\"firmware\":{{\"name\":\"{}\",\"queue_depth\":{},\"planner_depth\":{},"
                "\"rx_buffer_size\":{},\"max_cmd_size\":{},\"advanced_ok\":{},"
                "\"ok_after_resend\":{},\"emergency_parser\":{},\"baud\":{}}},\n",
             to_string(c.dialect), c.queue_depth, c.planner_depth, c.rx_buffer_size, c.max_cmd_size, c.advanced_ok,
             c.ok_after_resend, c.emergency_parser, c.baud);
  fmt::print(f, "\"faults\":{},\n\"state\":\"{}\",\n\"stop_reason\":{},\n", json_string(to_string(c.faults)),
             state_name(printer.state()), json_string(printer.stop_reason()));
  fmt::print(f, "\"sim_time\":{},\n\"motion_time\":{},\n\"planner_starved\":{},\n", printer.now(),
             printer.motion_time(), printer.planner_starved());
  fmt::print(f,
             "\"counters\":{{\"bytes_received\":{},\"bytes_sent\":{},\"lines\":{},\"commands\":{},"
             "\"resends\":{},\"errors\":{},\"faults_injected\":{},\"overflows\":{},"
             "\"overflow_bytes\":{},\"long_lines\":{},\"unknown_commands\":{},\"resets\":{},"
             "\"longest_idle\":{}}},\n",
             n.bytes_received, n.bytes_sent, n.lines, n.commands, n.resends, n.errors,
             n.faults_injected, n.overflows, n.overflow_bytes, n.long_lines, n.unknown_commands,
             n.resets, n.longest_idle);
  fmt::print(f, "\"lost_ok_waits\":[");
  const auto& waits = printer.lost_ok_waits();
  for (std::size_t i = 0; i < waits.size(); ++i) fmt::print(f, "{}{}", i ? "," : "", waits[i]);
  fmt::print(f, "],\n");
  fmt::print(f, "\"commands\":[");
  const auto& commands = printer.executed_commands();
  for (std::size_t i = 0; i < commands.size(); ++i) {
    fmt::print(f, "{}\n{}", i ? "," : "", json_string(commands[i]));
  }
  fmt::print(f, "],\n\"moves\":[");
  const DepositionRecord& record = printer.deposition();
  for (std::size_t i = 0; i < record.moves.size(); ++i) {
    const DepositedMove& m = record.moves[i];
    fmt::print(f, "{}\n{{\"layer\":{},\"z\":{},\"x0\":{},\"y0\":{},\"x1\":{},\"y1\":{},\"e\":{},\"f\":{}}}",
               i ? "," : "", m.layer, m.z, m.start.x, m.start.y, m.end.x, m.end.y, m.e, m.feedrate);
  }
  fmt::print(f, "],\n\"layers\":[");
  const auto layers = bead_polygons(record, c.filament_diameter);
  for (std::size_t i = 0; i < layers.size(); ++i) {
    fmt::print(f, "{}\n{{\"z\":{},\"height\":{},\"beads\":[", i ? "," : "", layers[i].z,
               layers[i].height);
    for (std::size_t b = 0; b < layers[i].beads.size(); ++b) {
      const auto& o = layers[i].beads[b].outline;
      fmt::print(f, "{}[[{},{}],[{},{}],[{},{}],[{},{}]]", b ? "," : "", o[0].x, o[0].y, o[1].x,
                 o[1].y, o[2].x, o[2].y, o[3].x, o[3].y);
    }
    fmt::print(f, "]}}");
  }
  fmt::print(f, "]\n}}\n");
  if (std::ferror(f) || std::fflush(f) != 0) {
    throw printer::ConfigError(fmt::format("cannot write the record {}: {}", path, std::strerror(errno)));
  }
}

void write_printed_stl(const Printer& printer, const std::string& path) {
  geometry::write_stl_binary(path, printed_part(printer.deposition(), printer.config().filament_diameter));
}

}  // namespace sim
