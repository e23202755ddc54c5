#!/usr/bin/env python3
"""Every printer of Debian's PrusaSlicer bundles, imported by mahost and evaluated by PrusaSlicer.

For each bundle in /usr/share/PrusaSlicer/profiles: `mahost profiles import BUNDLE --all` into a
scratch config folder (timed), then for each imported printer `mahost slice` a 20 mm cube, and
PrusaSlicer slices the same cube with the same printer, print and filament profiles (flattened
here, in Python, independently of mahost's reader: each section's parents, the last one
winning, then its own keys), and the two start G-code blocks are compared line by line (blank
lines and surrounding spaces aside; PrusaSlicer's block runs from ';TYPE:Custom' to 'G21',
mahost's from its 'start G-code' comment to the four lines it writes after it).

Each mahost G-code is also checked against the printer's bed as the bundle gives it (bed_shape,
a polygon, and max_print_height, read here, not by mahost): every move from the first layer to
the end G-code inside the polygon and below the height, and the extruded box the 20 mm cube's.

Prints the counts, the import time of all bundles, each refusal with its reason, each printer
whose G-code leaves its bed, and each whose start G-code differs with the first line that does. Hand-run (minutes: one prusa-slicer run per printer):
    tests/bench/prusaslicer_start_gcode.py [BUILD_DIR]
"""
import collections
import glob
import os
import re
import subprocess
import sys
import tempfile
import time

PROFILES = "/usr/share/PrusaSlicer/profiles"


def parse_ini(path):
    sections = collections.OrderedDict()
    current = None
    for line in open(path, encoding="utf-8"):
        s = line.strip()
        if not s or s[0] in "#;":
            continue
        if s.startswith("[") and s.endswith("]"):
            current = s[1:-1]
            sections[current] = {}
        elif "=" in line and current is not None:
            key, value = line.split("=", 1)
            sections[current][key.strip()] = value.strip()
    return sections


def flatten(sections, kind, name):
    own = sections[f"{kind}:{name}"]
    out = {}
    for parent in [p.strip().strip('"') for p in own.get("inherits", "").split(";") if p.strip()]:
        if f"{kind}:{parent}" in sections:
            out.update(flatten(sections, kind, parent))
    out.update({k: v for k, v in own.items() if k not in ("inherits", "renamed_from")})
    return out


def config_ini(bundle, printer, print_profile, filament, path):
    sections = parse_ini(bundle)
    config = {}
    for kind, name in (("print", print_profile), ("filament", filament), ("printer", printer)):
        keys = flatten(sections, kind, name)
        for k in ("compatible_printers", "compatible_printers_condition", "compatible_prints",
                  "compatible_prints_condition", "alias"):
            keys.pop(k, None)
        config.update(keys)
    config.update(printer_settings_id=printer, print_settings_id=print_profile,
                  filament_settings_id=filament)
    # What PrusaSlicer 2.5 itself refuses to slice with, put as the vendor meant it (neither
    # changes the start G-code): a first_layer_height in percent, which Slic3r took of
    # layer_height and PrusaSlicer 2.5 reads as mm; relative E without G92 E0 in layer_gcode.
    first = config.get("first_layer_height", "0.35")
    if first.endswith("%"):
        config["first_layer_height"] = "%g" % (float(first[:-1]) / 100 * float(config.get("layer_height", "0.3")))
    if config.get("use_relative_e_distances", "0") == "1" and "G92 E0" not in config.get("layer_gcode", ""):
        config["layer_gcode"] = config.get("layer_gcode", "") + "\\nG92 E0"
    with open(path, "w") as out:
        for k, v in config.items():
            out.write(f"{k} = {v}\n")


def parse_flat(path):
    """The key = value lines config_ini wrote."""
    return dict(line.rstrip("\n").split(" = ", 1) for line in open(path) if " = " in line)


def lines(block):
    return [l.strip() for l in block if l.strip()]


