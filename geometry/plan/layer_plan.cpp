#include "geometry/plan/layer_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <thread>
#include <tuple>

#include <tbb/parallel_for.h>

#include "geometry/plan/slab_bound.h"

namespace geometry {
namespace {

// Heights closer than this are one height, mm (far below any printer's step).
constexpr double kSameHeight = 1e-7;

long long nanometres(double mm) { return std::llround(mm * 1e6); }

// The spacing of every height the thicknesses reach from the first layer's top, mm: the
// greatest common divisor of the allowed thicknesses (the step's and min's for a range);
// 0 for a continuous range.
double reach_unit(const AllowedThicknesses& allowed) {
  long long common = 0;
  if (!allowed.listed.empty()) {
    for (double t : allowed.listed) common = std::gcd(common, nanometres(t));
  } else if (allowed.step > 0) {
    common = std::gcd(nanometres(allowed.min), nanometres(allowed.step));
  }
  return static_cast<double>(common) * 1e-6;
}

// The flat levels a plan should put on boundaries: above the bed, not above the top.
std::vector<double> flat_heights(std::span<const FlatLevel> flats, double top) {
  std::vector<double> heights;
  for (const FlatLevel& level : flats) {
    if (level.z > kSameHeight && level.z <= top + kSameHeight) heights.push_back(level.z);
  }
  return heights;
}

// How many of the sorted heights lie strictly between a and b.
std::size_t crossed(std::span<const double> heights, double a, double b) {
  const auto first = std::upper_bound(heights.begin(), heights.end(), a + kSameHeight);
  const auto last = std::lower_bound(heights.begin(), heights.end(), b - kSameHeight);
  return last > first ? static_cast<std::size_t>(last - first) : 0;
}

std::vector<FlatPlacement> placements(std::span<const double> flats,
                                      const std::vector<Layer>& layers) {
  std::vector<double> boundaries{0};
  for (const Layer& layer : layers) boundaries.push_back(layer.z_hi);
  std::vector<FlatPlacement> placed;
  for (double z : flats) {
    auto next = std::lower_bound(boundaries.begin(), boundaries.end(), z);
    double nearest = next == boundaries.end() ? boundaries.back() : *next;
    if (next != boundaries.begin() && (next == boundaries.end() || z - next[-1] < *next - z)) {
      nearest = next[-1];
    }
    if (std::abs(nearest - z) <= kSameHeight) nearest = z;
    placed.push_back({z, nearest});
  }
  return placed;
}

}  // namespace

double AllowedThicknesses::thinnest() const {
  return listed.empty() ? min : *std::min_element(listed.begin(), listed.end());
}

double AllowedThicknesses::thickest() const {
  return listed.empty() ? max : *std::max_element(listed.begin(), listed.end());
}

bool AllowedThicknesses::allows(double t) const {
  if (!listed.empty()) {
    return std::any_of(listed.begin(), listed.end(),
                       [&](double l) { return std::abs(l - t) <= kSameHeight; });
  }
  if (t < min - kSameHeight || t > max + kSameHeight) return false;
  if (!(step > 0)) return true;
  const double steps = (t - min) / step;
  return std::abs(steps - std::round(steps)) * step < kSameHeight;
}

// ---------------------------------------------------------------------------------------------
// Uniform

UniformPlan uniform_plan(double part_height, double thickness, const AllowedThicknesses& allowed,
                         std::span<const FlatLevel> flat_levels) {
  UniformPlan plan;
  plan.layers = uniform_layers(part_height, thickness, allowed.first);
  if (plan.layers.empty()) return plan;
  const std::vector<double> flats = flat_heights(flat_levels, part_height);
  const double first = plan.layers.front().z_hi;
  const double step = reach_unit(allowed);  // 0: any thickness in the range

  // Boundaries the layers must reach, in order; each segment between two of them gets whole
  // layers of `thickness`, adjusted a step at a time (the layers just under the flat level)
  // until they fill it exactly. A level the thicknesses cannot reach exactly is left where the
  // plain grid puts it.
  std::vector<Layer> layers{plan.layers.front()};
  double bottom = first;
  // Fills [bottom, level] with `count` layers of about `thickness`: the landed height (the
  // level, or with fixed steps the nearest height they reach) and what each layer adds to
  // `thickness`; nothing if the allowed thicknesses cannot do it.
  struct Segment {
    double z;
    std::vector<double> extra;  // mm, per layer of the segment
  };
  const auto segment = [&](double bottom, double level, std::size_t count) -> std::optional<Segment> {
    const double gap = level - bottom;
    // Enough layers that none must be thicker than allowed, few enough that none is thinner.
    while (gap / static_cast<double>(count) > allowed.thickest() + kSameHeight) ++count;
    while (count > 1 && gap / static_cast<double>(count) < allowed.thinnest() - kSameHeight) --count;
    Segment found{level, std::vector<double>(count, 0)};
    if (step > 0) {
      // A level between two reachable heights lands on the nearer one (8.03 mm on 8.05).
      const double steps = (gap - static_cast<double>(count) * thickness) / step;
      long units = std::lround(steps);
      const double reached = bottom + static_cast<double>(count) * thickness +
                             static_cast<double>(units) * step;
      if (std::abs(reached - level) > kSameHeight) found.z = reached;
      // How many steps a layer may grow or shrink and stay allowed.
      long room_up = 0, room_down = 0;
      while (allowed.allows(thickness + static_cast<double>(room_up + 1) * step)) ++room_up;
      while (allowed.allows(thickness - static_cast<double>(room_down + 1) * step)) ++room_down;
      // One step per layer from the top of the segment down, again while steps are left.
      std::vector<long> taken(count, 0);
      for (long pass = 0; units != 0 && pass <= std::max(room_up, room_down); ++pass) {
        for (std::size_t k = count; k-- > 0 && units != 0;) {
          if (units > 0 && taken[k] < room_up) ++taken[k], --units;
          if (units < 0 && -taken[k] < room_down) --taken[k], ++units;
        }
      }
      if (units != 0) return std::nullopt;
      for (std::size_t k = 0; k < count; ++k) found.extra[k] = static_cast<double>(taken[k]) * step;
    } else if (double left = gap - static_cast<double>(count) * thickness; left < 0) {
      // Any thickness, thinner: every layer of the segment a little, none far from the rest.
      const double each = left / static_cast<double>(count);
      if (thickness + each < allowed.thinnest() - kSameHeight) return std::nullopt;
      std::fill(found.extra.begin(), found.extra.end(), each);
    } else {
      // Any thickness, thicker: the difference on the top layers, as few as stay within range.
      for (std::size_t k = count; k-- > 0 && std::abs(left) > kSameHeight;) {
        const double room =
            left > 0 ? allowed.thickest() - thickness : allowed.thinnest() - thickness;
        found.extra[k] = left > 0 ? std::min(left, room) : std::max(left, room);
        left -= found.extra[k];
      }
      if (std::abs(left) > kSameHeight) return std::nullopt;
    }
    return found;
  };
  for (double level : flats) {
    const double gap = level - bottom;
    if (gap < allowed.thinnest() - kSameHeight) continue;  // too close to the one before
    // As many layers as the grid's nearest to the level asks for; half way, one more, thinner
    // ones (they follow a slope closer and keep an overhang within its reach, for a layer's
    // time), not fewer thicker ones. If the thicknesses cannot do that, the other way.
    const double needed = gap / thickness;
    const std::size_t most = static_cast<std::size_t>(std::max(1.0, std::ceil(needed - 1e-6)));
    const std::size_t fewest = static_cast<std::size_t>(std::max(1.0, std::floor(needed + 1e-6)));
    const bool thinner = needed - std::floor(needed + 1e-6) >= 0.5 - 1e-6;
    std::optional<Segment> found = segment(bottom, level, thinner ? most : fewest);
    if (!found && fewest != most) found = segment(bottom, level, thinner ? fewest : most);
    if (!found) continue;  // left where the plain grid puts it
    double z_lo = bottom;
    double offset = 0;
    const std::size_t count = found->extra.size();
    for (std::size_t k = 0; k < count; ++k) {
      offset += found->extra[k];
      // From the segment's bottom, not accumulated, as uniform_layers does.
      const double z_hi =
          k + 1 == count ? found->z : bottom + static_cast<double>(k + 1) * thickness + offset;
      layers.push_back({z_lo, z_hi});
      z_lo = z_hi;
    }
    bottom = found->z;
  }
  if (bottom == first) {
    plan.flats = placements(flats, plan.layers);
    return plan;  // no level moved anything: the plain grid
  }
  // Above the last level: the plain grid from there, up to and past the top.
  if (part_height > bottom + kSameHeight) {
    const double more = std::max(1.0, std::ceil((part_height - bottom) / thickness - 1e-9));
    for (std::size_t k = 1; k <= static_cast<std::size_t>(more); ++k) {
      layers.push_back({layers.back().z_hi, bottom + static_cast<double>(k) * thickness});
    }
  }
  plan.layers = std::move(layers);
  plan.flats = placements(flats, plan.layers);
  return plan;
}

// ---------------------------------------------------------------------------------------------
// Adaptive

namespace {

// The grid of reachable heights: nodes (ascending, the bed first) and, per node, the
// candidate slabs (edges) starting there.
struct HeightGrid {
  std::vector<double> z;
  std::vector<std::uint32_t> edge_begin;  // edges of node i: [edge_begin[i], edge_begin[i+1])
  std::vector<std::uint32_t> edge_to;
  std::vector<std::uint32_t> edge_from;
  std::vector<char> edge_thinnest;        // the thinnest thickness (or the fixed first layer)
};

HeightGrid height_grid(double top, const AllowedThicknesses& allowed, std::span<const double> flats,
                       double grid) {
  HeightGrid g;
  // Every reachable height is the first layer's top plus whole multiples of the unit.
  const double unit = reach_unit(allowed) > 0 ? std::max(1e-3, reach_unit(allowed)) : grid;
  const double first = allowed.first > 0 ? allowed.first : 0;
  // Heights counted in whole nanometres, so that 0.3 + 74 x 0.05 is 4.0, not 3.9999999999999996.
  const long long first_nm = nanometres(first), unit_nm = std::max(1LL, nanometres(unit));
  const long long last_nm = nanometres(top + allowed.thickest());
  g.z.push_back(0);
  for (long long k = first > 0 ? 0 : 1; first_nm + k * unit_nm <= last_nm; ++k) {
    g.z.push_back(static_cast<double>(first_nm + k * unit_nm) * 1e-6);
  }
  // The flat levels (already on reachable heights, flat_targets) at their own heights.
  for (double z : flats) g.z.push_back(z);
  std::sort(g.z.begin(), g.z.end());
  std::vector<double> nodes;
  for (double z : g.z) {
    if (!nodes.empty() && z - nodes.back() <= kSameHeight) {
      if (std::binary_search(flats.begin(), flats.end(), z)) nodes.back() = z;
      continue;
    }
    nodes.push_back(z);
  }
  g.z = std::move(nodes);

  const std::size_t n = g.z.size();
  g.edge_begin.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    g.edge_begin[i] = static_cast<std::uint32_t>(g.edge_to.size());
    if (g.z[i] >= top - kSameHeight && i > 0) continue;  // at or above the top: done
    if (i == 0 && first > 0) {
      for (std::size_t j = 1; j < n; ++j) {
        if (std::abs(g.z[j] - first) <= kSameHeight) {
          g.edge_to.push_back(static_cast<std::uint32_t>(j));
          g.edge_from.push_back(0);
          g.edge_thinnest.push_back(1);
        }
      }
      continue;
    }
    const auto lo = std::lower_bound(g.z.begin() + static_cast<long>(i) + 1, g.z.end(),
                                     g.z[i] + allowed.thinnest() - kSameHeight);
    for (auto it = lo; it != g.z.end() && *it <= g.z[i] + allowed.thickest() + kSameHeight; ++it) {
      const double t = *it - g.z[i];
      if (!allowed.allows(t)) continue;
      g.edge_to.push_back(static_cast<std::uint32_t>(it - g.z.begin()));
      g.edge_from.push_back(static_cast<std::uint32_t>(i));
      g.edge_thinnest.push_back(t <= allowed.thinnest() + kSameHeight);
    }
  }
  g.edge_begin[n] = static_cast<std::uint32_t>(g.edge_to.size());
  return g;
}

// A path's cost, compared in this order: flat levels crossed, layers over the tolerance,
// layers; among paths equal in those, the fewest slabs not yet measured (so that the search
// keeps to what it has measured instead of wandering among equally short paths). Unreached:
// the largest.
using Cost = std::tuple<std::size_t, std::size_t, std::size_t, std::size_t>;
constexpr Cost kUnreached{std::numeric_limits<std::size_t>::max(), 0, 0, 0};

class LazyPlanner {
 public:
  LazyPlanner(const LayerStack& stack, double top, const AllowedThicknesses& allowed,
              std::span<const double> flats, const AdaptiveOptions& options,
              const PlanProgress& progress)
      : stack_(stack), top_(top), flats_(flats), options_(options), progress_(progress),
        grid_(height_grid(top, allowed, flats, options.grid)), meter_(stack, options.error),
        max_thickness_(allowed.thickest()) {
    const std::size_t edges = grid_.edge_to.size();
    const SlabSpreadEstimate estimate(stack.mesh());
    const AdaptiveOptions::ThickOverhangs& thick = options.thick_overhangs;
    std::optional<ThickOverhangEstimate> overhangs;
    if (thick.overhang_angle > 0) overhangs.emplace(stack.mesh(), thick.overhang_angle, thick.bead_width);
    estimate_.resize(edges);
    crossed_.resize(edges);
    refused_.assign(edges, 0);
    // Node by node: its candidates share their bottom, and the estimate takes them together.
    tbb::parallel_for(std::size_t{0}, grid_.z.size(), [&](std::size_t i) {
      const std::uint32_t first = grid_.edge_begin[i], last = grid_.edge_begin[i + 1];
      if (first == last) return;
      std::vector<double> tops;
      for (std::uint32_t e = first; e < last; ++e) tops.push_back(grid_.z[grid_.edge_to[e]]);
      estimate(grid_.z[i], tops, std::span(estimate_).subspan(first, last - first));
      for (std::uint32_t e = first; e < last; ++e) {
        const double a = grid_.z[i], b = grid_.z[grid_.edge_to[e]];
        crossed_[e] = static_cast<std::uint32_t>(crossed(flats_, a, b));
        refused_[e] = overhangs && !grid_.edge_thinnest[e] && (*overhangs)(a, b) > thick.min_area;
      }
    });
    exact_.assign(edges, NAN);
    proven_.assign(edges, NAN);
  }

