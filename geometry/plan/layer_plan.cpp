#include "geometry/plan/layer_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <thread>
#include <tuple>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "geometry/analysis/layer_analysis.h"
#include "geometry/plan/slab_bound.h"
#include "geometry/plan/swept_volume.h"

namespace geometry {
namespace {

// Heights closer than this are one height, mm: far below any printer's step, and above the
// rounding of a binary STL's 32-bit coordinates (a flat top at 11.2 mm reads 11.1999998, and
// the boundary that lands it is put at the flat's own height, so that the flat lies on it).
constexpr double kSameHeight = 1e-4;

// The share of a plan's height whose D a by-height percentile bounds (budget_by_height).
constexpr double kByHeightShare = 0.95;

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
  // Levels one height apart but for a binary STL's rounding (4.13 read as 4.1300001 and
  // 4.1299996) are one level.
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end(), [](double a, double b) { return b - a <= kSameHeight; }),
                heights.end());
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

namespace {

// One segment of a uniform plan between two boundaries it must reach: the landed height (the
// level, or with fixed steps the nearest height they reach) and what each of its layers adds
// to the plan's thickness, mm.
struct Segment {
  double z;
  std::vector<double> extra;  // mm, per layer of the segment
};

// With fixed steps (`step` > 0): `count` layers of `thickness` from `bottom`, a step at a time
// thicker or thinner (one per layer from the top of the segment down, again while steps are
// left) until they reach the height the steps reach nearest to `level` (8.03 mm on 8.05);
// nothing if the allowed thicknesses cannot.
std::optional<Segment> stepped_segment(double bottom, double level, std::size_t count, double thickness,
                                       const AllowedThicknesses& allowed, double step) {
  const double gap = level - bottom;
  Segment found{level, std::vector<double>(count, 0)};
  const double steps = (gap - static_cast<double>(count) * thickness) / step;
  long units = std::lround(steps);
  const double reached = bottom + static_cast<double>(count) * thickness + static_cast<double>(units) * step;
  if (std::abs(reached - level) > kSameHeight) found.z = reached;
  // How many steps a layer may grow or shrink and stay allowed.
  long room_up = 0, room_down = 0;
  while (allowed.allows(thickness + static_cast<double>(room_up + 1) * step)) ++room_up;
  while (allowed.allows(thickness - static_cast<double>(room_down + 1) * step)) ++room_down;
  std::vector<long> taken(count, 0);
  for (long pass = 0; units != 0 && pass <= std::max(room_up, room_down); ++pass) {
    for (std::size_t k = count; k-- > 0 && units != 0;) {
      if (units > 0 && taken[k] < room_up) ++taken[k], --units;
      if (units < 0 && -taken[k] < room_down) --taken[k], ++units;
    }
  }
  if (units != 0) return std::nullopt;
  for (std::size_t k = 0; k < count; ++k) found.extra[k] = static_cast<double>(taken[k]) * step;
  return found;
}

// With any thickness in a range: `count` layers of `thickness` from `bottom` made to end at
// `level`; thinner, every layer a little, none far from the rest; thicker, the difference on
// the top layers, as few as stay within range. Nothing if the range cannot do it.
std::optional<Segment> continuous_segment(double bottom, double level, std::size_t count, double thickness,
                                          const AllowedThicknesses& allowed) {
  Segment found{level, std::vector<double>(count, 0)};
  double left = (level - bottom) - static_cast<double>(count) * thickness;
  if (left < 0) {
    const double each = left / static_cast<double>(count);
    if (thickness + each < allowed.thinnest() - kSameHeight) return std::nullopt;
    std::fill(found.extra.begin(), found.extra.end(), each);
    return found;
  }
  for (std::size_t k = count; k-- > 0 && std::abs(left) > kSameHeight;) {
    const double room = left > 0 ? allowed.thickest() - thickness : allowed.thinnest() - thickness;
    found.extra[k] = left > 0 ? std::min(left, room) : std::max(left, room);
    left -= found.extra[k];
  }
  if (std::abs(left) > kSameHeight) return std::nullopt;
  return found;
}

// Fills [bottom, level] with about `count` layers of about `thickness` (enough that none must
// be thicker than allowed, few enough that none is thinner); `step` the spacing of the heights
// the thicknesses reach (0: any in the range).
std::optional<Segment> fill_segment(double bottom, double level, std::size_t count, double thickness,
                                    const AllowedThicknesses& allowed, double step) {
  const double gap = level - bottom;
  while (gap / static_cast<double>(count) > allowed.thickest() + kSameHeight) ++count;
  while (count > 1 && gap / static_cast<double>(count) < allowed.thinnest() - kSameHeight) --count;
  return step > 0 ? stepped_segment(bottom, level, count, thickness, allowed, step)
                  : continuous_segment(bottom, level, count, thickness, allowed);
}

// The segment landing `level` from `bottom`: as many layers as the grid's nearest to the level
// asks for; half way, one more, thinner ones (they follow a slope closer and keep an overhang
// within its reach, for a layer's time), not fewer thicker ones. If the thicknesses cannot do
// that, the other way.
std::optional<Segment> landing_segment(double bottom, double level, double thickness,
                                       const AllowedThicknesses& allowed, double step) {
  const double needed = (level - bottom) / thickness;
  const std::size_t most = static_cast<std::size_t>(std::max(1.0, std::ceil(needed - 1e-6)));
  const std::size_t fewest = static_cast<std::size_t>(std::max(1.0, std::floor(needed + 1e-6)));
  const bool thinner = needed - std::floor(needed + 1e-6) >= 0.5 - 1e-6;
  std::optional<Segment> found = fill_segment(bottom, level, thinner ? most : fewest, thickness, allowed, step);
  if (!found && fewest != most) found = fill_segment(bottom, level, thinner ? fewest : most, thickness, allowed, step);
  return found;
}

// The segment's layers after `layers`, from `bottom`; each boundary from the segment's bottom,
// not accumulated, as uniform_layers does.
void append_segment(std::vector<Layer>& layers, double bottom, double thickness, const Segment& segment) {
  double z_lo = bottom;
  double offset = 0;
  const std::size_t count = segment.extra.size();
  for (std::size_t k = 0; k < count; ++k) {
    offset += segment.extra[k];
    const double z_hi = k + 1 == count ? segment.z : bottom + static_cast<double>(k + 1) * thickness + offset;
    layers.push_back({z_lo, z_hi});
    z_lo = z_hi;
  }
}

}  // namespace

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
  for (double level : flats) {
    if (level - bottom < allowed.thinnest() - kSameHeight) continue;  // too close to the one before
    const std::optional<Segment> found = landing_segment(bottom, level, thickness, allowed, step);
    if (!found) continue;  // left where the plain grid puts it
    append_segment(layers, bottom, thickness, *found);
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
// candidate slabs (edges) starting there; every plan ends at one of the nodes `ends`.
struct HeightGrid {
  std::vector<double> z;
  std::vector<std::uint32_t> edge_begin;  // edges of node i: [edge_begin[i], edge_begin[i+1])
  std::vector<std::uint32_t> edge_to;
  std::vector<std::uint32_t> edge_from;
  std::vector<char> edge_thinnest;        // the thinnest thickness (or the fixed first layer)
  std::vector<char> edge_empty;           // into an end, and prints nothing (mark_empty_ends)
  std::vector<std::uint32_t> ends;
};

// Marks the layers into an end that print nothing (`prints`): a tip no bead fits in, the last
// 0.145 mm of a 45-degree pyramid, narrower than 0.3 mm. A plan ending in one is the plan
// below it: the layer is not printed, so it is not counted against a budget, nor kept.
void mark_empty_ends(HeightGrid& g, const std::function<bool(const Layer&)>& prints) {
  std::vector<char> is_end(g.z.size(), 0);
  for (std::uint32_t end : g.ends) is_end[end] = 1;
  std::vector<std::uint32_t> last;  // the edges into an end
  for (std::uint32_t e = 0; e < g.edge_to.size(); ++e) {
    if (is_end[g.edge_to[e]] && g.edge_from[e] != 0) last.push_back(e);
  }
  g.edge_empty.assign(g.edge_to.size(), 0);
  tbb::parallel_for(std::size_t{0}, last.size(), [&](std::size_t k) {
    g.edge_empty[last[k]] = !prints(Layer{g.z[g.edge_from[last[k]]], g.z[g.edge_to[last[k]]]});
  });
}

// Every height the thicknesses reach from the first layer's top, the flat levels (`targets`,
// on reachable heights already: flat_targets) and, for a printer of any thickness in a
// range, the top itself. A plan ends at the lowest reachable height at or above the top, or
// the next if that is within a step of the top (a tip the thinnest layers pass rather than
// land with a thicker one): never more than the printer's step above the part (with a range,
// at the top).
// With `prints`, the layers into an end that print nothing are marked (mark_empty_ends).
HeightGrid height_grid(double top, const AllowedThicknesses& allowed,
                       std::span<const double> targets, double grid,
                       const std::function<bool(const Layer&)>& prints = {}) {
  HeightGrid g;
  const bool stepped = reach_unit(allowed) > 0;
  const double unit = stepped ? std::max(1e-3, reach_unit(allowed)) : grid;
  const double first = allowed.first > 0 ? allowed.first : 0;
  // Heights counted in whole nanometres, so that 0.3 + 74 x 0.05 is 4.0, not 3.9999999999999996.
  const long long first_nm = nanometres(first), unit_nm = std::max(1LL, nanometres(unit));
  const long long last_nm = nanometres(top + allowed.thickest());
  std::vector<double> heights{0};
  for (long long k = first > 0 ? 0 : 1; first_nm + k * unit_nm <= last_nm; ++k) {
    heights.push_back(static_cast<double>(first_nm + k * unit_nm) * 1e-6);
  }
  std::vector<double> own(targets.begin(), targets.end());  // heights kept as they are
  if (!stepped) own.push_back(top);
  std::sort(own.begin(), own.end());
  heights.insert(heights.end(), own.begin(), own.end());
  std::sort(heights.begin(), heights.end());
  for (double z : heights) {
    if (!g.z.empty() && z - g.z.back() <= kSameHeight) {
      if (std::binary_search(own.begin(), own.end(), z)) g.z.back() = z;
      continue;
    }
    g.z.push_back(z);
  }

  const std::size_t n = g.z.size();
  const auto add_edges = [&](std::size_t i) {
    if (i == 0 && first > 0) {
      for (std::size_t j = 1; j < n; ++j) {
        if (std::abs(g.z[j] - first) <= kSameHeight) {
          g.edge_to.push_back(static_cast<std::uint32_t>(j));
          g.edge_from.push_back(0);
          g.edge_thinnest.push_back(1);
        }
      }
      return;
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
  };
  // Which nodes the edges reach, bottom up; the ends are the lowest reached at or above the
  // top and the next if it is within a step of the top.
  std::vector<char> reached(n, 0);
  reached[0] = 1;
  g.edge_begin.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    g.edge_begin[i] = static_cast<std::uint32_t>(g.edge_to.size());
    if (i > 0 && g.z[i] >= top - kSameHeight) {
      const bool within = g.ends.empty() || (stepped && g.z[i] <= top + unit + kSameHeight);
      if (reached[i] && within) g.ends.push_back(static_cast<std::uint32_t>(i));
      continue;  // at or above the top: done
    }
    add_edges(i);
    for (std::uint32_t e = g.edge_begin[i]; e < g.edge_to.size(); ++e) {
      if (reached[i]) reached[g.edge_to[e]] = 1;
    }
  }
  g.edge_begin[n] = static_cast<std::uint32_t>(g.edge_to.size());
  if (prints) mark_empty_ends(g, prints);
  else g.edge_empty.assign(g.edge_to.size(), 0);
  return g;
}

// The flat levels a plan can land, at the heights that land them (with a printer's fixed
// steps, a height they reach from the first layer within kSameHeight of the level: a binary
// STL's rounding), and those off every height the steps reach (the knob's ledge at 15.62 mm,
// between 15.60 and 15.65 at 0.3 + k x 0.05), which some layer holds inside whatever the plan.
struct FlatTargets {
  std::vector<double> landed, off_grid;
};
FlatTargets flat_targets(std::span<const double> flats, const AllowedThicknesses& allowed) {
  FlatTargets targets;
  for (double z : flats) {
    double target = z;
    if (reach_unit(allowed) > 0) {
      const long long unit = nanometres(reach_unit(allowed));
      const long long first = nanometres(std::max(0.0, allowed.first));
      const long long k = std::llround(static_cast<double>(nanometres(z) - first) / static_cast<double>(unit));
      target = static_cast<double>(first + std::max(0LL, k) * unit) * 1e-6;
    }
    if (std::abs(target - z) <= kSameHeight) {
      targets.landed.push_back(z);
    } else {
      targets.off_grid.push_back(z);
    }
  }
  return targets;
}

// What a search asks of its layers: each within `tolerance` or counted over it (PathCost),
// and none at all above `most` (a budget's plan keeps the max D of the least tolerance's).
struct Limits {
  double tolerance = 0;
  double most = INFINITY;
  // A by-height cap (budget_by_height): a layer over the tolerance counts by its height
  // whatever its thickness, never as a landing term, and its D past it is not ranked.
  bool by_height = false;
  bool operator==(const Limits&) const = default;
};

// What one candidate adds to a path's cost at a search's limits (PathCost::through), worked
// out once per candidate and limits and again only where the candidate is measured or bounded
// anew: the searches relax every candidate above a changed node in every round (the bunny on
// generic-marlin at --tolerance 0.3: 7,656 rounds over 129,481 candidates), and reading the
// dozen per-candidate facts behind it each time cost more than the search's own arithmetic.
struct EdgeStep {
  enum Over : std::uint8_t { kWithin, kLanding, kUnmet };
  double swept = 0;              // mm^3
  std::uint32_t to = 0;          // the node it ends at
  std::uint32_t thickness = 0;   // nm
  std::uint32_t flats = 0;       // flat levels it crosses
  Over over = kWithin;           // within the tolerance, or counted as a landing or unmet layer
  bool usable = false;           // LazyPlanner::usable
  bool printed = false;          // a layer that prints (not a last one printing nothing)
  bool unsettled = false;
  bool forced = false;           // holds a flat level no allowed layer lands (measured exactly)
  bool excess = false;           // unmet under a ceiling: its D past the tolerance counts too
};

// A path's cost in the tolerance's objective, compared in this order: flat levels crossed
// (of those an allowed layer lands); over the layers holding a flat level no allowed layer
// lands (every plan has one per such level) and past the tolerance, their height, then their
// largest D past it, then the sum of those (Alexa et al.'s min-max objective for the layers
// the flat levels force over the tolerance: for the knob's ledge at 15.62 mm, a 0.15 mm layer
// cut below it, its walls 4.545 mm inside the dome's rim, errs less than one cut above it,
// its walls 4.560 mm outside the grip's top; thin first, since a thicker one, though its D
// may be a little less, puts more height over the tolerance); layers thicker than the thinnest yet over the tolerance (the only way to
// land a flat level or the top the thinnest layers miss: on a slope too shallow for the
// tolerance between two flat levels 0.5 mm apart, 0.15 mm layers cannot land both), the
// height of the thinnest layers over it (not their count: more of them, thinner, are no
// worse, and a budget can spend layers there); under a budget then their D past it times
// their thickness (of boundaries as high over it, those nearer it: the bunny in 207 layers
// puts one at 39.9 mm, a 0.15 mm layer of D 2.23 mm above it, without this and at 39.8 mm,
// D 1.30, with it; least_swept_path ranks a plan's end and its count of layers after the
// terms of landing, before the thinnest layers); layers; the volume swept (swept_volume.h);
// among paths equal in those, the fewest slabs not yet settled (so that the search keeps to
// what it knows instead of wandering among paths equally good by their bounds). Heights and
// D in whole nanometres: sums of thicknesses taken at different heights (0.45 - 0.3 and
// 1.25 - 1.1) differ in their last bits, which must not decide before the swept volume does.
struct PathCost {
  std::uint32_t flats = 0;
  long long forced_height = 0, forced_most = 0, forced_sum = 0;  // nm
  std::uint32_t landing = 0;
  long long landing_thickness = 0;  // of those layers, nm: the thinnest that land
  long long unmet = 0;  // height of the thinnest layers over it, nm
  long long unmet_excess = 0;  // under a budget, their D past it times their thickness, nm·mm
  std::uint32_t layers = 0;
  double swept = 0;
  std::uint32_t unsettled = 0;
  bool operator<(const PathCost& other) const {
    return std::tie(flats, forced_height, forced_most, forced_sum, landing, landing_thickness, unmet, unmet_excess,
                    layers, swept, unsettled) <
           std::tie(other.flats, other.forced_height, other.forced_most, other.forced_sum, other.landing,
                    other.landing_thickness, other.unmet, other.unmet_excess, other.layers, other.swept,
                    other.unsettled);
  }
  // The terms of landing: flat levels crossed, the layers a flat level forces over the
  // tolerance, those thicker than the thinnest over it.
  auto landing_terms() const {
    return std::make_tuple(flats, forced_height, forced_most, forced_sum, landing, landing_thickness);
  }
  // The cost of this path followed by one of cost `rest`.
  PathCost then(const PathCost& rest) const {
    PathCost c = *this;
    c.flats += rest.flats;
    c.forced_height += rest.forced_height;
    c.forced_most = std::max(c.forced_most, rest.forced_most);
    c.forced_sum += rest.forced_sum;
    c.landing += rest.landing, c.landing_thickness += rest.landing_thickness;
    c.unmet += rest.unmet, c.unmet_excess += rest.unmet_excess;
    c.layers += rest.layers;
    c.swept += rest.swept;
    c.unsettled += rest.unsettled;
    return c;
  }
  // The cost of a path with edge e of `planner` added, `step` being what e adds at `limits`
  // (LazyPlanner::step_of).
  template <class Planner>
  PathCost through(const Planner& planner, std::uint32_t e, const EdgeStep& step, Limits limits) const {
    PathCost c = *this;
    c.flats += step.flats;
    const long long thickness = step.thickness;
    if (step.forced) {
      // Measured exactly from the start (LazyPlanner::measure_forced).
      const long long past = nanometres(std::max(0.0, planner.exact(e) - limits.tolerance));
      if (past > 0) c.forced_height += thickness;
      c.forced_most = std::max(c.forced_most, past);
      c.forced_sum += past;
    }
    if (step.over == EdgeStep::kLanding) {
      c.landing += 1, c.landing_thickness += thickness;
    } else if (step.over == EdgeStep::kUnmet) {
      c.unmet += thickness;
      // A budget's search measures them exactly (a ceiling leaves them unsettled until then).
      if (step.excess) c.unmet_excess += nanometres(std::max(0.0, planner.known(e) - limits.tolerance)) * thickness / 1000000;
    }
    c.layers += step.printed;
    c.swept += step.swept;
    c.unsettled += step.unsettled;
    return c;
  }
};
const PathCost kUnreached{std::numeric_limits<std::uint32_t>::max(), 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
constexpr std::uint32_t kNoEdge = std::numeric_limits<std::uint32_t>::max();

class LazyPlanner {
 public:
  LazyPlanner(const LayerStack& stack, double top, const AllowedThicknesses& allowed,
              const FlatTargets& flats, const AdaptiveOptions& options,
              const PlanProgress& progress)
      : options_(options), progress_(progress),
        grid_(height_grid(top, allowed, flats.landed, options.grid, options.prints)), meter_(stack, options.error),
        max_thickness_(allowed.thickest()),
        fixed_first_(allowed.first > 0) {
    const std::size_t edges = grid_.edge_to.size();
    const SweptVolume swept(stack.mesh());
    const AdaptiveOptions::ThickOverhangs& thick = options.thick_overhangs;
    std::optional<ThickOverhangEstimate> overhangs;
    if (thick.overhang_angle > 0) overhangs.emplace(stack.mesh(), thick.overhang_angle, thick.bead_width);
    // Q at every node and every middle, once each (neighbouring candidates share them: on a
    // printer of fine steps the bunny's 129,481 candidates have 14,591).
    std::vector<double> below(grid_.z.size());
    tbb::parallel_for(std::size_t{0}, grid_.z.size(), [&](std::size_t i) { below[i] = swept.integral_below(grid_.z[i]); });
    std::vector<double> middle_of(edges);
    for (std::size_t e = 0; e < edges; ++e) middle_of[e] = 0.5 * (grid_.z[grid_.edge_from[e]] + grid_.z[grid_.edge_to[e]]);
    std::vector<double> middles = middle_of;
    std::sort(middles.begin(), middles.end());
    middles.erase(std::unique(middles.begin(), middles.end()), middles.end());
    std::vector<double> below_middle(middles.size());
    tbb::parallel_for(std::size_t{0}, middles.size(), [&](std::size_t k) { below_middle[k] = swept.integral_below(middles[k]); });
    swept_.resize(edges);
    crossed_.resize(edges);
    forced_.resize(edges);
    refused_.assign(edges, 0);
    tbb::parallel_for(std::size_t{0}, edges, [&](std::size_t e) {
      const double a = grid_.z[grid_.edge_from[e]], b = grid_.z[grid_.edge_to[e]];
      const double middle = below_middle[std::lower_bound(middles.begin(), middles.end(), middle_of[e]) - middles.begin()];
      swept_[e] = std::max(0.0, below[grid_.edge_from[e]] + below[grid_.edge_to[e]] - 2 * middle);
      crossed_[e] = static_cast<std::uint32_t>(crossed(flats.landed, a, b));
      forced_[e] = crossed(flats.off_grid, a, b) > 0;
      refused_[e] = overhangs && !grid_.edge_thinnest[e] && (*overhangs)(a, b) > thick.min_area;
    });
    for (std::uint32_t e = 0; e < edges; ++e) span_ = std::max(span_, grid_.edge_to[e] - grid_.edge_from[e]);
    // The edges into each node, in the order of the nodes they come from (a counting sort of
    // the edges, which are numbered so), and the highest node any comes from.
    const std::size_t nodes = grid_.z.size();
    in_begin_.assign(nodes + 1, 0);
    for (std::uint32_t e = 0; e < edges; ++e) ++in_begin_[grid_.edge_to[e] + 1];
    for (std::size_t j = 0; j < nodes; ++j) in_begin_[j + 1] += in_begin_[j];
    in_edges_.resize(edges);
    std::vector<std::uint32_t> next(in_begin_.begin(), in_begin_.end() - 1);
    for (std::uint32_t e = 0; e < edges; ++e) in_edges_[next[grid_.edge_to[e]]++] = e;
    wave_from_.assign(nodes, 0);
    for (std::uint32_t e = 0; e < edges; ++e) {
      wave_from_[grid_.edge_to[e]] = std::max<std::size_t>(wave_from_[grid_.edge_to[e]], grid_.edge_from[e] + 1);
    }
    lower_.assign(edges, 0);
    exact_.assign(edges, NAN);
    proven_.assign(edges, NAN);
    counted_.assign(edges, 0);
    ends_within_.assign(edges, NAN);
  }

  // The candidates holding a flat level no allowed layer lands, measured exactly (a few dozen
  // per level): a path's cost takes their D past the tolerance, not only whether it is past.
  void measure_forced(double tolerance) {
    std::vector<std::uint32_t> edges;
    for (std::uint32_t e = 0; e < forced_.size(); ++e) {
      if (forced_[e]) edges.push_back(e);
    }
    measure(edges, tolerance, 0, false, true);
  }

  // Every candidate measured exactly: the search then needs one round.
  void measure_all(double tolerance) {
    std::vector<std::uint32_t> all(grid_.edge_to.size());
    std::iota(all.begin(), all.end(), 0u);
    measure(all, tolerance, tolerance, false, true);
  }

  // The slabs of a path not measured exactly (only shown within a tolerance), measured
  // exactly: a plan gives every layer's D (of the first contour within `tolerance`, else the
  // least). (Counted once among the measured.)
  void measure_exactly(const std::vector<std::uint32_t>& path, double tolerance) {
    std::vector<std::uint32_t> inexact;
    for (std::uint32_t e : path) {
      if (std::isnan(exact_[e])) inexact.push_back(e);
    }
    measure(inexact, tolerance, 0, false, false);
  }

  std::size_t candidates() const { return grid_.edge_to.size(); }
  std::size_t refused() const { return static_cast<std::size_t>(std::count(refused_.begin(), refused_.end(), 1)); }
  std::size_t measured() const { return measured_; }
  std::size_t rounds() const { return rounds_; }

  // The optimum at `tolerance` (PathCost's order), every slab on it settled: its edges,
  // bottom up. `settle`: a slab is measured only until it is seen within the tolerance or
  // past it (a search at one tolerance); else exactly (a budget's, which tries many).
  // `by_swept`: the swept volume decides among paths of as many layers (else the first found).
  std::vector<std::uint32_t> plan(double tolerance, bool settle, bool by_swept = true) {
    const Limits limits{tolerance};
    return lazily(limits, settle, [&] { return shortest_path(limits, by_swept); }, batch_);
  }

  // The least swept volume in at most `budget` layers at `limits` (least_swept_path's order),
  // every slab on it settled.
  std::vector<std::uint32_t> plan_within(std::size_t budget, Limits limits) {
    return lazily(limits, true, [&] { return least_swept_path(budget, limits); }, kBudgetBatch);
  }

  // Whether an edge may be within the tolerance, as far as is known (its D or a lower
  // bound), and whether that is settled (known within, or known past it).
  bool may_meet(std::uint32_t e, double tolerance) const {
    if (!std::isnan(exact_[e])) return exact_[e] <= tolerance;
    return proven_[e] <= tolerance || lower_[e] <= tolerance;
  }
  // A budget's limits from the plan of its least tolerance (measured exactly), over the layers
  // above a fixed first one: that tolerance, or if higher the by-height 95th percentile of D
  // of those layers less the thinnest ones above the percentile of them all (as thin as the
  // printer goes, they are over it in every plan; counted, they lift the cap by their share
  // of the height: on the bunny's hole-filled base, 2 mm of 0.15 mm layers of D up to 4.7 mm,
  // from 0.447 to 0.63 mm at 290 layers); and its largest D.
  Limits budget_limits(const std::vector<std::uint32_t>& path, double tolerance) const {
    std::vector<std::tuple<double, double, bool>> layers;  // (D, thickness, the thinnest)
    double most = 0;
    for (std::uint32_t e : path) {
      if (fixed_first(e) || !printed(e)) continue;
      layers.push_back({exact_[e], thickness(e), thinnest(e)});
      most = std::max(most, exact_[e]);
    }
    std::sort(layers.begin(), layers.end());
    // The by-height 95th percentile of D of the layers, less the thinnest above `above`.
    const auto percentile = [&](double above) {
      double total = 0, covered = 0, found = 0;
      for (const auto& [d, t, thin] : layers) total += thin && d > above ? 0 : t;
      for (const auto& [d, t, thin] : layers) {
        if (thin && d > above) continue;
        covered += t;
        found = d;
        if (covered >= 0.95 * total * (1 - 1e-12)) break;
      }
      return found;
    };
    const double cap = std::max(tolerance, percentile(percentile(INFINITY)));
    return {cap, std::max(cap, most)};
  }

  // Settled: its D is known, or known within the tolerance, or known too large to take, or
  // (with no ceiling) known over the tolerance.
  bool settled(std::uint32_t e, Limits limits) const {
    return !std::isnan(exact_[e]) || proven_[e] <= limits.tolerance || lower_[e] > limits.most ||
           (!std::isfinite(limits.most) && lower_[e] > limits.tolerance);
  }
  // An edge a path may take: not refused, and not known above the ceiling (the fixed first
  // layer always).
  bool usable(std::uint32_t e, Limits limits) const {
    return !refused_[e] &&
           (fixed_first(e) || !printed(e) || (std::isnan(exact_[e]) ? lower_[e] : exact_[e]) <= limits.most);
  }
  // What e adds to a path's cost at `limits` (PathCost::through). (A last layer that prints
  // nothing has no D of its own: the tip above it is left out whatever the plan.)
  EdgeStep step_of(std::uint32_t e, Limits limits) const {
    EdgeStep step;
    step.swept = swept_[e];
    step.to = grid_.edge_to[e];
    step.thickness = static_cast<std::uint32_t>(nanometres(thickness(e)));
    step.flats = crossed_[e];
    step.printed = printed(e) != 0;
    step.forced = forced_[e] != 0;
    step.usable = usable(e, limits);
    step.unsettled = !settled(e, limits);
    const bool over = step.printed && !step.forced && !may_meet(e, limits.tolerance);
    if (over && (limits.by_height || thinnest(e))) {
      step.over = EdgeStep::kUnmet;
      step.excess = !limits.by_height && std::isfinite(limits.most);
    } else if (over) {
      step.over = EdgeStep::kLanding;
    }
    return step;
  }
  bool fixed_first(std::uint32_t e) const { return fixed_first_ && grid_.edge_from[e] == 0; }
  bool thinnest(std::uint32_t e) const { return grid_.edge_thinnest[e]; }
  // 1 for a layer that prints, 0 for a last layer that prints nothing (mark_empty_ends).
  std::uint32_t printed(std::uint32_t e) const { return grid_.edge_empty[e] ? 0 : 1; }
  double thickness(std::uint32_t e) const { return grid_.z[grid_.edge_to[e]] - grid_.z[grid_.edge_from[e]]; }
  double exact(std::uint32_t e) const { return exact_[e]; }
  double known(std::uint32_t e) const { return std::isnan(exact_[e]) ? lower_[e] : exact_[e]; }  // or a lower bound
  double swept(std::uint32_t e) const { return swept_[e]; }
  // D of the region the layer prints (AdaptiveOptions::printed), measured the first time it is
  // asked for; where the plan measures that contour itself, its exact D.
  double printed_distance(std::uint32_t e) {
    const ContourStrategy* strategy = options_.printed;
    if (strategy == nullptr || (options_.contours.size() == 1 && options_.contours.front() == strategy)) {
      return exact_[e];
    }
    if (const auto it = printed_.find(e); it != printed_.end()) return it->second;
    const ContourStrategy* const strategies[] = {strategy};
    const double d = meter_(grid_.z[grid_.edge_from[e]], grid_.z[grid_.edge_to[e]], strategies).distance();
    printed_.emplace(e, d);
    return d;
  }
  std::size_t missed(std::uint32_t e) const { return missed_.count(e) ? missed_.at(e) : 0; }
  std::uint32_t crossed_flats(std::uint32_t e) const { return crossed_[e]; }
  bool forced(std::uint32_t e) const { return forced_[e]; }
  double z(std::uint32_t node) const { return grid_.z[node]; }
  std::uint32_t from(std::uint32_t e) const { return grid_.edge_from[e]; }
  std::uint32_t to(std::uint32_t e) const { return grid_.edge_to[e]; }

 private:
  // LazySP (Dellin and Srinivasa 2016): the best path by what is known, every edge not
  // measured taken at its lower bound (a D of 0 unless a measurement bounds it: honest, so a
  // path whose every edge is settled is the optimum); its unsettled edges measured, lowest
  // first (a slab found past the tolerance reroutes the path above it, so measuring the rest
  // of this path would mostly be wasted), at most `batch` at a time, until none is left.
  // A slab is measured until it is seen past the ceiling, or with no ceiling the tolerance;
  // with `settle`, only until it is seen within the tolerance.
  template <class Search>
  std::vector<std::uint32_t> lazily(Limits limits, bool settle, const Search& search, std::size_t batch) {
    const double refute = std::isfinite(limits.most) ? limits.most : limits.tolerance;
    for (;;) {
      ++rounds_;
      std::vector<std::uint32_t> path = search();
      std::vector<std::uint32_t> unsettled;
      for (std::uint32_t e : path) {
        if (!settled(e, limits)) unsettled.push_back(e);
      }
      if (unsettled.empty()) return path;
      // Most candidates a path tries are refused, and most of those by their end sections
      // alone; a slab is measured in full only once the next few unsettled slabs of its path
      // all pass that (the bunny on generic-marlin at --tolerance 0.3: 3,459 slabs measured
      // in full, 2,427 of them found within it, instead of 30,753 and 4,720).
      if (refuted_by_ends({unsettled.begin(), std::min(unsettled.end(), unsettled.begin() + 2 * batch)}, refute)) {
        continue;
      }
      if (unsettled.size() > batch) unsettled.resize(batch);
      // The sections far below are rarely wanted again (the path below is settled); let go of
      // them a layer's worth at a time (each time goes through every section kept).
      const double below = grid_.z[grid_.edge_from[unsettled.front()]] - 2 * max_thickness_;
      if (below > forgotten_ + max_thickness_) meter_.forget_below(below), forgotten_ = below;
      measure(unsettled, limits.tolerance, refute, settle, true);
    }
  }

  std::vector<std::uint32_t> path_to(std::uint32_t node, const std::vector<std::uint32_t>& via) const {
    std::vector<std::uint32_t> path;
    for (std::uint32_t i = node; i != 0 && via[i] != kNoEdge; i = grid_.edge_from[via[i]]) path.push_back(via[i]);
    std::reverse(path.begin(), path.end());
    return path;
  }

  // The search of `plan` by PathCost's order over the grid, a dynamic program over the nodes
  // bottom up (every edge goes up). The costs are kept from one round of `lazily` to the next:
  // a node's cost depends only on the edges below it, so where the same limits are searched
  // again only the nodes above the lowest whose edges were measured since (Search::dirty) are
  // worked out again, from the edges into them, in the same order as a search from the bed,
  // so that ties go the same way (up to the cut below). On a printer of fine steps that is
  // most of the search: the cap (tests/bench/models/cap.scad) at --tolerance 0.1 on
  // generic-marlin runs 2,800 rounds over 43,681 candidates.
  std::vector<std::uint32_t> shortest_path(Limits limits, bool by_swept) {
    const std::size_t n = grid_.z.size();
    Search& s = search_;
    // The nodes from `cut` up have no candidate measured or bounded yet: the best way from each
    // to an end is the untouched grid's (untouched_rest), so the search works out only the
    // nodes below, and those above as far as the candidates from below reach, a few layers'
    // worth where the measuring goes bottom up, not the height left above them (the bunny on
    // generic-marlin at --tolerance 0.3 searches 7,656 times). Of paths equal
    // in every term, the swept volume summed to the last bit, the one kept may differ from a
    // search over the whole grid's; where the swept volume does not decide (by_swept false)
    // the first found of as many layers is the whole grid's, so the search is.
    const std::size_t cut = options_.search_afresh || !by_swept ? n : std::min(n, std::max<std::size_t>(1, touched_top_ + 1));
    std::size_t from = 0;  // the nodes above it are worked out again
    if (!options_.search_afresh && s.cost.size() == n && s.limits == limits && s.by_swept == by_swept) {
      // The nodes from the last search's cut up hold only what the edges from below it give.
      from = std::min({s.dirty, s.cut - 1, n});
    } else {
      s.cost.assign(n, kUnreached);
      s.via.assign(n, kNoEdge);
      s.cost[0] = {};
      s.limits = limits, s.by_swept = by_swept;
    }
    s.dirty = n;
    s.cut = cut;
    const std::size_t reach = std::min(n, cut + span_);  // the nodes the edges from below the cut reach
    // The nodes worked out again: above `from`, up to those the edges from below the cut reach.
    const auto redone_lo = static_cast<std::ptrdiff_t>(std::min(from + 1, n));
    const auto redone_hi = std::max(static_cast<std::ptrdiff_t>(reach), redone_lo);
    std::fill(s.cost.begin() + redone_lo, s.cost.begin() + redone_hi, kUnreached);
    std::fill(s.via.begin() + redone_lo, s.via.begin() + redone_hi, kNoEdge);
    const EdgeStep* const steps = up_to_date(s.steps, limits).data();
    // Edges into the nodes above `from` start at most span_ nodes below them.
    for (std::size_t i = from > span_ ? from - span_ : 0; i < cut; ++i) {
      if (!(s.cost[i] < kUnreached)) continue;
      for (std::uint32_t e = grid_.edge_begin[i]; e < grid_.edge_begin[i + 1]; ++e) {
        const EdgeStep& step = steps[e];
        const std::uint32_t j = step.to;
        if (j <= from || !step.usable) continue;
        PathCost through = s.cost[i].through(*this, e, step, limits);
        if (!by_swept) through.swept = 0;
        if (through < s.cost[j]) s.cost[j] = through, s.via[j] = e;
      }
    }
    // The best end below the cut, or way through the first node at or above it.
    PathCost best = kUnreached;
    std::uint32_t end = grid_.ends.empty() ? 0 : grid_.ends.front();
    for (std::uint32_t i : grid_.ends) {
      if (i < cut && s.cost[i] < best) best = s.cost[i], end = i;
    }
    if (cut == n) return path_to(end, s.via);
    const Rest& rest = untouched_rest(limits);
    for (std::size_t j = cut; j < reach; ++j) {
      if (!(s.cost[j] < kUnreached) || !(rest.cost[j] < kUnreached)) continue;
      const PathCost total = s.cost[j].then(rest.cost[j]);
      if (total < best) best = total, end = static_cast<std::uint32_t>(j);
    }
    std::vector<std::uint32_t> path = path_to(end, s.via);
    for (std::uint32_t i = end; i >= cut && rest.next[i] != kNoEdge; i = grid_.edge_to[rest.next[i]]) path.push_back(rest.next[i]);
    return path;
  }

  // The best way from each node to an end over the grid as it was before any candidate was
  // measured (every candidate within the tolerance as far as is known, none settled), by
  // PathCost's order: its cost and first edge. Worked out once, the first time a search asks;
  // it holds for the nodes no candidate from which has been measured or bounded since.
  struct Rest {
    std::vector<PathCost> cost;
    std::vector<std::uint32_t> next;
  };
  const Rest& untouched_rest(Limits limits) {
    Rest& rest = rest_;
    if (!rest.cost.empty()) return rest;
    const std::size_t n = grid_.z.size();
    rest.cost.assign(n, kUnreached);
    rest.next.assign(n, kNoEdge);
    for (std::uint32_t i : grid_.ends) rest.cost[i] = {};
    for (std::size_t i = n; i-- > 0;) {
      for (std::uint32_t e = grid_.edge_begin[i]; e < grid_.edge_begin[i + 1]; ++e) {
        const EdgeStep step = step_of(e, limits);
        if (!step.usable || !(rest.cost[step.to] < kUnreached)) continue;
        const PathCost way = PathCost{}.through(*this, e, step, limits).then(rest.cost[step.to]);
        if (way < rest.cost[i]) rest.cost[i] = way, rest.next[i] = e;
      }
    }
    return rest;
  }

  // The least-cost path of at most `budget` edges: by the terms of landing (PathCost), the
  // lowest end, the most edges, then the rest of PathCost's order (the thinnest layers over
  // the cap by height, then by excess, the swept volume). A dynamic
  // program over (node, edges used), each node's counts limited to those a path through it
  // can have (at least the fewest edges reaching it, at most the budget less the fewest from
  // it to the end).
  std::vector<std::uint32_t> least_swept_path(std::size_t budget, Limits limits) {
    const std::size_t n = grid_.z.size();
    constexpr std::uint32_t kFar = std::numeric_limits<std::uint32_t>::max() / 2;
    std::vector<std::uint32_t> fewest_to(n, kFar), fewest_from(n, kFar);
    fewest_to[0] = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (fewest_to[i] == kFar) continue;
      for (std::uint32_t e = grid_.edge_begin[i]; e < grid_.edge_begin[i + 1]; ++e) {
        if (usable(e, limits)) fewest_to[grid_.edge_to[e]] = std::min(fewest_to[grid_.edge_to[e]], fewest_to[i] + printed(e));
      }
    }
    for (std::uint32_t end : grid_.ends) fewest_from[end] = 0;
    for (std::size_t i = n; i-- > 0;) {
      for (std::uint32_t e = grid_.edge_begin[i]; e < grid_.edge_begin[i + 1]; ++e) {
        if (usable(e, limits)) fewest_from[i] = std::min(fewest_from[i], fewest_from[grid_.edge_to[e]] + printed(e));
      }
    }
    // A budget below the fewest layers: the fewest layers' optimum.
    std::size_t fewest = kFar;
    for (std::uint32_t end : grid_.ends) fewest = std::min<std::size_t>(fewest, fewest_to[end]);
    if (fewest == kFar) return {};
    const std::size_t most = std::max(budget, fewest);
    std::vector<std::size_t> offset(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const bool on_a_path = fewest_to[i] != kFar && fewest_from[i] != kFar && fewest_to[i] + fewest_from[i] <= most;
      offset[i + 1] = offset[i] + (on_a_path ? most - fewest_from[i] - fewest_to[i] + 1 : 0);
    }
    // The states' costs are kept from the round before (as shortest_path's) where the limits,
    // the budget and so every node's range of counts are the same: the states of the nodes above
    // the lowest whose edges were measured since are worked out again, from the edges into them.
    BudgetSearch& kept = budget_search_;
    std::size_t from = 0;
    if (!options_.search_afresh && kept.budget == budget && kept.limits == limits && kept.fewest_to == fewest_to &&
        kept.fewest_from == fewest_from && kept.cost.size() == offset[n]) {
      from = std::min(kept.dirty, n);
    } else {
      kept.cost.assign(offset[n], kUnreached);
      kept.via.assign(offset[n], kNoEdge);
      kept.budget = budget, kept.limits = limits;
      kept.fewest_to = fewest_to, kept.fewest_from = fewest_from;
      if (offset[n] > 0) kept.cost[0] = {};
    }
    kept.dirty = n;
    std::vector<PathCost>& cost = kept.cost;
    std::vector<std::uint32_t>& via = kept.via;
    const std::size_t above = offset[std::min(from + 1, n)];
    std::fill(cost.begin() + static_cast<std::ptrdiff_t>(above), cost.end(), kUnreached);
    std::fill(via.begin() + static_cast<std::ptrdiff_t>(above), via.end(), kNoEdge);
    const auto state = [&](std::size_t i, std::size_t k) -> std::ptrdiff_t {
      if (offset[i + 1] == offset[i] || k < fewest_to[i] || k + fewest_from[i] > most) return -1;
      return static_cast<std::ptrdiff_t>(offset[i] + k - fewest_to[i]);
    };
    const EdgeStep* const steps = up_to_date(kept.steps, limits).data();
    // Node j's states from the edges into it, in the order of the nodes they come from: the
    // order in which a search pushing from each node in turn offers them, so ties go the same
    // way. The nodes of a wave (wave_from_) take nothing from each other and are worked out side
    // by side.
    // An edge at a time over all of j's counts: each state still takes the edges in that
    // order, and an edge's share of the cost is worked out once.
    const auto pull = [&](std::size_t j) {
      if (offset[j + 1] == offset[j]) return;
      const std::size_t k_hi = most - fewest_from[j];  // j's states: counts fewest_to[j]..k_hi
      for (std::uint32_t x = in_begin_[j]; x < in_begin_[j + 1]; ++x) {
        const std::uint32_t e = in_edges_[x];
        const EdgeStep& step = steps[e];
        const std::uint32_t i = grid_.edge_from[e];
        if (!step.usable || offset[i + 1] == offset[i]) continue;
        PathCost share = PathCost{}.through(*this, e, step, limits);
        share.layers = 0;  // the budget counts them
        // From i's state of k - printed layers, where it has one.
        const std::size_t first = std::max<std::size_t>(fewest_to[j], fewest_to[i] + step.printed);
        const std::size_t last = std::min(k_hi, most - fewest_from[i] + step.printed);
        for (std::size_t k = first; k <= last; ++k) {
          const std::size_t s = offset[i] + (k - step.printed - fewest_to[i]);
          if (!(cost[s] < kUnreached)) continue;
          const std::size_t t = offset[j] + (k - fewest_to[j]);
          const PathCost through = cost[s].then(share);
          if (through < cost[t]) cost[t] = through, via[t] = e;
        }
      }
    };
    for (std::size_t j = from + 1; j < n;) {
      std::size_t end = j + 1;
      while (end < n && wave_from_[end] <= j) ++end;
      if (end - j == 1) {
        pull(j);
      } else {
        tbb::parallel_for(j, end, [&](std::size_t t) { pull(t); });
      }
      j = end;
    }
    // Of the plans that end: the least by the terms of landing (flat levels, and the top by
    // thicker layers over the cap), then the lowest end (layer_plan.h: the lowest height the
    // layers reach at or above the top), then the most layers (the budget is the user's: the
    // bunny's 331 layers end at its top in 331, not in 330 at 50.05 mm, which leaves 0.3 mm
    // fewer of its thinnest layers over the cap), then the rest of a state's own order (the
    // height of the thinnest layers over the cap, their excess, the swept volume).
    std::ptrdiff_t best = -1;
    std::size_t best_end = 0, best_k = 0;
    const auto key = [&](std::ptrdiff_t s, std::uint32_t end, std::size_t k) {
      return std::make_tuple(cost[s].landing_terms(), grid_.z[end], -static_cast<std::ptrdiff_t>(k), cost[s].unmet);
    };
    for (std::uint32_t end : grid_.ends) {
      for (std::size_t k = fewest_to[end]; k <= most; ++k) {
        const std::ptrdiff_t s = state(end, k);
        if (s < 0 || !(cost[s] < kUnreached)) continue;
        if (best < 0 || key(s, end, k) < key(best, best_end, best_k)) best = s, best_end = end, best_k = k;
      }
    }
    std::vector<std::uint32_t> path;
    for (std::size_t i = best_end, k = best_k; best >= 0 && i != 0;) {
      const std::uint32_t e = via[state(i, k)];
      path.push_back(e);
      i = grid_.edge_from[e];
      k -= printed(e);
    }
    std::reverse(path.begin(), path.end());
    return path;
  }

  // Measures candidate slabs (in parallel). `refute` > 0: a slab that is not the thinnest is
  // measured only until it is seen past that (it cannot be printed so; the thinnest may be,
  // and is measured exactly); `settle`: one seen within `tolerance` is not measured further.
  // What is found either way bounds D from below. `counted`: the slabs are new to the search
  // (measured() and the progress count them).
  void measure(const std::vector<std::uint32_t>& edges, double tolerance, double refute,
               bool settle, bool counted) {
    if (edges.empty()) return;
    std::vector<SlabError> found(edges.size());
    tbb::parallel_for(std::size_t{0}, edges.size(), [&](std::size_t k) {
      const std::uint32_t e = edges[k];
      found[k] = meter_(grid_.z[grid_.edge_from[e]], grid_.z[grid_.edge_to[e]], options_.contours,
                        tolerance, grid_.edge_thinnest[e] ? 0 : refute, settle);
    });
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const std::uint32_t e = edges[k];
      const SlabError& error = found[k];
      if (error.exact()) {
        exact_[e] = error.distance();
      } else if (error.settled() && !(proven_[e] <= tolerance)) {
        proven_[e] = tolerance;
      }
      if (!error.trials.empty() && error.trials[error.best].missed > 0) missed_[e] = error.trials[error.best].missed;
      bound(e, error.distance());
    }
    if (!counted) return;
    for (const std::uint32_t e : edges) count(e);
    if (progress_) progress_(measured_);
  }

  // Slab e measured (or refused from its end sections): D at least d there and, as widen
  // proves, on the wider slabs cutting the same section.
  void bound(std::uint32_t e, double d) {
    touch(e);
    lower_[e] = std::max(lower_[e], d);
    widen(e, d);
  }
  // A slab measured again (exactly after settled, or by a budget's search at another
  // tolerance) is one candidate: measured() never exceeds candidates().
  void count(std::uint32_t e) {
    if (!counted_[e]) ++measured_;
    counted_[e] = 1;
  }

  // Refuses those of the slabs whose end sections alone show D past `refute`
  // (SlabMeter::ends_past, a single section contour's), as measuring them would first, and
  // then from each slab refused the next thinner one from the same height, and so on down to
  // one the ends do not refuse: where the search would turn next, a round each otherwise (the
  // bunny on generic-marlin at --tolerance 0.3: 2,671 rounds instead of 13,481). Whether any
  // was refused. The thinnest are measured exactly instead.
  bool refuted_by_ends(std::span<const std::uint32_t> slabs, double refute) {
    if (!(refute > 0) || options_.contours.size() != 1 || !options_.contours.front()->cuts_at) return false;
    const auto open = [&](std::uint32_t e) {
      return !thinnest(e) && !(ends_within_[e] <= refute) && !(lower_[e] > refute) && std::isnan(exact_[e]);
    };
    std::vector<std::uint32_t> edges;
    for (const std::uint32_t e : slabs) {
      if (open(e)) edges.push_back(e);
    }
    bool any = false;
    std::vector<double> past;
    while (!edges.empty()) {
      past.assign(edges.size(), 0);
      tbb::parallel_for(std::size_t{0}, edges.size(), [&](std::size_t k) {
        const std::uint32_t e = edges[k];
        past[k] = meter_.ends_past(grid_.z[grid_.edge_from[e]], grid_.z[grid_.edge_to[e]],
                                   *options_.contours.front(), refute);
      });
      std::vector<std::uint32_t> thinner;
      for (std::size_t k = 0; k < edges.size(); ++k) {
        const std::uint32_t e = edges[k];
        if (!(past[k] > 0)) {
          ends_within_[e] = refute;
          continue;
        }
        any = true;
        bound(e, past[k]);
        count(e);
        // The edges from a node are numbered thinnest first.
        for (std::uint32_t f = e; f-- > grid_.edge_begin[grid_.edge_from[e]];) {
          if (!open(f)) continue;
          if (std::find(thinner.begin(), thinner.end(), f) == thinner.end()) thinner.push_back(f);
          break;
        }
      }
      edges = std::move(thinner);
    }
    if (any && progress_) progress_(measured_);
    return any;
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
        if (wider.z_hi < b - kSameHeight || std::abs(cuts_at(wider) - h) > 1e-9) continue;
        if (d > lower_[f]) lower_[f] = d, touch(f);
      }
    }
  }

  const AdaptiveOptions& options_;
  const PlanProgress& progress_;
  HeightGrid grid_;
  SlabMeter meter_;
  double max_thickness_;
  bool fixed_first_;            // the first layer is the printer's: not planned
  std::vector<double> swept_;   // swept_volume.h's U of each candidate, mm^3
  std::vector<double> lower_;   // a lower bound of D (0 until measured), mm
  std::vector<double> exact_;   // D measured exactly (NaN: not), mm
  std::vector<double> proven_;  // a tolerance the slab is shown within, unmeasured (NaN: none)
  std::unordered_map<std::uint32_t, std::size_t> missed_;  // features the best trial misses
  std::unordered_map<std::uint32_t, double> printed_;  // printed_distance, once measured
  std::vector<std::uint32_t> crossed_;
  std::vector<char> forced_;   // holds a flat level no allowed layer lands
  std::vector<char> refused_;  // thick_overhangs: not a layer of any path
  std::vector<char> counted_;  // measured at least once (measured())
  // The least `refute` a slab's end sections were seen within (ends_past; NaN: none).
  std::vector<double> ends_within_;
  double forgotten_ = -std::numeric_limits<double>::infinity();  // forget_below's last height
  std::size_t measured_ = 0, rounds_ = 0;
  std::size_t batch_ = 2 * std::max(1u, std::thread::hardware_concurrency());
  // A budget's search works out a state per count of layers at every height, a round far
  // longer than measuring a slab on a printer of fine steps (the bunny on generic-marlin in
  // 845 layers: 271 s at batch_'s 4 slabs a round, 93 s at 64, within 0.1% of the slabs).
  static constexpr std::size_t kBudgetBatch = 64;
  std::uint32_t span_ = 0;               // the most nodes a candidate spans
  // The edges into node j: in_edges_[in_begin_[j]..in_begin_[j + 1]), by the node they come
  // from. wave_from_[j]: one past the highest node an edge into j comes from (0: none), so a
  // run of nodes each with wave_from_ at most the run's first takes nothing from the others.
  std::vector<std::uint32_t> in_begin_, in_edges_;
  std::vector<std::size_t> wave_from_;
  // Each search's EdgeSteps at the limits it last searched, and how many of changes_ they take in.
  struct Steps {
    std::vector<EdgeStep> of;
    Limits limits;
    std::size_t seen = 0;
  };
  // The candidates measured or bounded anew, in turn, not yet taken in by every search's steps.
  std::vector<std::uint32_t> changes_;
  // shortest_path's costs and edges in, per node, for `limits` and `by_swept`; nodes above
  // `dirty` are out of date (an edge from there measured since).
  struct Search {
    Steps steps;
    std::vector<PathCost> cost;
    std::vector<std::uint32_t> via;
    Limits limits;
    bool by_swept = false;
    std::size_t dirty = 0;
    std::size_t cut = 1;  // the nodes from here up held only what the edges from below give
  } search_;
  Rest rest_;  // untouched_rest's
  std::size_t touched_top_ = 0;  // the highest node a candidate measured or bounded starts at
  // least_swept_path's, per state, for `budget`, `limits` and the nodes' ranges of counts.
  struct BudgetSearch {
    Steps steps;
    std::vector<PathCost> cost;
    std::vector<std::uint32_t> via;
    std::vector<std::uint32_t> fewest_to, fewest_from;
    std::size_t budget = 0;
    Limits limits;
    std::size_t dirty = 0;
  } budget_search_;
  // `steps` at `limits`: worked out afresh for other limits, else again for the candidates
  // changed since; the changes every search has taken in are let go.
  const std::vector<EdgeStep>& up_to_date(Steps& steps, Limits limits) {
    const std::size_t edges = grid_.edge_to.size();
    if (options_.search_afresh || steps.of.size() != edges || !(steps.limits == limits)) {
      steps.of.resize(edges);
      tbb::parallel_for(std::size_t{0}, edges, [&](std::size_t e) {
        steps.of[e] = step_of(static_cast<std::uint32_t>(e), limits);
      });
      steps.limits = limits;
    } else {
      for (std::size_t k = steps.seen; k < changes_.size(); ++k) steps.of[changes_[k]] = step_of(changes_[k], limits);
    }
    steps.seen = changes_.size();
    std::size_t taken = changes_.size();
    for (const Steps* kept : {&search_.steps, &budget_search_.steps}) {
      if (!kept->of.empty()) taken = std::min(taken, kept->seen);
    }
    changes_.erase(changes_.begin(), changes_.begin() + static_cast<std::ptrdiff_t>(taken));
    for (Steps* kept : {&search_.steps, &budget_search_.steps}) kept->seen -= std::min(kept->seen, taken);
    return steps.of;
  }
  // Edge e measured (or bounded) anew: its step is out of date, and so are the kept costs
  // above the node it starts at.
  void touch(std::uint32_t e) {
    const std::size_t node = grid_.edge_from[e];
    changes_.push_back(e);
    touched_top_ = std::max(touched_top_, node);
    search_.dirty = std::min(search_.dirty, node);
    budget_search_.dirty = std::min(budget_search_.dirty, node);
  }
};

