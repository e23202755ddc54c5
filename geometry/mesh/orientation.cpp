// Orientation; see orientation.h. Eigen for the vectors, matrices and rotations, CGAL for the
// convex hull, both kept in this file.
#include "geometry/mesh/orientation.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace geometry {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using HullMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Eigen::Matrix3d;
using Eigen::Vector3d;

// Hull facets whose normals are closer than this are one face (degrees).
constexpr double kCoplanarDegrees = 1;
// The centre of mass must stand this far inside a face, as a share of the part's diagonal.
constexpr double kStableMargin = 0.005;
// Support volumes this close to the least count as equal: relative, and mm^3.
constexpr double kVolumeTieShare = 0.01;
constexpr double kVolumeTie = 1;

Matrix3d to_eigen(const Rotation& r) {
  Matrix3d m;
  m << r.m[0], r.m[1], r.m[2], r.m[3], r.m[4], r.m[5], r.m[6], r.m[7], r.m[8];
  return m;
}

Rotation from_eigen(const Matrix3d& m) {
  Rotation r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r.m[static_cast<std::size_t>(3 * i + j)] = m(i, j);
  }
  return r;
}

Vector3d to_eigen(Vec3 p) { return {p.x, p.y, p.z}; }
Vec3 from_eigen(const Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Per facet of the mesh: its area vector (normal times area) and centroid, as rows.
struct Facets {
  Eigen::Matrix<double, Eigen::Dynamic, 3> area;      // n * A
  Eigen::Matrix<double, Eigen::Dynamic, 3> centroid;
  Eigen::VectorXd size;                               // A
};

Facets facets_of(const Mesh& mesh) {
  const auto n = static_cast<Eigen::Index>(mesh.faces.size());
  Facets f{decltype(Facets::area)(n, 3), decltype(Facets::centroid)(n, 3), Eigen::VectorXd(n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& face = mesh.faces[static_cast<std::size_t>(i)];
    const Vector3d a = to_eigen(mesh.vertices[face[0]]), b = to_eigen(mesh.vertices[face[1]]),
                   c = to_eigen(mesh.vertices[face[2]]);
    const Vector3d v = 0.5 * (b - a).cross(c - a);
    f.area.row(i) = v.transpose();
    f.centroid.row(i) = ((a + b + c) / 3).transpose();
    f.size(i) = v.norm();
  }
  return f;
}

// The estimate for the part resting on the plane with outward normal `down` (unit): the
// facets leaning past the angle, their area across `down`, times their height over the
// plane that touches the part's lowest point along `down`.
double volume_resting_on(const Facets& f, const Vector3d& down, double top, double sin_angle) {
  const Eigen::VectorXd across = f.area * down;  // A (down . n)
  const Eigen::VectorXd depth = f.centroid * down;
  double volume = 0;
  for (Eigen::Index i = 0; i < across.size(); ++i) {
    if (across(i) > sin_angle * f.size(i)) volume += across(i) * (top - depth(i));
  }
  return volume;
}

// Volume-weighted centre of the closed mesh (tetrahedra from the origin); the vertices' mean
// for a mesh without volume.
Vector3d centre_of_mass(const Mesh& mesh) {
  Vector3d sum = Vector3d::Zero();
  double volume = 0;
  for (const auto& face : mesh.faces) {
    const Vector3d a = to_eigen(mesh.vertices[face[0]]), b = to_eigen(mesh.vertices[face[1]]),
                   c = to_eigen(mesh.vertices[face[2]]);
    const double v = a.dot(b.cross(c)) / 6;
    sum += v * (a + b + c) / 4;
    volume += v;
  }
  if (std::abs(volume) > 1e-12) return sum / volume;
  Vector3d mean = Vector3d::Zero();
  for (const Vec3& p : mesh.vertices) mean += to_eigen(p);
  return mesh.vertices.empty() ? mean : mean / static_cast<double>(mesh.vertices.size());
}

// Whether q lies inside the convex hull of the points (2D), at least `margin` from its edges.
bool inside_hull(std::vector<Eigen::Vector2d> points, const Eigen::Vector2d& q, double margin) {
  if (points.size() < 3) return false;
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a.x() != b.x() ? a.x() < b.x() : a.y() < b.y();
  });
  auto turn = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const auto& p : points) {  // Andrew's monotone chain, counter-clockwise
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && turn(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  if (hull.size() < 3) return false;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d a = hull[i], b = hull[(i + 1) % hull.size()];
    const double length = (b - a).norm();
    if (!(length > 0)) continue;
    if (turn(a, b, q) / length < margin) return false;
  }
  return true;
}

struct HullFace {
  Vector3d normal;          // area-weighted, unit
  Vector3d seed;            // the largest facet's normal, for merging
  double area = 0;
  std::vector<Vector3d> corners;
};