  // Every candidate measured exactly: the search then needs one round.
  void measure_all(double tolerance) {
    std::vector<std::uint32_t> all(grid_.edge_to.size());
    std::iota(all.begin(), all.end(), 0u);
    measure(all, tolerance, false, true);
  }

  // The slabs of a path that were only shown within `tolerance` (see measure), measured
  // exactly: a plan gives every layer's D. (Counted once among the measured.)
  void measure_exactly(const std::vector<std::uint32_t>& path, double tolerance) {
    std::vector<std::uint32_t> settled;
    for (std::uint32_t e : path) {
      if (std::isnan(exact_[e])) settled.push_back(e);
    }
    measure(settled, tolerance, false, false);
  }

  std::size_t candidates() const { return grid_.edge_to.size(); }
  std::size_t refused() const { return static_cast<std::size_t>(std::count(refused_.begin(), refused_.end(), 1)); }
  std::size_t measured() const { return measured_; }
  std::size_t rounds() const { return rounds_; }
  double largest_estimate() const {
    double m = 0;
    for (std::size_t e = 0; e < exact_.size(); ++e) {
      m = std::max(m, std::isnan(exact_[e]) ? estimate_[e] : exact_[e]);
    }
    return m;
  }

  // The best path at `tolerance` with every slab on it measured: its edges, bottom up.
  std::vector<std::uint32_t> plan(double tolerance) {
    for (;;) {
      ++rounds_;
      std::vector<std::uint32_t> path = shortest_path(tolerance);
      std::vector<std::uint32_t> unmeasured;
      for (std::uint32_t e : path) {
        if (!settled(e, tolerance)) unmeasured.push_back(e);
      }
      if (unmeasured.empty()) return path;
      // The lowest few first (LazySP's forward selector): a slab found worse than estimated
      // reroutes the path above it, so measuring the rest of this path would mostly be wasted.
      if (unmeasured.size() > batch_) unmeasured.resize(batch_);
      // The sections far below are rarely wanted again (the path below is measured).
      meter_.forget_below(grid_.z[grid_.edge_from[unmeasured.front()]] - 2 * max_thickness_);
      measure(unmeasured, tolerance, settle_, true);
    }
  }