// The least angle from horizontal of the model's sloped surface inside [z_lo, z_hi], degrees
// (90: none but vertical).
double least_lean(const LayerStack& stack, double z_lo, double z_hi) {
  const Mesh& mesh = stack.mesh();
  double least = 90;
  for (std::uint32_t f : stack.faces_between(z_lo, z_hi)) {
    const auto& face = mesh.faces[f];
    const Vec3 a = mesh.vertices[face[0]], b = mesh.vertices[face[1]], c = mesh.vertices[face[2]];
    const double low = std::min({a.z, b.z, c.z}), high = std::max({a.z, b.z, c.z});
    if (!(high > low) || !(high > z_lo && low < z_hi)) continue;  // horizontal, or outside
    const Vec3 n = cross(b - a, c - a);
    least = std::min(least, std::atan2(std::hypot(n.x, n.y), std::abs(n.z)) * 180 / std::numbers::pi);
  }
  return least;
}

// A path's layers that print, bottom up (a last one printing nothing is left out).
std::vector<Layer> layers_of(const LazyPlanner& planner, const std::vector<std::uint32_t>& path) {
  std::vector<Layer> layers;
  for (std::uint32_t e : path) {
    if (planner.printed(e)) layers.push_back({planner.z(planner.from(e)), planner.z(planner.to(e))});
  }
  return layers;
}