# The lines PrusaSlicer's writer adds to the start G-code (heating the start G-code does not do
# itself, progress): mahost heats before the start G-code and writes no M73 inside it.
WRITER_COMMENTS = ("set temperature", "set temperature and wait for it to be reached",
                   "set bed temperature", "set bed temperature and wait for it to be reached")


def prusaslicer_start(gcode):
    text = open(gcode).read().splitlines()
    start = text.index(";TYPE:Custom") + 1
    end = text.index("G21 ; set units to millimeters", start)
    kept = [l for l in text[start:end] if not (l.startswith("M73 ") and ";" not in l)
            and l.partition(";")[2].strip() not in WRITER_COMMENTS]
    return lines(kept)


def mahost_start(gcode):
    text = open(gcode).read().splitlines()
    start = text.index(";start G-code from the printer profile") + 1
    end = text.index(";LAYER:0", start)
    return lines(text[start:end - 4])  # G90, M82/M83, G92 E0, M107 after it


def inside(polygon, x, y, tolerance=1e-3):
    """Whether (x, y) is in the polygon or within `tolerance` mm of its edge (even-odd rule)."""
    crossings = False
    for (x0, y0), (x1, y1) in zip(polygon, polygon[1:] + polygon[:1]):
        dx, dy = x1 - x0, y1 - y0
        t = max(0.0, min(1.0, ((x - x0) * dx + (y - y0) * dy) / (dx * dx + dy * dy or 1)))
        if (x0 + t * dx - x) ** 2 + (y0 + t * dy - y) ** 2 <= tolerance ** 2:
            return True
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * dx / dy:
            crossings = not crossings
    return crossings