  // What the search takes an edge's D to be: measured, or else the larger of the estimate and
  // what a measured slab proves (see measure).
  double value(std::uint32_t e) const { return std::isnan(exact_[e]) ? estimate_[e] : exact_[e]; }
  // Whether the search knows all it needs of an edge at `tolerance`: its D, or that it is
  // within the tolerance.
  bool settled(std::uint32_t e, double tolerance) const {
    return !std::isnan(exact_[e]) || proven_[e] <= tolerance;
  }
  double exact(std::uint32_t e) const { return exact_[e]; }
  double z(std::uint32_t node) const { return grid_.z[node]; }
  std::uint32_t from(std::uint32_t e) const { return grid_.edge_from[e]; }
  std::uint32_t to(std::uint32_t e) const { return grid_.edge_to[e]; }

 private:
  std::vector<std::uint32_t> shortest_path(double tolerance) const {
    const std::size_t n = grid_.z.size();
    std::vector<Cost> cost(n, kUnreached);
    std::vector<std::uint32_t> via(n, std::numeric_limits<std::uint32_t>::max());
    cost[0] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < n; ++i) {
      if (cost[i] == kUnreached) continue;
      for (std::uint32_t e = grid_.edge_begin[i]; e < grid_.edge_begin[i + 1]; ++e) {
        if (refused_[e]) continue;
        const bool met = proven_[e] <= tolerance || value(e) <= tolerance;
        if (!met && !grid_.edge_thinnest[e]) continue;
        const auto& [flats, unmet, layers, unmeasured] = cost[i];
        const Cost through{flats + crossed_[e], unmet + (met ? 0 : 1), layers + 1,
                           unmeasured + (settled(e, tolerance) ? 0 : 1)};
        const std::uint32_t j = grid_.edge_to[e];
        if (through < cost[j]) cost[j] = through, via[j] = e;
      }
    }
    std::size_t end = 0;
    for (std::size_t i = 1; i < n; ++i) {
      if (grid_.z[i] >= top_ - kSameHeight && cost[i] != kUnreached &&
          (end == 0 || cost[i] < cost[end])) {
        end = i;
      }
    }
    std::vector<std::uint32_t> path;
    for (std::size_t i = end; i != 0; i = grid_.edge_from[via[i]]) path.push_back(via[i]);
    std::reverse(path.begin(), path.end());
    return path;
  }