// How many layers of a path print.
std::size_t printed_count(const LazyPlanner& planner, const std::vector<std::uint32_t>& path) {
  std::size_t count = 0;
  for (std::uint32_t e : path) count += planner.printed(e);
  return count;
}

// A layer budget's plan: its path, the least tolerance whose plan has at most the budget's
// layers, and, where the least-error plan was found, the limits it was found within.
struct CountPlan {
  std::vector<std::uint32_t> path;
  double tolerance = 0;
  std::optional<Limits> limits;
  bool by_height = false;  // limits' tolerance is a by-height cap (budget_by_height)
};

// A plan's layers that print (a fixed first one too: it is part of the height): the by-height
// 95th percentile of their D (kByHeightShare), their total swept volume, and the share of
// their height over `cap`.
struct PathSummary {
  double percentile = 0, swept = 0, over = 0;
};
PathSummary summarize(const LazyPlanner& planner, const std::vector<std::uint32_t>& path, double cap) {
  std::vector<double> distances, thicknesses;
  PathSummary s;
  double over = 0;
  for (std::uint32_t e : path) {
    if (!planner.printed(e)) continue;
    distances.push_back(planner.exact(e));
    thicknesses.push_back(planner.thickness(e));
    s.swept += planner.swept(e);
    if (planner.exact(e) > cap) over += planner.thickness(e);
  }
  if (distances.empty()) return s;
  s.over = over / std::accumulate(thicknesses.begin(), thicknesses.end(), 0.0);
  s.percentile = weighted_percentile(distances, thicknesses, 100 * kByHeightShare);
  return s;
}

