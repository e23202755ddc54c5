#include "geometry/slicing/plane_section.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "geometry/core/number_table.h"

namespace geometry {

namespace {

// The identity of a crossing point, from the mesh alone: the undirected edge (a, b), a < b,
// it lies on, or, when the edge's lower vertex v lies exactly at z, that vertex itself
// (encoded as the edge (v, v)), since every edge of v that crosses the plane crosses it there.
using Node = std::uint64_t;

struct NodeHash {
  std::size_t operator()(Node node) const {
    return (node ^ (node >> 29)) * 0x9e3779b97f4a7c15ull >> 20;
  }
};

Node node_of(const Mesh& mesh, std::uint32_t a, std::uint32_t b, double z) {
  const std::uint32_t below = mesh.vertices[a].z <= z ? a : b;
  if (mesh.vertices[below].z == z) return (Node{below} << 32) | below;
  if (a > b) std::swap(a, b);
  return (Node{a} << 32) | b;
}

bool is_vertex(Node node) { return (node >> 32) == (node & 0xffffffffu); }

Vec2 crossing_point(const Mesh& mesh, Node node, double z) {
  Vec3 below = mesh.vertices[node >> 32];
  Vec3 above = mesh.vertices[node & 0xffffffffu];
  if (below.z > above.z) std::swap(below, above);
  if (below.z == z) return {below.x, below.y};
  const double t = (z - below.z) / (above.z - below.z);
  return {below.x + t * (above.x - below.x), below.y + t * (above.y - below.y)};
}

// One face's piece of the section, directed so that the solid lies on its left.
struct Segment {
  Node start, end;
};

// Segments by their start node: a segment's number, or the first of those from the node.
using Starts = NumberTable<Node, NodeHash>;

// Segments that have zero width in the limit from above cancel: one of zero length (a face
// touching the plane at one vertex), and a pair u -> v, v -> u (the two sides of a slit, as
// where a notch's tip or a ring of vertices touches the plane from above).
void cancel_zero_width(std::vector<Segment>& segments) {
  std::erase_if(segments, [](const Segment& s) { return s.start == s.end; });
  const auto undirected = [](const Segment& s) {
    return std::pair{std::min(s.start, s.end), std::max(s.start, s.end)};
  };
  std::sort(segments.begin(), segments.end(), [&](const Segment& a, const Segment& b) {
    return undirected(a) < undirected(b);
  });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < segments.size();) {
    std::size_t j = i, forward = 0;
    while (j < segments.size() && undirected(segments[j]) == undirected(segments[i])) {
      forward += segments[j].start < segments[j].end;
      ++j;
    }
    const std::size_t backward = (j - i) - forward;
    const auto [lo, hi] = undirected(segments[i]);
    for (std::size_t k = forward; k > backward; --k) segments[kept++] = {lo, hi};
    for (std::size_t k = backward; k > forward; --k) segments[kept++] = {hi, lo};
    i = j;
  }
  segments.resize(kept);
}

void finish_loop(Loop& loop, Region& region) {
  // Distinct nodes rarely share coordinates (an unmerged duplicate vertex); drop such repeats.
  loop.erase(std::unique(loop.begin(), loop.end()), loop.end());
  while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
  if (loop.size() < 3) return;
  // Of no area: |area| <= 1e-12 perimeter^2. Most loops have far more than that even against
  // a bound on the perimeter (the sum of |dx| + |dy|), which needs no square roots.
  const double area = std::abs(signed_area(loop));
  const double bound = perimeter_bound(loop);
  if (!(area > 1e-12 * bound * bound)) {
    const double length = perimeter(loop);
    if (area <= 1e-12 * length * length) return;
  }
  region.loops.push_back(std::move(loop));
}

// The usual case, no vertex on the plane: every crossed edge starts one segment and ends one,
// so the segments close into loops through a table of their starts, without the general way's
// sorts. The loops come out as that way gives them: each from its segment of least start node,
// in the order of those nodes. None if a node starts two segments, or ends one that no segment
// starts or that another ends (a non-manifold or open mesh): then the general way.
std::optional<Region> closed_loops(const Mesh& mesh, const std::vector<Segment>& segments, double z) {
  Starts starts(segments.size());
  const auto start_of = [&](std::uint32_t i) { return segments[i].start; };
  for (std::uint32_t i = 0; i < segments.size(); ++i) {
    if (starts.find_or_insert(segments[i].start, i, start_of) != i) return std::nullopt;
  }
  struct Chain {
    Node least;
    std::size_t first, size;  // its segments, in `order`
  };
  std::vector<Chain> chains;
  std::vector<std::uint32_t> order;
  order.reserve(segments.size());
  std::vector<char> used(segments.size(), 0);
  for (std::uint32_t i = 0; i < segments.size(); ++i) {
    if (used[i]) continue;
    Chain chain{segments[i].start, order.size(), 0};
    std::size_t least_at = 0;
    for (std::uint32_t k = i;;) {
      used[k] = 1;
      if (segments[k].start < chain.least) chain.least = segments[k].start, least_at = chain.size;
      order.push_back(k);
      ++chain.size;
      const std::uint32_t next = starts.find(segments[k].end, start_of);
      if (next == i) break;
      if (next == Starts::kNone || used[next]) return std::nullopt;
      k = next;
    }
    const auto begin = order.begin() + static_cast<std::ptrdiff_t>(chain.first);
    std::rotate(begin, begin + static_cast<std::ptrdiff_t>(least_at), order.end());
    chains.push_back(chain);
  }
  std::sort(chains.begin(), chains.end(),
            [](const Chain& a, const Chain& b) { return a.least < b.least; });
  Region region;
  for (const Chain& chain : chains) {
    Loop loop;
    loop.reserve(chain.size);
    for (std::size_t k = chain.first; k < chain.first + chain.size; ++k) {
      loop.push_back(crossing_point(mesh, segments[order[k]].start, z));
    }
    finish_loop(loop, region);
  }
  return region;
}

// Each face the plane crosses gives one segment; whether an end of one lies at a vertex on
// the plane.
bool crossing_segments(const Mesh& mesh, std::span<const std::uint32_t> faces, double z,
                       std::vector<Segment>& segments) {
  segments.reserve(faces.size());
  bool on_plane = false;
  for (std::uint32_t f : faces) {
    const auto& face = mesh.faces[f];
    bool below[3];
    for (int i = 0; i < 3; ++i) below[i] = mesh.vertices[face[i]].z <= z;
    if (below[0] == below[1] && below[1] == below[2]) continue;
    // Walking the face counter-clockwise (seen from outside), the edge that goes down through
    // the plane is where the section enters this face with the solid on its left.
    Segment segment{};
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      if (!below[i] && below[j]) segment.start = node_of(mesh, face[i], face[j], z);
      if (below[i] && !below[j]) segment.end = node_of(mesh, face[i], face[j], z);
    }
    segments.push_back(segment);
    on_plane |= is_vertex(segment.start) || is_vertex(segment.end);
  }
  return on_plane;
}

