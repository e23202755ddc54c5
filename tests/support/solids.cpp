#include "support/solids.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

namespace solids {

using geometry::Loop;
using geometry::Mesh;
using geometry::Region;
using geometry::Vec2;
using geometry::Vec3;

namespace {

constexpr double kPi = std::numbers::pi;

struct MeshBuilder {
  Mesh mesh;
  std::uint32_t vertex(Vec3 p) {
    mesh.vertices.push_back(p);
    return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    mesh.faces.push_back({a, b, c});
  }
  // Vertical wall over the edge u -> v, outward to the right of u -> v seen from above when
  // the enclosed region runs counter-clockwise (u_lo, v_lo at the bottom, u_hi, v_hi on top).
  void wall(std::uint32_t u_lo, std::uint32_t v_lo, std::uint32_t v_hi, std::uint32_t u_hi) {
    triangle(u_lo, v_lo, v_hi);
    triangle(u_lo, v_hi, u_hi);
  }
};

// The crossings of a closed polygon's edges with the horizontal line at height z (second
// coordinate), as first coordinates, sorted. Limit from above: a vertex at exactly z counts
// as below the line, so horizontal edges at z never cross and a vertex on it is crossed once.
std::vector<double> crossings(const std::vector<Vec2>& polygon, double z) {
  std::vector<double> result;
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    Vec2 a = polygon[i], b = polygon[(i + 1) % n];
    const bool a_below = a.y <= z, b_below = b.y <= z;
    if (a_below == b_below) continue;
    if (!a_below) std::swap(a, b);
    const double t = (z - a.y) / (b.y - a.y);
    result.push_back(a.x + t * (b.x - a.x));
  }
  std::sort(result.begin(), result.end());
  return result;
}

// A profile's section at z as the intervals (lo, hi) of positive width between its crossings.
// Intervals that touch are one: the slit between them has zero width in the limit from above
// (a notch whose tip is at z). An interval that has shrunk to a point is no area.
std::vector<std::pair<double, double>> intervals_at(const std::vector<Vec2>& profile, double z) {
  const std::vector<double> at = crossings(profile, z);
  std::vector<std::pair<double, double>> intervals;
  for (std::size_t i = 0; i + 1 < at.size(); i += 2) {
    if (!(at[i] < at[i + 1])) continue;
    if (!intervals.empty() && intervals.back().second == at[i]) {
      intervals.back().second = at[i + 1];
    } else {
      intervals.push_back({at[i], at[i + 1]});
    }
  }
  return intervals;
}

Loop reversed(Loop loop) {
  std::reverse(loop.begin(), loop.end());
  return loop;
}

Loop rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// The flat ring between an axis-aligned rectangle and a convex polygon strictly inside it,
// triangulated without new vertices inside: every inner vertex is projected from the inner
// polygon's vertex centroid onto the rectangle, the rectangle's corners are added between
// those projections, and each wedge between two consecutive rays (a convex polygon, because
// the wedge, the rectangle and the half-plane beyond the inner edge all are) is fanned from
// its inner vertex. Triangles are counter-clockwise seen from above; index i < inner.size()
// is inner vertex i, inner.size() + j is outer[j].
struct FlatRing {
  std::vector<Vec2> outer;  // counter-clockwise, every point on the rectangle's boundary
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

FlatRing flat_ring(Vec2 lo, Vec2 hi, const Loop& inner) {
  const std::size_t n = inner.size();
  Vec2 c{0, 0};
  for (Vec2 p : inner) c = c + p;
  c = (1.0 / static_cast<double>(n)) * c;

  const double width = hi.x - lo.x, height = hi.y - lo.y;
  const double snap = 1e-12 * std::max(width, height);
  auto project = [&](Vec2 p) {
    const Vec2 d = p - c;
    double t = INFINITY;
    bool on_x_side = false;
    if (d.x > 0) t = (hi.x - c.x) / d.x, on_x_side = true;
    if (d.x < 0) t = (lo.x - c.x) / d.x, on_x_side = true;
    if (d.y > 0 && (hi.y - c.y) / d.y < t) t = (hi.y - c.y) / d.y, on_x_side = false;
    if (d.y < 0 && (lo.y - c.y) / d.y < t) t = (lo.y - c.y) / d.y, on_x_side = false;
    Vec2 q = c + t * d;
    // Land exactly on the boundary (and on a corner when within rounding of one) so that
    // boundary parameters below compare exactly.
    auto nearest = [&](double v, double a, double b) {
      return std::abs(v - a) <= std::abs(v - b) ? a : b;
    };
    if (on_x_side) {
      q.x = nearest(q.x, lo.x, hi.x);
      const double y = nearest(q.y, lo.y, hi.y);
      if (std::abs(q.y - y) <= snap) q.y = y;
    } else {
      q.y = nearest(q.y, lo.y, hi.y);
      const double x = nearest(q.x, lo.x, hi.x);
      if (std::abs(q.x - x) <= snap) q.x = x;
    }
    return q;
  };
  // Arc length along the boundary, counter-clockwise from the corner lo.
  auto boundary_s = [&](Vec2 q) {
    if (q.y == lo.y && q.x < hi.x) return q.x - lo.x;
    if (q.x == hi.x && q.y < hi.y) return width + (q.y - lo.y);
    if (q.y == hi.y && q.x > lo.x) return width + height + (hi.x - q.x);
    return 2 * width + height + (hi.y - q.y);
  };
  const double full = 2 * (width + height);
  const std::array<std::pair<double, Vec2>, 4> corners{{{0.0, lo},
                                                        {width, {hi.x, lo.y}},
                                                        {width + height, hi},
                                                        {2 * width + height, {lo.x, hi.y}}}};

  std::vector<Vec2> projected(n);
  for (std::size_t k = 0; k < n; ++k) projected[k] = project(inner[k]);

  FlatRing ring;
  std::vector<std::size_t> first_outer(n);  // index in ring.outer of projected[k]
  std::vector<std::vector<Vec2>> between(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double s = boundary_s(projected[k]);
    double s_next = boundary_s(projected[(k + 1) % n]);
    if (s_next <= s) s_next += full;
    first_outer[k] = ring.outer.size();
    ring.outer.push_back(projected[k]);
    for (int lap = 0; lap < 2; ++lap) {
      for (const auto& [corner_s, corner] : corners) {
        const double cs = corner_s + lap * full;
        if (s < cs && cs < s_next) ring.outer.push_back(corner);
      }
    }
  }
  const auto outer_index = [&](std::size_t j) {
    return static_cast<std::uint32_t>(n + j % ring.outer.size());
  };
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t apex = static_cast<std::uint32_t>(k);
    const std::size_t last = k + 1 < n ? first_outer[k + 1] : ring.outer.size();
    std::vector<std::uint32_t> fan;
    for (std::size_t j = first_outer[k]; j <= last; ++j) fan.push_back(outer_index(j));
    fan.push_back(static_cast<std::uint32_t>((k + 1) % n));
    for (std::size_t j = 0; j + 1 < fan.size(); ++j) {
      ring.triangles.push_back({apex, fan[j], fan[j + 1]});
    }
  }
  return ring;
}

// Emits a flat ring at height z: `inner` and `outer` are the vertex indices of the ring's
// inner polygon and outer points; up = counter-clockwise seen from above.
void emit_ring(MeshBuilder& builder, const FlatRing& ring, const std::vector<std::uint32_t>& inner,
               const std::vector<std::uint32_t>& outer, bool up) {
  auto id = [&](std::uint32_t local) {
    return local < inner.size() ? inner[local] : outer[local - inner.size()];
  };
  for (const auto& t : ring.triangles) {
    if (up) {
      builder.triangle(id(t[0]), id(t[1]), id(t[2]));
    } else {
      builder.triangle(id(t[0]), id(t[2]), id(t[1]));
    }
  }
}

std::vector<std::uint32_t> add_loop(MeshBuilder& builder, const std::vector<Vec2>& points,
                                    double z) {
  std::vector<std::uint32_t> ids;
  for (Vec2 p : points) ids.push_back(builder.vertex({p.x, p.y, z}));
  return ids;
}

// Walls around a counter-clockwise loop of vertices, outward (solid inside the loop) or
// inward (solid outside: a hole).
void emit_walls(MeshBuilder& builder, const std::vector<std::uint32_t>& lo,
                const std::vector<std::uint32_t>& hi, bool outward) {
  for (std::size_t i = 0, n = lo.size(); i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    if (outward) {
      builder.wall(lo[i], lo[j], hi[j], hi[i]);
    } else {
      builder.wall(lo[j], lo[i], hi[i], hi[j]);
    }
  }
}

// A flat convex face over a counter-clockwise loop of vertices that may contain collinear
// points: fanned from an added centre vertex so that no triangle degenerates.
void emit_cap(MeshBuilder& builder, const std::vector<Vec2>& points,
              const std::vector<std::uint32_t>& ids, double z, bool up) {
  Vec2 c{0, 0};
  for (Vec2 p : points) c = c + p;
  c = (1.0 / static_cast<double>(points.size())) * c;
  const std::uint32_t centre = builder.vertex({c.x, c.y, z});
  for (std::size_t i = 0, n = ids.size(); i < n; ++i) {
    const std::uint32_t a = ids[i], b = ids[(i + 1) % n];
    if (up) {
      builder.triangle(centre, a, b);
    } else {
      builder.triangle(centre, b, a);
    }
  }
}

// Triangles of a simple counter-clockwise polygon (ear clipping; test-sized inputs).
std::vector<std::array<std::size_t, 3>> ear_clipping(const std::vector<Vec2>& polygon) {
  std::vector<std::size_t> left(polygon.size());
  for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
  std::vector<std::array<std::size_t, 3>> triangles;
  const auto inside = [&](Vec2 p, Vec2 a, Vec2 b, Vec2 c) {
    return geometry::cross(b - a, p - a) >= 0 && geometry::cross(c - b, p - b) >= 0 &&
           geometry::cross(a - c, p - c) >= 0;
  };
  while (left.size() > 3) {
    bool clipped = false;
    for (std::size_t i = 0, n = left.size(); i < n && !clipped; ++i) {
      const std::size_t ia = left[(i + n - 1) % n], ib = left[i], ic = left[(i + 1) % n];
      const Vec2 a = polygon[ia], b = polygon[ib], c = polygon[ic];
      if (geometry::cross(b - a, c - b) <= 0) continue;  // reflex or flat: not an ear
      bool empty = true;
      for (std::size_t j : left) {
        if (j != ia && j != ib && j != ic && inside(polygon[j], a, b, c)) empty = false;
      }
      if (!empty) continue;
      triangles.push_back({ia, ib, ic});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) break;  // not a simple polygon: give up rather than loop
  }
  if (left.size() == 3) triangles.push_back({left[0], left[1], left[2]});
  return triangles;
}

Solid rectangle_prism_solid(Mesh mesh, Vec2 lo, Vec2 hi, double z0, double z1) {
  Solid solid;
  solid.mesh = std::move(mesh);
  const double w = hi.x - lo.x, d = hi.y - lo.y;
  solid.volume = w * d * (z1 - z0);
  solid.area = [=](double z) { return z0 <= z && z < z1 ? w * d : 0.0; };
  solid.perimeter = [=](double z) { return z0 <= z && z < z1 ? 2 * (w + d) : 0.0; };
  solid.section = [=](double z) {
    return z0 <= z && z < z1 ? Region{{rectangle(lo.x, lo.y, hi.x, hi.y)}} : Region{};
  };
  return solid;
}

}  // namespace