// The largest D as printed (LazyPlanner::printed_distance) of `path`'s layers that print,
// the fixed first one too. The planned D bounds the printed one from above, so the layers are
// measured as printed in the order of their planned D, down to the first planned no higher than
// the largest printed so far.
double printed_most(LazyPlanner& planner, const std::vector<std::uint32_t>& path) {
  std::vector<std::uint32_t> layers;
  for (std::uint32_t e : path) {
    if (planner.printed(e)) layers.push_back(e);
  }
  std::sort(layers.begin(), layers.end(), [&](std::uint32_t a, std::uint32_t b) { return planner.exact(a) > planner.exact(b); });
  double most = 0;
  for (std::uint32_t e : layers) {
    if (planner.exact(e) <= most) break;
    most = std::max(most, planner.printed_distance(e));
  }
  return most;
}

// Whether a layer of `path` prints a D over `most` (measured as printed only where its
// planned D is over it).
bool prints_over(LazyPlanner& planner, const std::vector<std::uint32_t>& path, double most) {
  for (std::uint32_t e : path) {
    if (planner.printed(e) && planner.exact(e) > most && planner.printed_distance(e) > most) return true;
  }
  return false;
}

// A layer budget's plan aimed at the by-height percentile itself (layer_plan.h): where `plan`'s
// path (`base`) leaves more than the share of the height the percentile leaves out (5%) over
// its cap, the least cap between that cap and base's own percentile (to within 1% of the cap,
// bisected) at which the plan of the least height over it (Limits::by_height: over it at any
// thickness) leaves at most that share over it; taken if its percentile is lower than base's,
// its largest D as printed (printed_most: the planned one, a section's, may be far above it:
// the bottle's punt, 11 mm planned by mid, 0.3 mm printed by best) and its total swept volume
// no more.
// Each cap tried costs one least_swept_path and the measuring of the slabs new on it; the
// comparison, the layers of either plan planned over the other's largest D as printed,
// measured as printed. Taken, it replaces `plan`'s path and cap.
void budget_by_height(LazyPlanner& planner, std::size_t budget, CountPlan& plan) {
  if (!plan.limits) return;
  const std::vector<std::uint32_t>& base = plan.path;
  const double tolerance = plan.tolerance, ceiling = plan.limits->most;
  const PathSummary was = summarize(planner, base, plan.limits->tolerance);
  const auto at = [&](double cap) {
    std::vector<std::uint32_t> path = planner.plan_within(budget, Limits{cap, ceiling, true});
    if (printed_count(planner, path) > budget) path.clear();
    if (!path.empty()) planner.measure_exactly(path, tolerance);
    return path;
  };
  const auto within = [&](const std::vector<std::uint32_t>& path, double cap) {
    return !path.empty() && summarize(planner, path, cap).over <= 1 - kByHeightShare + 1e-9;
  };
  // A plan within the share at its cap has its percentile there already: no lower one is
  // sought (the cap is at least the least tolerance).
  if (!(was.over > 1 - kByHeightShare + 1e-9)) return;
  double lo = plan.limits->tolerance, hi = was.percentile;
  std::vector<std::uint32_t> best = at(hi);
  if (!within(best, hi)) return;
  while (hi - lo > 0.01 * plan.limits->tolerance) {
    const double mid = 0.5 * (lo + hi);
    std::vector<std::uint32_t> tried = at(mid);
    if (within(tried, mid)) {
      hi = mid, best = std::move(tried);
    } else {
      lo = mid;
    }
  }
  const PathSummary now = summarize(planner, best, hi);
  if (!(now.percentile < was.percentile) || now.swept > was.swept * (1 + 1e-9)) return;
  if (prints_over(planner, best, printed_most(planner, base))) return;
  plan.limits->tolerance = hi;
  plan.by_height = true;
  plan.path = std::move(best);
}

