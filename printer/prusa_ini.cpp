// PrusaSlicer's .ini files; see prusa_ini.h.
#include "printer/prusa_ini.h"

#include <charconv>
#include <cmath>
#include <functional>
#include <set>

#include <fmt/core.h>

#include "printer/error.h"

namespace printer {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

struct Section {
  std::string name;  // "printer:Creality Ender-3 (0.4 mm nozzle)"; "" for a flat config
  std::map<std::string, std::string, std::less<>> keys;
  std::size_t line = 0;
};

std::vector<Section> sections_of(std::string_view text, const std::string& name) {
  std::vector<Section> sections;
  std::size_t line_number = 0;
  while (!text.empty()) {
    const std::size_t newline = text.find('\n');
    const std::string_view line = trim(text.substr(0, newline));
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
    ++line_number;
    if (line.empty() || line.front() == '#' || line.front() == ';') continue;
    if (line.front() == '[') {
      if (line.back() != ']') {
        throw ConfigError(fmt::format("{}:{}: a section name must end with ']'", name, line_number));
      }
      sections.push_back({std::string(line.substr(1, line.size() - 2)), {}, line_number});
      continue;
    }
    const std::size_t equals = line.find('=');
    if (equals == std::string_view::npos) {
      throw ConfigError(fmt::format("{}:{}: expected key = value, a [section] or a # comment, found "
                                    "'{}'", name, line_number, line.substr(0, 40)));
    }
    if (sections.empty()) sections.push_back({"", {}, line_number});
    // A key set twice: the last one counts, as in PrusaSlicer's property tree.
    sections.back().keys[std::string(trim(line.substr(0, equals)))] =
        std::string(trim(line.substr(equals + 1)));
  }
  return sections;
}

bool is_abstract(std::string_view preset) {
  return preset.size() >= 2 && preset.front() == '*' && preset.back() == '*';
}

// One group's presets (print, filament, printer) flattened: each preset's parents' keys it
// does not set itself, the last parent's first.
std::map<std::string, PrusaPreset, std::less<>> flatten(const std::vector<Section>& sections,
                                                        std::string_view group,
                                                        const std::string& file) {
  const std::string prefix = std::string(group) + ":";
  std::map<std::string, const Section*, std::less<>> raw;
  for (const Section& s : sections) {
    if (s.name.size() > prefix.size() && s.name.compare(0, prefix.size(), prefix) == 0) {
      raw[s.name.substr(prefix.size())] = &s;
    }
  }
  std::map<std::string, PrusaPreset, std::less<>> done;
  std::set<std::string, std::less<>> active;
  std::function<const PrusaPreset&(const std::string&)> resolve = [&](const std::string& preset) -> const PrusaPreset& {
    if (const auto found = done.find(preset); found != done.end()) return found->second;
    if (!active.insert(preset).second) {
      throw ConfigError(fmt::format("{}: [{}{}] inherits from itself", file, prefix, preset));
    }
    const Section& section = *raw.at(preset);
    PrusaPreset flat;
    flat.name = preset;
    for (const auto& [key, value] : section.keys) {
      if (key != "inherits") flat.keys[key] = value;
    }
    if (const auto inherits = section.keys.find("inherits"); inherits != section.keys.end()) {
      const std::vector<std::string> parents = prusa_strings(inherits->second);
      // The last parent first: a key is taken from the first parent (in that order) that has it.
      for (auto parent = parents.rbegin(); parent != parents.rend(); ++parent) {
        if (!raw.count(*parent)) continue;  // PrusaSlicer logs an unknown parent and goes on
        for (const auto& [key, value] : resolve(*parent).keys) {
          if (key != "renamed_from") flat.keys.emplace(key, value);
        }
      }
    }
    active.erase(preset);
    return done.emplace(preset, std::move(flat)).first->second;
  };
  for (const auto& [preset, section] : raw) resolve(preset);
  return done;
}

std::optional<double> number_of(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

std::optional<std::string_view> PrusaPreset::raw(std::string_view key) const {
  const auto found = keys.find(key);
  if (found == keys.end()) return std::nullopt;
  return std::string_view(found->second);
}

PrusaIni read_prusa_ini(std::string_view text, const std::string& name) {
  const std::vector<Section> sections = sections_of(text, name);
  PrusaIni ini;
  if (sections.size() == 1 && sections.front().name.empty()) {
    // An exported config.ini: the printer, the print and the filament in one set of keys,
    // named by printer_settings_id, print_settings_id and filament_settings_id.
    const Section& flat = sections.front();
    auto preset = [&](std::string_view id_key, std::string_view fallback) {
      PrusaPreset p;
      p.keys = flat.keys;
      const auto id = flat.keys.find(id_key);
      p.name = id != flat.keys.end() ? prusa_strings(id->second).front() : std::string(fallback);
      if (p.name.empty()) p.name = std::string(fallback);
      return p;
    };
    ini.printers.push_back(preset("printer_settings_id", "PrusaSlicer printer"));
    const PrusaPreset print = preset("print_settings_id", "PrusaSlicer print");
    const PrusaPreset filament = preset("filament_settings_id", "PrusaSlicer filament");
    ini.prints.emplace(print.name, print);
    ini.filaments.emplace(filament.name, filament);
    return ini;
  }
  ini.is_bundle = true;
  std::set<std::string, std::less<>> models;
  for (const Section& s : sections) {
    if (s.name == "vendor") {
      ini.is_vendor = true;
      if (const auto n = s.keys.find("name"); n != s.keys.end()) ini.vendor = prusa_string(n->second);
    }
    if (s.name.rfind("printer_model:", 0) == 0) models.insert(s.name.substr(14));
  }
  for (auto& [preset, flat] : flatten(sections, "print", name)) {
    if (!is_abstract(preset)) ini.prints.emplace(preset, std::move(flat));
  }
  for (auto& [preset, flat] : flatten(sections, "filament", name)) {
    if (!is_abstract(preset)) ini.filaments.emplace(preset, std::move(flat));
  }
  std::map<std::string, PrusaPreset, std::less<>> printers = flatten(sections, "printer", name);
  for (const Section& s : sections) {  // file order
    if (s.name.rfind("printer:", 0) != 0) continue;
    const std::string preset = s.name.substr(8);
    if (is_abstract(preset)) continue;
    PrusaPreset& p = printers.at(preset);
    if (ini.is_vendor) {
      // PrusaSlicer installs a vendor's printer only under one of the vendor's models.
      const auto model = p.raw("printer_model");
      if (!model || prusa_string(*model).empty()) {
        ini.skipped_printers.emplace_back(preset, "it names no printer_model");
        continue;
      }
      if (!models.count(prusa_string(*model))) {
        ini.skipped_printers.emplace_back(
            preset, fmt::format("its printer_model {} is not one of the bundle's models", prusa_string(*model)));
        continue;
      }
    }
    ini.printers.push_back(std::move(p));
  }
  return ini;
}

std::string prusa_string(std::string_view raw) {
  raw = trim(raw);
  if (raw.size() >= 2 && raw.front() == '"' && raw.back() == '"') raw = raw.substr(1, raw.size() - 2);
  std::string out;
  out.reserve(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    char c = raw[i];
    if (c == '\\' && i + 1 < raw.size()) {
      c = raw[++i];
      if (c == 'n') c = '\n';
      else if (c == 'r') c = '\r';
      else if (c == 't') c = '\t';
    }
    out += c;
  }
  return out;
}

std::vector<std::string> prusa_strings(std::string_view raw) {
  std::vector<std::string> out;
  raw = trim(raw);
  while (!raw.empty()) {
    std::size_t end = 0;
    if (raw.front() == '"') {
      // A quoted element: up to the next unescaped quote.
      end = 1;
      while (end < raw.size() && raw[end] != '"') end += raw[end] == '\\' ? 2 : 1;
      end = std::min(end + 1, raw.size());
    } else {
      end = std::min(raw.find(';'), raw.size());
    }
    out.push_back(prusa_string(raw.substr(0, end)));
    raw.remove_prefix(end);
    raw = trim(raw);
    if (!raw.empty() && raw.front() == ';') raw.remove_prefix(1);
    raw = trim(raw);
  }
  if (out.empty()) out.emplace_back();
  return out;
}

std::optional<std::vector<PrusaNumber>> prusa_numbers(std::string_view raw) {
  std::vector<PrusaNumber> out;
  raw = trim(raw);
  if (raw.size() >= 2 && raw.front() == '"' && raw.back() == '"') raw = trim(raw.substr(1, raw.size() - 2));
  while (true) {
    const std::size_t comma = raw.find(',');
    std::string_view item = trim(raw.substr(0, comma));
    // Each item's leading number, as PrusaSlicer's stream extraction reads it: the rest of
    // "0 # comment" is ignored; a '%' right after it makes it a percent.
    if (!item.empty() && item.front() == '+') item.remove_prefix(1);
    PrusaNumber n;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), n.value);
    if (item.empty() || ec != std::errc() || !std::isfinite(n.value)) return std::nullopt;
    n.percent = end < item.data() + item.size() && *end == '%';
    out.push_back(n);
    if (comma == std::string_view::npos) break;
    raw.remove_prefix(comma + 1);
  }
  return out;
}

std::optional<std::vector<PrusaPoint>> prusa_points(std::string_view raw) {
  std::vector<PrusaPoint> out;
  raw = trim(raw);
  while (!raw.empty()) {
    const std::size_t comma = raw.find(',');
    const std::string_view item = trim(raw.substr(0, comma));
    const std::size_t x = item.find('x');
    if (x == std::string_view::npos) return std::nullopt;
    const auto px = number_of(item.substr(0, x));
    const auto py = number_of(item.substr(x + 1));
    if (!px || !py) return std::nullopt;
    out.push_back({*px, *py});
    if (comma == std::string_view::npos) break;
    raw.remove_prefix(comma + 1);
  }
  if (out.empty()) return std::nullopt;
  return out;
}

}  // namespace printer