Loop regular_polygon(int n, double circumradius, Vec2 centre, double phase) {
  Loop loop;
  loop.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * kPi * i / n;
    loop.push_back({centre.x + circumradius * std::cos(a), centre.y + circumradius * std::sin(a)});
  }
  return loop;
}

double regular_polygon_area(int n, double circumradius) {
  return 0.5 * n * circumradius * circumradius * std::sin(2 * kPi / n);
}

double regular_polygon_perimeter(int n, double circumradius) {
  return 2.0 * n * circumradius * std::sin(kPi / n);
}

Solid box(Vec3 min, Vec3 max) {
  MeshBuilder b;
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        b.vertex({i ? max.x : min.x, j ? max.y : min.y, k ? max.z : min.z});
      }
    }
  }
  // Vertex i + 2j + 4k; each pair of triangles is one face, counter-clockwise from outside.
  const std::array<std::array<std::uint32_t, 3>, 12> faces{{{0, 2, 3},
                                                           {0, 3, 1},
                                                           {4, 5, 7},
                                                           {4, 7, 6},
                                                           {0, 4, 6},
                                                           {0, 6, 2},
                                                           {1, 3, 7},
                                                           {1, 7, 5},
                                                           {0, 1, 5},
                                                           {0, 5, 4},
                                                           {2, 6, 7},
                                                           {2, 7, 3}}};
  for (const auto& f : faces) b.triangle(f[0], f[1], f[2]);
  return rectangle_prism_solid(std::move(b.mesh), {min.x, min.y}, {max.x, max.y}, min.z, max.z);
}

