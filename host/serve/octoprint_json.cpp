#include "host/serve/octoprint_json.h"

#include <cmath>

#include <fmt/core.h>

namespace host::serve {

using nlohmann::json;

namespace {

json or_null(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

// Temperatures to two decimals, as Marlin prints them.
json temperature(const std::optional<double>& v) {
  return v ? json(std::round(*v * 100) / 100) : json(nullptr);
}

json seconds(std::chrono::nanoseconds t) {
  return json(static_cast<long long>(std::llround(std::chrono::duration<double>(t).count())));
}

std::string job_state_name(const Status& s) {
  if (s.job_active) {
    if (!s.progress) return "starting";
    return std::string(printer::to_string(s.progress->state));
  }
  if (s.ended) return std::string(printer::to_string(*s.ended));
  return "none";
}

}  // namespace

json version_json(const std::string& mahost_version) {
  return {{"api", kOctoPrintApi},
          {"server", kOctoPrintServer},
          {"text", fmt::format("OctoPrint (mahost {})", mahost_version)},
          {"mahost", mahost_version}};
}

json abridged_file_json(const std::string& name, const std::string& base) {
  return {{"name", name},
          {"display", name},
          {"path", name},
          {"origin", "local"},
          {"refs",
           {{"resource", base + "/api/files/local/" + name},
            {"download", base + "/downloads/files/local/" + name}}}};
}

json file_json(const StoredFile& file, const std::string& base) {
  json j = abridged_file_json(file.name, base);
  j["type"] = std::string(to_string(file.kind));
  j["typePath"] = file.kind == FileKind::gcode ? json::array({"machinecode", "gcode"})
                                               : json::array({"model", "stl"});
  j["size"] = file.size;
  j["date"] = file.date;
  if (file.analysis && file.analysis->error.empty()) {
    const GcodeAnalysis& a = *file.analysis;
    j["gcodeAnalysis"] = {
        {"estimatedPrintTime", std::llround(a.estimated_seconds)},
        {"filament", {{"length", std::llround(a.filament_mm)}, {"volume", std::round(a.filament_cm3 * 100) / 100}}}};
    j["mahost"] = {{"commands", a.commands}, {"layers", a.layers}, {"contour", a.contour}};
  } else if (file.analysis) {
    j["mahost"] = {{"error", file.analysis->error}};
  }
  return j;
}

json files_json(const std::vector<StoredFile>& files, std::uint64_t free_bytes, const std::string& base) {
  json list = json::array();
  for (const StoredFile& f : files) list.push_back(file_json(f, base));
  return {{"files", list}, {"free", free_bytes}};
}

json job_json(const Status& s) {
  json file = {{"name", nullptr}, {"path", nullptr}, {"display", nullptr},
               {"origin", nullptr}, {"size", nullptr}, {"date", nullptr}};
  json estimated = nullptr, filament = nullptr;
  if (s.selected) {
    file = {{"name", s.selected->name}, {"path", s.selected->name}, {"display", s.selected->name},
            {"origin", "local"},        {"size", s.selected->size},  {"date", s.selected->date}};
    if (s.selected->analysis && s.selected->analysis->error.empty()) {
      estimated = std::llround(s.selected->analysis->estimated_seconds);
      filament = {{"length", std::llround(s.selected->analysis->filament_mm)},
                  {"volume", std::round(s.selected->analysis->filament_cm3 * 100) / 100}};
    }
  }
  json progress = {{"completion", nullptr}, {"filepos", nullptr}, {"printTime", nullptr},
                   {"printTimeLeft", nullptr}, {"printTimeLeftOrigin", nullptr}};
  json mahost = {{"jobState", job_state_name(s)}};
  if (s.progress) {
    const printer::JobProgress& p = *s.progress;
    const bool completed = !s.job_active && s.ended == printer::JobState::completed;
    progress["completion"] = completed ? 100.0 : 100.0 * p.fraction;
    progress["filepos"] = s.filepos;
    progress["printTime"] = seconds(p.elapsed);
    if (completed) {
      progress["printTimeLeft"] = 0;
    } else if (p.remaining) {
      // The heat-up still to come is in the time left, where its pace is known.
      const double heating = s.job_active && s.heating ? s.heating->seconds_left.value_or(0) : 0;
      progress["printTimeLeft"] = std::llround(std::chrono::duration<double>(*p.remaining).count() + heating);
      progress["printTimeLeftOrigin"] = "estimate";
    }
    mahost["layer"] = p.layer;
    mahost["layers"] = p.layers;
    mahost["z"] = or_null(s.layer_z);
    mahost["commandsDone"] = p.commands_done;
    mahost["commandsTotal"] = p.commands_total;
    mahost["pauseBeforeLayer"] = p.pause_before_layer;
    mahost["estimating"] = p.estimating;
  }
  if (s.job_active && s.heating) {
    mahost["heating"] = {{"secondsLeft", s.heating->seconds_left ? json(std::llround(*s.heating->seconds_left)) : json(nullptr)}};
  }
  if (s.selected && s.selected->analysis) mahost["contour"] = s.selected->analysis->contour;
  if (!s.job_active && s.ended) mahost["endedReason"] = s.ended_reason;
  json j = {{"job",
             {{"file", file},
              {"estimatedPrintTime", estimated},
              {"lastPrintTime", nullptr},
              {"filament", filament},
              {"user", "_api"}}},
            {"progress", progress},
            {"state", state_text(s)},
            {"mahost", mahost}};
  if (s.connection == Connection::error && !s.error.empty()) {
    j["error"] = s.error;
  } else if (!s.job_active && s.ended == printer::JobState::failed) {
    j["error"] = s.ended_reason;
  }
  return j;
}

json printer_state_json(const Status& s) {
  const std::string text = state_text(s);
  const bool operational = s.connection == Connection::operational;
  return {{"text", text},
          {"flags",
           {{"operational", operational},
            {"paused", text == "Paused"},
            {"printing", text == "Printing"},
            {"pausing", text == "Pausing"},
            {"cancelling", text == "Cancelling"},
            {"sdReady", false},
            {"error", s.connection == Connection::error},
            {"ready", operational && !s.job_active},
            {"closedOrError", s.connection == Connection::error || s.connection == Connection::closed}}}};
}

json temperature_json(const Status& s) {
  const printer::Temperatures t = s.temperatures.value_or(printer::Temperatures{});
  return {{"tool0", {{"actual", temperature(t.hotend)}, {"target", or_null(t.hotend_target)}, {"offset", 0}}},
          {"bed", {{"actual", temperature(t.bed)}, {"target", or_null(t.bed_target)}, {"offset", 0}}}};
}

json history_json(const std::vector<TemperaturePoint>& history) {
  json list = json::array();
  for (const TemperaturePoint& p : history) {
    list.push_back({{"time", p.time},
                    {"tool0", {{"actual", temperature(p.temperatures.hotend)}, {"target", or_null(p.temperatures.hotend_target)}}},
                    {"bed", {{"actual", temperature(p.temperatures.bed)}, {"target", or_null(p.temperatures.bed_target)}}}});
  }
  return list;
}

json printer_json(const Status& s, const std::set<std::string>& exclude,
                  const std::optional<std::vector<TemperaturePoint>>& history) {
  json j = json::object();
  if (!exclude.count("temperature")) {
    j["temperature"] = temperature_json(s);
    // OctoPrint lists the newest point first.
    if (history) j["temperature"]["history"] = history_json({history->rbegin(), history->rend()});
  }
  if (!exclude.count("sd")) j["sd"] = {{"ready", false}};
  if (!exclude.count("state")) j["state"] = printer_state_json(s);
  return j;
}

json connection_json(const Status& s, int baud) {
  const std::string port = s.link;
  return {{"current",
           {{"state", state_text(s)}, {"port", port}, {"baudrate", baud}, {"printerProfile", "_default"}}},
          {"options",
           {{"ports", json::array({port})},
            {"baudrates", json::array({baud})},
            {"printerProfiles", json::array({{{"id", "_default"}, {"name", "_default"}}})},
            {"portPreference", port},
            {"baudratePreference", baud},
            {"printerProfilePreference", "_default"},
            {"autoconnect", true}}}};
}

json printer_profiles_json(const printer::PrinterProfile& p) {
  auto axis = [&](std::size_t i) {
    return json{{"speed", std::llround(p.motion.max_speed[i] * 60)}, {"inverted", false}};
  };
  return {{"profiles",
           {{"_default",
             {{"id", "_default"},
              {"name", p.name},
              {"model", p.name},
              {"color", "default"},
              {"current", true},
              {"default", true},
              {"heatedBed", true},
              {"heatedChamber", false},
              {"volume",
               {{"width", p.bed_x}, {"depth", p.bed_y}, {"height", p.bed_z},
                {"formFactor", "rectangular"}, {"origin", "lowerleft"}}},
              {"axes", {{"x", axis(0)}, {"y", axis(1)}, {"z", axis(2)}, {"e", axis(3)}}},
              {"extruder",
               {{"count", 1}, {"nozzleDiameter", p.nozzle_diameter},
                {"offsets", json::array({json::array({0.0, 0.0})})}, {"sharedNozzle", false}}}}}}}};
}

json settings_json() {
  return {{"api", {{"allowCrossOrigin", false}}},
          {"feature", {{"sdSupport", false}, {"temperatureGraph", true}}},
          {"webcam", {{"webcamEnabled", false}, {"streamUrl", ""}, {"snapshotUrl", ""},
                      {"flipH", false}, {"flipV", false}, {"rotate90", false}}},
          {"plugins", json::object()}};
}

json user_json() {
  return {{"name", "_api"},
          {"active", true},
          {"admin", true},
          {"user", true},
          {"apikey", nullptr},
          {"settings", json::object()},
          {"groups", json::array({"admins", "users"})},
          {"permissions", json::array()},
          {"_is_external_client", false},
          {"_login_mechanism", "apikey"}};
}

json page_status_json(const Status& s, const std::vector<Event>& events) {
  json j = job_json(s);
  j["printer"] = printer_state_json(s);
  j["temperature"] = temperature_json(s);
  json connection = {{"link", s.link}, {"firmware", s.firmware}, {"dryRun", s.dry_run},
                     {"error", s.error}, {"retries", s.retries}};
  j["connection"] = connection;
  j["instance"] = s.instance;
  j["version"] = s.version;
  json locks = json::object();
  for (const auto& [name, reason] : file_locks(s)) locks[name] = reason;
  j["fileLocks"] = locks;
  j["startRefusal"] = start_refusal(s);
  j["journal"] = s.journal;
  j["pauseAt"] = s.pause_at;
  if (s.slicing) {
    const SliceStatus& sl = *s.slicing;
    j["slicing"] = {{"model", sl.model}, {"gcode", sl.gcode}, {"stage", sl.stage},
                    {"done", sl.done}, {"total", sl.total}, {"error", sl.error},
                    {"summary", sl.summary}, {"plan", sl.plan}};
  } else {
    j["slicing"] = nullptr;
  }
  if (s.interrupted) {
    const InterruptedJob& i = *s.interrupted;
    j["interrupted"] = {{"journal", i.journal}, {"file", i.file}, {"state", i.state},
                        {"reason", i.reason}, {"updated", i.updated}, {"layer", i.layer},
                        {"layers", i.layers}};
  } else {
    j["interrupted"] = nullptr;
  }
  json list = json::array();
  for (const Event& e : events) list.push_back({{"id", e.id}, {"time", e.time}, {"text", e.text}});
  j["events"] = list;
  return j;
}

}  // namespace host::serve