def off_bed(gcode, config):
    """The first thing wrong with where mahost's G-code goes on the bed, or None.

    Moves from ';LAYER:0' to the end G-code (the start and end G-code are the vendor's, whose
    purge lines may run at the bed's edge on purpose) must stay in bed_shape and below
    max_print_height, and the outer wall's extrusions must make the 20 mm cube in X and Y, its
    centre line half a bead inside the cube's side."""
    bed_shape = config.get("bed_shape", "0x0,200x0,200x200,0x200")  # PrusaSlicer's defaults
    polygon = [tuple(float(c) for c in p.split("x")) for p in bed_shape.split(",")]
    height = float(config.get("max_print_height", "0")) or float("inf")
    text = open(gcode).read().splitlines()
    start = text.index(";LAYER:0")
    end = text.index(";end G-code from the printer profile", start)
    x = y = z = None
    box = [float("inf"), float("inf"), -float("inf"), -float("inf")]
    outer_wall = False
    relative_e = any(l.partition(";")[0].split() == ["M83"] for l in text[:start])
    e = 0.0
    for line in text[start:end]:
        if line.startswith(";TYPE:"):
            outer_wall = line == ";TYPE:WALL-OUTER"
        words = line.partition(";")[0].split()
        if words in (["M82"], ["M83"]):
            relative_e = words == ["M83"]
        if words and words[0] == "G92":
            e = next((float(w[1:]) for w in words[1:] if w[0] == "E"), e)
        if not words or words[0] not in ("G0", "G1"):
            continue
        axes = {w[0]: float(w[1:]) for w in words[1:]}
        extruded = 0.0
        if "E" in axes:
            extruded = axes["E"] if relative_e else axes["E"] - e
            e = e + axes["E"] if relative_e else axes["E"]
        x, y, z = axes.get("X", x), axes.get("Y", y), axes.get("Z", z)
        if x is None or y is None:
            continue
        if not inside(polygon, x, y):
            return f"move to X{x} Y{y} off the bed {bed_shape}"
        if z is not None and z > height + 1e-6:
            return f"move to Z{z} above max_print_height {height}"
        if extruded > 0 and outer_wall:
            box = [min(box[0], x), min(box[1], y), max(box[2], x), max(box[3], y)]
    width, depth = box[2] - box[0], box[3] - box[1]
    nozzle = float(config.get("nozzle_diameter", "0.4").split(",")[0])
    if not all(20 - 2 * nozzle < side < 20 for side in (width, depth)):
        return f"extrusions span {width:.3f} x {depth:.3f} mm, not the 20 mm cube"
    return None


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    mahost = os.path.abspath(os.path.join(build, "mahost"))
    work = tempfile.mkdtemp(prefix="prusaslicer_start_gcode.")
    env = dict(os.environ, XDG_CONFIG_HOME=os.path.join(work, "config"))
    cube = os.path.join(work, "cube.stl")
    with open(cube, "w") as out:  # 20 mm, corner at the origin
        v = [(0, 0, 0), (20, 0, 0), (20, 20, 0), (0, 20, 0), (0, 0, 20), (20, 0, 20), (20, 20, 20), (0, 20, 20)]
        faces = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5),
                 (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
        out.write("solid cube\n")
        for f in faces:
            out.write("facet normal 0 0 0\nouter loop\n")
            for i in f:
                out.write("vertex %g %g %g\n" % v[i])
            out.write("endloop\nendfacet\n")
        out.write("endsolid cube\n")

    bundles = sorted(glob.glob(os.path.join(PROFILES, "*.ini")))
    began = time.monotonic()
    refusals = []
    for bundle in bundles:
        r = subprocess.run([mahost, "profiles", "import", bundle, "--all"], env=env,
                           capture_output=True, text=True)
        refusals += [l for l in r.stdout.splitlines() if l.startswith("refused ")]
    import_seconds = time.monotonic() - began
    printers_dir = os.path.join(work, "config", "mahost", "printers")
    imported = sorted(os.listdir(printers_dir))
    print(f"{len(bundles)} bundles imported in {import_seconds:.2f} s: {len(imported)} printers, "
          f"{len(refusals)} refused")
    for r in refusals:
        print("  " + r[:200])

    same = differing = failed = off = peer_failed = 0
    for name in imported:
        toml = open(os.path.join(printers_dir, name)).read()
        header = re.search(r'bundle of .* \((.*)\)\n# with the print profile "(.*)" and the filament "(.*)"\.', toml)
        printer = re.search(r'^name = "(.*)"$', toml, re.M).group(1).replace('\\"', '"')
        bundle, print_profile, filament = header.groups()
        ours = os.path.join(work, name + ".gcode")
        theirs = os.path.join(work, name + ".prusaslicer.gcode")
        ini = os.path.join(work, name + ".ini")
        m = subprocess.run([mahost, "slice", cube, "--printer", name[:-5], "-o", ours], env=env,
                           capture_output=True, text=True)
        config_ini(bundle, printer, print_profile, filament, ini)
        if m.returncode != 0:
            failed += 1
            print(f"FAILED {printer}: mahost {m.returncode} {m.stderr.strip()[:160]}")
            continue
        wrong = off_bed(ours, parse_flat(ini))
        if wrong:
            off += 1
            print(f"OFF THE BED {printer}: {wrong}")
        p = subprocess.run(["prusa-slicer", "--load", ini, "--export-gcode", "-o", theirs, cube],
                           capture_output=True, text=True)
        if p.returncode != 0 or not os.path.exists(theirs):
            peer_failed += 1
            print(f"PRUSASLICER FAILED {printer}: {p.returncode} {(p.stderr or p.stdout).strip()[-160:]}")
            continue
        a, b = mahost_start(ours), prusaslicer_start(theirs)
        if a == b:
            same += 1
            continue
        differing += 1
        first = next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))
        print(f"DIFFERS {printer}: line {first + 1}: mahost {a[first] if first < len(a) else '(end)'!r} "
              f"PrusaSlicer {b[first] if first < len(b) else '(end)'!r}")
    sliced = len(imported) - failed
    print(f"sliced by mahost: {sliced} of {len(imported)}; on the bed: {sliced - off}, off it {off}")
    print(f"start G-code as PrusaSlicer's: {same} of {sliced - peer_failed} PrusaSlicer sliced; "
          f"differing {differing}; PrusaSlicer failed {peer_failed}")


if __name__ == "__main__":
    main()
