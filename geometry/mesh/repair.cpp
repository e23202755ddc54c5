// Mesh repair with CGAL Polygon_mesh_processing; see repair.h for the steps and the contract.
#include "geometry/mesh/repair.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/core.h>

#include "geometry/core/error.h"
#include "geometry/core/number_table.h"
#include "geometry/mesh/corner_key.h"

namespace geometry {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Polygon = std::array<std::size_t, 3>;

struct EdgeHash {
  std::size_t operator()(std::uint64_t k) const {
    const std::uint64_t h = k * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(h ^ (h >> 32));
  }
};

// A facet's corners in increasing order: the same for every copy of the facet.
CornerKey facet_key(const Polygon& p) {
  Polygon sorted = p;
  std::sort(sorted.begin(), sorted.end());
  return {sorted[0], sorted[1], sorted[2]};
}

Point to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

std::uint64_t edge_key(std::size_t a, std::size_t b) {
  if (a > b) std::swap(a, b);
  return static_cast<std::uint64_t>(a) << 32 | static_cast<std::uint64_t>(b);
}

// Records which polygons CGAL reverses while it orients the soup.
struct OrientationVisitor : PMP::Default_orientation_visitor {
  std::vector<char>* reversed = nullptr;
  void polygon_orientation_reversed(std::size_t id) { (*reversed)[id] ^= 1; }
};

// Area enclosed by a closed polygon in space: half the length of its vector area. A lower
// bound of the area of any surface that fills it.
double vector_area(const std::vector<Point>& loop) {
  Kernel::Vector_3 sum(0, 0, 0);
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point& p = loop[i];
    const Point& q = loop[(i + 1) % loop.size()];
    sum = sum + CGAL::cross_product(p - CGAL::ORIGIN, q - CGAL::ORIGIN);
  }
  return 0.5 * std::sqrt(sum.squared_length());
}

double face_area(const SurfaceMesh& mesh, SurfaceMesh::Face_index f) {
  const auto h = mesh.halfedge(f);
  const Point& a = mesh.point(mesh.source(h));
  const Point& b = mesh.point(mesh.target(h));
  const Point& c = mesh.point(mesh.target(mesh.next(h)));
  return 0.5 * std::sqrt(CGAL::cross_product(b - a, c - a).squared_length());
}

// Signed volume of a possibly open surface (PMP::volume wants it closed).
double open_signed_volume(const SurfaceMesh& mesh) {
  double six_volume = 0;
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    const auto a = mesh.point(mesh.source(h)) - CGAL::ORIGIN;
    const auto b = mesh.point(mesh.target(h)) - CGAL::ORIGIN;
    const auto c = mesh.point(mesh.target(mesh.next(h))) - CGAL::ORIGIN;
    six_volume += a * CGAL::cross_product(b, c);
  }
  return six_volume / 6;
}

std::size_t count_border_edges(const SurfaceMesh& mesh) {
  std::size_t n = 0;
  for (auto e : mesh.edges()) n += mesh.is_border(e) ? 1 : 0;
  return n;
}

}  // namespace

bool RepairReport::anything_repaired() const {
  return degenerate_faces_dropped || duplicate_faces_dropped || non_manifold_vertices_split ||
         faces_reoriented || holes_filled;
}

