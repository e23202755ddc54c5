#include "geometry/plan/slab_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

#include "geometry/metrics/layer_metrics.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/slab/slab.h"

namespace geometry {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// How far below a flat top its slab's surface is taken, mm: far below any printer's step.
constexpr double kBelow = 1e-6;

// The distance from the walls of the first of the sections' vertices farther than
// `stop_above` from them, mm; 0 when there is none. A vertex with a wall nearer than that is
// passed over without finding the nearest.
double first_beyond(std::span<const Region* const> sections, const BoundaryGrid& walls,
                    double stop_above) {
  for (const Region* section : sections) {
    for (const Loop& loop : section->loops) {
      for (const Vec2& v : loop) {
        if (walls.any_within(v, stop_above)) continue;
        const double d = walls.nearest_distance(v);
        if (d > stop_above) return d;
      }
    }
  }
  return 0;
}

}  // namespace

// The section at one height and the grid over its walls, each made the first time it is asked
// for. The grid is shared between threads: only its queries that keep no state (nearest,
// any_within, winding_number) are asked of it; a search that marks segments (for_each_near,
// distance_error's) gets a copy.
struct SlabMeter::Section {
  std::once_flag cut, gridded;
  std::shared_ptr<const Region> region;
  std::shared_ptr<const BoundaryGrid> walls;
};

std::shared_ptr<SlabMeter::Section> SlabMeter::entry(double z) const {
  std::shared_ptr<Section> entry;
  {
    std::lock_guard lock(sections_mutex_);
    auto& slot = sections_[z];
    if (!slot) slot = std::make_shared<Section>();
    entry = slot;
  }
  std::call_once(entry->cut, [&] { entry->region = std::make_shared<Region>(stack_.cross_section(z)); });
  return entry;
}

std::shared_ptr<const Region> SlabMeter::section(double z) const { return entry(z)->region; }

std::shared_ptr<const BoundaryGrid> SlabMeter::section_walls(double z) const {
  const std::shared_ptr<Section> at = entry(z);
  std::call_once(at->gridded, [&] { at->walls = std::make_shared<const BoundaryGrid>(*at->region); });
  return at->walls;
}

void SlabMeter::forget_below(double z) const {
  std::lock_guard lock(sections_mutex_);
  std::erase_if(sections_, [&](const auto& entry) { return entry.first < z; });
}

SlabMeter::SlabMeter(const LayerStack& stack, SlabErrorOptions options)
    : stack_(stack), options_(std::move(options)) {
  const Mesh& mesh = stack.mesh();
  neighbours_.assign(mesh.faces.size(), {kNone, kNone, kNone});
  // Each edge met twice in a closed mesh, once in each direction.
  std::unordered_map<std::uint64_t, std::uint32_t> open;
  open.reserve(mesh.faces.size() * 2);
  const auto key = [](std::uint32_t a, std::uint32_t b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (std::uint32_t f = 0; f < mesh.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t edge = key(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]);
      const auto [it, added] = open.try_emplace(edge, f * 3 + k);
      if (added) continue;
      const std::uint32_t other = it->second;
      neighbours_[f][k] = other / 3;
      neighbours_[other / 3][other % 3] = f;
      open.erase(it);
    }
    const auto& face = mesh.faces[f];
    const double z = mesh.vertices[face[0]].z;
    if (mesh.vertices[face[1]].z == z && mesh.vertices[face[2]].z == z) flat_heights_.push_back(z);
  }
  std::sort(flat_heights_.begin(), flat_heights_.end());
  flat_heights_.erase(std::unique(flat_heights_.begin(), flat_heights_.end()), flat_heights_.end());
  // The vertices no neighbour rises above, or none falls below: a piece of surface that stays
  // on one side of a height inside a slab has its highest or lowest point at one of them.
  std::vector<char> higher(mesh.vertices.size(), 0), lower(mesh.vertices.size(), 0);
  for (const auto& face : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = face[k], b = face[(k + 1) % 3];
      const double za = mesh.vertices[a].z, zb = mesh.vertices[b].z;
      if (zb > za) higher[a] = 1, lower[b] = 1;
      if (zb < za) lower[a] = 1, higher[b] = 1;
    }
  }
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!higher[v] || !lower[v]) extreme_heights_.push_back(mesh.vertices[v].z);
  }
  std::sort(extreme_heights_.begin(), extreme_heights_.end());
  extreme_heights_.erase(std::unique(extreme_heights_.begin(), extreme_heights_.end()), extreme_heights_.end());
}