Solid cube(double side) { return box({0, 0, 0}, {side, side, side}); }

Solid revolve(const std::vector<Vec2>& profile, int n, Vec2 axis, double phase) {
  MeshBuilder b;
  const Loop unit = regular_polygon(n, 1.0, {0, 0}, phase);
  std::vector<std::vector<std::uint32_t>> rings(profile.size());
  for (std::size_t j = 0; j < profile.size(); ++j) {
    const double rho = profile[j].x, z = profile[j].y;
    if (rho == 0) {
      rings[j].push_back(b.vertex({axis.x, axis.y, z}));
      continue;
    }
    for (Vec2 u : unit) rings[j].push_back(b.vertex({axis.x + rho * u.x, axis.y + rho * u.y, z}));
  }
  for (std::size_t j = 0; j < profile.size(); ++j) {
    const auto& lo = rings[j];
    const auto& hi = rings[(j + 1) % profile.size()];
    for (std::size_t i = 0, m = static_cast<std::size_t>(n); i < m; ++i) {
      const std::size_t next = (i + 1) % m;
      if (lo.size() == 1 && hi.size() == 1) break;  // along the axis: not surface
      if (lo.size() == 1) {
        b.triangle(lo[0], hi[next], hi[i]);
      } else if (hi.size() == 1) {
        b.triangle(lo[i], lo[next], hi[0]);
      } else {
        b.triangle(lo[i], lo[next], hi[next]);
        b.triangle(lo[i], hi[next], hi[i]);
      }
    }
  }

  Solid solid;
  solid.mesh = std::move(b.mesh);
  const double k = regular_polygon_area(n, 1.0);
  double green = 0;  // closed integral of rho^2 dz over the profile = integral of 2 rho dA
  for (std::size_t j = 0; j < profile.size(); ++j) {
    const Vec2 a = profile[j], c = profile[(j + 1) % profile.size()];
    green += (c.y - a.y) * (a.x * a.x + a.x * c.x + c.x * c.x) / 3.0;
  }
  solid.volume = k * green;
  solid.area = [profile, k](double z) {
    double sum = 0;
    for (auto [inner, outer] : intervals_at(profile, z)) sum += outer * outer - inner * inner;
    return k * sum;
  };
  solid.perimeter = [profile, n](double z) {
    double sum = 0;
    for (auto [inner, outer] : intervals_at(profile, z)) {
      sum += regular_polygon_perimeter(n, outer) + regular_polygon_perimeter(n, inner);
    }
    return sum;
  };
  solid.section = [profile, n, axis, phase](double z) {
    Region region;
    for (auto [inner, outer] : intervals_at(profile, z)) {
      region.loops.push_back(regular_polygon(n, outer, axis, phase));
      if (inner > 0) region.loops.push_back(reversed(regular_polygon(n, inner, axis, phase)));
    }
    return region;
  };
  return solid;
}

