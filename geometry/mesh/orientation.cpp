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
#include <optional>
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
// The columns' grid: cells across the part, and the least cell (mm); its offset, in cells.
constexpr double kColumnCells = 256;
constexpr double kLeastCell = 0.2;
constexpr double kGridShift = 0.3719;
// Resting faces whose columns are measured: the best by the facets' quick estimate.
constexpr std::size_t kMeasured = 16;
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
// facets leaning past the angle, their area across `down`, times the cost of a column from
// them to the plane that touches the part's lowest point along `down`.
double volume_resting_on(const Facets& f, const Vector3d& down, double top, double sin_angle,
                         const SupportCost& cost) {
  const Eigen::VectorXd across = f.area * down;  // A (down . n)
  const Eigen::VectorXd depth = f.centroid * down;
  double volume = 0;
  for (Eigen::Index i = 0; i < across.size(); ++i) {
    if (across(i) > sin_angle * f.size(i)) {
      volume += across(i) * cost.per_area(top - depth(i), false);
    }
  }
  return volume;
}

// Support columns under the mesh turned by `turn`, everywhere: on a grid of cells (about 256
// across the part, at least 0.2 mm), down every cell's centre line, from each facet facing
// down more steeply than the angle allows to the next facet facing up below it, or to the
// lowest point (the bed), each costed by `cost`; mm^3. The grid is offset by a fraction of a
// cell so that centre lines miss the vertices of axis-aligned meshes.
double column_volume(const Mesh& mesh, const Matrix3d& turn, double sin_angle,
                     const SupportCost& cost) {
  if (mesh.faces.empty()) return 0;
  std::vector<Vector3d> v(mesh.vertices.size());
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] = turn * to_eigen(mesh.vertices[i]);
    lo = lo.cwiseMin(v[i]);
    hi = hi.cwiseMax(v[i]);
  }
  const double size = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (!(size > 0)) return 0;
  const double cell = std::max(size / kColumnCells, kLeastCell);
  const auto nx = static_cast<long>((hi.x() - lo.x()) / cell) + 2;
  const auto ny = static_cast<long>((hi.y() - lo.y()) / cell) + 2;
  const double x0 = lo.x() - kGridShift * cell, y0 = lo.y() - kGridShift * cell;
  struct Hit {
    long cell;
    double z;
    int kind;  // 1 facing up, -1 down and steep, -2 down and gentle
  };
  std::vector<Hit> hits;
  hits.reserve(mesh.faces.size() * 2);
  for (const auto& face : mesh.faces) {
    const Vector3d& a = v[face[0]];
    const Vector3d& b = v[face[1]];
    const Vector3d& c = v[face[2]];
    const Vector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    if (!(length > 0) || std::abs(n.z()) < 1e-12 * length) continue;
    const int kind = n.z() > 0 ? 1 : (-n.z() > sin_angle * length ? -1 : -2);
    const double ax = std::min({a.x(), b.x(), c.x()}), bx = std::max({a.x(), b.x(), c.x()});
    const double ay = std::min({a.y(), b.y(), c.y()}), by = std::max({a.y(), b.y(), c.y()});
    const long i0 = static_cast<long>(std::ceil((ax - x0) / cell - 0.5)), i1 = static_cast<long>(std::floor((bx - x0) / cell - 0.5));
    const long j0 = static_cast<long>(std::ceil((ay - y0) / cell - 0.5)), j1 = static_cast<long>(std::floor((by - y0) / cell - 0.5));
    const double area2 = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    for (long j = std::max(j0, 0L); j <= std::min(j1, ny - 1); ++j) {
      for (long i = std::max(i0, 0L); i <= std::min(i1, nx - 1); ++i) {
        const double px = x0 + (static_cast<double>(i) + 0.5) * cell, py = y0 + (static_cast<double>(j) + 0.5) * cell;
        // Barycentric weights of the centre line's point in the facet's projection.
        const double wa = ((b.x() - px) * (c.y() - py) - (c.x() - px) * (b.y() - py)) / area2;
        const double wb = ((c.x() - px) * (a.y() - py) - (a.x() - px) * (c.y() - py)) / area2;
        const double wc = 1 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        hits.push_back({j * nx + i, wa * a.z() + wb * b.z() + wc * c.z(), kind});
      }
    }
  }
  std::sort(hits.begin(), hits.end(), [](const Hit& p, const Hit& q) {
    return p.cell != q.cell ? p.cell < q.cell : p.z > q.z;
  });
  double per_cell = 0;  // mm^3 per mm^2 of cell
  for (std::size_t first = 0; first < hits.size();) {
    std::size_t last = first;
    while (last < hits.size() && hits[last].cell == hits[first].cell) ++last;
    // Downwards along the centre line: out of the part through a steep underside, a column
    // of support to whatever faces up below.
    std::optional<double> column;
    for (std::size_t k = first; k < last; ++k) {
      if (hits[k].kind == 1) {
        if (column) per_cell += cost.per_area(*column - hits[k].z, true);
        column.reset();
      } else if (hits[k].kind == -1) {
        column = hits[k].z;
      }
    }
    if (column) per_cell += cost.per_area(*column - lo.z(), false);
    first = last;
  }
  return per_cell * cell * cell;
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

double SupportCost::per_area(double length, bool on_part) const {
  const double laid = std::max(0.0, length - top_gap - (on_part ? bottom_gap : 0.0));
  const double dense = std::min(laid, std::max(interface_thickness, 0.0));
  return interface_share * dense + body_share * (laid - dense);
}

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

double support_volume_estimate(const Mesh& mesh, double overhang_angle, const SupportCost& cost) {
  const double angle = std::clamp(overhang_angle, 0.0, 89.0) * std::numbers::pi / 180;
  return column_volume(mesh, Matrix3d::Identity(), std::sin(angle), cost);
}

