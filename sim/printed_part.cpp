// The only sim/ file that includes CGAL: caps are a constrained Delaunay triangulation of the
// layer's loops, keeping the faces at odd nesting depth (inside an outer loop, outside its
// holes), as in CGAL's "polygon with holes" triangulation example.
#include "sim/printed_part.h"

#include <cstdint>
#include <list>
#include <map>
#include <utility>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include "geometry/core/polygon.h"

namespace sim {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int nesting = -1;
};
using FaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>>;
using Tds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<Kernel>, FaceBase>;
// Exact_predicates_tag: constraints that cross (never from a Clipper union, but total anyway)
// get a vertex at the crossing instead of an exception.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

void flood(Cdt& cdt, Cdt::Face_handle start, int nesting, std::list<Cdt::Edge>& border) {
  std::list<Cdt::Face_handle> queue{start};
  while (!queue.empty()) {
    const Cdt::Face_handle face = queue.front();
    queue.pop_front();
    if (face->info().nesting != -1) continue;
    face->info().nesting = nesting;
    for (int i = 0; i < 3; ++i) {
      const Cdt::Face_handle next = face->neighbor(i);
      if (next->info().nesting != -1) continue;
      if (cdt.is_constrained(Cdt::Edge(face, i))) {
        border.emplace_back(face, i);
      } else {
        queue.push_back(next);
      }
    }
  }
}

void mark_nesting(Cdt& cdt) {
  std::list<Cdt::Edge> border;
  flood(cdt, cdt.infinite_face(), 0, border);
  while (!border.empty()) {
    const Cdt::Edge edge = border.front();
    border.pop_front();
    const Cdt::Face_handle next = edge.first->neighbor(edge.second);
    if (next->info().nesting == -1) flood(cdt, next, edge.first->info().nesting + 1, border);
  }
}

// Vertices by position, so walls and caps share them and each layer's shell is closed.
class VertexIndex {
 public:
  VertexIndex(geometry::Mesh& mesh, double z) : mesh_(mesh), z_(z) {}
  std::uint32_t operator()(double x, double y) {
    const auto [at, added] = index_.try_emplace({x, y}, static_cast<std::uint32_t>(mesh_.vertices.size()));
    if (added) mesh_.vertices.push_back({x, y, z_});
    return at->second;
  }

 private:
  geometry::Mesh& mesh_;
  double z_;
  std::map<std::pair<double, double>, std::uint32_t> index_;
};

}  // namespace

void append_prism(const geometry::Region& region, double z_bottom, double z_top,
                  geometry::Mesh& mesh) {
  if (!(z_top > z_bottom)) return;
  Cdt cdt;
  for (const geometry::Loop& loop : region.loops) {
    if (loop.size() < 3) continue;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const geometry::Vec2 a = loop[i], b = loop[(i + 1) % loop.size()];
      if (a == b) continue;
      cdt.insert_constraint(Kernel::Point_2(a.x, a.y), Kernel::Point_2(b.x, b.y));
    }
  }
  if (cdt.number_of_faces() == 0) return;
  mark_nesting(cdt);

  VertexIndex bottom(mesh, z_bottom), top(mesh, z_top);
  for (auto face = cdt.finite_faces_begin(); face != cdt.finite_faces_end(); ++face) {
    if (face->info().nesting % 2 != 1) continue;
    std::array<std::uint32_t, 3> up{}, down{};
    for (int i = 0; i < 3; ++i) {
      const Kernel::Point_2& p = face->vertex(i)->point();
      up[static_cast<std::size_t>(i)] = top(p.x(), p.y());
      down[static_cast<std::size_t>(i)] = bottom(p.x(), p.y());
    }
    mesh.faces.push_back(up);                          // CCW from above: normal +z
    mesh.faces.push_back({down[0], down[2], down[1]});  // reversed: normal -z
  }
  // Walls along every constrained edge, facing away from the inside (the face at odd depth).
  for (auto edge = cdt.finite_edges_begin(); edge != cdt.finite_edges_end(); ++edge) {
    if (!cdt.is_constrained(*edge)) continue;
    Cdt::Face_handle face = edge->first;
    int i = edge->second;
    if (face->info().nesting % 2 != 1) {
      const Cdt::Face_handle other = face->neighbor(i);
      if (other->info().nesting % 2 != 1) continue;  // a constraint with no inside next to it
      i = cdt.mirror_index(face, i);
      face = other;
    }
    // Seen from inside face, the edge runs ccw from vertex (i+1) to vertex (i+2).
    const Kernel::Point_2& a = face->vertex(Cdt::ccw(i))->point();
    const Kernel::Point_2& b = face->vertex(Cdt::cw(i))->point();
    const std::uint32_t a0 = bottom(a.x(), a.y()), b0 = bottom(b.x(), b.y());
    const std::uint32_t a1 = top(a.x(), a.y()), b1 = top(b.x(), b.y());
    mesh.faces.push_back({a0, b0, b1});
    mesh.faces.push_back({a0, b1, a1});
  }
}

geometry::Mesh printed_part(const DepositionRecord& record, double filament_diameter) {
  geometry::Mesh mesh;
  for (const LayerBeads& layer : bead_polygons(record, filament_diameter)) {
    if (layer.beads.empty()) continue;
    append_prism(printed_region(layer), layer.z - layer.height, layer.z, mesh);
  }
  return mesh;
}

}  // namespace sim