// The plan in at most `count` printed layers: the least tolerance whose plan has at most that
// many, by bisection between 0 and `thickest`'s tolerance `hi` (the thickest plan's: a budget
// it breaks gets it), then the least swept volume in at most `count` layers with no layer
// above the first over that plan's largest D and every one over the cap (budget_limits)
// counted first: the layers go where they take off the most volume, P95h D and max D no worse
// than the least tolerance's; then budget_by_height's, where it takes one.
CountPlan plan_in_count(LazyPlanner& planner, std::size_t count, const std::vector<std::uint32_t>& thickest,
                        double hi) {
  CountPlan plan{thickest, hi, std::nullopt};
  if (printed_count(planner, thickest) > count) return plan;
  double lo = 0;
  while (hi - lo > 1e-3 * std::max(1.0, hi) * 0.5) {
    const double mid = 0.5 * (lo + hi);
    std::vector<std::uint32_t> tried = planner.plan(mid, false, false);
    if (printed_count(planner, tried) <= count) {
      hi = mid;
      plan.path = std::move(tried);
    } else {
      lo = mid;
    }
  }
  plan.tolerance = hi;
  planner.measure_exactly(plan.path, hi);
  const Limits limits = planner.budget_limits(plan.path, hi);
  std::vector<std::uint32_t> least = planner.plan_within(count, limits);
  planner.measure_exactly(least, hi);
  if (!least.empty()) plan.path = std::move(least), plan.limits = limits;
  budget_by_height(planner, count, plan);
  return plan;
}