bool SlabMeter::spans_every_piece(double z_lo, double z_hi) const {
  const auto any_inside = [&](const std::vector<double>& heights) {
    const auto it = std::upper_bound(heights.begin(), heights.end(), z_lo);
    return it != heights.end() && *it < z_hi;
  };
  return !any_inside(extreme_heights_) && !any_inside(flat_heights_);
}

bool SlabMeter::every_piece_meets(std::span<const std::uint32_t> faces, double z_lo, double z_hi,
                                  double h, const BoundaryGrid& walls) const {
  const Mesh& mesh = stack_.mesh();
  const auto range = [&](std::uint32_t f) {
    const auto& face = mesh.faces[f];
    const double a = mesh.vertices[face[0]].z, b = mesh.vertices[face[1]].z,
                 c = mesh.vertices[face[2]].z;
    return std::pair{std::min({a, b, c}), std::max({a, b, c})};
  };
  // Each face's state in this call, one stamp per face of the mesh (kept per thread, so
  // calls need not clear it): `in_slab` for a face of the slab (a piece of positive height
  // inside it, or flat strictly inside), `in_slab + 1` once its piece was walked.
  thread_local std::vector<std::uint32_t> stamp;
  thread_local std::uint32_t epoch = 0;
  if (stamp.size() != mesh.faces.size() || epoch > kNone - 3) {
    stamp.assign(mesh.faces.size(), 0);
    epoch = 0;
  }
  epoch += 2;
  const std::uint32_t in_slab = epoch, walked = epoch + 1;
  for (const std::uint32_t f : faces) {
    const auto [lo, hi] = range(f);
    if (hi > z_lo && lo < z_hi) stamp[f] = in_slab;
  }
  // A vertex of the piece's surface (on a face of it, inside the closed slab) inside the
  // section's region at least this far from its walls: the piece's island, which holds a disc
  // of the footprint's margin round the vertex, overlaps the region by far more than
  // kTouchArea (pi x 1e-6 mm^2).
  const double clear = 0.5 * kFootprintMargin;
  const auto inside = [&](std::span<const std::uint32_t> piece) {
    for (const std::uint32_t f : piece) {
      for (const std::uint32_t v : mesh.faces[f]) {
        const Vec3 p = mesh.vertices[v];
        if (!(p.z >= z_lo && p.z <= z_hi)) continue;
        double clearance = 0;
        if (walls.winding_number({p.x, p.y}, &clearance) != 0 && clearance >= clear) return true;
      }
    }
    return false;
  };
  // Pieces joined where two faces share an edge that reaches into the open slab.
  std::vector<std::uint32_t> pending, piece;
  for (const std::uint32_t start : faces) {
    if (stamp[start] != in_slab) continue;
    bool crosses = false;
    stamp[start] = walked;
    pending.assign(1, start);
    piece.clear();
    while (!pending.empty()) {
      const std::uint32_t f = pending.back();
      pending.pop_back();
      piece.push_back(f);
      const auto [lo, hi] = range(f);
      if (lo < h && h < hi) crosses = true;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t g = neighbours_[f][k];
        if (g == kNone || stamp[g] != in_slab) continue;
        const double za = mesh.vertices[mesh.faces[f][k]].z;
        const double zb = mesh.vertices[mesh.faces[f][(k + 1) % 3]].z;
        if (!(std::max(za, zb) > z_lo && std::min(za, zb) < z_hi)) continue;
        stamp[g] = walked;
        pending.push_back(g);
      }
    }
    if (!crosses && !inside(piece)) return false;
  }
  return true;
}