Solid cylinder(double radius, double height, int n, Vec3 base) {
  const double z0 = base.z, z1 = base.z + height;
  return revolve({{0, z0}, {radius, z0}, {radius, z1}, {0, z1}}, n, {base.x, base.y});
}

Solid tube(double inner_radius, double outer_radius, double height, int n, Vec3 base) {
  const double z0 = base.z, z1 = base.z + height;
  return revolve({{inner_radius, z0}, {outer_radius, z0}, {outer_radius, z1}, {inner_radius, z1}},
                 n, {base.x, base.y});
}

Solid frustum(double r_bottom, double r_top, double height, int n, Vec3 base) {
  const double z0 = base.z, z1 = base.z + height;
  std::vector<Vec2> profile{{0, z0}};
  if (r_bottom > 0) profile.push_back({r_bottom, z0});
  if (r_top > 0) profile.push_back({r_top, z1});
  profile.push_back({0, z1});
  return revolve(profile, n, {base.x, base.y});
}

Solid cone(double radius, double height, int n, Vec3 base) {
  return frustum(radius, 0, height, n, base);
}

Solid sphere(double radius, int segments, int rings, Vec3 centre) {
  std::vector<Vec2> profile{{0, centre.z - radius}};
  for (int k = rings - 1; k >= 1; --k) {
    const double polar = kPi * k / rings;
    profile.push_back({radius * std::sin(polar), centre.z + radius * std::cos(polar)});
  }
  profile.push_back({0, centre.z + radius});
  return revolve(profile, segments, {centre.x, centre.y});
}

