// Orientation: turning a model before it is placed on the bed, by hand (--rotate) or to the
// resting position that needs the least support (--orient auto).
//
// Rotations are proper (determinant +1): facets stay outward. Units: mm, degrees, mm^3. The
// matrices and the hull's normals are Eigen types inside orientation.cpp; this header hands
// out plain row-major 3 x 3 arrays, so nothing that includes it compiles Eigen or CGAL.
//
// support_volume_estimate(mesh, angle, cost): with the mesh as it stands (z up), the support
//   columns everywhere (the support stage's default): down from every facet that faces down
//   more steeply than the overhang angle allows (angle from vertical a wall may lean:
//   n_z < -sin(angle)) to the next facet facing up below it, or to the mesh's lowest point
//   (the bed), measured along the centre lines of a grid about 256 cells across the part
//   (cells at least 0.2 mm), mm^3. What each column costs is `cost`'s: by default its whole
//   volume; with the support's own figures, the material the support stage lays in it (the
//   contact gaps left empty, a dense interface at its top, a sparse body below), which is
//   what an orientation should save: many short columns under a broad, low overhang are
//   nearly all interface and cost several times their volume's share of body.
// orient_for_least_support(mesh, options): the model's stable resting orientations are the
//   faces of its convex hull (coplanar hull facets within 1 degree merged) on which the
//   centre of mass stands inside the face, at least 0.5% of the part's size from its edge;
//   for each, the rotation that turns the face's outward normal to -Z, its support cost
//   and its height. The faces are ranked by a quick estimate (each steep facet's projected
//   area times its height over the bed, costed alike, which overstates what the part itself
//   carries), and the best 16 measured by support_volume_estimate. Chosen: the least support
//   cost, then (within 1% or 1 mm^3 of it) the least height, then the orientation as given,
//   then the largest face. A face within 1 degree of the orientation as given keeps it as
//   given (a flat base whose hull face leans a little on a few points of its rim stays flat
//   on the bed) and competes with the input's support and height. A part that needs support
//   as given is turned only when the chosen face's estimate is more than turn_margin (10%)
//   below the input's: between faces of like support the estimate is rough. The orientation
//   as it stands is reported beside it ("input"). An empty or flat mesh keeps its
//   orientation.
//   On the bunny (tests/bench/compare_orientations.sh, supports everywhere at 50 degrees,
//   lines 2.5 mm apart, 0.4 mm of interface at 80%), the estimate of the face turned 87
//   degrees is 697 mm^3 against 708 as given, 1.6% less, but the slicer lays 0.60 m of
//   support filament there against 0.54 m as given (the interface widened to the body's
//   lines, and each island's sheath, are not in the columns): so it stays as given. By the
//   columns' volume alone (3078 against 3198 mm^3) it was turned. Where a face saves most of
//   the support (a T, an arch, a table, a mushroom cap, a hook) the estimate is not in doubt.
#pragma once

#include <array>
#include <cstddef>

#include "geometry/mesh/mesh.h"

namespace geometry {

// Row-major: p' = m p.
struct Rotation {
  std::array<double, 9> m{1, 0, 0, 0, 1, 0, 0, 0, 1};
  bool identity() const;
};

// Right-handed rotation by `degrees` about `axis` (any length > 0; a zero axis: identity).
Rotation rotation_about(Vec3 axis, double degrees);
// First b, then a.
Rotation operator*(const Rotation& a, const Rotation& b);
Vec3 apply(const Rotation& r, Vec3 p);
// Every vertex turned about the origin.
Mesh rotated(Mesh mesh, const Rotation& r);
// The axis (unit) and angle (degrees, in [0, 180]) of a rotation.
struct AxisAngle {
  Vec3 axis{0, 0, 1};
  double degrees = 0;
};
AxisAngle axis_angle(const Rotation& r);

// What support costs per column (see support_volume_estimate). The default counts every
// column's whole volume.
struct SupportCost {
  double body_share = 1;           // of the body's volume laid: bead width / line spacing
  double interface_share = 1;      // of the interface's volume laid: its density
  double interface_thickness = 0;  // mm of interface at a column's top
  double top_gap = 0;              // mm of air between a column's top and the part
  double bottom_gap = 0;           // mm of air under a column that stands on the part
  // mm^3 laid per mm^2 of a column `length` mm tall, standing on the part or the bed.
  double per_area(double length, bool on_part) const;
};

double support_volume_estimate(const Mesh& mesh, double overhang_angle,
                               const SupportCost& cost = {});

struct OrientOptions {
  double overhang_angle = 50;  // degrees from vertical
  SupportCost cost;            // the support's figures (default: the columns' volume)
  // A part that needs support as given is turned only onto a face whose estimate is less
  // than the input's by more than this share of it.
  double turn_margin = 0.1;
};

struct RestingOrientation {
  Rotation rotation;        // turns the model so that it rests on this face
  Vec3 down{0, 0, -1};      // the face's outward normal, in the model as given
  double face_area = 0;     // mm^2 of hull face on the bed
  double support_volume = 0;  // mm^3, support_volume_estimate after the rotation (costed)
  double height = 0;        // mm, the part's height after it
};

struct OrientResult {
  RestingOrientation chosen;
  RestingOrientation input;      // the orientation as given (rotation identity)
  std::size_t stable_faces = 0;  // resting orientations compared
  std::size_t hull_faces = 0;    // hull faces after merging coplanar facets
};

OrientResult orient_for_least_support(const Mesh& mesh, const OrientOptions& options = {});

}  // namespace geometry
