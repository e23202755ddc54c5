// PrusaSlicer's printers as mahost printer and material profiles (`mahost profiles import`).
//
// Input: a PrusaSlicer .ini (prusa_ini.h): a vendor bundle, a user's config bundle or an
// exported config.ini. For each printer asked for: its settings, inheritance resolved, with
// its print profile (default_print_profile, else the first print profile compatible with it,
// by compatible_printers or compatible_printers_condition as PrusaSlicer decides) and its
// filament profile (default_filament_profile, else the first of its model's default_materials,
// else the first compatible one); every key a profile leaves out is PrusaSlicer's default
// (src/libslic3r/PrintConfig.cpp). Output: the TOML text of a printer profile and of its
// material, each checked as `mahost slice` will load them, the start and end G-code
// evaluated once with the material (prusa_variables.h), or a refusal saying why:
//  - bed_shape -> build_volume (x, y, origin; a circle for delta printers), max_print_height
//    -> z; nozzle_diameter (its count: nozzle.count), filament_diameter;
//  - layer_height, first_layer_height, min_layer_height, max_layer_height (0: 75% of the
//    nozzle) -> layer; extrusion widths (0: 1.125 x the nozzle; percents of the layer);
//  - the print's speeds (percents of the ones they refer to; 0, PrusaSlicer's "auto": its
//    max_print_speed) -> speed; machine_max_feedrate_* and machine_max_acceleration_* ->
//    motion; retract_* -> retraction; perimeters, infill, solid layers, skirt, seam,
//    supports, brim, raft -> print, support, brim, raft;
//  - gcode_flavor: marlin, marlin2, klipper, smoothie, reprap and reprapfirmware write Marlin's
//    G-code (M104/M109, M140/M190, M106/M107, M82/M83, which they all take), repetier and
//    teacup their own; makerware, sailfish (binary x3g), mach3, machinekit and no-extrusion
//    are refused;
//  - start_gcode, end_gcode -> gcode.start, gcode.end in PrusaSlicer syntax; the settings they
//    name that mahost has no key for (printer_model, printer_notes, print_settings_id, ...)
//    -> gcode.constants;
//  - the filament: temperatures, filament_type, extrusion_multiplier, filament_density, the
//    fan (min_fan_speed when fan_always_on, else off; disable_fan_first_layers), the bridge
//    fan.
// Refused: SLA printers, a z_offset (mahost has none), a bed neither rectangular nor round, no
// print or filament profile, a G-code flavour mahost cannot write, start or end G-code naming
// what mahost does not know, values outside what mahost's profiles take.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace printer {

struct ImportedProfile {
  std::string name;  // "Creality Ender-3 (0.4 mm nozzle)"
  std::string stem;  // its file name without .toml (profile_file_stem)
  std::string toml;  // the profile, checked
};

struct ImportedPrinter {
  ImportedProfile printer, material;
  std::string print_profile;  // the PrusaSlicer print profile its speeds and layers come from
};

struct ImportRefusal {
  std::string printer;
  std::string reason;  // one line
};

struct PrusaImport {
  std::vector<ImportedPrinter> printers;
  std::vector<ImportRefusal> refused;
  std::vector<std::string> available;  // every printer the file has, for messages
};

// Imports the printers named in `only` (empty: all of them). A name `only` gives that the
// file does not have throws ConfigError naming the ones that come close. `name` is the file's
// path, for messages and the profiles' comments.
PrusaImport import_prusa_ini(std::string_view text, const std::string& name,
                             const std::vector<std::string>& only = {});

// The same for the file at `path`, read whole (geometry::InputError naming it when it cannot
// be read).
PrusaImport import_prusa_ini_file(const std::string& path, const std::vector<std::string>& only = {});

}  // namespace printer