// What the strategies may use of one slab (contour_input.h): the faces through it, the slab
// and its surface cut out of the mesh, the footprint's islands, each the first time it is
// needed; no columns (optimal-height builds its own).
struct SlabMeter::Cut {
  const LayerStack& stack;
  double z_lo, z_hi;
  const DistanceOptions& distance;
  const LayerStack view;  // the slab as the one layer of a stack, for a strategy's input
  LayerReference reference;
  std::vector<std::uint32_t> face_list;
  bool have_faces = false, have_slab = false, have_surface = false, have_islands = false;

  Cut(const LayerStack& stack, double z_lo, double z_hi, const DistanceOptions& distance)
      : stack(stack), z_lo(z_lo), z_hi(z_hi), distance(distance), view(stack, {Layer{z_lo, z_hi}}) {
    reference.layer = {z_lo, z_hi};
  }
  const std::vector<std::uint32_t>& faces() {
    if (!have_faces) face_list = stack.faces_between(z_lo, z_hi), have_faces = true;
    return face_list;
  }
  void need_slab() {
    if (!have_slab) reference.slab = slab_of(stack.mesh(), faces(), z_lo, z_hi), have_slab = true;
  }
  const SlabSurface& surface() {
    need_slab();
    if (!have_surface) reference.surface = slab_surface(reference.slab, distance), have_surface = true;
    return reference.surface;
  }
  const std::vector<BoundaryPair>& islands() {
    need_slab();
    if (!have_islands) reference.islands = slab_islands(reference.slab), have_islands = true;
    return reference.islands;
  }
};

namespace {

// distance_error to `walls`; a section's grid shared between threads (`shared`) copied first,
// since the surface's search marks the segments it visits (for_each_near).
DistanceError distance_to(const SlabSurface& surface, const BoundaryGrid& walls, bool shared,
                          std::span<const BoundaryPair> missed, const DistanceOptions& options) {
  if (!shared) return distance_error(surface, walls, missed, options);
  const BoundaryGrid own = walls;
  return distance_error(surface, own, missed, options);
}

// The metric's options for one measurement: stopping past `refute_above` (> 0), and with
// `settle`, once D is seen within `enough` by the metric's tolerance at least (so that a
// settled D is within it).
DistanceOptions trial_distance(DistanceOptions distance, double enough, double refute_above, bool settle) {
  distance.reverse = false;
  if (refute_above > 0) distance.stop_above = refute_above;
  if (settle && enough > 0) distance.settle_below = enough - distance.tolerance;
  return distance;
}

}  // namespace

bool SlabMeter::section_meets_every_piece(Cut& cut, const ContourStrategy& strategy, const BoundaryGrid& walls) const {
  return strategy.cuts_at != nullptr && !cut.have_islands &&
         (spans_every_piece(cut.z_lo, cut.z_hi) ||
          every_piece_meets(cut.faces(), cut.z_lo, cut.z_hi, strategy.cuts_at(cut.reference.layer), walls));
}

double SlabMeter::ends_farthest(Cut& cut, const BoundaryGrid& walls) const {
  if (!std::isfinite(cut.distance.stop_above)) return 0;
  // A section is the limit from above: at a flat face on the top plane (a step's top)
  // the slab's own surface there is the limit from below, a hair lower.
  const bool flat_top = std::binary_search(flat_heights_.begin(), flat_heights_.end(), cut.z_hi);
  const auto bottom = section(cut.z_lo), top = section(flat_top ? cut.z_hi - kBelow : cut.z_hi);
  const Region* ends[] = {bottom.get(), top.get()};
  return first_beyond(ends, walls, cut.distance.stop_above);
}