std::vector<HullFace> hull_faces(const Mesh& mesh) {
  std::vector<Kernel::Point_3> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x, p.y, p.z);
  HullMesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  struct Facet {
    Vector3d normal;
    double area;
    std::array<Vector3d, 3> corners;
  };
  std::vector<Facet> facets;
  for (auto f : hull.faces()) {
    std::array<Vector3d, 3> c;
    int i = 0;
    for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
      if (i == 3) break;
      const auto& p = hull.point(v);
      c[static_cast<std::size_t>(i++)] = {p.x(), p.y(), p.z()};
    }
    if (i != 3) continue;
    const Vector3d v = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]);
    const double area = v.norm();
    if (!(area > 0)) continue;
    facets.push_back({v / area, area, c});
  }
  std::sort(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) { return a.area > b.area; });
  const double close = std::cos(kCoplanarDegrees * std::numbers::pi / 180);
  std::vector<HullFace> faces;
  for (const Facet& facet : facets) {
    HullFace* into = nullptr;
    for (HullFace& face : faces) {
      if (face.seed.dot(facet.normal) >= close) {
        into = &face;
        break;
      }
    }
    if (!into) {
      faces.push_back({Vector3d::Zero(), facet.normal, 0, {}});
      into = &faces.back();
    }
    into->normal += facet.area * facet.normal;
    into->area += facet.area;
    into->corners.insert(into->corners.end(), facet.corners.begin(), facet.corners.end());
  }
  for (HullFace& face : faces) face.normal.normalize();
  return faces;
}

}  // namespace

bool Rotation::identity() const { return m == Rotation{}.m; }

Rotation rotation_about(Vec3 axis, double degrees) {
  const Vector3d a = to_eigen(axis);
  if (!(a.norm() > 0) || !std::isfinite(degrees)) return {};
  return from_eigen(
      Eigen::AngleAxisd(degrees * std::numbers::pi / 180, a.normalized()).toRotationMatrix());
}

Rotation operator*(const Rotation& a, const Rotation& b) {
  return from_eigen(Matrix3d(to_eigen(a) * to_eigen(b)));
}

Vec3 apply(const Rotation& r, Vec3 p) { return from_eigen(Vector3d(to_eigen(r) * to_eigen(p))); }

Mesh rotated(Mesh mesh, const Rotation& r) {
  if (r.identity()) return mesh;
  const Matrix3d m = to_eigen(r);
  for (Vec3& p : mesh.vertices) p = from_eigen(Vector3d(m * to_eigen(p)));
  return mesh;
}

AxisAngle axis_angle(const Rotation& r) {
  const Eigen::AngleAxisd aa(to_eigen(r));
  AxisAngle result;
  result.degrees = aa.angle() * 180 / std::numbers::pi;
  if (result.degrees > 1e-9) result.axis = from_eigen(aa.axis());
  return result;
}

double support_volume_estimate(const Mesh& mesh, double overhang_angle) {
  if (mesh.faces.empty()) return 0;
  const Facets f = facets_of(mesh);
  const Vector3d down{0, 0, -1};
  double top = -1e300;  // the lowest point, along `down`
  for (const auto& face : mesh.faces) {
    for (auto v : face) top = std::max(top, -mesh.vertices[v].z);
  }
  return volume_resting_on(f, down, top, std::sin(overhang_angle * std::numbers::pi / 180));
}

OrientResult orient_for_least_support(const Mesh& mesh, const OrientOptions& options) {
  OrientResult result;
  if (mesh.faces.empty()) return result;
  const Facets f = facets_of(mesh);
  const double sin_angle = std::sin(std::clamp(options.overhang_angle, 0.0, 89.0) * std::numbers::pi / 180);
  // Reach of the part along a direction: min and max of the vertices' projections.
  auto extent = [&](const Vector3d& u) {
    double lo = 1e300, hi = -1e300;
    for (const Vec3& p : mesh.vertices) {
      const double d = u.dot(to_eigen(p));
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    return std::pair{lo, hi};
  };
  auto resting = [&](const Vector3d& down, double area) {
    RestingOrientation r;
    r.down = from_eigen(down);
    r.face_area = area;
    r.rotation = from_eigen(
        Eigen::Quaterniond::FromTwoVectors(down, Vector3d(0, 0, -1)).toRotationMatrix());
    const auto [lo, hi] = extent(down);
    r.height = hi - lo;
    r.support_volume = volume_resting_on(f, down, hi, sin_angle);
    return r;
  };
  result.input = resting(Vector3d(0, 0, -1), 0);
  result.input.rotation = Rotation{};
  result.chosen = result.input;

  const Box3 box = bounding_box(mesh);
  const double diagonal = std::sqrt(dot(box.max - box.min, box.max - box.min));
  if (!(diagonal > 0)) return result;
  const std::vector<HullFace> faces = hull_faces(mesh);
  result.hull_faces = faces.size();
  const Vector3d centre = centre_of_mass(mesh);
  std::vector<RestingOrientation> stable;
  for (const HullFace& face : faces) {
    // The centre of mass, dropped along the normal onto the face, in the face's plane.
    const Vector3d n = face.normal;
    const Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    std::vector<Eigen::Vector2d> corners;
    corners.reserve(face.corners.size());
    for (const Vector3d& c : face.corners) corners.emplace_back(c.dot(e1), c.dot(e2));
    if (!inside_hull(std::move(corners), {centre.dot(e1), centre.dot(e2)}, kStableMargin * diagonal)) {
      continue;
    }
    stable.push_back(resting(n, face.area));
  }
  result.stable_faces = stable.size();
  if (stable.empty()) return result;
  double least = stable.front().support_volume;
  for (const RestingOrientation& r : stable) least = std::min(least, r.support_volume);
  const double tie = std::max(kVolumeTie, kVolumeTieShare * least);
  const RestingOrientation* best = nullptr;
  for (const RestingOrientation& r : stable) {
    if (r.support_volume > least + tie) continue;
    if (!best || r.height < best->height - 1e-9 ||
        (std::abs(r.height - best->height) <= 1e-9 && r.face_area > best->face_area)) {
      best = &r;
    }
  }
  result.chosen = *best;
  return result;
}

}  // namespace geometry