std::string RepairReport::summary() const {
  std::vector<std::string> parts;
  if (degenerate_faces_dropped) {
    parts.push_back(fmt::format("{} degenerate facets dropped", degenerate_faces_dropped));
  }
  if (duplicate_faces_dropped) {
    parts.push_back(fmt::format("{} duplicate facets dropped", duplicate_faces_dropped));
  }
  if (non_manifold_vertices_split) {
    parts.push_back(
        fmt::format("{} non-manifold vertices split", non_manifold_vertices_split));
  }
  if (faces_reoriented) parts.push_back(fmt::format("{} facets reoriented", faces_reoriented));
  if (holes_filled) {
    parts.push_back(fmt::format("{} hole{} filled (+{} faces)", holes_filled,
                                holes_filled == 1 ? "" : "s", faces_added));
  }
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

namespace {

// 1. Corners with identical coordinates merged: the facets as corner numbers into `points`.
std::vector<Polygon> merged_corners(const std::vector<Triangle>& facets, std::vector<Vec3>& points,
                                    RepairReport& report) {
  std::vector<Polygon> polygons;
  polygons.reserve(facets.size());
  // Closed meshes have about F/2 vertices.
  NumberTable<CornerKey, CornerHash> index(facets.size() * 3 / 5 + 16);
  const auto key_of_point = [&points](std::uint32_t n) { return corner_key(points[n]); };
  for (const Triangle& t : facets) {
    Polygon p;
    for (int i = 0; i < 3; ++i) {
      const auto next = static_cast<std::uint32_t>(points.size());
      p[i] = index.find_or_insert(corner_key(t.v[i]), next, key_of_point);
      if (p[i] == next) points.push_back(t.v[i]);
    }
    polygons.push_back(p);
  }
  report.vertices_merged = 3 * facets.size() - points.size();
  return polygons;
}

// 2. Degenerate facets (repeated or collinear corners) and second copies of a facet dropped.
void drop_degenerate_and_duplicate(const std::vector<Vec3>& points, std::vector<Polygon>& polygons,
                                   RepairReport& report) {
  std::vector<Polygon> kept;
  kept.reserve(polygons.size());
  NumberTable<CornerKey, CornerHash> seen(polygons.size());  // of kept facets
  const auto key_of_kept = [&kept](std::uint32_t n) { return facet_key(kept[n]); };
  for (const Polygon& p : polygons) {
    if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2] ||
        CGAL::collinear(to_point(points[p[0]]), to_point(points[p[1]]),
                        to_point(points[p[2]]))) {
      ++report.degenerate_faces_dropped;
      continue;
    }
    const auto next = static_cast<std::uint32_t>(kept.size());
    if (seen.find_or_insert(facet_key(p), next, key_of_kept) != next) {
      ++report.duplicate_faces_dropped;
      continue;
    }
    kept.push_back(p);
  }
  polygons = std::move(kept);
}

// Corners that only degenerate facets used are not part of the surface: renumbered away.
void drop_unused_corners(std::vector<Vec3>& points, std::vector<Polygon>& polygons) {
  std::vector<std::size_t> renumber(points.size(), SIZE_MAX);
  std::vector<Vec3> used;
  used.reserve(points.size());
  for (Polygon& p : polygons) {
    for (std::size_t& v : p) {
      if (renumber[v] == SIZE_MAX) {
        renumber[v] = used.size();
        used.push_back(points[v]);
      }
      v = renumber[v];
    }
  }
  points = std::move(used);
}