double SlabMeter::ends_past(double z_lo, double z_hi, const ContourStrategy& strategy, double stop_above) const {
  if (strategy.cuts_at == nullptr || !(stop_above > 0) || !std::isfinite(stop_above)) return 0;
  const DistanceOptions distance = trial_distance(options_.distance, 0, stop_above, false);
  Cut cut(stack_, z_lo, z_hi, distance);
  const std::shared_ptr<const BoundaryGrid> walls = section_walls(strategy.cuts_at(cut.reference.layer));
  if (!section_meets_every_piece(cut, strategy, *walls)) return 0;
  const double d = ends_farthest(cut, *walls);
  return d > stop_above ? d : 0;
}

void SlabMeter::measure_to_walls(Cut& cut, const BoundaryGrid& walls, bool shared, SlabTrial& trial) const {
  // Every surface point counts to the walls; the sections on the slab's two planes, where a
  // section's walls stand farthest from the surface, first: one point past `enough` refuses
  // the slab without the rest of the surface.
  const DistanceOptions& distance = cut.distance;
  const double end_farthest = ends_farthest(cut, walls);
  if (end_farthest > distance.stop_above) {
    trial.distance = end_farthest;
    return;
  }
  const DistanceError measured = distance_to(cut.surface(), walls, shared, {}, distance);
  trial.distance = measured.forward;
  trial.settled = measured.settled;
}

void SlabMeter::measure_with_islands(Cut& cut, const BoundaryGrid& walls, bool shared, SlabTrial& trial) const {
  cut.surface();
  const std::vector<BoundaryPair> missed = missed_features(cut.islands(), trial.region);
  trial.missed = missed.size();
  const DistanceError measured = distance_to(cut.surface(), walls, shared, missed, cut.distance);
  trial.distance = measured.forward;
  trial.settled = measured.settled;
}

SlabTrial SlabMeter::trial(Cut& cut, const ContourStrategy& strategy) const {
  SlabTrial trial;
  trial.strategy = &strategy;
  // A section's walls are shared by every slab cut there (a height halves many candidates).
  std::shared_ptr<const BoundaryGrid> shared;
  BoundaryGrid own;
  if (strategy.cuts_at != nullptr) {
    const double h = strategy.cuts_at(cut.reference.layer);
    trial.region = *section(h);
    shared = section_walls(h);
  } else {
    cut.islands(), cut.surface();
    trial.region = strategy.contour({cut.view, 0, options_.contour, &cut.reference}).region;
    own = BoundaryGrid(trial.region);
  }
  const BoundaryGrid& walls = shared ? *shared : own;
  if (section_meets_every_piece(cut, strategy, walls)) {
    measure_to_walls(cut, walls, shared != nullptr, trial);
  } else {
    measure_with_islands(cut, walls, shared != nullptr, trial);
  }
  trial.bounded = trial.distance > cut.distance.stop_above;
  return trial;
}

SlabError SlabMeter::operator()(double z_lo, double z_hi,
                                std::span<const ContourStrategy* const> strategies, double enough,
                                double refute_above, bool settle) const {
  SlabError error;
  error.z_lo = z_lo;
  error.z_hi = z_hi;
  const DistanceOptions distance = trial_distance(options_.distance, enough, refute_above, settle);
  Cut cut(stack_, z_lo, z_hi, distance);
  for (const ContourStrategy* strategy : strategies) {
    error.trials.push_back(trial(cut, *strategy));
    const std::size_t last = error.trials.size() - 1;
    if (error.trials[last].distance < error.trials[error.best].distance - 1e-3) error.best = last;
    if (enough > 0 && error.trials[last].distance <= enough) break;
  }
  return error;
}

SlabError slab_error(const LayerStack& stack, double z_lo, double z_hi,
                     std::span<const ContourStrategy* const> strategies, double enough,
                     const SlabErrorOptions& options) {
  return SlabMeter(stack, options)(z_lo, z_hi, strategies, enough);
}

}  // namespace geometry
