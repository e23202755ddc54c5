// The medial-axis contour's one CGAL translation unit (triangulation.h).
#include "geometry/contour/ma/triangulation.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace geometry::ma {

namespace {

// Which sample a vertex is (a vertex CGAL made where two constraints cross has none), and its
// number in the plain copy.
struct VertexInfo {
  std::uint32_t sample = SampleTriangulation::kNoSample;
  std::uint32_t id = 0;
};

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

// Epick, with its in-circle and orientation tests first tried against one error bound each for
// the whole island. Epick's own filters (Static_filters/Side_of_oriented_circle_2.h and
// Orientation_2.h) evaluate the determinants below and trust their signs where |det| >
// 8.8878565762001373e-15 * maxx * maxy * maxy^2 (in-circle), 8.8872057372592798e-16 * maxx *
// maxy (orientation), maxx and maxy the largest x and y differences of the points (maxx the
// lesser), else decide exactly. Here those differences are bounded once per island, by the
// extent of the box of its samples: every point of the triangulation lies in that box (CGAL's
// points where two constraints cross lie on both, up to rounding far below the margin of 2
// taken), so each eps is at least Epick's bound for every test; where |det| <= eps, Epick's
// test decides. The signs are exact either way, so the triangulation is the same, without the
// absolute values and their maxima per test (measured on bench_ma --quick: 3.9 million
// in-circle tests, 144 M instructions fewer; 3.3 million orientation tests in point location,
// 84 M fewer; Epick decides 0.4% and 1.4% of them). Epick's test is a call of its own, so
// that the inlined test stays short.
class Kernel : public Epick {
 public:
  class Side_of_oriented_circle_2 {
   public:
    explicit Side_of_oriented_circle_2(double eps) : eps_(eps) {}
    CGAL::Oriented_side operator()(const Point_2& p, const Point_2& q, const Point_2& r,
                                   const Point_2& t) const {
      const double px = p.x(), py = p.y(), qx = q.x(), qy = q.y();
      const double rx = r.x(), ry = r.y(), tx = t.x(), ty = t.y();
      // Evaluated as Epick's filter evaluates it (its bound is for this evaluation).
      const double qpx = qx - px, qpy = qy - py, rpx = rx - px, rpy = ry - py;
      const double tpx = tx - px, tpy = ty - py, tqx = tx - qx, tqy = ty - qy;
      const double rqx = rx - qx, rqy = ry - qy;
      const double det = CGAL::determinant(qpx * tpy - qpy * tpx, tpx * tqx + tpy * tqy,
                                           qpx * rpy - qpy * rpx, rpx * rqx + rpy * rqy);
      if (det > eps_) return CGAL::ON_POSITIVE_SIDE;
      if (det < -eps_) return CGAL::ON_NEGATIVE_SIDE;
      return epick(p, q, r, t);
    }
    [[gnu::noinline]] static CGAL::Oriented_side epick(const Point_2& p, const Point_2& q,
                                                       const Point_2& r, const Point_2& t) {
      return Epick().side_of_oriented_circle_2_object()(p, q, r, t);
    }

   private:
    double eps_;
  };

  class Orientation_2 : public Epick::Orientation_2 {
   public:
    using Epick::Orientation_2::operator();
    explicit Orientation_2(double eps) : eps_(eps) {}
    CGAL::Orientation operator()(const Epick::Point_2& p, const Epick::Point_2& q,
                                 const Epick::Point_2& r) const {
      // Evaluated as Epick's filter evaluates it.
      const double pqx = q.x() - p.x(), pqy = q.y() - p.y();
      const double prx = r.x() - p.x(), pry = r.y() - p.y();
      const double det = CGAL::determinant(pqx, pqy, prx, pry);
      if (det > eps_) return CGAL::POSITIVE;
      if (det < -eps_) return CGAL::NEGATIVE;
      return epick(p, q, r);
    }
    [[gnu::noinline]] static CGAL::Orientation epick(const Epick::Point_2& p,
                                                     const Epick::Point_2& q,
                                                     const Epick::Point_2& r) {
      return Epick().orientation_2_object()(p, q, r);
    }

