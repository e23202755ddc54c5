#!/usr/bin/python3
"""An independent judge of a layer plan: the layered part a slicer prints against the model.

It shares no code with mahost (numpy and shapely only, Debian's python3-numpy and
python3-shapely): it reads the model's triangles itself, cuts its own sections, and measures
per layer, for the slab S = model between the layer's planes z_lo < z_hi and the region R the
layer prints (the prism R x [z_lo, z_hi]):

  D   the distance error (the paper's, DESIGN.md section 3): the largest horizontal distance
      from a point of the model's surface inside the slab to the layer's walls (the boundary
      of R). The surface is sampled: the model's sections at the slab's two planes (as limits
      from inside) and at three levels between, their vertices and points along their edges
      every 0.1 mm, every mesh vertex strictly inside the slab, and the outline of every
      flat level strictly inside it (a step a layer straddles), also every 0.1 mm; strictly:
      more than ON_PLANE, half a G-code file's Z step, from both planes. The inside
      of a flat level is not sampled: it is parallel to the layer's top and bottom, where the
      error is vertical and a horizontal distance means nothing (DESIGN.md section 3 decides
      the same; it is where the paper's slice mesh has no vertex). A piece of the
      slab's footprint that R does not touch at all (a tip the layer leaves out) is measured
      to its own outline, and counted as missed.
  dV  the volume deviation vol(S sym-diff P) = integral over [z_lo, z_hi] of
      area(C(z) sym-diff R) dz, C(z) the model's section, by composite Simpson over
      sub-levels (the heights of horizontal facets inside the slab as breakpoints, where the
      section jumps).

The whole part: mean D (over layers), P95h D (the D within which layers covering 95% of the
judged height stay, each layer weighing its thickness), max D, total dV. A plan ending below
the model's top leaves that part out: it is judged as one more slab printing nothing (its D
measured to its own outline, its whole volume deviation), in all four measures but not in the
layer count, and its height reported as `uncovered`.

Layers: --layers takes a G-code file (the heights at which it extrudes: CuraEngine, Slic3r,
PrusaSlicer, mahost), a text file of layer tops (one per line, # comments) or a comma list.
Regions: --part LAYERED.stl (the layered part as `mahost analyze --export-layers` writes it:
each layer's region is its section at the layer's middle), or --mid (the model's own section
at each layer's middle: what CuraEngine and Slic3r print).

Usage:
  judge.py MODEL.stl --layers F [--part LAYERED.stl | --mid] [--exclude-z LO:HI]
           [--json OUT] [--csv OUT]
  judge.py MODEL.stl --layers F --count     the number of layers F has over the model
MODEL.stl is the placed model (mm, on the bed), as `mahost info --export` writes it.
--exclude-z leaves the layers overlapping that height range out of all four measures (the
bunny's hole-filled base, 0:2.25).
"""
import argparse
import json
import math
import re
import struct
import sys

import numpy as np
from shapely import vectorized
from shapely.geometry import MultiPolygon, Polygon
from shapely.ops import unary_union

# Sections are cut this far inside a slab's planes (the limit from inside), mm.
END_INSET = 1e-5
# A vertex or flat level this close to a layer's plane lies on it, mm: half the 0.001 mm step
# of a G-code file's Z, far above a binary STL's rounding (a flat top at 11.2 mm reads
# 11.1999998, and a plan's boundary there is written Z11.2).
ON_PLANE = 5e-4
# Spacing of samples along section edges and over horizontal facets, mm.
SAMPLE_SPACING = 0.1
# Simpson intervals per layer for dV (split among the pieces between breakpoints).
INTERVALS = 8
# The grid cell of the nearest-wall search, mm.
CELL = 0.5


