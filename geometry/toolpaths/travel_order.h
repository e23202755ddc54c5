// Travel order: the order and direction in which a layer's paths are printed, where closed
// paths start (the seam), and which travels need a retraction.
//
// Paths in mm (toolpaths.h). Closed paths end where they begin and may start at any vertex;
// open paths may run either way. All functions accept empty input.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

enum class SeamPosition {
  aligned,  // the same place on every layer: a corner at the rear of the loop
  nearest,  // the loop point nearest to where the nozzle is (least travel)
};

std::string_view seam_position_name(SeamPosition seam);  // "aligned", "nearest"
std::optional<SeamPosition> parse_seam_position(std::string_view name);

// The vertex where an aligned seam goes on a closed path (its points, last = first): among
// the vertices near the rear (within max(0.5 mm, 2% of the loop's depth) of the largest y),
// the sharpest concave corner of the part (the seam hides in it), else the sharpest convex
// corner, else the rearmost vertex, ties to the smallest x. Similar loops on consecutive
// layers give the same place. Returns 0 for fewer than 2 points.
std::size_t aligned_seam(const std::vector<Vec2>& points);

// Where a closed path started on a layer: its seam, for the layer above to line up with.
struct Seam {
  PathRole role = PathRole::outer_wall;
  bool hole = false;  // the path runs clockwise (round a hole)
  Vec2 at;
};

// The aligned seam of a closed path (its points, last = first) with the seams of the layer
// below in mind. The seam below of the same role and direction nearest to the path, if it
// is within `reach` mm of a vertex, marks the place: the best corner within `radius` mm
// of it (ranked as aligned_seam ranks: concave, then convex, then none; then the nearer)
// is kept, so that seams stay in one line layer after layer, unless it is no corner at all
// and aligned_seam finds a concave corner to hide the seam in. Otherwise, and without a
// seam below, aligned_seam. Returns 0 for fewer than 3 points.
std::size_t remembered_seam(const std::vector<Vec2>& points, PathRole role,
                            const std::vector<Seam>& below, double reach, double radius);

// Appends `paths` to `out` nearest first: from `position`, repeatedly the path whose start is
// nearest; a closed path starts at its seam (rotated to it), an open path runs from its
// nearer end (reversed if that is its last point). `position` ends where the last path ends.
// Ties go to the earlier path, so the order is deterministic.
// With aligned seams and `below` (the seams of the layer below), a closed path's seam is
// remembered_seam's (reach 3 and radius 1 bead widths); the seams laid are appended to
// `laid` when given.
void append_nearest_first(std::vector<ExtrusionPath> paths, SeamPosition seam, Vec2& position,
                          std::vector<ExtrusionPath>& out, const std::vector<Seam>* below = nullptr,
                          std::vector<Seam>* laid = nullptr);

// Where append_nearest_first would start among `paths` from `position`, and the distance.
struct NearestStart {
  std::size_t path = 0;
  Vec2 point;
  double distance = 0;
};
std::optional<NearestStart> nearest_start(const std::vector<ExtrusionPath>& paths,
                                          SeamPosition seam, Vec2 position);

// Sets retract_before on every path whose travel from the end of the one before leaves
// `region` (crosses its boundary: a wall, into a hole or across open air) and is longer than
// min_travel, and on the first path (the travel from the previous layer). Clears it
// elsewhere: a travel that stays inside the region, however long, oozes only onto the part,
// where the next beads cover it (Cura's combing), so it keeps the filament where it is.
void mark_retractions(std::vector<ExtrusionPath>& paths, const Region& region,
                      double min_travel);

// Whether the segment [a, b] meets the boundary of `region`.
bool crosses_boundary(const Region& region, Vec2 a, Vec2 b);

}  // namespace geometry
