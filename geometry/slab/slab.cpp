#include "geometry/slab/slab.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <numbers>
#include <utility>

#include "geometry/core/clipper.h"
#include "geometry/core/number_table.h"

namespace geometry {

namespace {

// A facet is seen edge-on from above when it is thinner than this across in projection (mm):
// what rounding to whole nanometres can leave of a vertical face.
constexpr double kEdgeOnWidth = 1e-5;

// Whether a projected facet of twice this area and this longest side (squared) is thinner
// than `width` across (all in one unit): area < width * longest / 2, squared.
bool seen_edge_on(double twice_area, double longest_squared, double width) {
  return !(twice_area * twice_area > width * width * longest_squared);
}

using ClipperLib::cInt;
using ClipperLib::IntPoint;

// A polygon of at most kMaxCorners corners, on the stack: a convex polygon of n corners cut
// by two planes has at most n + 2, so a mesh face (a triangle) and anything up to ten corners
// is clipped without allocating, and slab_of cuts every face of the model into its one array
// of corners (SlabFacets). Larger polygons take a std::vector through the same code.
constexpr std::size_t kMaxCorners = 12;
struct SmallPolygon {
  std::array<Vec3, kMaxCorners> at;
  std::size_t count = 0;
  void clear() { count = 0; }
  void push_back(Vec3 p) { at[count++] = p; }
  void pop_back() { --count; }
  bool empty() const { return count == 0; }
  std::size_t size() const { return count; }
  const Vec3* data() const { return at.data(); }
  const Vec3* begin() const { return at.data(); }
  const Vec3* end() const { return at.data() + count; }
  const Vec3& front() const { return at[0]; }
  const Vec3& back() const { return at[count - 1]; }
};

// Keeps the part of a convex polygon on the side where side * (z - plane) >= 0.
template <class Corners>
void clip_half(std::span<const Vec3> in, double plane, double side, Corners& out) {
  const auto keep = [&](double z) { return side * (z - plane); };
  out.clear();
  for (std::size_t i = 0, n = in.size(); i < n; ++i) {
    const Vec3 a = in[i], b = in[i + 1 == n ? 0 : i + 1];
    const double ka = keep(a.z), kb = keep(b.z);
    if (ka >= 0) out.push_back(a);
    if ((ka < 0 && kb > 0) || (ka > 0 && kb < 0)) {
      // From the lower end, so the face on the other side of this edge, which walks it the
      // other way, computes the very same point, and the footprint's shared edges cancel.
      const Vec3 lo = a.z < b.z ? a : b, hi = a.z < b.z ? b : a;
      Vec3 p = lo + ((plane - lo.z) / (hi.z - lo.z)) * (hi - lo);
      p.z = plane;  // exactly, so later tests against the plane are exact
      out.push_back(p);
    }
  }
}

bool same_point(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// The piece of `polygon` in the slab into `merged`; false (and `merged` of no use) if fewer
// than 3 points remain or the piece lies in the plane z_lo or z_hi. `above` and `inside` are
// scratch space, so that a caller clipping many faces makes them once.
// A plane the polygon lies wholly on the kept side of (every corner at or above z_lo, or every
// one at or below z_hi) keeps every corner and adds none: that half is not clipped.
template <class Corners, class Merged>
bool clip_into(std::span<const Vec3> polygon, double z_lo, double z_hi, Corners& above,
               Corners& inside, Merged& merged) {
  bool above_lo = true, below_hi = true;  // false for a corner whose z is not a number
  for (const Vec3& p : polygon) {
    above_lo = above_lo && p.z >= z_lo;
    below_hi = below_hi && p.z <= z_hi;
  }
  std::span<const Vec3> kept = polygon;
  if (!above_lo) {
    clip_half(kept, z_lo, 1.0, above);
    kept = std::span<const Vec3>(above.data(), above.size());
  }
  if (!below_hi) {
    clip_half(kept, z_hi, -1.0, inside);
    kept = std::span<const Vec3>(inside.data(), inside.size());
  }
  // Repeated points merged, the first and last too.
  merged.clear();
  for (const Vec3& p : kept) {
    if (merged.empty() || !same_point(p, merged.back())) merged.push_back(p);
  }
  while (merged.size() > 1 && same_point(merged.front(), merged.back())) merged.pop_back();
  if (merged.size() < 3) return false;
  const bool on_lo = std::all_of(merged.begin(), merged.end(), [&](Vec3 p) { return p.z == z_lo; });
  const bool on_hi = std::all_of(merged.begin(), merged.end(), [&](Vec3 p) { return p.z == z_hi; });
  return !(on_lo || on_hi);
}

}  // namespace

std::vector<Vec3> clip_to_slab(std::span<const Vec3> polygon, double z_lo, double z_hi) {
  std::vector<Vec3> merged;
  bool kept;
  if (polygon.size() + 2 <= kMaxCorners) {
    SmallPolygon above, inside;
    kept = clip_into(polygon, z_lo, z_hi, above, inside, merged);
  } else {
    std::vector<Vec3> above, inside;
    kept = clip_into(polygon, z_lo, z_hi, above, inside, merged);
  }
  if (!kept) return {};
  return merged;
}

Slab slab_of(const Mesh& mesh, std::span<const std::uint32_t> faces, double z_lo, double z_hi) {
  Slab slab{z_lo, z_hi, {}};
  if (!(z_lo < z_hi)) return slab;
  // Most pieces of a triangle are triangles or quadrilaterals.
  slab.facets.reserve(faces.size(), 4 * faces.size());
  SmallPolygon above, inside, piece;  // a triangle's pieces
  for (std::uint32_t f : faces) {
    if (f >= mesh.faces.size()) continue;
    const auto& face = mesh.faces[f];
    if (face[0] >= mesh.vertices.size() || face[1] >= mesh.vertices.size() ||
        face[2] >= mesh.vertices.size()) {
      continue;
    }
    const std::array<Vec3, 3> corners{mesh.vertices[face[0]], mesh.vertices[face[1]],
                                      mesh.vertices[face[2]]};
    const double lo = std::min({corners[0].z, corners[1].z, corners[2].z});
    const double hi = std::max({corners[0].z, corners[1].z, corners[2].z});
    if (hi < z_lo || lo > z_hi) continue;
    if (clip_into(std::span<const Vec3>(corners), z_lo, z_hi, above, inside, piece)) {
      slab.facets.push_back(std::span<const Vec3>(piece.data(), piece.size()));
    }
  }
  return slab;
}

Slab slab_of(const LayerStack& stack, std::size_t layer) {
  if (layer >= stack.size()) return {};
  const Layer& bounds = stack.layers()[layer];
  const std::vector<std::uint32_t> faces = stack.faces_between(bounds.z_lo, bounds.z_hi);
  return slab_of(stack.mesh(), faces, bounds.z_lo, bounds.z_hi);
}

bool is_prism(const Slab& slab) {
  for (const auto& facet : slab.facets) {
    // Twice the projected area, and the longest projected side: the facet is thinner than
    // the width across if the one is below the width times the other. Corners taken from
    // the first, so that far from the origin nothing cancels.
    double twice_area = 0, longest2 = 0;
    for (std::size_t i = 0, n = facet.size(); i < n; ++i) {
      const Vec3 a = facet[i] - facet[0], b = facet[i + 1 == n ? 0 : i + 1] - facet[0];
      twice_area += a.x * b.y - b.x * a.y;
      longest2 = std::max(longest2, (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
    }
    if (!seen_edge_on(twice_area, longest2, kEdgeOnWidth)) return false;
  }
  return !slab.facets.empty();
}

namespace {

bool before(IntPoint a, IntPoint b) { return a.X < b.X || (a.X == b.X && a.Y < b.Y); }

// One edge of a facet's projection, its ends sorted.
struct Edge {
  IntPoint lo, hi;  // lo before hi
  int direction;    // +1: walked lo -> hi (summed: the net number of times)
};

void add_edges(const ClipperLib::Path& facet, std::vector<Edge>& edges) {
  for (std::size_t i = 0, n = facet.size(); i < n; ++i) {
    const IntPoint a = facet[i], b = facet[i + 1 == n ? 0 : i + 1];
    if (a == b) continue;
    edges.push_back(before(a, b) ? Edge{a, b, 1} : Edge{b, a, -1});
  }
}

// A hash of a few coordinates, for open-addressing tables indexed by its low bits.
std::uint64_t hash_of(std::initializer_list<cInt> values) {
  std::uint64_t h = 0;
  for (const cInt v : values) h = (h ^ static_cast<std::uint64_t>(v)) * 0x9e3779b97f4a7c15ull;
  return h ^ (h >> 32);
}

struct PointHash {
  std::size_t operator()(const IntPoint& p) const { return hash_of({p.X, p.Y}); }
};

// The edges summed by their ends: each distinct segment once, with the net number of times
// it is walked from lo to hi (most segments are shared by two facets walking it opposite
// ways and sum to 0). Then the segments left, sorted by their ends.
std::vector<Edge> net_edges(const std::vector<Edge>& edges) {
  std::vector<Edge> summed;
  summed.reserve(edges.size());
  // Open addressing on the edges' ends, the slots numbers into `summed` (NumberTable's
  // layout, its probe written out: the key compared in place, not copied out as a pair).
  std::size_t capacity = 16;
  while (capacity < 2 * edges.size()) capacity *= 2;
  const std::size_t mask = capacity - 1;
  constexpr std::uint32_t kNone = UINT32_MAX;
  std::vector<std::uint32_t> slots(capacity, kNone);
  for (const Edge& e : edges) {
    for (std::size_t i = hash_of({e.lo.X, e.lo.Y, e.hi.X, e.hi.Y}) & mask;; i = (i + 1) & mask) {
      const std::uint32_t slot = slots[i];
      if (slot == kNone) {
        slots[i] = static_cast<std::uint32_t>(summed.size());
        summed.push_back(e);
        break;
      }
      Edge& same = summed[slot];
      if (same.lo == e.lo && same.hi == e.hi) {
        same.direction += e.direction;
        break;
      }
    }
  }
  summed.erase(std::remove_if(summed.begin(), summed.end(), [](const Edge& e) { return e.direction == 0; }),
               summed.end());
  std::sort(summed.begin(), summed.end(), [](const Edge& x, const Edge& y) {
    return before(x.lo, y.lo) || (x.lo == y.lo && before(x.hi, y.hi));
  });
  return summed;
}

// Whether b lies on the line through a and c (exactly, on the grid): Clipper's test for a
// vertex its output leaves out.
bool collinear(IntPoint a, IntPoint b, IntPoint c) {
  return static_cast<__int128>(b.X - a.X) * (c.Y - b.Y) ==
         static_cast<__int128>(b.Y - a.Y) * (c.X - b.X);
}

// The loop without the vertices that lie on the line through their neighbours (a spike
// folded back on itself too), as Clipper's union leaves them out; fewer than 3 left: empty.
void drop_collinear(ClipperLib::Path& loop) {
  std::size_t kept = 0;
  for (const IntPoint p : loop) {
    while (kept >= 2 && collinear(loop[kept - 2], loop[kept - 1], p)) --kept;
    loop[kept++] = p;
  }
  loop.resize(kept);
  // Round the join of the last vertex to the first.
  std::size_t first = 0;
  for (bool changed = true; changed && loop.size() - first >= 3;) {
    changed = false;
    const std::size_t n = loop.size();
    if (collinear(loop[n - 2], loop[n - 1], loop[first])) {
      loop.pop_back();
      changed = true;
    } else if (collinear(loop[n - 1], loop[first], loop[first + 1])) {
      ++first;
      changed = true;
    }
  }
  if (loop.size() - first < 3) {
    loop.clear();
    return;
  }
  loop.erase(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(first));
}

// The boundary of the facets' projections taken as a 2-chain (each facet counter-clockwise,
// weight one; `edges` are their edges, add_edges), as closed paths: a shared edge is walked
// once each way and cancels, so only the lower and upper contours and the silhouettes remain.
// Their winding number at a point is the number of facets over it: never negative, positive
// exactly on the union of the projections; and Clipper sees a few hundred edges instead of
// every facet. The edges are summed by their ends (net_edges), then sorted by their start to
// walk them; a vertex on the line through its neighbours is left out, as Clipper's union
// leaves it out (where the paths bound their fill as they stand, the same loops as that
// union's; the margin's mitres and the medial axis see every vertex).
// Measured (callgrind, bench_footprint, the bunny's 333 slabs at 0.15 mm) and not taken: the
// paths depend on the order std::sort leaves the edges out of one point in, wherever two
// leave it for different points (a pinch: 322 of the 333 slabs have one), so the sort stays;
// walking the edges as cycles through a table of their starts where no point is a pinch
// (the same paths) cost 12 M instructions more than it saved, and sorting packed 64-bit keys
// with the same comparisons (the same order) 10 M more.
ClipperLib::Paths chain_boundary(const std::vector<Edge>& edges) {
  std::vector<std::pair<IntPoint, IntPoint>> remaining;  // directed, after cancelling
  for (const Edge& e : net_edges(edges)) {
    for (int k = 0; k < std::abs(e.direction); ++k) {
      remaining.push_back(e.direction > 0 ? std::pair{e.lo, e.hi} : std::pair{e.hi, e.lo});
    }
  }
  std::sort(remaining.begin(), remaining.end(),
            [](const auto& x, const auto& y) { return before(x.first, y.first); });
  std::vector<char> used(remaining.size(), 0);
  // The first unused edge out of `at`, or remaining.size().
  std::vector<std::size_t> cursor(remaining.size());
  for (std::size_t i = 0; i < remaining.size(); ++i) {
    cursor[i] = i > 0 && remaining[i].first == remaining[i - 1].first ? cursor[i - 1] : i;
  }
  // Where the edges out of each point begin in `remaining`, by the point.
  using Starts = NumberTable<IntPoint, PointHash>;
  Starts starts(remaining.size());
  const auto start_of = [&](std::uint32_t i) { return remaining[i].first; };
  for (std::size_t i = 0; i < remaining.size(); ++i) {
    if (cursor[i] == i) starts.find_or_insert(remaining[i].first, static_cast<std::uint32_t>(i), start_of);
  }
  const auto take_from = [&](IntPoint at) -> std::size_t {
    const std::uint32_t start = starts.find(at, start_of);
    if (start == Starts::kNone) return remaining.size();
    std::size_t& next = cursor[start];
    while (next < remaining.size() && remaining[next].first == at && used[next]) ++next;
    if (next >= remaining.size() || !(remaining[next].first == at)) return remaining.size();
    return next;
  };
  ClipperLib::Paths paths;
  for (std::size_t s = 0; s < remaining.size(); ++s) {
    if (used[s]) continue;
    used[s] = 1;
    const IntPoint start = remaining[s].first;
    ClipperLib::Path path{start};
    IntPoint at = remaining[s].second;
    // Every vertex has as many edges in as out, so the walk ends where it began; should
    // rounding ever break that, the walk stops and the path closes itself.
    while (!(at == start)) {
      path.push_back(at);
      const std::size_t next = take_from(at);
      if (next == remaining.size()) break;
      used[next] = 1;
      at = remaining[next].second;
    }
    drop_collinear(path);
    if (path.size() >= 3) paths.push_back(std::move(path));
  }
  return paths;
}

using Chord = std::pair<IntPoint, IntPoint>;  // first before second

// Each edge-on facet's projection reduced to its longest chord (the segment it lies on),
// sorted, duplicates dropped (a wall's two triangles give the same one).
std::vector<Chord> longest_chords(const ClipperLib::Paths& edge_on) {
  std::vector<Chord> chords;
  for (const ClipperLib::Path& path : edge_on) {
    Chord longest{path[0], path[0]};
    double best = -1;
    for (std::size_t i = 0; i < path.size(); ++i) {
      for (std::size_t j = i + 1; j < path.size(); ++j) {
        const double dx = double(path[j].X - path[i].X), dy = double(path[j].Y - path[i].Y);
        if (dx * dx + dy * dy > best) {
          best = dx * dx + dy * dy;
          longest = before(path[i], path[j]) ? Chord{path[i], path[j]} : Chord{path[j], path[i]};
        }
      }
    }
    chords.push_back(longest);
  }
  std::sort(chords.begin(), chords.end(), [](const Chord& a, const Chord& b) {
    return before(a.first, b.first) || (a.first == b.first && before(a.second, b.second));
  });
  chords.erase(std::unique(chords.begin(), chords.end()), chords.end());
  return chords;
}

// The chords as a graph: their distinct ends (sorted) and the chords that touch each; a chord
// that is a point touches none. walk() follows unused chords from an end.
class ChordGraph {
 public:
  explicit ChordGraph(std::vector<Chord> chords)
      : chords_(std::move(chords)), used_(chords_.size(), 0) {
    for (const auto& [a, b] : chords_) {
      ends_.push_back(a);
      ends_.push_back(b);
    }
    std::sort(ends_.begin(), ends_.end(), before);
    ends_.erase(std::unique(ends_.begin(), ends_.end()), ends_.end());
    touching_.resize(ends_.size());
    for (std::size_t k = 0; k < chords_.size(); ++k) {
      if (chords_[k].first == chords_[k].second) continue;  // a point: kept as a path of its own
      touching_[index(chords_[k].first)].push_back(k);
      touching_[index(chords_[k].second)].push_back(k);
    }
  }

  std::size_t end_count() const { return ends_.size(); }
  // Whether two chords meet at end c (a polyline passes through it).
  bool passes_through(std::size_t c) const { return touching_[c].size() == 2; }
  bool has_unused(std::size_t c) const {
    return std::any_of(touching_[c].begin(), touching_[c].end(), [&](std::size_t k) { return !used_[k]; });
  }
  const std::vector<Chord>& chords() const { return chords_; }

  // The polyline of unused chords from end `from`, on through every end where exactly two
  // meet, marking them used; is_closed where it came back to `from`.
  ClipperLib::Path walk(std::size_t from, bool& is_closed) {
    ClipperLib::Path path{ends_[from]};
    std::size_t at = from;
    is_closed = false;
    for (;;) {
      const auto next = std::find_if(touching_[at].begin(), touching_[at].end(),
                                     [&](std::size_t k) { return !used_[k]; });
      if (next == touching_[at].end()) break;
      const Chord& chord = chords_[*next];
      used_[*next] = 1;
      at = index(chord.first == ends_[at] ? chord.second : chord.first);
      if (at == from) {
        is_closed = true;
        break;
      }
      path.push_back(ends_[at]);
      if (!passes_through(at)) break;
    }
    return path;
  }

 private:
  std::size_t index(IntPoint p) const {
    return static_cast<std::size_t>(std::lower_bound(ends_.begin(), ends_.end(), p, before) - ends_.begin());
  }

  std::vector<Chord> chords_;
  std::vector<IntPoint> ends_;
  std::vector<std::vector<std::size_t>> touching_;
  std::vector<char> used_;
};

// Edge-on facets as few polylines: each facet's longest chord, joined end to end where
// exactly two meet. Offsetting a wall loop as one closed line gives a clean ring; offsetting
// its hundreds of segments one by one gives the same set through thousands of overlapping
// rectangles.
void chain_segments(const ClipperLib::Paths& edge_on, ClipperLib::Paths& open,
                    ClipperLib::Paths& closed) {
  ChordGraph graph(longest_chords(edge_on));
  // Paths start where they end or branch; what is left after that are closed loops.
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t c = 0; c < graph.end_count(); ++c) {
      if (pass == 0 && graph.passes_through(c)) continue;
      while (graph.has_unused(c)) {
        bool is_closed = false;
        ClipperLib::Path path = graph.walk(c, is_closed);
        (is_closed && path.size() >= 3 ? closed : open).push_back(std::move(path));
      }
    }
  }
  for (const Chord& chord : graph.chords()) {
    if (chord.first == chord.second) open.push_back({chord.first});
  }
}

}  // namespace

namespace {

// The closed loops of a union (outer loops counter-clockwise, holes clockwise), grown by delta
// > 0 with mitred joins, as raw paths whose positive fill is the grown set: the paths
// ClipperOffset (jtMiter, miter limit 2, Clipper 6.4) hands to its union, to the bit, except
// at concave corners. There ClipperOffset puts the corner itself between the two shifted
// edges, a small self-crossing loop at every concave corner that its union must then resolve
// (two intersections each: most of the offset's cost on a slab's ragged contours). Here the
// two shifted edges meet at their intersection instead, the point that union finds, where
// that point lies within the first half of both edges, so that neighbouring corners cannot
// cross; elsewhere (a spike, a very short edge) the corner is built as ClipperOffset builds
// it. The same arithmetic as ClipperOffset matters: a wall's ring (offset by ClipperOffset)
// lies exactly on the grown loop beside it, and a nanometre between the two would leave a
// zigzag of extra vertices in the footprint; so are its roundings (clipper_rounded).
void add_grown(const ClipperLib::Paths& loops, double delta, ClipperLib::Paths& out) {
  struct Normal {
    double x, y, length;
  };
  std::vector<Normal> normals;
  for (const ClipperLib::Path& loop : loops) {
    const std::size_t n = loop.size();
    if (n < 3) continue;
    normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) {  // edge i: from vertex i to i + 1, outward normal
      const IntPoint a = loop[i], b = loop[i + 1 == n ? 0 : i + 1];
      double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
      const double length = std::sqrt(dx * dx + dy * dy);
      if (length == 0) {
        normals[i] = {0, 0, 0};
        continue;
      }
      const double f = 1.0 / length;  // as ClipperLib's GetUnitNormal
      dx *= f;
      dy *= f;
      normals[i] = {dy, -dx, length};
    }
    ClipperLib::Path grown;
    grown.reserve(n + n / 4 + 4);
    const auto shifted = [&](IntPoint p, double x, double y) {
      grown.push_back(
          {clipper_rounded(double(p.X) + x * delta), clipper_rounded(double(p.Y) + y * delta)});
    };
    std::size_t k = n - 1;  // the edge the last join was made from
    for (std::size_t j = 0; j < n; ++j) {
      const Normal& nk = normals[k];
      const Normal& nj = normals[j];
      const IntPoint p = loop[j];
      double sin_a = nk.x * nj.y - nj.x * nk.y;
      const double cos_a = nk.x * nj.x + nj.y * nk.y;
      if (std::abs(sin_a * delta) < 1.0) {
        if (cos_a > 0) {  // straight on, to within a unit; k stays (as ClipperOffset)
          shifted(p, nk.x, nk.y);
          continue;
        }
      } else {
        sin_a = std::clamp(sin_a, -1.0, 1.0);
      }
      const double r = 1 + cos_a;
      if (sin_a * delta < 0) {  // concave
        // The shifted edges meet |sin| / (1 + cos) * delta back along the edge in and as far
        // on along the edge out.
        const bool adjacent = k + 1 == j || (j == 0 && k == n - 1);
        const double reach = r > 0 ? std::abs(sin_a) / r * delta : HUGE_VAL;
        if (adjacent && 2 * reach <= std::min(nk.length, nj.length)) {
          const double q = delta / r;
          grown.push_back({clipper_rounded(double(p.X) + (nk.x + nj.x) * q),
                           clipper_rounded(double(p.Y) + (nk.y + nj.y) * q)});
        } else {
          shifted(p, nk.x, nk.y);
          grown.push_back(p);
          shifted(p, nj.x, nj.y);
        }
      } else if (r >= 0.5) {  // convex, mitred (miter limit 2)
        const double q = delta / r;
        grown.push_back({clipper_rounded(double(p.X) + (nk.x + nj.x) * q),
                         clipper_rounded(double(p.Y) + (nk.y + nj.y) * q)});
      } else {  // convex and sharp: squared off
        const double t = std::tan(std::atan2(sin_a, cos_a) / 4);
        grown.push_back({clipper_rounded(double(p.X) + delta * (nk.x - nk.y * t)),
                         clipper_rounded(double(p.Y) + delta * (nk.y + nk.x * t))});
        grown.push_back({clipper_rounded(double(p.X) + delta * (nj.x + nj.y * t)),
                         clipper_rounded(double(p.Y) + delta * (nj.y - nj.x * t))});
      }
      k = j;
    }
    out.push_back(std::move(grown));
  }
}

// The footprint as Clipper's nesting (the tree must be the caller's: a PolyTree cannot be
// copied). Of its 1.09 G instructions in the bunny's best slice at 0.15 mm the union is
// 0.65 G; there is nothing to drop before it: a facet inside the covered set has every edge
// shared and cancels in the chains, which are only the lower and upper contours and the
// silhouettes, all on the footprint's boundary but at folds; and other input (loops dropped,
// the union split by boxes) can order its output loops or begin them elsewhere, which the
// medial axis samples from.
void footprint_tree(const Slab& slab, double margin, ClipperLib::PolyTree& tree) {
  // The union of the projections grown by the margin, in one positive union of the boundary
  // chains grown as they stand (add_grown), without their own union first. The same set: the
  // grown chain (each edge shifted right by the margin, joined at the vertices) is, as a
  // 1-chain, the chain itself plus, for each edge, the rectangle it sweeps to its right, plus
  // at each left turn the mitre's wedge, minus at each right turn add_grown cuts short the
  // small square that lies in both neighbouring edges' rectangles: so its winding number is
  // the chain's (>= 0, > 0 exactly on the covered set) plus the rectangles' and wedges' (>= 0),
  // positive on the covered set and within the margin of its boundary, which runs along the
  // chain's edges with the outside on their right; nowhere else but in a mitre of a left turn
  // inside the covered set within twice the margin of its boundary (up to 2 margins out, where
  // the union's own corners mitre as far). Clipper's union rounded the chains' crossings to
  // the grid: the two sets differ by about a unit along the boundary (slab_test checks it on
  // a cone, a sphere and stacked overhangs; analyze's D and ΔV of bunny and models agree to 5
  // digits). Facets seen edge-on (vertical walls) project to segments of no area and join the
  // offset as open paths.
  std::vector<Edge> edges;
  edges.reserve(3 * slab.facets.size());
  ClipperLib::Paths edge_on;
  ClipperLib::Path projected;
  for (const auto& facet : slab.facets) {
    // The corners on the grid (to_clipper, inline), repeats merged, the first and last too.
    projected.clear();
    for (const Vec3& v : facet) {
      const IntPoint p{rounded_units(v.x * kClipperScale), rounded_units(v.y * kClipperScale)};
      if (projected.empty() || !(p == projected.back())) projected.push_back(p);
    }
    while (projected.size() > 1 && projected.front() == projected.back()) projected.pop_back();
    // Edge-on: thinner than 10 nm across, which rounding to whole nanometres can leave of a
    // vertical face; as a polygon such a sliver would vanish in the union. Twice the area as
    // -2 ClipperLib::Area(projected) sums it, term for term (no area below 3 corners), and the
    // longest side, in one pass.
    const std::size_t n = projected.size();
    double longest2 = 0, sum = 0;
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
      const IntPoint a = projected[j], b = projected[i];
      const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
      longest2 = std::max(longest2, dx * dx + dy * dy);
      sum += (double(a.X) + double(b.X)) * (double(a.Y) - double(b.Y));
    }
    const double twice_area = n < 3 ? 0.0 : -sum;
    const bool thin = seen_edge_on(twice_area, longest2, kEdgeOnWidth * kClipperScale);
    if (n >= 3 && !thin) {
      if (twice_area < 0) std::reverse(projected.begin(), projected.end());
      add_edges(projected, edges);
    } else if (n > 0) {
      edge_on.push_back(projected);
    }
  }
  const ClipperLib::Paths boundary = chain_boundary(edges);
  const double margin_mm = std::max(margin, 0.0);
  if (!(margin_mm > 0)) {
    clipper::union_nonzero_tree(boundary, tree);
    return;
  }
  const double delta = margin_mm * kClipperScale;
  ClipperLib::Paths grown;
  add_grown(boundary, delta, grown);
  if (!edge_on.empty()) {
    ClipperLib::Paths open_lines, closed_lines;
    chain_segments(edge_on, open_lines, closed_lines);
    if (!open_lines.empty()) {  // squared ends: left to ClipperOffset (rare: a wall's loose end)
      // ClipperOffset's defaults: miter limit 2, arc tolerance 0.25 units (no arcs here).
      const ClipperLib::Paths ends = clipper::library_offset(
          open_lines, margin_mm, ClipperLib::jtMiter, ClipperLib::etOpenSquare,
          0.25 / kClipperScale);
      grown.insert(grown.end(), ends.begin(), ends.end());
    }
    // A closed line (a wall's loop) grows to both sides: the loop counter-clockwise and
    // clockwise, each grown as a polygon (ClipperOffset's etClosedLine).
    for (ClipperLib::Path& line : closed_lines) {
      if (!ClipperLib::Orientation(line)) ClipperLib::ReversePath(line);
      ClipperLib::Paths sides{line};
      ClipperLib::ReversePath(line);
      sides.push_back(std::move(line));
      add_grown(sides, delta, grown);
    }
  }
  clipper::union_positive_tree(grown, tree);
}

}  // namespace

Region slab_footprint(const Slab& slab, double margin) {
  ClipperLib::PolyTree tree;
  footprint_tree(slab, margin, tree);
  return from_clipper(tree);
}

std::vector<BoundaryPair> slab_islands(const Slab& slab, double margin) {
  ClipperLib::PolyTree tree;
  footprint_tree(slab, margin, tree);
  return boundary_pairs(tree);
}

}  // namespace geometry