   private:
    double eps_;
  };

  // Without a box every test is Epick's.
  Kernel() = default;
  // `box`: holds every sample. b = twice its extent bounds maxx and maxy with room for
  // rounding: b^4 >= 16 maxx maxy^3 and b^2 >= 4 maxx maxy, so each eps's own rounding is far
  // inside. The eps stay infinite (Epick decides every test) where the box is so small, next
  // to its distance from the origin, that rounding could leave it, or where underflow or
  // overflow would void Epick's bounds (its own guards are 1e-73 and 1e76 for in-circle,
  // 1e-146 and 1e153 for orientation).
  explicit Kernel(const Box2& box) {
    if (box.empty()) return;
    const double b = 2 * std::max(box.hi.x - box.lo.x, box.hi.y - box.lo.y);
    const double far = std::max({std::abs(box.lo.x), std::abs(box.lo.y), std::abs(box.hi.x),
                                 std::abs(box.hi.y)});
    if (b >= 1e-30 && b <= 1e30 && b >= 1e-9 * far) {
      circle_eps_ = 8.8878565762001373e-15 * b * b * (b * b);
      orientation_eps_ = 8.8872057372592798e-16 * b * b;
    }
  }
  Side_of_oriented_circle_2 side_of_oriented_circle_2_object() const {
    return Side_of_oriented_circle_2(circle_eps_);
  }
  Orientation_2 orientation_2_object() const { return Orientation_2(orientation_eps_); }

 private:
  double circle_eps_ = std::numeric_limits<double>::infinity();
  double orientation_eps_ = std::numeric_limits<double>::infinity();
};

using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<std::uint32_t, Kernel>>;  // its number
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Delaunay = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
// The same triangulation without constraints: points go in here (a third faster than into
// Delaunay, whose flips keep constraint flags up to date), then its faces are handed over.
using PlainDelaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;
using Face = Delaunay::Face_handle;
using Vertex = Delaunay::Vertex_handle;

// The samples' Delaunay triangulation, built as a plain one and its data structure moved into
// the constrained one (with no constraint yet, the two are the same: both break ties by the
// same symbolic perturbation; handles stay valid). Inserted in spatial (Hilbert) order, each
// located from a face of its neighbour along the loop where that is in already (at most the
// spacing away, where the previous sample in Hilbert order may be across the strip or in
// another round of the sort: on bench_ma --quick the location walks cost 150 M instructions
// where from the previous sample they cost 193 M), else from the previous sample. In loop order every new sample on a circle conflicts with much of what is built
// (measured: 40 000 points on two circles 6.9 s in loop order, 0.03 s in Hilbert order; with
// constraints and fairing 0.06 s, 200 000 points 0.3 s).
void insert_samples(std::span<const Sample> samples, Delaunay& triangulation,
                    std::vector<Vertex>& vertex_of) {
  std::vector<Kernel::Point_2> points;
  points.reserve(samples.size());
  Box2 box;
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    const Vec2 p = samples[i].at;
    points.emplace_back(p.x, p.y);
    box.add(p);
  }
  std::vector<std::size_t> order(samples.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  using SortTraits = CGAL::Spatial_sort_traits_adapter_2<
      Epick, CGAL::Pointer_property_map<Kernel::Point_2>::const_type>;
  const std::vector<Kernel::Point_2>& sorted_points = points;
  CGAL::spatial_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(sorted_points)),
                     CGAL::Hilbert_sort_middle_policy());
  vertex_of.assign(samples.size(), Vertex());
  PlainDelaunay plain{Kernel(box)};  // its traits go to `triangulation` with the swap
  Face hint;
  for (std::size_t i : order) {
    // Where no neighbour is in, the previous sample's face.
    if (i > 0 && samples[i - 1].loop == samples[i].loop && vertex_of[i - 1] != Vertex()) {
      hint = vertex_of[i - 1]->face();
    } else if (i + 1 < samples.size() && samples[i + 1].loop == samples[i].loop &&
               vertex_of[i + 1] != Vertex()) {
      hint = vertex_of[i + 1]->face();
    }
    const Vertex v = plain.insert(points[i], hint);
    if (i < v->info().sample) v->info().sample = static_cast<std::uint32_t>(i);
    vertex_of[i] = v;
    hint = v->face();
  }
  static_cast<PlainDelaunay::Triangulation&>(plain).swap(triangulation);
}