  // With `settle`, a slab seen to stay within the tolerance is not measured further: the
  // search asks only whether it is, and most such slabs are not layers of the plan in the
  // end (the mush of the benchmarks at 0.3 mm: about 70 of 269), which measure_exactly measures
  // again once the path is found. Planning and slicing adaptive at 0.2 mm, median of 5: a
  // sphere 0.38 -> 0.31 s, a dome 0.27 -> 0.23, the mush 0.33 -> 0.26, a torus and the bunny
  // (whose slabs within the tolerance are mostly near it) the same.
  // `counted`: the slabs are new to the search (measured() and the progress count them).
  void measure(const std::vector<std::uint32_t>& edges, double tolerance, bool settle,
               bool counted) {
    if (edges.empty()) return;
    std::vector<double> found(edges.size());
    std::vector<char> exact(edges.size()), within(edges.size());
    tbb::parallel_for(std::size_t{0}, edges.size(), [&](std::size_t k) {
      const std::uint32_t e = edges[k];
      // A slab that cannot be printed over the tolerance is measured only until it is seen
      // to exceed it; the thinnest may be printed anyway and is measured exactly.
      const SlabError error = meter_(grid_.z[grid_.edge_from[e]], grid_.z[grid_.edge_to[e]],
                                     options_.contours, tolerance, !grid_.edge_thinnest[e], settle);
      found[k] = error.distance();
      exact[k] = error.exact();
      within[k] = error.settled();
    });
    for (std::size_t k = 0; k < edges.size(); ++k) {
      if (exact[k]) {
        exact_[edges[k]] = found[k];
      } else {
        estimate_[edges[k]] = std::max(estimate_[edges[k]], found[k]);
        if (within[k] && !(proven_[edges[k]] <= tolerance)) proven_[edges[k]] = tolerance;
      }
      widen(edges[k], found[k]);
    }
    if (!counted) return;
    measured_ += edges.size();
    if (progress_) progress_(measured_);
  }