def read_stl(path):
    """Vertices (n x 3) and faces (m x 3) of an STL, corners welded where exactly equal."""
    with open(path, "rb") as f:
        data = f.read()
    triangles = None
    if len(data) >= 84:
        count = struct.unpack_from("<I", data, 80)[0]
        if len(data) == 84 + 50 * count:
            record = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
            triangles = np.frombuffer(data, dtype=record, count=count, offset=84)["v"].astype(np.float64)
    if triangles is None:
        text = data.decode("ascii", errors="replace")
        values = re.findall(r"vertex\s+(\S+)\s+(\S+)\s+(\S+)", text)
        if not values or len(values) % 3:
            sys.exit(f"judge: {path}: neither a binary nor an ASCII STL")
        triangles = np.array(values, dtype=np.float64).reshape(-1, 3, 3)
    corners = triangles.reshape(-1, 3)
    vertices, index = np.unique(corners, axis=0, return_inverse=True)
    faces = index.reshape(-1, 3)
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    return vertices, faces[keep]


class Solid:
    """A closed triangle mesh cut by horizontal planes (even-odd: nested loops are holes)."""

    def __init__(self, vertices, faces):
        self.v = vertices
        self.f = faces
        z = vertices[faces][:, :, 2]
        self.zlo = z.min(axis=1)
        self.zhi = z.max(axis=1)
        self.top = float(vertices[:, 2].max()) if len(vertices) else 0.0
        self.bottom = float(vertices[:, 2].min()) if len(vertices) else 0.0
        # Faces by their lowest corner, for the faces a plane cuts: those starting at most the
        # tallest face's height below it.
        self.by_low = np.argsort(self.zlo, kind="stable")
        self.low_sorted = self.zlo[self.by_low]
        self.tallest = float((self.zhi - self.zlo).max()) if len(faces) else 0.0
        self.vertex_z = np.unique(vertices[:, 2])
        flat = self.zhi - self.zlo <= 1e-9
        self.flat_faces = np.nonzero(flat)[0]
        self.flat_z = np.unique(self.zlo[flat])

    def loops(self, z):
        """The section at z as closed loops of (x, y), each an array (k x 2)."""
        # A plane through a vertex is moved off it by a hair (a section is a limit anyway).
        i = np.searchsorted(self.vertex_z, z)
        for j in (i - 1, i):
            if 0 <= j < len(self.vertex_z) and abs(self.vertex_z[j] - z) < 1e-9:
                z += 2e-9
        window = self.by_low[np.searchsorted(self.low_sorted, z - self.tallest, side="left"):
                             np.searchsorted(self.low_sorted, z, side="left")]
        cut = window[self.zhi[window] > z]
        if len(cut) == 0:
            return []
        faces = self.f[cut]
        p = self.v[faces]  # k x 3 x 3
        below = p[:, :, 2] < z
        points, keys = [], []
        for a, b in ((0, 1), (1, 2), (2, 0)):
            crossing = below[:, a] != below[:, b]
            pa, pb = p[:, a], p[:, b]
            t = (z - pa[:, 2]) / np.where(crossing, pb[:, 2] - pa[:, 2], 1.0)
            xy = pa[:, :2] + t[:, None] * (pb[:, :2] - pa[:, :2])
            va, vb = faces[:, a], faces[:, b]
            key = np.minimum(va, vb).astype(np.int64) * len(self.v) + np.maximum(va, vb)
            points.append(np.where(crossing[:, None], xy, np.nan))
            keys.append(np.where(crossing, key, -1))
        points = np.stack(points, axis=1)  # k x 3 x 2
        keys = np.stack(keys, axis=1)      # k x 3
        # Each face crossed has exactly two crossing edges: its segment.
        order = np.argsort(keys < 0, axis=1, kind="stable")[:, :2]
        rows = np.arange(len(cut))[:, None]
        seg_keys = keys[rows, order]
        seg_points = points[rows, order]
        return chain(seg_keys, seg_points)

    def section(self, z):
        return region_of_loops(self.loops(z))


