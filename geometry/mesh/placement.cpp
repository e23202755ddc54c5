// Placing a model on the bed; see placement.h.
#include "geometry/mesh/placement.h"

#include <cmath>

#include "geometry/core/clipper.h"

namespace geometry {
namespace {

// The proper rotation (determinant +1) that turns the model's `up` axis into +Z, so the
// facets' vertex order, and with it which side is outside, survives the turn.
Vec3 turn_up(const Vec3& p, Axis up) {
  switch (up) {
    case Axis::x:
      return {-p.z, p.y, p.x};  // about Y by -90 degrees: +X -> +Z, +Z -> -X
    case Axis::y:
      return {p.x, -p.z, p.y};  // about X by +90 degrees: +Y -> +Z, +Z -> -Y
    case Axis::z:
      break;
  }
  return p;
}

// Heights on a 1 nm grid. Files store flat faces with float noise (the stl-models gearwheel's
// bottom is at +-5e-17); without the snap, a plane exactly at such a face (z = 0 for the first
// layer's lower contour) would cut a ragged sliver instead of the whole face. 1 nm is the
// resolution of every 2D operation here (core/clipper.h), far below any printer's.
double snap_height(double z) { return std::round(z * kClipperScale) / kClipperScale; }

}  // namespace

Mesh place(Mesh mesh, const Placement& placement) {
  if (mesh.faces.empty()) return mesh;
  double factor = placement.units_to_mm * placement.scale;
  for (Vec3& p : mesh.vertices) p = turn_up(p, placement.up);
  mesh = rotated(std::move(mesh), placement.rotation);

  Box3 box = bounding_box(mesh);
  if (placement.height) {
    // Scale uniformly so the part is exactly this tall; a flat part has no height to scale.
    const double tall = box.max.z - box.min.z;
    if (tall > 0 && std::isfinite(tall)) factor = *placement.height / tall;
  }
  // Centre and lift in file units before scaling, so the lowest point lands on exactly 0.
  const Vec3 shift{(box.min.x + box.max.x) / 2, (box.min.y + box.max.y) / 2, box.min.z};
  for (Vec3& p : mesh.vertices) {
    const Vec3 q = p - shift;
    p = {placement.center.x + factor * q.x, placement.center.y + factor * q.y,
         snap_height(factor * q.z)};
  }
  return mesh;
}

}  // namespace geometry