  // A section contour measured on [a, b] proves D >= d on every slab that holds [a, b] and
  // cuts the same section: the same region, more surface to measure (and islands only grow,
  // so what is measured to its own outline here is measured at least as far there). For mid
  // that is [a - s, b + s], for lower [a, b + s].
  void widen(std::uint32_t e, double d) {
    if (options_.contours.size() != 1 || !options_.contours.front()->cuts_at) return;
    const auto cuts_at = options_.contours.front()->cuts_at;
    const double a = grid_.z[grid_.edge_from[e]], b = grid_.z[grid_.edge_to[e]];
    const double h = cuts_at({a, b});
    const auto first = std::lower_bound(grid_.z.begin(), grid_.z.end(),
                                        b - max_thickness_ - kSameHeight);
    for (auto i = static_cast<std::uint32_t>(first - grid_.z.begin());
         i < grid_.z.size() && grid_.z[i] <= a + kSameHeight; ++i) {
      for (std::uint32_t f = grid_.edge_begin[i]; f < grid_.edge_begin[i + 1]; ++f) {
        const Layer wider{grid_.z[i], grid_.z[grid_.edge_to[f]]};
        if (wider.z_hi < b - kSameHeight || std::abs(cuts_at(wider) - h) > kSameHeight) continue;
        if (std::isnan(exact_[f])) estimate_[f] = std::max(estimate_[f], d);
      }
    }
  }