def chain(seg_keys, seg_points):
    """Segments (their ends' edge keys s x 2, points s x 2 x 2) joined into closed loops where
    they share an end. Each key of a closed manifold mesh's section ends exactly two segments:
    the segments are then walked by index; otherwise (an open or non-manifold mesh) by search."""
    count = len(seg_keys)
    flat = seg_keys.ravel()
    order = np.argsort(flat, kind="stable")
    ranked = flat[order]
    paired = (len(ranked) % 2 == 0 and np.array_equal(ranked[0::2], ranked[1::2]) and
              (len(ranked) < 4 or not np.any(ranked[1:-1:2] == ranked[2::2])))
    if not paired:
        return chain_by_search(seg_keys, seg_points)
    partner = np.empty(2 * count, dtype=np.int64)
    partner[order[0::2]] = order[1::2]
    partner[order[1::2]] = order[0::2]
    partner = partner.tolist()
    ends = seg_points.reshape(-1, 2)
    used = bytearray(count)
    loops = []
    for start in range(count):
        if used[start]:
            continue
        walk = []  # occurrences left through, in order
        o = 2 * start + 1
        while True:
            s = o >> 1
            if used[s]:
                break
            used[s] = 1
            walk.append(o)
            o = partner[o] ^ 1  # in at the partner's end, out at the other
        if len(walk) >= 3:
            loops.append(ends[walk])
    return loops


def chain_by_search(seg_keys, seg_points):
    at = {}
    for s, (k0, k1) in enumerate(seg_keys.tolist()):
        at.setdefault(k0, []).append(s)
        at.setdefault(k1, []).append(s)
    used = np.zeros(len(seg_keys), dtype=bool)
    loops = []
    for start in range(len(seg_keys)):
        if used[start]:
            continue
        used[start] = True
        loop = [seg_points[start, 0]]
        key = int(seg_keys[start, 1])
        first = int(seg_keys[start, 0])
        s = start
        while key != first:
            loop.append(seg_points[s, 1] if int(seg_keys[s, 1]) == key else seg_points[s, 0])
            nxt = [t for t in at.get(key, []) if not used[t]]
            if not nxt:
                break  # an open mesh: the loop is closed as it stands
            s = nxt[0]
            used[s] = True
            key = int(seg_keys[s, 1]) if int(seg_keys[s, 0]) == key else int(seg_keys[s, 0])
        if len(loop) >= 3:
            loops.append(np.array(loop))
    return loops


def region_of_loops(loops):
    """Loops to a region by the even-odd rule."""
    result = Polygon()
    for loop in sorted(loops, key=lambda l: -abs(ring_area(l))):
        piece = Polygon(loop)
        if not piece.is_valid:
            piece = piece.buffer(0)
        if piece.is_empty:
            continue
        result = result.symmetric_difference(piece)
    return result


def ring_area(loop):
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def polygons_of(region):
    if region.is_empty:
        return []
    if isinstance(region, Polygon):
        return [region]
    if isinstance(region, MultiPolygon):
        return list(region.geoms)
    return [g for g in getattr(region, "geoms", []) if isinstance(g, Polygon) and not g.is_empty]


def wall_segments(region):
    """The boundary of a region as segments (s x 2 x 2)."""
    segments = []
    for polygon in polygons_of(region):
        for ring in [polygon.exterior, *polygon.interiors]:
            c = np.asarray(ring.coords)[:, :2]
            if len(c) >= 2:
                segments.append(np.stack([c[:-1], c[1:]], axis=1))
    return np.concatenate(segments) if segments else np.zeros((0, 2, 2))