// Open and non-manifold edges of the file's surface, before any topological repair, into the
// report; returns whether the soup already is a consistently oriented manifold surface, which
// most files are (a check ten times faster than CGAL's is_polygon_soup_a_polygon_mesh on the
// bunny).
// Union-find over item numbers: `parent[i] == i` at a set's root; each lookup halves its path.
std::vector<std::uint32_t> singletons(std::size_t count) {
  std::vector<std::uint32_t> parent(count);
  for (std::size_t i = 0; i < count; ++i) parent[i] = static_cast<std::uint32_t>(i);
  return parent;
}
std::uint32_t root(std::vector<std::uint32_t>& parent, std::size_t item) {
  auto i = static_cast<std::uint32_t>(item);
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

bool count_edges_and_check_manifold(std::size_t point_count, const std::vector<Polygon>& polygons,
                                    RepairReport& report, std::size_t& pieces) {
  bool oriented_manifold = true;
  // Facets joined across the edges they share: the surface's connected pieces.
  std::vector<std::uint32_t> piece = singletons(polygons.size());
  // Per undirected edge: how many facets use it, and the corner slot (3 * facet + corner)
  // of the first facet's start of that edge, to join corners of facets across the edge.
  struct EdgeUse {
    std::uint64_t key = 0;
    std::uint32_t count = 0;
    std::uint32_t first_slot = 0;
    bool first_forward = false;
  };
  std::vector<EdgeUse> uses;  // in order of first use
  uses.reserve(polygons.size() * 3 / 2 + 16);
  NumberTable<std::uint64_t, EdgeHash> edge_number(uses.capacity());
  const auto key_of_edge = [&uses](std::uint32_t n) { return uses[n].key; };
  // Corners around a vertex that are joined across shared edges form one fan; a vertex
  // with two fans is non-manifold (two surfaces touching in a point).
  // Corner slots fit the mesh's 32 bits.
  std::vector<std::uint32_t> fan = singletons(polygons.size() * 3);
  const auto join = [&](std::size_t a, std::size_t b) { fan[root(fan, a)] = root(fan, b); };
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const Polygon& p = polygons[f];
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t a = p[c], b = p[(c + 1) % 3];
      const std::uint64_t key = edge_key(a, b);
      const auto next = static_cast<std::uint32_t>(uses.size());
      const std::uint32_t number = edge_number.find_or_insert(key, next, key_of_edge);
      if (number == next) uses.push_back({key});
      EdgeUse& use = uses[number];
      const bool forward = a < b;
      if (++use.count == 1) {
        use.first_slot = static_cast<std::uint32_t>(3 * f + c);
        use.first_forward = forward;
        continue;
      }
      if (use.count > 2 || use.first_forward == forward) {
        oriented_manifold = false;  // three facets on an edge, or two facing each other
        continue;
      }
      // The other facet runs b -> a: its corner at b starts the edge, at a ends it.
      const std::size_t other = use.first_slot / 3, other_c = use.first_slot % 3;
      join(3 * f + c, 3 * other + (other_c + 1) % 3);         // corners at a
      join(3 * f + (c + 1) % 3, 3 * other + other_c);         // corners at b
      piece[root(piece, f)] = root(piece, other);
    }
  }
  pieces = 0;
  for (std::size_t f = 0; f < piece.size(); ++f) pieces += piece[f] == f;
  for (const EdgeUse& use : uses) {
    if (use.count == 1) ++report.open_edges_before;
    if (use.count > 2) ++report.non_manifold_edges;
  }
  if (oriented_manifold) {
    std::vector<std::uint32_t> fan_of_vertex(point_count, UINT32_MAX);
    for (std::size_t slot = 0; slot < fan.size() && oriented_manifold; ++slot) {
      const std::size_t v = polygons[slot / 3][slot % 3];
      const std::uint32_t its_fan = root(fan, slot);
      if (fan_of_vertex[v] == UINT32_MAX) {
        fan_of_vertex[v] = its_fan;
      } else if (fan_of_vertex[v] != its_fan) {
        oriented_manifold = false;
      }
    }
  }
  return oriented_manifold;
}

// 3. Oriented consistently, non-manifold vertices split (new points appended): which facets
// CGAL reversed.
std::vector<char> orient_and_split(std::vector<Vec3>& points, std::vector<Polygon>& polygons,
                                   RepairReport& report) {
  std::vector<char> reversed(polygons.size(), 0);
  std::vector<Point> soup_points;
  soup_points.reserve(points.size());
  for (const Vec3& v : points) soup_points.push_back(to_point(v));
  OrientationVisitor visitor;
  visitor.reversed = &reversed;
  PMP::orient_polygon_soup(soup_points, polygons, CGAL::parameters::visitor(visitor));
  report.non_manifold_vertices_split = soup_points.size() - points.size();
  for (std::size_t i = points.size(); i < soup_points.size(); ++i) {
    const Point& p = soup_points[i];
    points.push_back({p.x(), p.y(), p.z()});
  }
  return reversed;
}

// The oriented soup as a Surface_mesh; `face_polygon` gets each face's polygon.
void build_surface(const std::vector<Vec3>& points, const std::vector<Polygon>& polygons,
                   SurfaceMesh& mesh, std::vector<std::size_t>& face_polygon,
                   RepairReport& report) {
  // A closed surface has 3F/2 edges; hole filling adds a little on top.
  mesh.reserve(points.size(), polygons.size() * 3 / 2 + 16, polygons.size());
  for (const Vec3& v : points) mesh.add_vertex(to_point(v));
  face_polygon.reserve(polygons.size());
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const Polygon& p = polygons[i];
    const auto f = mesh.add_face(SurfaceMesh::Vertex_index(static_cast<std::uint32_t>(p[0])),
                                 SurfaceMesh::Vertex_index(static_cast<std::uint32_t>(p[1])),
                                 SurfaceMesh::Vertex_index(static_cast<std::uint32_t>(p[2])));
    // The oriented soup is a polygon mesh, so every face fits; a face that still does not
    // (a CGAL corner case) is dropped and counted as degenerate rather than trusted.
    if (f == SurfaceMesh::null_face()) {
      ++report.degenerate_faces_dropped;
      continue;
    }
    face_polygon.push_back(i);
  }
}