namespace {

// Reach of the part along a direction: min and max of the vertices' projections.
std::pair<double, double> extent(const Mesh& mesh, const Vector3d& u) {
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : mesh.vertices) {
    const double d = u.dot(to_eigen(p));
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return std::pair{lo, hi};
}

// The part resting on the plane with outward normal `down` (unit), a face of `area` on it;
// its support volume by the facets' quick estimate.
RestingOrientation resting_on(const Mesh& mesh, const Facets& f, const Vector3d& down,
                              double area, double sin_angle, const SupportCost& cost) {
  RestingOrientation r;
  r.down = from_eigen(down);
  r.face_area = area;
  r.rotation = from_eigen(
      Eigen::Quaterniond::FromTwoVectors(down, Vector3d(0, 0, -1)).toRotationMatrix());
  const auto [lo, hi] = extent(mesh, down);
  r.height = hi - lo;
  r.support_volume = volume_resting_on(f, down, hi, sin_angle, cost);
  return r;
}

// The hull faces the part stands on: its centre of mass, dropped along the normal onto the
// face, lies at least `margin` (mm) inside it, in the face's plane.
std::vector<RestingOrientation> stable_orientations(const Mesh& mesh, const Facets& f,
                                                    const std::vector<HullFace>& faces,
                                                    double margin, double sin_angle,
                                                    const SupportCost& cost) {
  const Vector3d centre = centre_of_mass(mesh);
  std::vector<RestingOrientation> stable;
  for (const HullFace& face : faces) {
    const Vector3d n = face.normal;
    const Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    std::vector<Eigen::Vector2d> corners;
    corners.reserve(face.corners.size());
    for (const Vector3d& c : face.corners) corners.emplace_back(c.dot(e1), c.dot(e2));
    if (!inside_hull(std::move(corners), {centre.dot(e1), centre.dot(e2)}, margin)) continue;
    stable.push_back(resting_on(mesh, f, n, face.area, sin_angle, cost));
  }
  return stable;
}

// A face within a degree of the orientation as given (a flat base whose hull face leans a
// little, on a few points of its rim) keeps the part as given, so that the base stays flat
// on the bed: it competes with what is then printed, the input's support and height.
bool as_given(const RestingOrientation& r) {
  return r.down.z < -std::cos(kCoplanarDegrees * std::numbers::pi / 180);
}

// The quick estimate (each steep facet's height over the bed) ranks the orientations; the
// columns, which stop on the part below, measure the best few.
void measure_best_few(std::vector<RestingOrientation>& stable, const Mesh& mesh,
                      const RestingOrientation& input, double sin_angle,
                      const SupportCost& cost) {
  std::sort(stable.begin(), stable.end(), [](const RestingOrientation& a, const RestingOrientation& b) {
    return a.support_volume < b.support_volume;
  });
  if (stable.size() > kMeasured) stable.resize(kMeasured);
  for (RestingOrientation& r : stable) {
    if (as_given(r)) {
      r.rotation = Rotation{};
      r.support_volume = input.support_volume;
      r.height = input.height;
    } else {
      r.support_volume = column_volume(mesh, to_eigen(r.rotation), sin_angle, cost);
    }
  }
}

// Of the orientations within a tie of the least support, the lowest; among equals, the
// orientation as given, else the largest face.
const RestingOrientation& least_support(const std::vector<RestingOrientation>& stable) {
  double least = stable.front().support_volume;
  for (const RestingOrientation& r : stable) least = std::min(least, r.support_volume);
  const double tie = std::max(kVolumeTie, kVolumeTieShare * least);
  const RestingOrientation* best = nullptr;
  for (const RestingOrientation& r : stable) {
    if (r.support_volume > least + tie) continue;
    const bool equal = best && std::abs(r.height - best->height) <= 1e-6;
    if (!best || r.height < best->height - 1e-6 ||
        (equal && as_given(r) && !as_given(*best)) ||
        (equal && as_given(r) == as_given(*best) && r.face_area > best->face_area)) {
      best = &r;
    }
  }
  return *best;
}

}  // namespace

OrientResult orient_for_least_support(const Mesh& mesh, const OrientOptions& options) {
  OrientResult result;
  if (mesh.faces.empty()) return result;
  const Facets f = facets_of(mesh);
  const double sin_angle = std::sin(std::clamp(options.overhang_angle, 0.0, 89.0) * std::numbers::pi / 180);
  result.input = resting_on(mesh, f, Vector3d(0, 0, -1), 0, sin_angle, options.cost);
  result.input.rotation = Rotation{};
  result.chosen = result.input;

  const Box3 box = bounding_box(mesh);
  const double diagonal = std::sqrt(dot(box.max - box.min, box.max - box.min));
  if (!(diagonal > 0)) return result;
  const std::vector<HullFace> faces = hull_faces(mesh);
  result.hull_faces = faces.size();
  std::vector<RestingOrientation> stable =
      stable_orientations(mesh, f, faces, kStableMargin * diagonal, sin_angle, options.cost);
  result.stable_faces = stable.size();
  if (stable.empty()) return result;
  result.input.support_volume = column_volume(mesh, Matrix3d::Identity(), sin_angle, options.cost);
  measure_best_few(stable, mesh, result.input, sin_angle, options.cost);
  const RestingOrientation& best = least_support(stable);
  result.chosen = best;
  // The estimate is rough between faces of like support (see the header), so a part that
  // needs support as given is turned only when a face needs clearly less.
  const double margin = 1 + std::max(options.turn_margin, 0.0);
  if (result.input.support_volume > kVolumeTie &&
      result.input.support_volume <= best.support_volume * margin) {
    result.chosen = result.input;
  }
  return result;
}

}  // namespace geometry
