// Orientation: turning a model before it is placed on the bed, by hand (--rotate) or to the
// resting position that needs the least support (--orient auto; issue 12).
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
//   on the bed), with the input's support and height. The orientation as it stands is
//   reported beside it ("input"). An empty or flat mesh keeps its orientation.
//   On the bunny (tests/bench/compare_orientations.sh, supports everywhere at 50 degrees,
//   lines 2.5 mm apart, 0.4 mm of interface at 80%), ranking the 8 resting faces measured by
//   their columns' volume turned it 87 degrees, onto a face whose support the slicer lays in
//   0.60 m of filament against the input's 0.54 m; ranked by the material, the 9 orientations
//   (as given and the 8 faces) come in the slicer's order but for the last three, whose
//   support is within 5% of each other, and the least is the hull face 0.7 degrees off the
//   base, so the bunny stays as given.
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
