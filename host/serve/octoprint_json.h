// The JSON of OctoPrint's REST API, the subset PrusaSlicer's and Cura's OctoPrint clients use
// (docs.octoprint.org, "REST API"; Moonraker's octoprint_compat answers the same), built from
// the session's Status. OctoPrint's fields keep their names, types and meaning; what mahost
// knows beyond them goes under a "mahost" key, never in place of theirs.
//
// Times are seconds, lengths mm, volumes cm³, temperatures °C, completion a percentage.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/serve/file_store.h"
#include "host/serve/printer_session.h"

namespace host::serve {

// OctoPrint's API version and the server version clients see; the text starts with
// "OctoPrint", which PrusaSlicer checks for.
inline constexpr const char* kOctoPrintApi = "0.1";
inline constexpr const char* kOctoPrintServer = "1.5.0";

// GET /api/version: {"api": "0.1", "server": "1.5.0", "text": "OctoPrint (mahost 0.1.0)"}.
nlohmann::json version_json(const std::string& mahost_version);

// A file as GET /api/files lists it: name, display, path, type, typePath, origin, size,
// date, refs, gcodeAnalysis (G-code), and "mahost": commands, layers, contour.
// `base` is the URL of the server ("http://host:port") for the refs.
nlohmann::json file_json(const StoredFile& file, const std::string& base);
// The abridged form in an upload's answer: name, display, path, origin, refs.
nlohmann::json abridged_file_json(const std::string& name, const std::string& base);
// GET /api/files and /api/files/local: {"files": [...], "free": bytes}.
nlohmann::json files_json(const std::vector<StoredFile>& files, std::uint64_t free_bytes,
                          const std::string& base);

// GET /api/job: {"job": {...}, "progress": {...}, "state": "...", "mahost": {...}}.
nlohmann::json job_json(const Status& status);

// GET /api/printer: {"temperature": {...}, "sd": {"ready": false}, "state": {"text", "flags"}};
// `exclude` as the query's (temperature, sd, state); history points when asked for.
nlohmann::json printer_json(const Status& status, const std::set<std::string>& exclude,
                            const std::optional<std::vector<TemperaturePoint>>& history);
// {"text": ..., "flags": {...}} of OctoPrint's printer state.
nlohmann::json printer_state_json(const Status& status);
// {"tool0": {"actual", "target", "offset"}, "bed": {...}} from the current temperatures.
nlohmann::json temperature_json(const Status& status);
nlohmann::json history_json(const std::vector<TemperaturePoint>& history);

// GET /api/connection.
nlohmann::json connection_json(const Status& status, int baud);
// GET /api/printerprofiles: the one profile served, current and default.
nlohmann::json printer_profiles_json(const printer::PrinterProfile& profile);
// GET /api/settings: what Cura's plugin reads (features, webcam, plugins), all off.
nlohmann::json settings_json();
// POST /api/login (passive) and GET /api/currentuser: the API key's user.
nlohmann::json user_json();

// The page's view of everything at once (GET /api/mahost/status and each live update):
// OctoPrint's job and printer state plus the connection, slicing, an interrupted job and
// events after `events_after`.
nlohmann::json page_status_json(const Status& status, const std::vector<Event>& events);

}  // namespace host::serve