// 4. Holes filled with flat patches, unless filling would invent too much of the surface.
void fill_holes(SurfaceMesh& mesh, std::size_t original_faces, const RepairOptions& options,
                RepairReport& report) {
  double area_before_fill = 0;
  for (auto f : mesh.faces()) area_before_fill += face_area(mesh, f);
  std::vector<SurfaceMesh::Halfedge_index> holes;
  PMP::extract_boundary_cycles(mesh, std::back_inserter(holes));
  report.holes_found = holes.size();
  double estimated_hole_area = 0;
  for (auto h : holes) {
    std::vector<Point> loop;
    for (auto e : CGAL::halfedges_around_face(h, mesh)) loop.push_back(mesh.point(mesh.source(e)));
    estimated_hole_area += vector_area(loop);
  }
  report.hole_area = estimated_hole_area;
  const double allowed = options.max_hole_share * area_before_fill;
  if (!holes.empty() && original_faces > 0 && estimated_hole_area <= allowed) {
    double filled_area = 0;
    for (std::size_t i = 0; i < holes.size(); ++i) {
      std::vector<SurfaceMesh::Face_index> patch;
      std::vector<SurfaceMesh::Vertex_index> added_vertices;
      // A flat patch (triangulated, then refined to the size of the surrounding triangles so
      // the slicer sees no long sliver), never a faired one: fairing continues the surface's
      // curvature, and on the bunny's base it bulges 0.06 mm below the face the part stands
      // on, so the first layer would print only the bulge's tip.
      PMP::triangulate_and_refine_hole(mesh, holes[i], std::back_inserter(patch),
                                       std::back_inserter(added_vertices));
      if (patch.empty()) PMP::triangulate_hole(mesh, holes[i], std::back_inserter(patch));
      if (patch.empty()) continue;
      ++report.holes_filled;
      report.faces_added += patch.size();
      for (auto f : patch) filled_area += face_area(mesh, f);
    }
    report.hole_area = std::max(filled_area, estimated_hole_area);
  }
  report.hole_share = area_before_fill > 0 ? report.hole_area / area_before_fill
                                           : (report.hole_area > 0 ? 1.0 : 0.0);
}

// 5. Oriented outward. A closed surface knows its inside; an open one gets the orientation
// with positive signed volume, the best guess there is.
void orient_outward(SurfaceMesh& mesh, RepairReport& report) {
  report.open_edges_after = count_border_edges(mesh);
  report.closed = mesh.number_of_faces() > 0 && report.open_edges_after == 0;
  if (report.closed) {
    PMP::orient_to_bound_a_volume(mesh);
  } else if (mesh.number_of_faces() > 0 && open_signed_volume(mesh) < 0) {
    PMP::reverse_face_orientations(mesh);
  }
}

Mesh plain_mesh(const SurfaceMesh& mesh) {
  Mesh out;
  out.vertices.reserve(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.vertices.push_back({p.x(), p.y(), p.z()});
  }
  out.faces.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    out.faces.push_back({static_cast<std::uint32_t>(mesh.source(h)),
                         static_cast<std::uint32_t>(mesh.target(h)),
                         static_cast<std::uint32_t>(mesh.target(mesh.next(h)))});
  }
  return out;
}

// A file's facet was reoriented when its final corner order is the reverse of the order in the
// file (up to rotation).
std::size_t faces_reoriented(const Mesh& out, std::size_t original_faces,
                             const std::vector<Polygon>& polygons,
                             const std::vector<std::size_t>& face_polygon,
                             const std::vector<char>& reversed) {
  std::size_t count = 0;
  for (std::size_t k = 0; k < original_faces; ++k) {
    const auto& f = out.faces[k];
    const Polygon& p = polygons[face_polygon[k]];
    const bool same_as_oriented_soup =
        (f[0] == p[0] && f[1] == p[1]) || (f[0] == p[1] && f[1] == p[2]) ||
        (f[0] == p[2] && f[1] == p[0]);
    if (same_as_oriented_soup == (reversed[face_polygon[k]] != 0)) ++count;
  }
  return count;
}

// The repaired mesh with the report's last figures (its volume the caller's), handed out.
Mesh with_figures(Mesh out, RepairReport& report, RepairReport* report_out) {
  report.vertices = out.vertices.size();
  report.surface_area = surface_area(out);
  report.bounds = bounding_box(out);
  if (report_out) *report_out = report;
  return out;
}

}  // namespace