// A segment's start node by its number, for the table of starts.
struct StartOf {
  const std::vector<Segment>* segments;
  Node operator()(std::uint32_t i) const { return (*segments)[i].start; }
};

// Sorts the segments by their start; returns where the segments from each node begin, by the
// node.
Starts sort_by_start(std::vector<Segment>& segments) {
  std::sort(segments.begin(), segments.end(),
            [](const Segment& a, const Segment& b) { return a.start < b.start; });
  Starts starts(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (i == 0 || segments[i].start != segments[i - 1].start) {
      starts.find_or_insert(segments[i].start, static_cast<std::uint32_t>(i), StartOf{&segments});
    }
  }
  return starts;
}

// The first unused segment from `node` (segments sorted by start), or segments.size(). An
// edge starts one segment; a vertex on the plane (or a non-manifold edge) may start several,
// and any unused one continues a valid loop.
std::size_t unused_from(const std::vector<Segment>& segments, const Starts& starts, Node node,
                        const std::vector<char>& used) {
  const std::uint32_t start = starts.find(node, StartOf{&segments});
  std::size_t i = start == Starts::kNone ? segments.size() : start;
  while (i < segments.size() && segments[i].start == node && used[i]) ++i;
  return i < segments.size() && segments[i].start == node ? i : segments.size();
}

// The loop from segment `first` on through unused segments, marked used as they are taken,
// until it closes or ends at an open edge.
void walk_loop(const Mesh& mesh, const std::vector<Segment>& segments, const Starts& starts,
               std::size_t first, double z, std::vector<char>& used, Region& region) {
  Loop loop;
  std::size_t current = first;
  used[current] = 1;
  loop.push_back(crossing_point(mesh, segments[current].start, z));
  for (;;) {
    const Node wanted = segments[current].end;
    if (wanted == segments[first].start) break;  // closed
    current = unused_from(segments, starts, wanted, used);
    if (current == segments.size()) {
      loop.push_back(crossing_point(mesh, wanted, z));  // open chain: ends at an open edge
      break;
    }
    used[current] = 1;
    loop.push_back(crossing_point(mesh, segments[current].start, z));
  }
  finish_loop(loop, region);
}

// The general way, for vertices on the plane and open or non-manifold meshes: open chains
// first, from the nodes where more segments leave than arrive, so that none is picked up in
// its middle; what is left are closed loops.
Region chained_loops(const Mesh& mesh, std::vector<Segment>& segments, double z) {
  const Starts starts = sort_by_start(segments);
  std::vector<Node> ends(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) ends[i] = segments[i].end;
  std::sort(ends.begin(), ends.end());
  std::vector<char> used(segments.size(), 0);
  Region region;
  for (std::size_t i = 0; i < segments.size();) {
    std::size_t j = i;
    while (j < segments.size() && segments[j].start == segments[i].start) ++j;
    const auto [in_lo, in_hi] = std::equal_range(ends.begin(), ends.end(), segments[i].start);
    std::ptrdiff_t surplus = static_cast<std::ptrdiff_t>(j - i) - (in_hi - in_lo);
    for (std::size_t k = i; k < j && surplus > 0; ++k) {
      if (!used[k]) walk_loop(mesh, segments, starts, k, z, used, region), --surplus;
    }
    i = j;
  }
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (!used[i]) walk_loop(mesh, segments, starts, i, z, used, region);
  }
  return region;
}

}  // namespace

Region plane_section(const Mesh& mesh, std::span<const std::uint32_t> faces, double z) {
  std::vector<Segment> segments;
  const bool on_plane = crossing_segments(mesh, faces, z, segments);
  // Zero width needs a vertex exactly on the plane (in a manifold mesh two faces share at
  // most one edge), so a plane that meets none, the usual case, skips the search for it.
  if (on_plane) cancel_zero_width(segments);
  if (segments.empty()) return {};
  if (!on_plane) {
    if (std::optional<Region> loops = closed_loops(mesh, segments, z)) return std::move(*loops);
  }
  return chained_loops(mesh, segments, z);
}

}  // namespace geometry