Solid torus(double major, double minor, int segments, int tube_segments, Vec3 centre) {
  std::vector<Vec2> profile;
  for (int j = 0; j < tube_segments; ++j) {
    const double a = 2 * kPi * j / tube_segments;
    profile.push_back({major + minor * std::cos(a), centre.z + minor * std::sin(a)});
  }
  return revolve(profile, segments, {centre.x, centre.y});
}

Solid bipyramid(double radius, int n, double z_bottom, double z_equator, double z_top, Vec2 axis) {
  return revolve({{0, z_bottom}, {radius, z_equator}, {0, z_top}}, n, axis);
}

Solid cube_with_hole(double side, const Loop& hole) {
  const double h = side / 2;
  const Vec2 lo{-h, -h}, hi{h, h};
  const FlatRing ring = flat_ring(lo, hi, hole);
  MeshBuilder b;
  const auto inner_bottom = add_loop(b, hole, 0), inner_top = add_loop(b, hole, side);
  const auto outer_bottom = add_loop(b, ring.outer, 0), outer_top = add_loop(b, ring.outer, side);
  emit_ring(b, ring, inner_bottom, outer_bottom, false);
  emit_ring(b, ring, inner_top, outer_top, true);
  emit_walls(b, outer_bottom, outer_top, true);
  emit_walls(b, inner_bottom, inner_top, false);

  Solid solid;
  solid.mesh = std::move(b.mesh);
  const double hole_area = geometry::signed_area(hole);
  const double hole_perimeter = geometry::perimeter(hole);
  solid.volume = (side * side - hole_area) * side;
  solid.area = [=](double z) { return 0 <= z && z < side ? side * side - hole_area : 0.0; };
  solid.perimeter = [=](double z) {
    return 0 <= z && z < side ? 4 * side + hole_perimeter : 0.0;
  };
  solid.section = [=](double z) {
    if (!(0 <= z && z < side)) return Region{};
    return Region{{rectangle(-h, -h, h, h), reversed(hole)}};
  };
  return solid;
}

Solid cube_with_square_hole(double side, double hole_side) {
  const double a = hole_side / 2;
  Solid solid = cube_with_hole(side, rectangle(-a, -a, a, a));
  // The square's closed form, not its shoelace.
  solid.volume = (side * side - hole_side * hole_side) * side;
  solid.area = [=](double z) {
    return 0 <= z && z < side ? side * side - hole_side * hole_side : 0.0;
  };
  solid.perimeter = [=](double z) { return 0 <= z && z < side ? 4 * (side + hole_side) : 0.0; };
  return solid;
}

Solid cube_with_round_hole(double side, double hole_radius, int n) {
  Solid solid = cube_with_hole(side, regular_polygon(n, hole_radius));
  const double hole_area = regular_polygon_area(n, hole_radius);
  const double hole_perimeter = regular_polygon_perimeter(n, hole_radius);
  solid.volume = (side * side - hole_area) * side;
  solid.area = [=](double z) { return 0 <= z && z < side ? side * side - hole_area : 0.0; };
  solid.perimeter = [=](double z) {
    return 0 <= z && z < side ? 4 * side + hole_perimeter : 0.0;
  };
  return solid;
}