Mesh repair(const std::vector<Triangle>& facets, RepairReport* report_out,
            const RepairOptions& options) {
  RepairReport report;
  report.facets_read = facets.size();
  std::vector<Vec3> points;
  std::vector<Polygon> polygons = merged_corners(facets, points, report);
  drop_degenerate_and_duplicate(points, polygons, report);
  drop_unused_corners(points, polygons);
  std::vector<char> reversed(polygons.size(), 0);
  std::size_t pieces = 0;
  const bool oriented = count_edges_and_check_manifold(points.size(), polygons, report, pieces);
  if (oriented && report.open_edges_before == 0 && pieces == 1) {
    // Closed, in one piece, oriented alike throughout: if it bounds a positive volume it is
    // what steps 3-5 would give back (no hole, nothing to reorient), without CGAL's mesh
    // (4% of slicing the bunny). Each face starts at its third corner, as Surface_mesh
    // hands a face back.
    Mesh out;
    out.vertices = points;
    out.faces.reserve(polygons.size());
    for (const Polygon& p : polygons) {
      out.faces.push_back({static_cast<std::uint32_t>(p[2]), static_cast<std::uint32_t>(p[0]),
                           static_cast<std::uint32_t>(p[1])});
    }
    report.volume = signed_volume(out);
    if (report.volume > 0) {
      report.closed = true;
      return with_figures(std::move(out), report, report_out);
    }
  }
  if (!oriented) reversed = orient_and_split(points, polygons, report);
  SurfaceMesh mesh;
  std::vector<std::size_t> face_polygon;  // Surface_mesh face index -> polygon
  build_surface(points, polygons, mesh, face_polygon, report);
  const std::size_t original_faces = mesh.number_of_faces();
  fill_holes(mesh, original_faces, options, report);
  orient_outward(mesh, report);
  Mesh out = plain_mesh(mesh);
  report.faces_reoriented = faces_reoriented(out, original_faces, polygons, face_polygon, reversed);
  report.volume = signed_volume(out);
  return with_figures(std::move(out), report, report_out);
}

void check_printable(const RepairReport& report, std::string_view name,
                     const RepairOptions& options) {
  const auto refuse = [name](const std::string& problem) {
    throw InputError(fmt::format("{}: {}", name, problem));
  };
  if (report.facets_read == 0) refuse("no facets: there is nothing to print");
  if (report.vertices == 0) {
    refuse(fmt::format("all {} facets are degenerate (zero area): there is nothing to print",
                       report.facets_read));
  }
  const Vec3 size = report.bounds.max - report.bounds.min;
  const double largest = std::max({size.x, size.y, size.z});
  for (const auto& [extent, axis] : {std::pair{size.x, 'X'}, {size.y, 'Y'}, {size.z, 'Z'}}) {
    if (extent <= 1e-9 * largest) {
      refuse(fmt::format("zero volume: the model is flat (no thickness along {}), a surface "
                         "rather than a solid",
                         axis));
    }
  }
  if (!report.closed && report.non_manifold_edges > 0) {
    refuse(fmt::format("{} edge{} shared by more than two facets (parts touching along an "
                       "edge or a face, or faces inside the part), and the surface does not "
                       "close once they are split apart; join the parts into one solid in a "
                       "mesh editor",
                       report.non_manifold_edges, report.non_manifold_edges == 1 ? " is" : "s are"));
  }
  if (report.hole_share > options.max_hole_share) {
    refuse(fmt::format("the surface is missing too much to repair: its {} hole{} would need "
                       "{:.0f}% of its area invented (at most {:.0f}% is filled); add the "
                       "missing faces in a mesh editor",
                       report.holes_found, report.holes_found == 1 ? "" : "s",
                       100 * report.hole_share, 100 * options.max_hole_share));
  }
  if (!report.closed) {
    refuse(fmt::format("still open after repair ({} open edges, {} holes of {} filled): not a "
                       "closed solid; fix it in a mesh editor",
                       report.open_edges_after, report.holes_filled, report.holes_found));
  }
  if (!(report.volume > 1e-9 * size.x * size.y * size.z)) {
    refuse(fmt::format("zero volume: the closed surface encloses {:g} units^3, nothing to "
                       "print",
                       report.volume));
  }
}

}  // namespace geometry