def distances_to_segments(points, segments):
    """Each point's distance to the nearest segment; inf where there is none.

    Exact: segments are filed in a grid of cells CELL wide, each in every cell its box grown by
    CELL covers, so that a point finds every segment within CELL of it in its own cell; a point
    with none that near is measured against all of them."""
    if len(points) == 0:
        return np.zeros(0)
    if len(segments) == 0:
        return np.full(len(points), np.inf)
    lo = np.minimum(segments[:, 0], segments[:, 1]) - CELL
    hi = np.maximum(segments[:, 0], segments[:, 1]) + CELL
    origin = lo.min(axis=0)
    first = np.floor((lo - origin) / CELL).astype(np.int64)
    last = np.floor((hi - origin) / CELL).astype(np.int64)
    columns = int(last[:, 0].max()) + 1
    spans = (last - first + 1)
    counts = spans[:, 0] * spans[:, 1]
    owner = np.repeat(np.arange(len(segments)), counts)
    # Each filing's cell: the segment's first cell plus its offset within the box.
    offset = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    width = np.repeat(spans[:, 0], counts)
    cx = np.repeat(first[:, 0], counts) + offset % width
    cy = np.repeat(first[:, 1], counts) + offset // width
    cell = cy * columns + cx
    order = np.argsort(cell, kind="stable")
    cell, owner = cell[order], owner[order]
    out = np.full(len(points), np.inf)
    p = np.floor((points - origin) / CELL).astype(np.int64)
    inside = (p[:, 0] >= 0) & (p[:, 1] >= 0) & (p[:, 0] < columns)
    key = np.where(inside, p[:, 1] * columns + p[:, 0], -1)
    start = np.searchsorted(cell, key, side="left")
    stop = np.searchsorted(cell, key, side="right")
    count = np.where(inside, stop - start, 0)
    # Points in groups of like candidate counts (up to 2^j), so that few are padded far.
    group = np.ceil(np.log2(np.maximum(count, 1))).astype(int)
    for j in np.unique(group[count > 0]):
        has = (count > 0) & (group == j)
        k = int(count[has].max())
        index = start[has][:, None] + np.arange(k)[None, :]
        valid = np.arange(k)[None, :] < count[has][:, None]
        candidates = owner[np.minimum(index, len(owner) - 1)]
        d = point_segment_distances(points[has][:, None, :], segments[candidates])
        out[has] = np.where(valid, d, np.inf).min(axis=1)
    far = ~(out <= CELL)
    if far.any():
        out[far] = brute_distances(points[far], segments)
    return out


def point_segment_distances(q, segments):
    """Distances from points q (... x 2) to segments (... x 2 x 2), broadcast."""
    a = segments[..., 0, :]
    d = segments[..., 1, :] - a
    w = q - a
    t = np.clip((w * d).sum(axis=-1) / np.maximum((d * d).sum(axis=-1), 1e-300), 0.0, 1.0)
    e = w - t[..., None] * d
    return np.sqrt((e * e).sum(axis=-1))