  const LayerStack& stack_;
  double top_;
  std::span<const double> flats_;
  const AdaptiveOptions& options_;
  const PlanProgress& progress_;
  HeightGrid grid_;
  SlabMeter meter_;
  double max_thickness_;
  std::vector<double> estimate_, exact_;
  std::vector<double> proven_;  // a tolerance the slab is shown within, unmeasured (NaN: none)
  std::vector<std::uint32_t> crossed_;
  std::vector<char> refused_;  // thick_overhangs: not a layer of any path
  std::size_t measured_ = 0, rounds_ = 0;
  std::size_t batch_ = 2 * std::max(1u, std::thread::hardware_concurrency());
  // Slabs shown within the tolerance are not measured further: at one tolerance only (a
  // budget's search tries many, and would measure them again at each).
  bool settle_ = options_.max_layers == 0 && !options_.fits;
};

// Where each flat level should land: itself, or with a printer's fixed steps the nearest
// height they reach from the first layer (8.03 mm on 8.05 at 0.3 + k x 0.05).
std::vector<double> flat_targets(std::span<const double> flats, const AllowedThicknesses& allowed) {
  std::vector<double> targets;
  for (double z : flats) {
    double target = z;
    if (reach_unit(allowed) > 0) {
      const long long unit = nanometres(reach_unit(allowed));
      const long long first = nanometres(std::max(0.0, allowed.first));
      const long long k = std::llround(static_cast<double>(nanometres(z) - first) / static_cast<double>(unit));
      target = static_cast<double>(first + std::max(0LL, k) * unit) * 1e-6;
      if (std::abs(target - z) <= kSameHeight) target = z;
    }
    targets.push_back(target);
  }
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  return targets;
}

}  // namespace