// A budget's plan: for max_layers, plan_in_count's; for `overrun` (a print time), the plan in
// count of the most layers whose plan is within it, searched for on the count between the
// thickest plan's and the thinnest layers' (a plan's time grows with its layers, nearly: a
// least-error plan of more layers puts its thin layers where the part may be wider, and the
// estimate samples its layers; the search finds a count the budget takes with the next one
// refused). Searching on the tolerance instead, whose plans' times are further from
// monotone, took 0.3997 mm on the bunny at --max-time 80min (211 layers; its least-error plan
// in those did not fit, in 207 it did) where 0.3728 mm's least-error plan fits in 217 layers:
// 3% of the budget left unspent, mean D 0.429 mm and total ΔV 174 mm³ against 0.408 and 163.
// Each count tried gets max_layers' plan, the by-height aim too, so that the count taken is
// the most whose --max-layers plan fits, and a plan made again in fewer layers (app/slice.cpp's
// keep_time_budget) is of the same kind: with the search's plans not aimed by height and the
// replans aimed, the bunny at --max-time 80min fitted 219 layers by the estimate, whose
// program was over, and took 211 after three replans (mean D 0.4056 mm, P95h D 0.6451, total
// ΔV 164.30 mm³, by `mahost analyze`); neither aimed, 218 after one (0.4072, 0.6336, 162.41);
// both aimed, 214 and no replan (0.4009, 0.6311, 162.31). The cap at --max-time 30min
// (tests/bench/models/cap.scad): 71 layers aimed against 73 not (0.1357, 0.2336, 62.31
// against 0.1320, 0.2569, 60.57), a by-height plan there taking longer per layer.
// A budget even the thickest plan breaks gets that plan. Returns the path and the tolerance
// reached; the cap and ceiling into `plan`.
std::pair<std::vector<std::uint32_t>, double> budget_path(LazyPlanner& planner, const AdaptiveOptions& options,
                                                          AdaptivePlan& plan) {
  std::vector<std::uint32_t> thickest = planner.plan(INFINITY, false);
  planner.measure_exactly(thickest, INFINITY);
  // (Its thinnest layers, the fixed first one among them, are on it whatever the tolerance.)
  double hi = 0;
  for (std::uint32_t e : thickest) {
    if (!planner.thinnest(e)) hi = std::max(hi, planner.exact(e));
  }
  hi += 1e-3;
  CountPlan taken;
  if (options.max_layers > 0) {
    taken = plan_in_count(planner, options.max_layers, thickest, hi);
  } else {
    const auto overrun = [&](const std::vector<std::uint32_t>& path) { return options.overrun(layers_of(planner, path)); };
    double fitting_over = overrun(thickest);
    if (fitting_over > 0) return {std::move(thickest), hi};
    taken = {thickest, hi, std::nullopt};
    // Counts below `fitting` are taken, from `refused` up refused (or past the thinnest plan).
    std::size_t fitting = printed_count(planner, thickest);
    const std::vector<std::uint32_t> thinnest = planner.plan(0, false, false);
    std::size_t refused = printed_count(planner, thinnest) + 1;
    double refused_over = overrun(thinnest);  // the thinnest plan's, for `refused`
    // The more layers, the longer a count's plan takes to find (the bunny on generic-marlin:
    // 47 s in 582 layers, 3 s in 315), and each takes seconds, so the count tried is where a
    // straight line between the overruns of the counts known to fit and to be refused puts
    // the budget (regula falsi), the first time a little above it, and halfway where the
    // last such step left more than half the counts open.
    bool halve = !(refused_over > 0), first = true;
    while (refused - fitting > 1) {
      std::size_t count = fitting + (refused - fitting) / 2;
      if (!halve) {
        const double share = -fitting_over / (refused_over - fitting_over);
        count = fitting + static_cast<std::size_t>(std::llround(share * static_cast<double>(refused - fitting)));
        if (first) count += std::max<std::size_t>(2, count / 20);
        count = std::clamp(count, fitting + 1, refused - 1);
      }
      const std::size_t open = refused - fitting;
      first = false;
      CountPlan tried = plan_in_count(planner, count, thickest, hi);
      const double over = printed_count(planner, tried.path) <= count ? overrun(tried.path) : INFINITY;
      if (over <= 0) {
        fitting = count, fitting_over = over, taken = std::move(tried);
      } else {
        refused = count, refused_over = over;
      }
      halve = (!halve && 2 * (refused - fitting) > open) || !std::isfinite(refused_over);
    }
  }
  if (taken.limits) plan.cap = taken.limits->tolerance, plan.ceiling = taken.limits->most;
  plan.cap_by_height = taken.by_height;
  return {std::move(taken.path), taken.tolerance};
}