Solid stepped_box(Vec2 lower_size, double lower_height, Vec2 upper_size, double upper_height) {
  const double z0 = 0, z1 = lower_height, z2 = lower_height + upper_height;
  const bool overhang = upper_size.x > lower_size.x;
  const Vec2 big = overhang ? upper_size : lower_size;
  const Vec2 small = overhang ? lower_size : upper_size;
  const Loop small_rect = rectangle(-small.x / 2, -small.y / 2, small.x / 2, small.y / 2);
  const FlatRing ring = flat_ring({-big.x / 2, -big.y / 2}, {big.x / 2, big.y / 2}, small_rect);

  MeshBuilder b;
  // The two boxes meet at z1; each has one more face away from the step ("far").
  const auto small_at_step = add_loop(b, small_rect, z1);
  const auto outer_at_step = add_loop(b, ring.outer, z1);
  const double far_z = overhang ? z2 : z0;
  const auto outer_far = add_loop(b, ring.outer, far_z);
  const double small_far_z = overhang ? z0 : z2;
  const auto small_far = add_loop(b, small_rect, small_far_z);

  emit_ring(b, ring, small_at_step, outer_at_step, /*up=*/!overhang);
  emit_cap(b, ring.outer, outer_far, far_z, /*up=*/overhang);
  if (overhang) {
    emit_walls(b, outer_at_step, outer_far, true);
    emit_walls(b, small_far, small_at_step, true);
    b.triangle(small_far[0], small_far[2], small_far[1]);  // bottom of the lower box, facing down
    b.triangle(small_far[0], small_far[3], small_far[2]);
  } else {
    emit_walls(b, outer_far, outer_at_step, true);
    emit_walls(b, small_at_step, small_far, true);
    b.triangle(small_far[0], small_far[1], small_far[2]);  // top of the upper box, facing up
    b.triangle(small_far[0], small_far[2], small_far[3]);
  }

  Solid solid;
  solid.mesh = std::move(b.mesh);
  const Vec2 ls = lower_size, us = upper_size;
  solid.volume = ls.x * ls.y * lower_height + us.x * us.y * upper_height;
  auto size_at = [=](double z) -> std::optional<Vec2> {
    if (z0 <= z && z < z1) return ls;
    if (z1 <= z && z < z2) return us;
    return std::nullopt;
  };
  solid.area = [=](double z) {
    const auto s = size_at(z);
    return s ? s->x * s->y : 0.0;
  };
  solid.perimeter = [=](double z) {
    const auto s = size_at(z);
    return s ? 2 * (s->x + s->y) : 0.0;
  };
  solid.section = [=](double z) {
    const auto s = size_at(z);
    if (!s) return Region{};
    return Region{{rectangle(-s->x / 2, -s->y / 2, s->x / 2, s->y / 2)}};
  };
  return solid;
}

Solid lying_prism(const std::vector<Vec2>& profile_yz, double x0, double x1) {
  MeshBuilder b;
  const std::size_t m = profile_yz.size();
  for (double x : {x0, x1}) {
    for (Vec2 p : profile_yz) b.vertex({x, p.x, p.y});
  }
  const auto id = [](std::size_t i) { return static_cast<std::uint32_t>(i); };
  for (const auto& t : ear_clipping(profile_yz)) {
    b.triangle(id(m + t[0]), id(m + t[1]), id(m + t[2]));  // end at x1, normal +x
    b.triangle(id(t[0]), id(t[2]), id(t[1]));              // end at x0, normal -x
  }
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t k = (j + 1) % m;
    b.wall(id(j), id(k), id(m + k), id(m + j));
  }

  Solid solid;
  solid.mesh = std::move(b.mesh);
  const double length = x1 - x0;
  solid.volume = length * geometry::signed_area(profile_yz);
  solid.area = [=](double z) {
    double sum = 0;
    for (auto [lo, hi] : intervals_at(profile_yz, z)) sum += length * (hi - lo);
    return sum;
  };
  solid.perimeter = [=](double z) {
    double sum = 0;
    for (auto [lo, hi] : intervals_at(profile_yz, z)) sum += 2 * (length + hi - lo);
    return sum;
  };
  solid.section = [=](double z) {
    Region region;
    for (auto [lo, hi] : intervals_at(profile_yz, z)) {
      region.loops.push_back(rectangle(x0, lo, x1, hi));
    }
    return region;
  };
  return solid;
}

Solid diamond_prism(double length, double half_width, double z_mid, double half_height) {
  return lying_prism({{0, z_mid - half_height},
                      {half_width, z_mid},
                      {0, z_mid + half_height},
                      {-half_width, z_mid}},
                     -length / 2, length / 2);
}

Solid combine(Solid a, Solid b) {
  Solid solid;
  solid.mesh = std::move(a.mesh);
  const auto offset = static_cast<std::uint32_t>(solid.mesh.vertices.size());
  solid.mesh.vertices.insert(solid.mesh.vertices.end(), b.mesh.vertices.begin(),
                             b.mesh.vertices.end());
  for (auto f : b.mesh.faces) {
    solid.mesh.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  }
  solid.volume = a.volume + b.volume;
  solid.area = [fa = a.area, fb = b.area](double z) { return fa(z) + fb(z); };
  solid.perimeter = [fa = a.perimeter, fb = b.perimeter](double z) { return fa(z) + fb(z); };
  solid.section = [fa = a.section, fb = b.section](double z) {
    Region region = fa(z);
    for (auto& loop : fb(z).loops) region.loops.push_back(std::move(loop));
    return region;
  };
  return solid;
}

}  // namespace solids