AdaptivePlan adaptive_plan(const LayerStack& stack, double part_height,
                           const AllowedThicknesses& allowed, std::span<const FlatLevel> flat_levels,
                           const AdaptiveOptions& options, const PlanProgress& progress) {
  AdaptivePlan plan;
  if (!(part_height > 0) || !(allowed.thinnest() > 0) || !(allowed.thickest() >= allowed.thinnest())) {
    return plan;
  }
  const std::vector<double> flats = flat_heights(flat_levels, part_height);
  const std::vector<double> targets = flat_targets(flats, allowed);
  LazyPlanner planner(stack, part_height, allowed, targets, options, progress);
  plan.candidates = planner.candidates();
  plan.refused_for_overhangs = planner.refused();
  if (options.measure_all) {
    planner.measure_all(options.max_layers > 0 || options.fits ? 0 : options.tolerance);
  }

  double tolerance = std::max(0.0, options.tolerance);
  std::vector<std::uint32_t> path;
  const auto layers_of = [&](const std::vector<std::uint32_t>& edges) {
    std::vector<Layer> layers;
    for (std::uint32_t e : edges) layers.push_back({planner.z(planner.from(e)), planner.z(planner.to(e))});
    return layers;
  };
  if (options.max_layers == 0 && !options.fits) {
    path = planner.plan(tolerance);
  } else {
    // The least tolerance whose plan the budget accepts, by bisection between 0 and one that
    // every candidate meets (the thickest layers everywhere); for `fits`, whose every trial
    // costs what it costs (an estimate of the print), on a log scale from a micrometre and
    // to within 2%. A budget even that plan breaks gets that plan.
    const bool by_count = options.max_layers > 0;
    const auto accepts = [&](const std::vector<std::uint32_t>& edges) {
      return by_count ? edges.size() <= options.max_layers : options.fits(layers_of(edges));
    };
    double lo = by_count ? 0 : 1e-3, hi = planner.largest_estimate() + 1;
    const auto open = [&] { return by_count ? hi - lo > 1e-3 * std::max(1.0, hi) * 0.5 : hi > 1.02 * lo; };
    path = planner.plan(hi);
    if (accepts(path)) {
      while (open()) {
        const double mid = by_count ? 0.5 * (lo + hi) : std::sqrt(lo * hi);
        std::vector<std::uint32_t> tried = planner.plan(mid);
        if (accepts(tried)) {
          hi = mid;
          path = std::move(tried);
        } else {
          lo = mid;
        }
      }
    }
    tolerance = hi;
  }
  plan.tolerance = tolerance;

  planner.measure_exactly(path, tolerance);
  plan.layers = layers_of(path);
  for (std::uint32_t e : path) {
    plan.distance.push_back(planner.exact(e));
    plan.met.push_back(planner.exact(e) <= tolerance);
    if (!plan.met.back()) ++plan.unmet;
  }
  plan.flats = placements(flats, plan.layers);
  plan.measured = planner.measured();
  plan.rounds = planner.rounds();
  return plan;
}

}  // namespace geometry