// Each layer of `path` into `plan`: its D and swept volume, and whether it is within the
// tolerance (with a budget whose least error was found within a cap, that cap: a layer the
// cap allows is there by choice, not over anything) and if not, why.
void judge_layers(const LayerStack& stack, const AllowedThicknesses& allowed, std::span<const double> flats,
                  const LazyPlanner& planner, const std::vector<std::uint32_t>& path, AdaptivePlan& plan) {
  const double judged = plan.cap > 0 ? plan.cap : plan.tolerance;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const std::uint32_t e = path[i];
    const double d = planner.exact(e);
    plan.distance.push_back(d);
    plan.swept.push_back(planner.swept(e));
    plan.met.push_back(d <= judged);
    OverTolerance why = OverTolerance::none;
    double lean = 90;
    if (d > judged) {
      const Layer& layer = plan.layers[i];
      if (i == 0 && allowed.first > 0) why = OverTolerance::first_layer;
      // (A flat level off the heights the layers reach is crossed by every plan: its target,
      // the nearest reachable height, is on a boundary, and the level inside a layer.)
      else if (planner.crossed_flats(e) > 0 || crossed(flats, layer.z_lo, layer.z_hi) > 0) why = OverTolerance::flat_level;
      // (A by-height cap lets 5% of the height be over it at any thickness, landing or not.)
      else if (!planner.thinnest(e)) why = plan.cap_by_height ? OverTolerance::height_share : OverTolerance::landing;
      else if (planner.missed(e) > 0) why = OverTolerance::missed_feature;
      else why = OverTolerance::shallow_surface, lean = least_lean(stack, layer.z_lo, layer.z_hi);
      if (why != OverTolerance::first_layer) ++plan.unmet;
    }
    plan.why.push_back(why);
    plan.lean.push_back(lean);
  }
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
  const FlatTargets targets = flat_targets(flats, allowed);
  LazyPlanner planner(stack, part_height, allowed, targets, options, progress);
  plan.candidates = planner.candidates();
  plan.refused_for_overhangs = planner.refused();
  planner.measure_forced(options.tolerance);
  if (options.measure_all) planner.measure_all(options.max_layers > 0 || options.overrun ? 0 : options.tolerance);

  std::vector<std::uint32_t> path;
  if (options.max_layers == 0 && !options.overrun) {
    plan.tolerance = std::max(0.0, options.tolerance);
    path = planner.plan(plan.tolerance, true);
  } else {
    std::tie(path, plan.tolerance) = budget_path(planner, options, plan);
  }
  planner.measure_exactly(path, plan.tolerance);
  if (!path.empty() && !planner.printed(path.back())) path.pop_back();  // a tip no layer prints
  plan.layers = layers_of(planner, path);
  judge_layers(stack, allowed, flats, planner, path, plan);
  plan.flats = placements(flats, plan.layers);
  plan.measured = planner.measured();
  plan.rounds = planner.rounds();
  return plan;
}

}  // namespace geometry
