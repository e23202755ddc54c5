#include "host/serve/http_api.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <thread>

#include <httplib.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/error.h"
#include "app/layer_choice.h"
#include "app/model.h"
#include "app/profile_paths.h"
#include "app/slice_options.h"
#include "host/local_time.h"
#include "host/serve/api_key.h"
#include "host/serve/file_store.h"
#include "host/serve/http_server.h"
#include "host/serve/octoprint_json.h"
#include "host/serve/printer_session.h"
#include "host/serve/web_assets.h"
#include "printer/error.h"
#include "printer/gcode_line.h"
#include "printer/line_protocol.h"
#include "printer/profile.h"

namespace host::serve {

using nlohmann::json;
using httplib::Request;
using httplib::Response;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// A refusal the handler answers with (status, message).
struct Refusal {
  int status;
  std::string message;
};

void send_json(Response& res, const json& body, int status = 200) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void send_error(Response& res, int status, const std::string& message) {
  send_json(res, json{{"error", message}}, status);
}

void send_outcome(Response& res, const Outcome& outcome) {
  if (outcome.ok()) {
    res.status = outcome.status;
  } else {
    send_error(res, outcome.status, outcome.message);
  }
}

// The body of a JSON request: an object, or a Refusal (400).
json json_body(const Request& req) {
  json body = json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) {
    throw Refusal{400, "the request body is not a JSON object"};
  }
  return body;
}

std::string string_field(const json& body, const char* key) {
  const auto it = body.find(key);
  if (it == body.end() || it->is_null()) return {};
  if (!it->is_string()) throw Refusal{400, fmt::format("\"{}\" must be a string", key)};
  return it->get<std::string>();
}

bool bool_field(const json& body, const char* key) {
  const auto it = body.find(key);
  if (it == body.end() || it->is_null()) return false;
  if (it->is_boolean()) return it->get<bool>();
  if (it->is_string()) {
    std::string v = it->get<std::string>();
    std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
    return v == "true" || v == "1" || v == "yes";
  }
  throw Refusal{400, fmt::format("\"{}\" must be true or false", key)};
}

bool truthy(std::string text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text == "true" || text == "1" || text == "yes" || text == "on";
}

// "http://host:port" as the client addressed us, for the refs OctoPrint gives as URLs.
std::string base_url(const Request& req) {
  std::string host = req.get_header_value("Host");
  if (host.empty() || host.size() > 255 || host.find_first_of(" \"\\<>") != std::string::npos) host = "localhost";
  return "http://" + host;
}

bool history_asked(const Request& req) {
  if (!req.has_param("history")) return false;
  std::string v = req.get_param_value("history");
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  return v == "true" || v == "yes" || v == "y" || v == "1";
}

std::size_t history_limit(const Request& req) {
  if (!req.has_param("limit")) return SIZE_MAX;
  try {
    const long n = std::stol(req.get_param_value("limit"));
    return n < 0 ? 0 : static_cast<std::size_t>(n);
  } catch (const std::exception&) {
    throw Refusal{400, "limit must be a whole number"};
  }
}

// The location part of /api/files/<location>/...: only "local" exists (no SD card).
void check_location(const std::string& location) {
  if (location != "local") {
    throw Refusal{404, fmt::format("no storage '{}': mahost keeps files in 'local' only (no SD card)", location)};
  }
}

std::string checked_name(const std::string& given) {
  if (!is_clean_name(given)) {
    const CleanName clean = clean_file_name(given);
    throw Refusal{clean.status == 415 ? 404 : 400,
                  clean.status != 0 ? clean.error : fmt::format("{}: no such file", given)};
  }
  return given;
}

// A G-code line from a client, as the protocol will send it: comment and blanks removed.
// Refused: lines the host numbers itself, lines too long for Marlin, non-text, and commands
// that would wait for a button on the printer.
std::string checked_command(const std::string& line) {
  std::string c = line.substr(0, line.find(';'));
  while (!c.empty() && std::isspace(static_cast<unsigned char>(c.back()))) c.pop_back();
  std::size_t start = 0;
  while (start < c.size() && std::isspace(static_cast<unsigned char>(c[start]))) ++start;
  c = c.substr(start);
  for (char ch : c) {
    const auto u = static_cast<unsigned char>(ch);
    if (u < 0x20 || u >= 0x7f) throw Refusal{400, "a command contains control or non-ASCII characters"};
  }
  if (c.size() > 82) throw Refusal{400, fmt::format("a command of {} characters: Marlin reads 82 at most", c.size())};
  if (c.find('*') != std::string::npos ||
      (c.size() > 1 && (c[0] == 'N' || c[0] == 'n') && std::isdigit(static_cast<unsigned char>(c[1])))) {
    throw Refusal{400, "send the command alone: mahost numbers and checksums every line itself"};
  }
  // Marlin reads parameter letters in upper case only (without GCODE_CASE_INSENSITIVE), so the
  // line goes out in upper case, save the text of a command that takes text ("M117 Hello").
  std::string upper = c;
  const std::size_t word_end =
      printer::takes_text(printer::parse_gcode_line(c)) ? std::min(c.find(' '), c.size()) : c.size();
  std::transform(upper.begin(), upper.begin() + static_cast<std::ptrdiff_t>(word_end), upper.begin(),
                 [](unsigned char ch) { return std::toupper(ch); });
  if (upper.rfind("M110", 0) == 0) throw Refusal{400, "M110 would renumber the lines under mahost's feet"};
  if (printer::command_waits_for_user(upper)) {
    throw Refusal{400, fmt::format("{} waits for a button on the printer: not taken from the API", c)};
  }
  return upper;
}

