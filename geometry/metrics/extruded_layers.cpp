#include "geometry/metrics/extruded_layers.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <list>
#include <map>
#include <utility>

namespace geometry {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, Kernel>;
// Face info: nesting depth (how many loops enclose the face); odd = inside the region.
using FaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<int, Kernel>>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Exact_predicates_tag: constraints that cross (which a valid region never has, but touching
// loops come close) are split rather than refused.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

// CGAL's polygon-with-holes example: flood the faces from the infinite one, the depth growing
// by one across every constrained edge.
void mark_depths(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::list<Cdt::Edge> border;
  const auto flood = [&](Cdt::Face_handle start, int depth) {
    if (start->info() != -1) return;
    std::list<Cdt::Face_handle> queue{start};
    while (!queue.empty()) {
      const Cdt::Face_handle f = queue.front();
      queue.pop_front();
      if (f->info() != -1) continue;
      f->info() = depth;
      for (int i = 0; i < 3; ++i) {
        const Cdt::Edge e(f, i);
        const Cdt::Face_handle n = f->neighbor(i);
        if (n->info() != -1) continue;
        if (cdt.is_constrained(e)) border.push_back(e);
        else queue.push_back(n);
      }
    }
  };
  flood(cdt.infinite_face(), 0);
  while (!border.empty()) {
    const Cdt::Edge e = border.front();
    border.pop_front();
    const Cdt::Face_handle n = e.first->neighbor(e.second);
    if (n->info() == -1) flood(n, e.first->info() + 1);
  }
}

}  // namespace

RegionTriangulation triangulate_region(const Region& region) {
  RegionTriangulation result;
  Cdt cdt;
  std::map<std::pair<double, double>, std::uint32_t> index;
  const auto vertex = [&](Vec2 p) {
    const auto [it, fresh] = index.emplace(std::pair{p.x, p.y}, 0);
    if (fresh) {
      it->second = static_cast<std::uint32_t>(result.points.size());
      result.points.push_back(p);
    }
    return it->second;
  };
  for (const Loop& loop : region.loops) {
    if (loop.size() < 3) continue;
    std::vector<Cdt::Vertex_handle> handles;
    for (Vec2 p : loop) {
      const Cdt::Vertex_handle v = cdt.insert(Kernel::Point_2(p.x, p.y));
      v->info() = vertex(p);
      handles.push_back(v);
    }
    for (std::size_t i = 0; i < handles.size(); ++i) {
      const auto a = handles[i], b = handles[(i + 1) % handles.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  }
  // Where constraints crossed, CGAL made new vertices: give them indices.
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    const Vec2 p{v->point().x(), v->point().y()};
    if (index.find({p.x, p.y}) == index.end()) v->info() = vertex(p);
  }
  mark_depths(cdt);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 != 1) continue;
    result.triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return result;
}

Mesh extruded_layers(std::span<const Layer> layers, std::span<const Region> regions) {
  Mesh mesh;
  const std::size_t count = std::min(layers.size(), regions.size());
  for (std::size_t i = 0; i < count; ++i) {
    const Layer layer = layers[i];
    if (!(layer.z_hi > layer.z_lo) || regions[i].loops.empty()) continue;
    const RegionTriangulation faces = triangulate_region(regions[i]);
    if (faces.triangles.empty()) continue;
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    const auto n = static_cast<std::uint32_t>(faces.points.size());
    for (Vec2 p : faces.points) mesh.vertices.push_back({p.x, p.y, layer.z_lo});
    for (Vec2 p : faces.points) mesh.vertices.push_back({p.x, p.y, layer.z_hi});
    for (const auto& t : faces.triangles) {
      mesh.faces.push_back({base + n + t[0], base + n + t[1], base + n + t[2]});  // top, up
      mesh.faces.push_back({base + t[0], base + t[2], base + t[1]});              // bottom, down
    }
    // Walls: one quad per loop edge, outward to the right of the edge (loops run with the
    // region on their left). Vertices are shared with the caps, so every prism is closed.
    std::map<std::pair<double, double>, std::uint32_t> index;
    for (std::uint32_t k = 0; k < n; ++k) index[{faces.points[k].x, faces.points[k].y}] = k;
    for (const Loop& loop : regions[i].loops) {
      for (std::size_t j = 0, m = loop.size(); j < m && m >= 3; ++j) {
        const Vec2 a = loop[j], b = loop[(j + 1) % m];
        if (a == b) continue;
        const std::uint32_t ia = index.at({a.x, a.y}), ib = index.at({b.x, b.y});
        mesh.faces.push_back({base + ia, base + ib, base + n + ib});
        mesh.faces.push_back({base + ia, base + n + ib, base + n + ia});
      }
    }
  }
  return mesh;
}

}  // namespace geometry