def brute_distances(points, segments):
    out = np.empty(len(points))
    chunk = max(1, 1_000_000 // len(segments))
    for start in range(0, len(points), chunk):
        q = points[start:start + chunk]
        out[start:start + chunk] = point_segment_distances(q[:, None, :], segments[None]).min(axis=1)
    return out


def densify(loop, spacing):
    """A closed loop's vertices and points along its edges at most `spacing` apart."""
    a = loop
    b = np.roll(loop, -1, axis=0)
    length = np.linalg.norm(b - a, axis=1)
    steps = np.maximum(1, np.ceil(length / spacing).astype(int))
    pieces = [a]
    for k in range(1, int(steps.max())):
        mask = steps > k
        if not mask.any():
            break
        t = (k / steps[mask])[:, None]
        pieces.append(a[mask] + t * (b[mask] - a[mask]))
    return np.concatenate(pieces)


def flat_outlines(solid, faces, spacing):
    """Points along the outlines of the flat levels the horizontal facets make."""
    out = []
    for z in np.unique(solid.zlo[faces]):
        level = unary_union([Polygon(solid.v[solid.f[f]][:, :2]) for f in faces if solid.zlo[f] == z])
        for polygon in polygons_of(level):
            for ring in [polygon.exterior, *polygon.interiors]:
                out.append(densify(np.asarray(ring.coords)[:-1, :2], spacing))
    return np.concatenate(out) if out else np.zeros((0, 2))


def sub_levels(solid, z_lo, z_hi):
    """Simpson nodes and weights over [z_lo, z_hi], breaking at horizontal facets inside, and
    whether each is one the surface is sampled at (every other node: the planes, the breaks
    and a quarter of the slab apart between)."""
    breaks = [z_lo] + [z for z in solid.flat_z if z_lo + END_INSET < z < z_hi - END_INSET] + [z_hi]
    nodes, weights, sampled = [], [], []
    for lo, hi in zip(breaks[:-1], breaks[1:]):
        n = max(2, 2 * round(INTERVALS * (hi - lo) / (z_hi - z_lo) / 2))
        h = (hi - lo) / n
        for k in range(n + 1):
            z = lo + k * h
            z = min(max(z, lo + END_INSET), hi - END_INSET)
            w = h / 3 * (1 if k in (0, n) else 4 if k % 2 else 2)
            nodes.append(z)
            weights.append(w)
            sampled.append(k % 2 == 0)
    return nodes, weights, sampled


def judge_layer(solid, z_lo, z_hi, region):
    """D, dV, and the number of missed footprint pieces of one layer."""
    nodes, weights, sampled = sub_levels(solid, z_lo, z_hi)
    walls = wall_segments(region)
    samples, deviation, sections = [], 0.0, []
    for z, w, sample in zip(nodes, weights, sampled):
        loops = solid.loops(z)
        section = region_of_loops(loops)
        sections.append(section)
        deviation += w * section.symmetric_difference(region).area
        if sample:
            for loop in loops:
                samples.append(densify(loop, SAMPLE_SPACING))
    inside = (solid.v[:, 2] > z_lo + ON_PLANE) & (solid.v[:, 2] < z_hi - ON_PLANE)
    samples.append(solid.v[inside][:, :2])
    flat_z = solid.zlo[solid.flat_faces]
    flat = solid.flat_faces[(flat_z > z_lo + ON_PLANE) & (flat_z < z_hi - ON_PLANE)]
    samples.append(flat_outlines(solid, flat, SAMPLE_SPACING))
    points = np.concatenate(samples) if samples else np.zeros((0, 2))
    if len(points) == 0:
        return 0.0, deviation, 0
    distance = distances_to_segments(points, walls)
    # Pieces of the footprint the region does not touch: measured to their own outline.
    missed = 0
    footprint = unary_union([s for s in sections if not s.is_empty] +
                            [Polygon(solid.v[solid.f[f]][:, :2]) for f in flat])
    for piece in polygons_of(footprint):
        if not region.is_empty and piece.intersects(region):
            continue
        grown = piece.buffer(1e-6)
        mask = vectorized.contains(grown, points[:, 0], points[:, 1])
        if mask.any():
            missed += 1
            distance[mask] = distances_to_segments(points[mask], wall_segments(piece))
    distance = distance[np.isfinite(distance)]
    return (float(distance.max()) if len(distance) else 0.0), deviation, missed


def layer_tops(argument):
    """Layer tops from a G-code file, a file of tops, or a comma list (mm, ascending)."""
    try:
        with open(argument, "r", errors="replace") as f:
            text = f.read()
    except OSError:
        try:
            return sorted({round(float(t), 6) for t in argument.split(",") if t.strip()})
        except ValueError:
            sys.exit(f"judge: --layers {argument}: not a file, nor a comma list of heights")
    if re.search(r"^\s*G[01]\s", text, re.M):
        return gcode_tops(text)
    tops = set()
    for line in text.splitlines():
        line = line.split("#")[0].strip()
        if line:
            tops.add(round(float(line), 6))
    return sorted(tops)


def gcode_tops(text):
    """The heights at which a program extrudes while moving in x or y."""
    z, e, relative, tops = 0.0, 0.0, False, set()
    word = re.compile(r"([A-Z])(-?\d*\.?\d+)")
    for line in text.splitlines():
        code = line.split(";")[0].strip().upper()
        if not code:
            continue
        if code.startswith("M83"):
            relative = True
        elif code.startswith("M82"):
            relative = False
        elif code.startswith("G92"):
            for k, v in word.findall(code):
                if k == "E":
                    e = float(v)
        elif code.startswith(("G0", "G1")) and not code.startswith(("G10", "G11")):
            words = dict(word.findall(code))
            if "Z" in words:
                z = float(words["Z"])
            if "E" in words:
                value = float(words["E"])
                delta = value if relative else value - e
                e = e + value if relative else value
                if delta > 1e-9 and ("X" in words or "Y" in words):
                    tops.add(round(z, 6))
    return sorted(tops)


def percentile_by_height(values, weights, share):
    order = np.argsort(values)
    covered = np.cumsum(np.asarray(weights)[order])
    wanted = share * covered[-1] * (1 - 1e-12)
    return float(np.asarray(values)[order][np.searchsorted(covered, wanted)])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("model")
    parser.add_argument("--layers", required=True)
    parser.add_argument("--count", action="store_true", help="print the number of layers and stop")
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--part")
    source.add_argument("--mid", action="store_true")
    parser.add_argument("--exclude-z")
    parser.add_argument("--json")
    parser.add_argument("--csv")
    args = parser.parse_args()

    solid = Solid(*read_stl(args.model))
    part = Solid(*read_stl(args.part)) if args.part else None
    tops = [t for t in layer_tops(args.layers) if t > solid.bottom + 1e-9]
    if not tops:
        sys.exit(f"judge: --layers {args.layers}: no layer above the model's bottom")
    # Layers starting at or above the model's top print nothing of it.
    while len(tops) > 1 and tops[-2] >= solid.top - 1e-6:
        tops.pop()
    if args.count:
        print(len(tops))
        return
    if not args.part and not args.mid:
        sys.exit("judge: give --part LAYERED.stl or --mid")
    excluded = None
    if args.exclude_z:
        lo, hi = (float(x) for x in args.exclude_z.split(":"))
        excluded = (lo, hi)

    rows = []
    z_lo = solid.bottom
    for z_hi in tops:
        middle = 0.5 * (z_lo + z_hi)
        region = (part or solid).section(middle)
        d, dv, missed = judge_layer(solid, z_lo, z_hi, region)
        judged = excluded is None or not (z_lo < excluded[1] and z_hi > excluded[0])
        rows.append({"z_lo": z_lo, "z_hi": z_hi, "D": d, "dV": dv, "missed": missed, "judged": judged})
        z_lo = z_hi
    # The part above the last layer, if any, prints nothing: judged as one more slab with no
    # region (its D to its own outline, all its volume deviation), not counted as a layer.
    uncovered = max(0.0, solid.top - tops[-1])
    if uncovered > 1e-6:
        d, dv, missed = judge_layer(solid, tops[-1], solid.top, Polygon())
        rows.append({"z_lo": tops[-1], "z_hi": solid.top, "D": d, "dV": dv, "missed": missed,
                     "judged": True, "uncovered": True})
    judged = [r for r in rows if r["judged"]]
    d = np.array([r["D"] for r in judged])
    t = np.array([r["z_hi"] - r["z_lo"] for r in judged])
    summary = {
        "model": args.model,
        "layers": len(tops),
        "top": tops[-1],
        "model_top": solid.top,
        "uncovered": uncovered,
        "judged_layers": len(judged),
        "mean_D": float(d.mean()),
        "p95h_D": percentile_by_height(d, t, 0.95),
        "max_D": float(d.max()),
        "total_dV": float(sum(r["dV"] for r in judged)),
        "missed": int(sum(r["missed"] for r in judged)),
        "worst_layer": max(judged, key=lambda r: r["D"]),
        "top_layer": rows[len(tops) - 1],
    }
    if args.csv:
        with open(args.csv, "w") as f:
            f.write("layer,z_lo,z_hi,D,dV,missed,judged\n")
            for i, r in enumerate(rows):
                f.write(f'{i},{r["z_lo"]:.6f},{r["z_hi"]:.6f},{r["D"]:.6f},{r["dV"]:.6f},{r["missed"]},{int(r["judged"])}\n')
    if args.json:
        with open(args.json, "w") as f:
            json.dump(summary, f, indent=1)
    print(f'{summary["layers"]} layers to {summary["top"]:.3f} mm (model {solid.top:.3f}): '
          f'mean D {summary["mean_D"]:.4f}, P95h D {summary["p95h_D"]:.4f}, max D {summary["max_D"]:.4f} mm, '
          f'total dV {summary["total_dV"]:.2f} mm3, {summary["missed"]} missed')


if __name__ == "__main__":
    main()