std::string names_of(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool is_upload_path(const std::string& path) {
  return path == "/api/files/local" || path == "/api/files/sdcard";
}

bool needs_key(const std::string& path) {
  return path.rfind("/api/", 0) == 0 || path == "/api" || path.rfind("/downloads/", 0) == 0;
}

// A refusal of the request's framing (its Content-Length), or "" when it is sound: a length
// that is not a number of bytes, two lengths that disagree, a length beside a chunked body.
std::string framing_refusal(const Request& req) {
  const std::size_t lengths = req.get_header_value_count("Content-Length");
  if (lengths == 0) return {};
  const std::string first = req.get_header_value("Content-Length");
  for (std::size_t i = 1; i < lengths; ++i) {
    if (const std::string other = req.get_header_value("Content-Length", i); other != first) {
      return fmt::format("the request has two Content-Length headers that disagree ({} and {}): send one", first, other);
    }
  }
  if (req.has_header("Transfer-Encoding")) {
    return "the request has both Content-Length and Transfer-Encoding: send one";
  }
  if (first.empty() || first.size() > 19 ||
      !std::all_of(first.begin(), first.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return fmt::format("Content-Length '{}' is not a number of bytes", first.substr(0, 40));
  }
  return {};
}

// The connection's share, the key and the framing and size limits, before any body is read.
// Returns a status to answer with, or 0 to go on.
int admit(const Request& req, Response& res, const std::string& key, const ServeLimits& limits) {
  if (const std::string refused = HttpServer::beyond_share_refusal(req); !refused.empty()) {
    send_error(res, 503, refused);
    return 503;
  }
  if (needs_key(req.path)) {
    const std::string given = req.get_header_value("X-Api-Key");
    if (given.empty()) {
      send_error(res, 401, "no API key: send it in the X-Api-Key header (mahost serve printed where it is kept)");
      return 401;
    }
    if (!same_key(given, key)) {
      send_error(res, 403, "wrong API key");
      return 403;
    }
  }
  if (const std::string refused = framing_refusal(req); !refused.empty()) {
    send_error(res, 400, refused);
    return 400;
  }
  if (req.method == "POST" || req.method == "PUT" || req.method == "PATCH" || req.method == "DELETE") {
    // A compressed body is not taken: its announced length says nothing of what it unpacks to.
    const std::string encoding = req.get_header_value("Content-Encoding");
    if (!encoding.empty() && encoding != "identity") {
      send_error(res, 415, fmt::format("request bodies are taken uncompressed, not as {}", encoding));
      return 415;
    }
    const bool upload = is_upload_path(req.path);
    const std::uint64_t limit = upload ? limits.max_upload + (1u << 20) : limits.max_json;
    if (req.has_header("Content-Length")) {
      const std::uint64_t length = std::stoull(req.get_header_value("Content-Length"));
      if (length > limit) {
        send_error(res, 413, upload ? fmt::format("the upload is {:.1f} MiB; this server takes {:.0f} MiB at most (--max-upload)",
                                                   length / 1048576.0, limits.max_upload / 1048576.0)
                                    : fmt::format("a request body of {} bytes; {} at most", length, limits.max_json));
        return 413;
      }
    } else if (!upload && req.get_header_value("Transfer-Encoding").find("chunked") != std::string::npos) {
      send_error(res, 411, "send the request with a Content-Length");
      return 411;
    }
  }
  return 0;
}

// The fields a slice request may carry, as the slice command's JSON keys and an STL upload's
// form fields (OctoPrint's slicing plugins take their options as extra form fields): what the
// upload passes on, and what a "profile." prefix may name. Besides the G-code's name and the
// profiles (by name only), each is an option of app/slice_options.h's table with an HTTP field.
bool is_slice_field(const std::string& key) {
  return key == "gcode" || key == "printer" || key == "material" || app::find_slice_option_field(key);
}

std::string slice_field_list() {
  std::string out = "gcode, printer, material";
  for (const app::SliceOption& option : app::slice_options()) {
    if (!option.field.empty()) out += ", " + std::string(option.field);
  }
  return out;
}

// OctoPrint's slice command names the printer profile "printerProfile" and overrides its slicing
// profile's keys as "profile.<key>": both taken as mahost's own fields. "_default" (the one
// printer profile GET /api/printerprofiles lists) is the server's printer. A "profile." key that
// is no slice field is refused, not ignored: the client meant something by it.
json with_octoprint_names(const json& body) {
  json merged = body;
  for (const auto& [key, value] : body.items()) {
    std::string field;
    if (key == "printerProfile") {
      if (value.is_string() && value.get<std::string>() == "_default") continue;
      field = "printer";
    } else if (key.rfind("profile.", 0) == 0) {
      field = key.substr(8);
      if (!is_slice_field(field) || field == "gcode") {
        throw Refusal{400, fmt::format("\"{}\": mahost slices with profile.<field> for the fields {}", key,
                                       slice_field_list())};
      }
    } else {
      continue;
    }
    if (body.contains(field) && body[field] != value) {
      throw Refusal{400, fmt::format("\"{}\" and \"{}\" disagree: give one", key, field)};
    }
    merged[field] = value;
  }
  return merged;
}

// A slice field's JSON value as the text the option table checks: a number as written, a
// string as given (true/false for a flag however a form spells it), "" for a field left out.
std::string slice_field_text(const json& body, const app::SliceOption& option) {
  const std::string key(option.field);
  const auto it = body.find(key);
  if (it == body.end() || it->is_null()) return {};
  const bool yes_no = option.kind == app::OptionKind::flag || option.kind == app::OptionKind::toggle;
  if (it->is_boolean()) {
    if (!yes_no) throw Refusal{400, fmt::format("\"{}\" must be a number or text, not true or false", key)};
    return it->get<bool>() ? "true" : "false";
  }
  if (it->is_number_integer()) return std::to_string(it->get<std::int64_t>());
  if (it->is_number()) return fmt::format("{}", it->get<double>());
  if (!it->is_string()) throw Refusal{400, fmt::format("\"{}\" must be a number, text or true or false", key)};
  std::string text = it->get<std::string>();
  if (yes_no) {
    std::string lower = text;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    if (lower == "true" || lower == "1" || lower == "yes" || lower == "on") return "true";
    if (lower == "false" || lower == "0" || lower == "no" || lower == "off") return "false";
  }
  return text;
}

// The table's options with an HTTP field, as the body gives them, checked and set; those that
// exclude each other refused as the command line refuses them.
void apply_slice_fields(const json& body, app::SliceOptions& o) {
  std::vector<const app::SliceOption*> given;
  for (const app::SliceOption& option : app::slice_options()) {
    if (option.field.empty()) continue;
    const std::string text = slice_field_text(body, option);
    if (text.empty()) continue;
    try {
      app::set_slice_option(o, option, text, option.field);
    } catch (const app::OptionError& e) {
      throw Refusal{400, e.what()};
    }
    // A flag given as false asks for nothing.
    if (!(option.kind == app::OptionKind::flag && text == "false")) given.push_back(&option);
  }
  try {
    app::check_exclusions(given, [](const app::SliceOption& option) { return std::string(option.field); });
  } catch (const app::OptionError& e) {
    throw Refusal{400, e.what()};
  }
}

// The slice command's fields (or an STL upload's form fields, as strings) as a request to
// slice `model`; Refusal (400) for a field out of its range, a profile the server does not
// have, or a layer thickness the printer cannot print.
SliceRequest slice_request(const json& given, const std::string& name, const printer::Profiles& serving) {
  const json body = with_octoprint_names(given);
  SliceRequest request;
  request.model = name;
  std::string gcode = string_field(body, "gcode");
  if (gcode.empty()) gcode = fs::path(name).stem().string() + ".gcode";
  const CleanName clean = clean_file_name(gcode);
  if (clean.status != 0) throw Refusal{clean.status == 415 ? 400 : clean.status, "gcode: " + clean.error};
  if (kind_of(clean.name) != FileKind::gcode) throw Refusal{400, "gcode: name a .gcode file"};
  request.gcode = clean.name;
  app::SliceOptions& o = request.options;
  const std::string config_dir = app::profile_search_path();
  // Profiles by name only: a client names one of the server's, never a path to read.
  const std::string printer_name = string_field(body, "printer");
  if (!printer_name.empty()) {
    const auto known = printer::available_profiles(config_dir, "printers");
    if (std::find(known.begin(), known.end(), printer_name) == known.end()) {
      throw Refusal{400, fmt::format("printer: '{}' is not one of {}", printer_name, names_of(known))};
    }
    o.printer = printer_name;
  } else {
    o.printer = serving.printer.source;
  }
  const std::string material = string_field(body, "material");
  if (!material.empty()) {
    const auto known = printer::available_profiles(config_dir, "materials");
    if (std::find(known.begin(), known.end(), material) == known.end()) {
      throw Refusal{400, fmt::format("material: '{}' is not one of {}", material, names_of(known))};
    }
    o.material = material;
  } else if (printer_name.empty()) {
    o.material = serving.material.source;  // the material the server was started with
  }
  apply_slice_fields(body, o);
  request.print = bool_field(body, "print");
  request.select = request.print || bool_field(body, "select");
  // The printer must allow the layer (and a raft's): said now, not after slicing.
  try {
    const printer::Profiles profiles = app::load_slice_profiles(o);
    printer::check_layer_thickness(profiles.printer, app::uniform_thickness(o, profiles.printer));
  } catch (const printer::ConfigError& e) {
    throw Refusal{400, e.what()};
  }
  return request;
}

// An upload's multipart form as read: the file (written to the files folder under a temporary
// name as it arrives), its name as the client gave it, and the other fields.
struct UploadForm {
  std::optional<FileStore::Upload> file;
  std::string filename;
  std::map<std::string, std::string> fields;

  std::string field(const std::string& key) const {
    const auto found = fields.find(key);
    return found == fields.end() ? std::string() : found->second;
  }
};

// Reads the form into `form`: the 'file' part into the files folder, at most 32 other fields
// of 4 KiB each. Refusal for a part without a name, a second file, a file over `max_upload`
// bytes or that cannot be written, too many or too long fields, a form cut short or without
// a file.
void read_upload_form(const httplib::ContentReader& reader, FileStore& files, std::uint64_t max_upload,
                      UploadForm& form) {
  constexpr std::size_t kFields = 32, kFieldBytes = 4096;  // a form's fields besides the file
  std::string field;
  std::string refused;  // why the form was refused while it was read
  int refused_status = 400;
  bool second_file = false;
  const bool read = reader(
      [&](const httplib::MultipartFormData& part) {
        field = part.name;
        if (field.empty()) {
          // httplib reads a part's name from its Content-Disposition line; a line break or
          // quote in the file name breaks that line.
          refused = "a part of the form has no name httplib could read: its Content-Disposition is "
                    "broken (a line break or a quote in the file name?)";
          return false;
        }
        if (field == "file") {
          if (form.file) {
            second_file = true;
            return false;
          }
          form.filename = part.filename;
          form.file.emplace(files);
        } else if (form.fields.size() >= kFields) {
          refused = fmt::format("the form has more than {} fields", kFields);
          return false;
        }
        return true;
      },
      [&](const char* data, std::size_t size) {
        if (field == "file") {
          if (form.file->size() + size > max_upload) {
            refused_status = 413;
            refused = fmt::format("the upload is larger than this server takes ({:.0f} MiB, --max-upload)",
                                  max_upload / 1048576.0);
            return false;
          }
          if (!form.file->write(data, size)) {
            refused_status = 507;
            refused = "the file could not be written to the files folder (disk full?)";
            return false;
          }
          return true;
        }
        std::string& value = form.fields[field];
        if (value.size() + size > kFieldBytes) {
          refused = fmt::format("the form field '{}' is longer than {} bytes", field.substr(0, 40), kFieldBytes);
          return false;
        }
        value.append(data, size);
        return true;
      });
  if (!refused.empty()) throw Refusal{refused_status, refused};
  if (second_file) throw Refusal{400, "one file per upload"};
  if (!read) throw Refusal{400, "the upload was cut short or is not valid multipart/form-data"};
  if (!form.file) throw Refusal{400, "no 'file' field in the upload"};
}

// The name an upload is stored under: the client's file name, checked; Refusal for a name
// that cannot be stored, or a folder ('path': the files folder has none).
std::string upload_name(const UploadForm& form) {
  const CleanName clean = clean_file_name(form.filename);
  if (clean.status != 0) throw Refusal{clean.status, clean.error};
  std::string path = form.field("path");
  path.erase(std::remove_if(path.begin(), path.end(), [](char c) { return c == '/' || std::isspace(static_cast<unsigned char>(c)); }),
             path.end());
  if (!path.empty()) throw Refusal{400, "folders are not supported: leave 'path' empty"};
  return clean.name;
}

// Reads the uploaded file at `path` as its name says it is: G-code every line checked (the
// analysis kept for the store), a model read whole. Refusal (415) for content that is not.
std::optional<GcodeAnalysis> check_upload_content(const FileStore& files, const std::string& path,
                                                  const std::string& name, FileKind kind) {
  if (kind == FileKind::gcode) {
    GcodeAnalysis analysis = files.analyse(path);
    if (!analysis.error.empty()) {
      const std::size_t colon = analysis.error.find(": ");
      throw Refusal{415, fmt::format("{}: {}", name, colon == std::string::npos ? analysis.error : analysis.error.substr(colon + 2))};
    }
    return analysis;
  }
  try {
    app::check_model_file(path, name);
  } catch (const app::InputError& e) {
    const std::string what = e.what();
    const std::string prefix = name + ": ";
    throw Refusal{415, fmt::format("{}: not a readable model file: {}", name,
                                   what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what)};
  }
  return std::nullopt;
}

// mahost's own fields of a model's upload: it is sliced on the host with the page's settings.
// They are checked before the file is stored: a value out of range is a 400 and leaves the
// folder as it was.
SliceRequest upload_slice_request(const UploadForm& form, const std::string& name, bool select, bool print,
                                  const printer::Profiles& serving) {
  json body = json::object();
  for (const auto& [key, value] : form.fields) {
    if (!value.empty() && (is_slice_field(key) || key == "printerProfile" || key.rfind("profile.", 0) == 0)) {
      body[key] = value;
    }
  }
  body["select"] = select;
  body["print"] = print;
  return slice_request(body, name, serving);
}

using Handler = void (HttpApi::*)(const Request&, Response&);

struct Route {
  const char* method;
  const char* pattern;
  Handler handle;
  // Served on a connection beyond its address's share too: the printer's controls.
  bool always_served = false;
};

// Every endpoint, in one place.
const Route kRoutes[] = {
    {"GET", "/api/version", &HttpApi::get_version},
    {"GET", "/api/server", &HttpApi::get_server},
    {"GET", "/api/settings", &HttpApi::get_settings},
    {"POST", "/api/login", &HttpApi::post_login},
    {"GET", "/api/currentuser", &HttpApi::post_login},
    {"GET", "/api/printerprofiles", &HttpApi::get_printer_profiles},
    {"GET", "/api/connection", &HttpApi::get_connection},
    {"POST", "/api/connection", &HttpApi::post_connection},
    {"GET", "/api/files", &HttpApi::get_files},
    {"GET", "/api/files/([^/]+)", &HttpApi::get_files},
    {"GET", "/api/files/([^/]+)/(.+)", &HttpApi::get_file},
    {"POST", "/api/files/([^/]+)/(.+)", &HttpApi::post_file},
    {"DELETE", "/api/files/([^/]+)/(.+)", &HttpApi::delete_file},
    {"GET", "/downloads/files/([^/]+)/(.+)", &HttpApi::download},
    {"GET", "/api/job", &HttpApi::get_job},
    {"POST", "/api/job", &HttpApi::post_job, true},
    {"GET", "/api/printer", &HttpApi::get_printer},
    {"GET", "/api/printer/tool", &HttpApi::get_tool},
    {"GET", "/api/printer/bed", &HttpApi::get_bed},
    {"POST", "/api/printer/command", &HttpApi::post_command, true},
    {"GET", "/api/mahost/status", &HttpApi::get_status},
    {"GET", "/api/mahost/events", &HttpApi::get_events},
    {"GET", "/api/mahost/layer", &HttpApi::get_layer},
    {"GET", "/api/mahost/profiles", &HttpApi::get_profiles},
    {"POST", "/api/mahost/interrupted", &HttpApi::post_interrupted},
    {"POST", "/api/mahost/stop", &HttpApi::post_stop, true},
    {"POST", "/api/mahost/pause-at", &HttpApi::post_pause_at},
};

}  // namespace

HttpApi::HttpApi(PrinterSession& session, FileStore& files, std::string api_key, ServeLimits limits,
                 std::string version)
    : session_(session), files_(files), api_key_(std::move(api_key)), limits_(limits), version_(std::move(version)) {}

namespace {

// One of the page's files by its path; 404 for any other.
void serve_web_asset(const Request& req, Response& res) {
  const WebAsset* asset = find_web_asset(req.path == "/index.html" ? "/" : req.path);
  if (asset == nullptr) {
    send_error(res, 404, "not found");
    return;
  }
  res.set_content(std::string(asset->body), std::string(asset->content_type).c_str());
  res.set_header("Cache-Control", "no-cache");
}

// A refusal's JSON body where the server has none yet (a route not found, a request that
// could not be read or timed out).
httplib::Server::HandlerResponse fill_error_body(const Request&, Response& res) {
  if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
  if (HttpServer::head_timed_out()) {
    send_error(res, 408, HttpServer::head_timeout_message());
    return httplib::Server::HandlerResponse::Handled;
  }
  const char* text = res.status == 404   ? "not found"
                     : res.status == 400 ? "the request could not be read as HTTP"
                     : res.status == 413 ? "request too large"
                     : res.status == 405 ? "method not allowed"
                                         : "the request could not be served";
  send_error(res, res.status, text);
  return httplib::Server::HandlerResponse::Handled;
}

// An exception out of a handler: logged with the request, a 500 to the client.
void report_internal_error(const Request& req, Response& res, std::exception_ptr ep) {
  std::string what = "unknown";
  try {
    if (ep) std::rethrow_exception(ep);
  } catch (const std::exception& e) {
    what = e.what();
  } catch (...) {
  }
  std::fprintf(stderr, "%s internal error on %s %s: %s\n", local_time().c_str(), req.method.c_str(),
               req.path.c_str(), what.c_str());
  send_error(res, 500, "internal error (logged by the server)");
}

// The headers every response carries: no framing, no sniffing, no referrer; no caching of
// what needs the key, a content policy for the page.
void set_response_headers(const Request& req, Response& res) {
  HttpServer::close_if_unread(req, res);
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_header("Referrer-Policy", "no-referrer");
  res.set_header("X-Frame-Options", "DENY");
  if (needs_key(req.path)) {
    res.set_header("Cache-Control", "no-store");
  } else {
    res.set_header("Content-Security-Policy",
                   "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
                   "connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'");
  }
}

// One line on stderr per request worth logging, with the error a refusal gave.
void log_request(const Request& req, const Response& res) {
  // Refusals always, changes always, reads that went well never (clients poll).
  if (res.status < 400 && (req.method == "GET" || req.method == "HEAD")) return;
  std::string error;
  if (res.status >= 400) {
    const json body = json::parse(res.body, nullptr, false);
    if (body.is_object() && body.contains("error") && body["error"].is_string()) {
      error = ": " + body["error"].get<std::string>();
    }
  }
  std::fprintf(stderr, "%s %s %s %s -> %d%s\n", local_time().c_str(),
               req.remote_addr.empty() ? "-" : req.remote_addr.c_str(),
               req.method.empty() ? "(unreadable request)" : req.method.c_str(),
               req.path.substr(0, 200).c_str(), res.status, error.c_str());
  std::fflush(stderr);
}

}  // namespace

void HttpApi::install(HttpServer& server) {
  server.always_served = [](const Request& req) {
    return std::any_of(std::begin(kRoutes), std::end(kRoutes), [&](const Route& route) {
      return route.always_served && req.method == route.method && req.path == route.pattern;
    });
  };
  for (const Route& route : kRoutes) {
    auto handler = [this, handle = route.handle](const Request& req, Response& res) {
      try {
        (this->*handle)(req, res);
      } catch (const Refusal& r) {
        send_error(res, r.status, r.message);
      }
    };
    const std::string method = route.method;
    if (method == "GET") server.Get(route.pattern, handler);
    else if (method == "POST") server.Post(route.pattern, handler);
    else if (method == "DELETE") server.Delete(route.pattern, handler);
  }
  // Uploads stream to a file in the folder instead of memory.
  server.Post("/api/files/(local|sdcard)",
              [this](const Request& req, Response& res, const httplib::ContentReader& reader) {
                try {
                  upload(req, res, reader);
                } catch (const Refusal& r) {
                  send_error(res, r.status, r.message);
                }
              });
  // The page: static files, no key needed to load them.
  server.Get("/(|index.html|app.js|style.css)", serve_web_asset);

  server.set_pre_routing_handler([this](const Request& req, Response& res) {
    return admit(req, res, api_key_, limits_) != 0 ? httplib::Server::HandlerResponse::Handled
                                                  : httplib::Server::HandlerResponse::Unhandled;
  });
  // A client that announces its body and waits (curl for large uploads) learns at once.
  server.set_expect_100_continue_handler([this](const Request& req, Response& res) {
    const int refused = admit(req, res, api_key_, limits_);
    return refused != 0 ? refused : 100;
  });
  server.set_error_handler(httplib::Server::HandlerWithResponse(fill_error_body));
  server.set_exception_handler(report_internal_error);
  server.set_post_routing_handler(set_response_headers);
  server.set_logger(log_request);
}

// ---- OctoPrint: server, settings, user -----------------------------------------------------

void HttpApi::get_version(const Request&, Response& res) { send_json(res, version_json(version_)); }

void HttpApi::get_server(const Request&, Response& res) {
  send_json(res, {{"version", kOctoPrintServer}, {"safemode", nullptr}});
}

void HttpApi::get_settings(const Request&, Response& res) { send_json(res, settings_json()); }

void HttpApi::post_login(const Request&, Response& res) { send_json(res, user_json()); }

void HttpApi::get_printer_profiles(const Request&, Response& res) {
  send_json(res, printer_profiles_json(session_.profiles().printer));
}

void HttpApi::get_connection(const Request&, Response& res) {
  send_json(res, connection_json(session_.status(), session_.profiles().printer.baud));
}

void HttpApi::post_connection(const Request& req, Response& res) {
  const json body = json_body(req);
  const std::string command = string_field(body, "command");
  if (command == "connect") {
    const Status s = session_.status();
    if (s.connection == Connection::operational) {
      res.status = 204;  // connected already: nothing to do
      return;
    }
    send_outcome(res, session_.reconnect());
  } else if (command == "disconnect" || command == "fake_ack") {
    send_error(res, 400, fmt::format("'{}' is not offered: mahost serve keeps its printer connected", command));
  } else {
    send_error(res, 400, "unknown command: use connect");
  }
}

// ---- OctoPrint: files ----------------------------------------------------------------------

void HttpApi::get_files(const Request& req, Response& res) {
  if (req.matches.size() > 1) check_location(req.matches[1]);
  send_json(res, files_json(files_.list(), files_.free_bytes(), base_url(req)));
}

void HttpApi::get_file(const Request& req, Response& res) {
  check_location(req.matches[1]);
  const std::string name = checked_name(req.matches[2]);
  const auto file = files_.find(name);
  if (!file) throw Refusal{404, fmt::format("{}: no such file", name)};
  send_json(res, file_json(*file, base_url(req)));
}

void HttpApi::delete_file(const Request& req, Response& res) {
  check_location(req.matches[1]);
  const std::string name = checked_name(req.matches[2]);
  send_outcome(res, session_.delete_file(name));
}

void HttpApi::download(const Request& req, Response& res) {
  check_location(req.matches[1]);
  const std::string name = checked_name(req.matches[2]);
  const auto file = files_.find(name);
  if (!file) throw Refusal{404, fmt::format("{}: no such file", name)};
  auto in = std::make_shared<std::ifstream>(files_.path_of(name), std::ios::binary);
  if (!*in) throw Refusal{404, fmt::format("{}: cannot be read", name)};
  res.set_header("Content-Disposition", fmt::format("attachment; filename=\"{}\"", name));
  res.set_content_provider(
      file->size, file->kind == FileKind::gcode ? "text/x.gcode" : "model/stl",
      [in](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
        char buffer[65536];
        in->seekg(static_cast<std::streamoff>(offset));
        const std::size_t want = std::min(length, sizeof buffer);
        in->read(buffer, static_cast<std::streamsize>(want));
        const auto got = in->gcount();
        if (got <= 0) return false;
        return sink.write(buffer, static_cast<std::size_t>(got));
      });
}

void HttpApi::post_file(const Request& req, Response& res) {
  check_location(req.matches[1]);
  const std::string name = checked_name(req.matches[2]);
  const json body = json_body(req);
  const std::string command = string_field(body, "command");
  if (command == "select") {
    send_outcome(res, session_.select(name, bool_field(body, "print")));
    return;
  }
  if (command == "unselect") {
    send_outcome(res, session_.unselect());
    return;
  }
  if (command != "slice") throw Refusal{400, "unknown command: use select, unselect or slice"};
  if (kind_of(name) != FileKind::model) throw Refusal{415, fmt::format("{} is not a model (STL, 3MF, OBJ)", name)};
  if (!files_.find(name)) throw Refusal{404, fmt::format("{}: no such file", name)};

  const SliceRequest request = slice_request(body, name, session_.profiles());
  const Outcome outcome = session_.slice(request);
  if (!outcome.ok()) throw Refusal{outcome.status, outcome.message};
  send_json(res, abridged_file_json(request.gcode, base_url(req)), 202);
}

void HttpApi::upload(const Request& req, Response& res, const httplib::ContentReader& reader) {
  check_location(req.matches[1]);
  if (!req.is_multipart_form_data()) throw Refusal{400, "an upload is multipart/form-data with a 'file' field"};
  if (req.has_header("Content-Length")) {
    const std::uint64_t length = std::stoull(req.get_header_value("Content-Length"));
    if (length > files_.free_bytes()) throw Refusal{507, "not enough free space in the files folder"};
  }
  UploadForm form;
  read_upload_form(reader, files_, limits_.max_upload, form);
  const std::string name = upload_name(form);
  // Said before the checks that read the file: a name that cannot be stored now.
  if (const std::string lock = file_lock(session_.status(), name); !lock.empty()) {
    throw Refusal{409, lock + ": upload it under another name"};
  }
  const FileKind kind = *kind_of(name);
  const std::optional<GcodeAnalysis> analysis = check_upload_content(files_, form.file->temporary_path(), name, kind);
  const bool print = truthy(form.field("print"));
  const bool select = print || truthy(form.field("select"));
  std::optional<SliceRequest> slicing;
  if (kind == FileKind::model && (truthy(form.field("slice")) || select)) {
    slicing = upload_slice_request(form, name, select, print, session_.profiles());
  }
  if (!form.file->finish()) throw Refusal{507, "the file could not be written to the files folder (disk full?)"};
  const PrinterSession::Stored stored =
      session_.store_upload(*form.file, name, analysis, select && kind == FileKind::gcode, print);
  if (!stored.outcome.ok()) throw Refusal{stored.outcome.status, stored.outcome.message};

  json reply = {{"files", {{"local", abridged_file_json(name, base_url(req))}}},
                {"done", true},
                {"effectiveSelect", stored.selected},
                {"effectivePrint", stored.printing}};
  if (!stored.not_printed.empty()) {
    // Stored, not printed: the client and the page's log say why.
    reply["mahost"] = {{"notPrinted", stored.not_printed}};
    session_.note(fmt::format("stored {}; not printed: {}", name, stored.not_printed));
  }
  if (slicing) {
    const Outcome o = session_.slice(std::move(*slicing));
    if (o.ok()) {
      reply["done"] = false;
    } else {
      // Stored, but not sliced: the answer says why; the file stays for another try.
      reply["error"] = o.message;
    }
  }
  res.set_header("Location", base_url(req) + "/api/files/local/" + name);
  send_json(res, reply, 201);
}

// ---- OctoPrint: job and printer ------------------------------------------------------------

void HttpApi::get_job(const Request&, Response& res) { send_json(res, job_json(session_.status())); }

void HttpApi::post_job(const Request& req, Response& res) {
  const json body = json_body(req);
  const std::string command = string_field(body, "command");
  if (command == "start") {
    send_outcome(res, session_.start_job());
  } else if (command == "cancel") {
    send_outcome(res, session_.cancel_job());
  } else if (command == "restart") {
    send_outcome(res, session_.restart_job());
  } else if (command == "pause") {
    const std::string action = string_field(body, "action");
    if (action.empty() || action == "toggle") {
      send_outcome(res, session_.pause_job(PauseAction::toggle));
    } else if (action == "pause") {
      send_outcome(res, session_.pause_job(PauseAction::pause));
    } else if (action == "resume") {
      send_outcome(res, session_.pause_job(PauseAction::resume));
    } else {
      throw Refusal{400, "action must be pause, resume or toggle"};
    }
  } else {
    throw Refusal{400, "unknown command: use start, cancel, restart or pause"};
  }
}

void HttpApi::get_printer(const Request& req, Response& res) {
  const Status s = session_.status();
  if (s.connection != Connection::operational) throw Refusal{409, "Printer is not operational"};
  std::set<std::string> exclude;
  if (req.has_param("exclude")) {
    std::string list = req.get_param_value("exclude");
    std::size_t start = 0;
    while (start <= list.size()) {
      const std::size_t end = std::min(list.find(',', start), list.size());
      exclude.insert(list.substr(start, end - start));
      start = end + 1;
    }
  }
  std::optional<std::vector<TemperaturePoint>> history;
  if (history_asked(req)) history = session_.history(history_limit(req));
  send_json(res, printer_json(s, exclude, history));
}

void HttpApi::get_tool(const Request& req, Response& res) {
  const Status s = session_.status();
  if (s.connection != Connection::operational) throw Refusal{409, "Printer is not operational"};
  json j = {{"tool0", temperature_json(s)["tool0"]}};
  if (history_asked(req)) {
    const auto points = session_.history(history_limit(req));
    json h = history_json({points.rbegin(), points.rend()});
    for (json& p : h) p.erase("bed");
    j["history"] = h;
  }
  send_json(res, j);
}

void HttpApi::get_bed(const Request& req, Response& res) {
  const Status s = session_.status();
  if (s.connection != Connection::operational) throw Refusal{409, "Printer is not operational"};
  json j = {{"bed", temperature_json(s)["bed"]}};
  if (history_asked(req)) {
    const auto points = session_.history(history_limit(req));
    json h = history_json({points.rbegin(), points.rend()});
    for (json& p : h) p.erase("tool0");
    j["history"] = h;
  }
  send_json(res, j);
}

void HttpApi::post_command(const Request& req, Response& res) {
  const json body = json_body(req);
  std::vector<std::string> lines;
  if (body.contains("command") && body.contains("commands")) {
    throw Refusal{400, "give command or commands, not both"};
  }
  if (body.contains("command")) {
    lines.push_back(string_field(body, "command"));
  } else if (body.contains("commands")) {
    const json& list = body["commands"];
    if (!list.is_array()) throw Refusal{400, "\"commands\" must be a list of strings"};
    if (list.size() > 64) throw Refusal{400, "64 commands per request at most"};
    for (const json& c : list) {
      if (!c.is_string()) throw Refusal{400, "\"commands\" must be a list of strings"};
      lines.push_back(c.get<std::string>());
    }
  } else {
    throw Refusal{400, "give \"command\" or \"commands\""};
  }
  std::vector<std::string> commands;
  for (const std::string& line : lines) {
    std::string c = checked_command(line);
    if (!c.empty()) commands.push_back(std::move(c));
  }
  if (commands.empty()) {
    res.status = 204;
    return;
  }
  send_outcome(res, session_.send_commands(commands));
}

// ---- mahost: the page's own ----------------------------------------------------------------

void HttpApi::get_status(const Request& req, Response& res) {
  std::uint64_t after = 0;
  if (req.has_param("events_after")) {
    try {
      after = std::stoull(req.get_param_value("events_after"));
    } catch (const std::exception&) {
      throw Refusal{400, "events_after must be a whole number"};
    }
  }
  json j = page_status_json(session_.status(), session_.events_after(after));
  j["history"] = history_json(session_.history(600));
  send_json(res, j);
}

void HttpApi::get_events(const Request&, Response& res) {
  if (streams_.fetch_add(1) >= limits_.max_streams) {
    streams_.fetch_sub(1);
    throw Refusal{503, fmt::format("{} live streams are open already: poll /api/mahost/status instead", limits_.max_streams)};
  }
  struct Stream {
    std::uint64_t version = 0, event = 0;
    std::chrono::steady_clock::time_point last_sent{};
  };
  auto stream = std::make_shared<Stream>();
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Accel-Buffering", "no");
  res.set_chunked_content_provider(
      "text/event-stream",
      [this, stream](std::size_t, httplib::DataSink& sink) {
        if (closing_.load()) return false;
        // Five updates a second at most: a print at full simulated speed changes all the time.
        const auto since = std::chrono::steady_clock::now() - stream->last_sent;
        if (since < 200ms) std::this_thread::sleep_for(200ms - since);
        const Status s = session_.wait_for_change(stream->version, 10s);
        if (closing_.load()) return false;
        std::string chunk;
        if (s.version == stream->version) {
          chunk = ": still here\n\n";  // keeps proxies and the browser from timing out
        } else {
          const std::vector<Event> events = session_.events_after(stream->event);
          if (!events.empty()) stream->event = events.back().id;
          stream->version = s.version;
          json j = page_status_json(s, events);
          chunk = "data: " + j.dump() + "\n\n";
        }
        stream->last_sent = std::chrono::steady_clock::now();
        return sink.write(chunk.data(), chunk.size());
      },
      [this](bool) { streams_.fetch_sub(1); });
}

void HttpApi::get_layer(const Request& req, Response& res) {
  const auto file = session_.job_file();
  if (!file) throw Refusal{404, "no job has run yet: nothing to draw"};
  const Status s = session_.status();
  const int layers = static_cast<int>(file->gcode.layers.size());
  int layer = s.progress && s.progress->layer > 0 ? s.progress->layer : 1;
  if (req.has_param("layer")) {
    try {
      layer = std::stoi(req.get_param_value("layer"));
    } catch (const std::exception&) {
      throw Refusal{400, "layer must be a whole number"};
    }
  }
  if (layers == 0) throw Refusal{404, "the file has no ;LAYER: marks: nothing to draw per layer"};
  if (layer < 1 || layer > layers) throw Refusal{404, fmt::format("layer {}: the file has layers 1 to {}", layer, layers)};
  std::vector<LayerMove> moves;
  try {
    moves = layer_moves(*file, layer - 1);  // read from the file on disk
  } catch (const printer::ConfigError&) {
    throw Refusal{409, "the job's file changed on disk or cannot be read: nothing to draw"};
  }
  const std::size_t done = s.progress ? s.progress->commands_done : 0;
  const auto& mark = file->gcode.layers[static_cast<std::size_t>(layer - 1)];
  const auto& bed = session_.profiles().printer;
  send_json(res, {{"layer", layer},
                  {"layers", layers},
                  {"z", mark.z ? json(*mark.z) : json(nullptr)},
                  {"bed", {bed.bed_x, bed.bed_y}},
                  {"bounds", {file->min_x, file->min_y, file->max_x, file->max_y}},
                  {"done", svg_path(moves, true, 0, done)},
                  {"todo", svg_path(moves, true, done, SIZE_MAX)},
                  {"travel", svg_path(moves, false, 0, SIZE_MAX)},
                  {"moves", moves.size()}});
}

void HttpApi::get_profiles(const Request&, Response& res) {
  const std::string config_dir = app::profile_search_path();
  json printers = json::array();
  for (const std::string& id : printer::available_profiles(config_dir, "printers")) {
    try {
      const printer::PrinterProfile p = printer::load_printer_profile(id, config_dir);
      // The thicknesses the page offers: the profile's list, or its range in its steps.
      json allowed = json::array();
      for (double t : p.layer.allowed) allowed.push_back(t);
      if (p.layer.allowed.empty() && p.layer.step > 0) {
        for (int i = 0; p.layer.min + i * p.layer.step <= p.layer.max + 1e-9 && i < 200; ++i) {
          allowed.push_back(std::round((p.layer.min + i * p.layer.step) * 1e6) / 1e6);
        }
      }
      // What a slice with this printer does where the request leaves a field out.
      printers.push_back({{"id", id}, {"name", p.name}, {"layers", allowed},
                          {"minLayer", p.layer.min}, {"maxLayer", p.layer.max},
                          {"defaultLayer", p.layer.default_thickness},
                          {"material", p.default_material},
                          {"defaults", {{"support", p.support.type}, {"brim", p.brim_width},
                                        {"raft", p.raft.enabled}, {"adaptive", false},
                                        {"tolerance", app::kDefaultTolerance}, {"orient", "none"}}}});
    } catch (const printer::ConfigError&) {
      // a broken profile is left out of the choice; slicing with it would say why
    }
  }
  json materials = json::array();
  for (const std::string& id : printer::available_profiles(config_dir, "materials")) {
    try {
      materials.push_back({{"id", id}, {"name", printer::load_material_profile(id, config_dir).name}});
    } catch (const printer::ConfigError&) {
    }
  }
  const printer::Profiles& serving = session_.profiles();
  send_json(res, {{"printers", printers},
                  {"materials", materials},
                  {"contours", app::contour_strategy_names()},
                  {"supports", app::support_placement_names()},
                  {"serving",
                   {{"printer", fs::path(serving.printer.source).stem().string()},
                    {"printerName", serving.printer.name},
                    {"material", fs::path(serving.material.source).stem().string()}}}});
}

void HttpApi::post_interrupted(const Request& req, Response& res) {
  const json body = json_body(req);
  const std::string command = string_field(body, "command");
  if (command == "resume") {
    send_outcome(res, session_.resume_interrupted());
  } else if (command == "discard") {
    send_outcome(res, session_.discard_interrupted());
  } else {
    throw Refusal{400, "unknown command: use resume or discard"};
  }
}

void HttpApi::post_stop(const Request&, Response& res) { send_outcome(res, session_.emergency_stop()); }

void HttpApi::post_pause_at(const Request& req, Response& res) {
  const json body = json_body(req);
  const auto it = body.find("layers");
  if (it == body.end() || !it->is_array() || it->size() > 1000) {
    throw Refusal{400, "give \"layers\": a list of layer numbers (from 1) to pause before"};
  }
  std::vector<int> layers;
  for (const json& l : *it) {
    if (!l.is_number_integer()) throw Refusal{400, "\"layers\" must be whole numbers"};
    layers.push_back(l.get<int>());
  }
  send_outcome(res, session_.set_pause_at(std::move(layers)));
}

}  // namespace host::serve
