// Printer and material profiles: what a printer can do and how a material prints.
//
// Profiles are TOML files printers/<name>.toml and materials/<name>.toml, found by name in a
// search path of folders (config_directory(); the shipped ones are configs/ in the source tree)
// or given as a path. Every key is checked on load: an
// unknown key, a wrong type or a value out of range throws ConfigError naming the file, the key
// and what is allowed. `--set key=value` overrides go through the same checks (dotted keys as in
// the file; `material.` in front of a key reaches the material profile).
// Units: mm, s, mm/s, mm/s^2, degrees Celsius, percent, g/cm^3.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "printer/firmware_dialect.h"
#include "printer/motion_model.h"
#include "printer/prusa_macro.h"

namespace printer {

// The layer thicknesses a printer can print: a list, or a range with an optional step.
struct LayerThicknesses {
  std::vector<double> allowed;  // if non-empty, exactly these
  double min = 0.05, max = 0.3;
  double step = 0;              // 0: any value in [min, max]
  double default_thickness = 0.2;

  bool allows(double thickness) const;
  // "0.15, 0.2, 0.25, 0.3, 0.35, 0.4 mm" or "0.05 to 0.3 mm".
  std::string describe() const;
};

// Speeds per feature, mm/s.
struct FeatureSpeeds {
  double outer_wall = 30, inner_wall = 45, thin_wall = 30, skirt = 30;
  double top_skin = 35, bottom_skin = 35, solid_infill = 45, sparse_infill = 60;
  double support = 50, support_interface = 40, bridge = 25, brim = 30, raft = 25;
  double travel = 120, z = 8;
};

// A box [x0, y0, z0, x1, y1, z1]: X and Y on the bed as the G-code has them, Z from the
// bed up to the part (a raft below does not count), mm.
using SupportBoxMm = std::array<double, 6>;

// Supports: where they go, how they keep clear of the part, how they are laid.
struct SupportSettings {
  std::string type = "none";          // "none", "buildplate" or "everywhere"
  double xy_gap = 0.2;                // mm between support and the part in the same layer
  double top_contact_distance = 0.2;  // mm of air under the part
  double bottom_contact_distance = 0.2;  // mm of air over the part, under support on it
  double interface_thickness = 0.4;  // mm of dense layers at the support's top
  double interface_density = 80;      // percent
  std::string pattern = "lines";      // "lines" or "grid"
  bool sheath = true;                 // a loop round the body's islands
  double spacing = 2.5;               // mm between the body's lines
  double angle = 0;                   // degrees from +X, the body's lines
  double min_area = 0.2;              // mm^2: smaller overhangs are left alone
  std::vector<SupportBoxMm> enforcers, blockers;
};

struct RaftSettings {
  bool enabled = false;
  double margin = 3;            // mm past the first layer
  double air_gap = 0.2;         // mm between the raft and the part
  double base_thickness = 0.3;  // mm
  double base_width = 0.8;      // mm, the base's bead width
  double base_spacing = 2.0;    // mm between the base's lines
  int interface_layers = 1;
  double interface_spacing = 1.0;  // mm between the interface's lines
  int surface_layers = 2;
  double layer_thickness = 0.2;    // mm, each interface and surface layer
};

struct Retraction {
  double length = 1.0;      // filament pulled back, mm (0: never retract)
  double speed = 30;        // mm/s
  double prime_speed = 30;  // pushing it back, mm/s
  double min_travel = 2.0;  // travels shorter than this do not retract, mm
  double z_hop = 0;         // lift during retracted travels, mm (0: none)
};

struct PrintSettings {
  int perimeters = 2;
  double infill_density = 20;  // percent
  std::string infill_pattern = "grid";  // "grid" or "rectilinear"
  int top_layers = 3, bottom_layers = 3;
  // Skins at least this thick as well, mm (0: no minimum): on layers of mixed thickness a
  // count of thin layers would leave a top or bottom too thin.
  double top_thickness = 0, bottom_thickness = 0;
  int skirt_loops = 1;
  double skirt_distance = 3.0;  // mm
  std::string seam = "aligned";  // "aligned" or "nearest"
};

// How a profile's start and end G-code name values: mahost's own {name} placeholders, or
// PrusaSlicer's macro language (prusa_macro.h), for printers imported from PrusaSlicer.
enum class GcodeSyntax { mahost, prusaslicer };

struct PrinterProfile {
  std::string name;         // as shown to the user: "UP Plus 2"
  std::string source;       // the file it came from, for messages
  double bed_x = 220, bed_y = 220, bed_z = 250;  // build volume, mm
  // Where the build volume's front left corner is in the G-code's X and Y, mm: 0, 0 for most
  // printers; -r, -r for a delta whose origin is the centre of its round bed.
  double bed_origin_x = 0, bed_origin_y = 0;
  bool round_bed = false;   // the bed is the circle inscribed in bed_x by bed_y (bed_x = bed_y)
  double nozzle_diameter = 0.4;
  // Extruders the printer has; mahost prints with the first (its nozzle_diameter and the
  // material). More than one only says that the others' values are not known.
  int extruders = 1;
  double filament_diameter = 1.75;
  double extrusion_width = 0.45;  // bead width of walls, skins and infill
  LayerThicknesses layer;
  double first_layer_height = 0.2, first_layer_width = 0.5, first_layer_speed = 20;
  MotionLimits motion;
  FeatureSpeeds speed;
  Retraction retraction;
  PrintSettings print;
  SupportSettings support;
  RaftSettings raft;
  double brim_width = 0;    // mm; 0: no brim
  bool relative_e = false;  // M83 (true) or M82
  // Largest distance a written path may stray from the planned one, mm: points closer than
  // this to the line through their neighbours are dropped (PrusaSlicer's gcode_resolution),
  // so a curve sampled every few microns does not flood the printer's serial line.
  double resolution = 0.0125;
  std::string start_gcode, end_gcode;  // with {placeholders}
  GcodeSyntax gcode_syntax = GcodeSyntax::mahost;
  // PrusaSlicer syntax: the printer's own PrusaSlicer settings its G-code names that mahost has
  // no key of its own for (printer_model, printer_notes, print_settings_id, ...).
  MacroVariables gcode_constants;
  int baud = 115200;
  // The firmware the G-code is written for (`firmware = "marlin" | "teacup" | "repetier"`): how
  // it heats and waits, whether it has M73 and M107 (printer/firmware_dialect.h).
  Firmware firmware = Firmware::marlin;
  std::string default_material = "pla";
};

struct MaterialProfile {
  std::string name;    // "ABS"
  std::string source;
  std::string type;    // "ABS", "PLA", "PETG", "FLEX", ... (PrusaSlicer's filament_type); "": the name
  double nozzle_temperature = 210, first_layer_nozzle_temperature = 215;
  double bed_temperature = 60, first_layer_bed_temperature = 60;
  double fan_speed = 100;  // percent, from fan_start_layer on
  int fan_start_layer = 1;  // 0-based: the first layer with the fan on
  double flow = 1.0;       // extrusion multiplier
  double density = 1.24;   // g/cm^3, for the filament weight
  double overhang_angle = 50;  // degrees from vertical a wall may lean without support
  double bridge_length = 10;   // mm a bridge may span without support
  double bridge_flow = 1.0;    // extrusion multiplier on bridges
  double bridge_fan = 100;     // percent, while bridging
};

struct Profiles {
  PrinterProfile printer;
  MaterialProfile material;
};

// The printer profile a command uses when none is named (configs/printers/up-plus-2.toml).
inline constexpr const char* kDefaultPrinter = "up-plus-2";

// Which profiles to load, as the user gave them.
struct ProfileRequest {
  std::string printer = kDefaultPrinter;  // a name found in config_dir, or a path to a .toml
  std::string material;               // empty: the printer's default_material
  std::string config_dir;             // see config_directory()
  std::vector<std::string> overrides;  // "key=value", applied in order
};

// Profiles are found by name in a search path: folders separated by ':', each holding
// printers/ and materials/, searched in order (the first folder with the name wins).
// config_directory() is $MAHOST_CONFIG_DIR alone when it is set and non-empty (tests, or a
// private set of profiles); else the user's folder (user_config_directory()), then each of
// $XDG_CONFIG_DIRS/mahost (default /etc/xdg/mahost: profiles an administrator shares), then
// `installed` (the profiles shipped with mahost; empty: none).
std::string config_directory(const std::string& installed);

// The user's profile folder, where `mahost profiles import` writes: $XDG_CONFIG_HOME/mahost,
// by default ~/.config/mahost.
std::string user_config_directory();

// The file name (without .toml) a profile named `name` is stored under, and found by:
// lower case, every run of other characters than letters, digits, '.', '+' and '_' one '-'
// ("Creality Ender-3 (0.4 mm nozzle)" -> "creality-ender-3-0.4-mm-nozzle").
std::string profile_file_stem(std::string_view name);

struct ProfileFile {
  std::string id;    // the file's name without .toml: what --printer and --material take
  std::string path;
};

// The profiles of one kind ("printers" or "materials") in a search path, each id once (the
// first folder's), sorted by id.
std::vector<ProfileFile> find_profiles(const std::string& config_dir, std::string_view kind);

// Their ids alone.
std::vector<std::string> available_profiles(const std::string& config_dir, std::string_view kind);

// Parses and checks a profile's TOML text; `source` names it in messages.
PrinterProfile parse_printer_profile(std::string_view toml, const std::string& source);
MaterialProfile parse_material_profile(std::string_view toml, const std::string& source);

// Reads a profile by path (a name ending in .toml, or an existing file's path) or by name: the
// first folder of config_dir holding printers/NAME.toml (materials/), or the file of the
// name's profile_file_stem, so that `--printer "Creality Ender-3 (0.4 mm nozzle)"` finds
// creality-ender-3-0.4-mm-nozzle.toml.
PrinterProfile load_printer_profile(const std::string& name_or_path, const std::string& config_dir);
MaterialProfile load_material_profile(const std::string& name_or_path, const std::string& config_dir);

// Applies one "key=value" override, checked like the file's own keys, then re-checks the
// profiles as a whole. Keys starting with "material." go to the material.
void apply_override(Profiles& profiles, std::string_view assignment);

// Loads both profiles and applies the overrides.
Profiles load_profiles(const ProfileRequest& request);

// Throws ConfigError unless the printer can print layers this thick (names the allowed ones).
void check_layer_thickness(const PrinterProfile& printer, double thickness);

// Throws ConfigError unless the printer can print every layer of a stack given by its layer
// tops (mm, ascending; the first layer starts on the bed at 0): the first layer
// first_layer.height thick, every other one a thickness `layer` allows. The message names the
// first layer that is not (counted from 1, with its heights) and what is allowed there.
void check_layer_tops(const PrinterProfile& printer, std::span<const double> tops);

// The bed's centre in the G-code's X and Y, mm: where a part is placed.
double bed_centre_x(const PrinterProfile& printer);
double bed_centre_y(const PrinterProfile& printer);

// Whether a point (G-code X and Y, mm) is on the bed, within `tolerance` mm.
bool on_bed(const PrinterProfile& printer, double x, double y, double tolerance = 1e-6);

// Throws ConfigError with the part's size and the build volume's unless a part of this size
// (mm) fits (on a round bed: its bounding box fits the bed's square; the toolpaths are checked
// against the circle when the G-code is written).
void check_part_fits(const PrinterProfile& printer, double size_x, double size_y, double size_z);

// How far a retracted travel lifts the nozzle above the layer (mm): the z-hop, or 0 where
// the profile does not retract.
double travel_lift(const PrinterProfile& printer);

// Throws ConfigError unless the top of the last layer, `top_z` (mm; a whole layer above the
// one before, so up to a layer above the part's `part_z`), plus a retracted travel's z-hop,
// is within the build height. The error names the tallest part whose layers of `thickness`
// after the printer's first layer fit. `raft`: the part stands that much higher, on a raft
// (both heights are then the part's own, the raft not counted).
void check_layer_tops_fit(const PrinterProfile& printer, double part_z, double top_z,
                          double thickness, double raft = 0);

// Values for the {placeholders} of start and end G-code that the slice decides.
struct PlaceholderValues {
  double layer_height = 0.2;
  std::size_t layer_count = 0;
  double max_layer_z = 0;  // the top of the last layer, mm (end G-code)
  // The first layer's extrusions' bounds in the G-code's X and Y, mm (PrusaSlicer's
  // first_layer_print_min and _max); unset (min > max): the bed's centre.
  double first_layer_min_x = 1, first_layer_min_y = 1, first_layer_max_x = 0, first_layer_max_y = 0;
  std::string input_filename_base;  // the model's file name without its extension
};

// Expands the placeholders of a profile's G-code (`key`: "gcode.start" or "gcode.end"); an
// unknown name or a malformed placeholder throws ConfigError naming the profile and `key`.
// mahost syntax, {name}: nozzle_temperature, first_layer_nozzle_temperature,
// bed_temperature, first_layer_bed_temperature, bed_x, bed_y, bed_z, nozzle_diameter,
// filament_diameter, layer_height, first_layer_height, fan_speed (0-255), printer_name,
// material_name. PrusaSlicer syntax: its macro language (prusa_macro.h) over the values
// prusa_variables.h names.
std::string expand_placeholders(std::string_view text, const Profiles& profiles,
                                const PlaceholderValues& values, std::string_view key);

}  // namespace printer