// The loops' edges as constraints: where the strip is thinner than the sample spacing a
// plain Delaunay edge may jump from one side of the strip across the other loop and split
// that loop's territory; constrained, every triangle with corners on two loops lies inside
// the strip. Where the strip is wider than the spacing the boundary edges are Delaunay edges
// anyway and nothing changes.
// Measured and not taken: marking the edges in the plain copy instead, where every loop edge is
// a Delaunay edge already, without is_edge and the constrained triangulation. On the bunny
// (bench_ma --quick) 3,787 loop edges are missing, in most islands, so most fell back to
// this and paid the copy twice: triangulate_samples 1,136 M -> 1,264 M instructions.
void constrain_loops(std::span<const Sample> samples, const std::vector<Vertex>& vertex_of,
                     Delaunay& triangulation) {
  std::vector<std::uint32_t> first_of_loop;
  for (std::uint32_t i = samples.size(); i-- > 0;) {
    if (samples[i].loop >= first_of_loop.size()) first_of_loop.resize(samples[i].loop + 1, 0);
    first_of_loop[samples[i].loop] = i;
  }
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    const std::uint32_t next = i + 1 < samples.size() && samples[i + 1].loop == samples[i].loop
                                   ? i + 1
                                   : first_of_loop[samples[i].loop];
    const Vertex a = vertex_of[i], b = vertex_of[next];
    if (a == b) continue;
    // Nearly always the edge is there already: mark it (what insert_constraint does then,
    // after a search for vertices on the segment and a std::stack per call).
    Face f;
    int k = 0;
    if (triangulation.dimension() == 2 && triangulation.is_edge(a, b, f, k)) {
      f->set_constraint(k, true);
      f->neighbor(k)->set_constraint(triangulation.mirror_index(f, k), true);
    } else {
      triangulation.insert_constraint(a, b);
    }
  }
}

// The plain copy: vertices and faces numbered in CGAL's order.
SampleTriangulation plain_copy(const Delaunay& triangulation) {
  SampleTriangulation copy;
  if (triangulation.dimension() != 2) return copy;
  std::uint32_t id = 0;
  copy.sample_of.reserve(triangulation.number_of_vertices() + 1);
  copy.point.reserve(triangulation.number_of_vertices() + 1);
  for (Vertex v : triangulation.all_vertex_handles()) {
    v->info().id = id++;
    copy.sample_of.push_back(v->info().sample);
    const auto& p = v->point();
    copy.point.push_back(triangulation.is_infinite(v) ? Vec2{} : Vec2{p.x(), p.y()});
  }
  id = 0;
  for (Face f : triangulation.all_face_handles()) f->info() = id++;
  copy.faces.reserve(id);
  for (Face f : triangulation.all_face_handles()) {
    SampleTriangulation::Face face;
    for (int k = 0; k < 3; ++k) {
      face.vertex[k] = f->vertex(k)->info().id;
      face.neighbour[k] = f->neighbor(k)->info();
      if (f->is_constrained(k)) face.constrained |= static_cast<std::uint8_t>(1 << k);
    }
    face.infinite = triangulation.is_infinite(f);
    copy.faces.push_back(face);
  }
  copy.infinite_face = triangulation.infinite_face()->info();
  return copy;
}

}  // namespace

SampleTriangulation triangulate_samples(std::span<const Sample> samples) {
  Delaunay triangulation;
  std::vector<Vertex> vertex_of;
  insert_samples(samples, triangulation, vertex_of);
  constrain_loops(samples, vertex_of, triangulation);
  return plain_copy(triangulation);
}

}  // namespace geometry::ma
