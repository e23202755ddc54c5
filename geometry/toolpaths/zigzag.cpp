#include "geometry/toolpaths/zigzag.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>

namespace geometry {

namespace {

// A line shorter than this is where a scan line grazes a corner: nothing to print.
constexpr double kMinLine = 1e-3;  // mm
// More scan lines than this means a spacing no printer can lay down.
constexpr double kMaxLines = 1e6;

// Where a scan line meets an edge of the area's boundary.
struct Crossing {
  double x = 0;        // along the line, in the rotated frame
  long line = 0;       // scan line index k
  std::size_t loop = 0, edge = 0;
  double t = 0;        // position along the edge, 0..1
  double arc = 0;      // distance along the loop from its vertex 0, mm
  int winding = 0;     // +1 where the edge runs up across the line, -1 down
  long segment = -1;   // the line piece this crossing ends, if any
  std::size_t ring = 0;  // index in its loop's crossings sorted by arc
};

struct Segment {
  std::size_t left = 0, right = 0;  // crossings
  bool used = false;
};

class Scan {
 public:
  Scan(const Region& area, const ScanLines& lines, const ScanFrame& frame) {
    for (const Loop& loop : area.loops) {
      if (loop.size() < 3) continue;
      Loop rotated;
      rotated.reserve(loop.size());
      for (Vec2 p : loop) rotated.push_back(frame.into(p));
      loops_.push_back(std::move(rotated));
    }
    if (loops_.empty() || !(lines.spacing > 0)) return;
    double y_min = loops_[0][0].y, y_max = y_min;
    for (const Loop& loop : loops_) {
      for (Vec2 p : loop) { y_min = std::min(y_min, p.y); y_max = std::max(y_max, p.y); }
    }
    if ((y_max - y_min) / lines.spacing > kMaxLines) return;
    cut(lines);
    pair_up();
    order_rings();
  }

  const std::vector<Loop>& loops() const { return loops_; }
  const std::vector<Crossing>& crossings() const { return crossings_; }
  std::vector<Segment>& segments() { return segments_; }
  const std::vector<Segment>& segments() const { return segments_; }
  const std::vector<std::vector<std::size_t>>& rings() const { return rings_; }
  double loop_length(std::size_t loop) const { return lengths_[loop]; }

  long first_line() const { return first_line_; }

  Vec2 point(std::size_t c) const {
    const Crossing& x = crossings_[c];
    return {x.x, y_[x.line]};
  }

 private:
  void cut(const ScanLines& lines) {
    const double spacing = lines.spacing, offset = lines.offset;
    for (std::size_t l = 0; l < loops_.size(); ++l) {
      const Loop& loop = loops_[l];
      const std::size_t n = loop.size();
      double arc = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const Vec2 p = loop[i], q = loop[(i + 1) % n];
        const double length = std::hypot(q.x - p.x, q.y - p.y);
        if (p.y != q.y) {
          // Each edge owns the heights [low, high): a vertex on a scan line counts once.
          const double low = std::min(p.y, q.y), high = std::max(p.y, q.y);
          for (long k = static_cast<long>(std::ceil((low - offset) / spacing));; ++k) {
            const double y = offset + static_cast<double>(k) * spacing;
            if (y >= high) break;
            if (y < low) continue;
            const double t = (y - p.y) / (q.y - p.y);
            Crossing c;
            c.x = p.x + t * (q.x - p.x);
            c.line = k;
            c.loop = l;
            c.edge = i;
            c.t = t;
            c.arc = arc + t * length;
            c.winding = q.y > p.y ? 1 : -1;
            crossings_.push_back(c);
          }
        }
        arc += length;
      }
      lengths_.push_back(arc);
    }
    if (crossings_.empty()) return;
    long k_min = crossings_[0].line, k_max = k_min;
    for (const Crossing& c : crossings_) {
      k_min = std::min(k_min, c.line);
      k_max = std::max(k_max, c.line);
    }
    // Heights by line index, shifted so the smallest index is 0.
    for (Crossing& c : crossings_) c.line -= k_min;
    first_line_ = k_min;
    for (long k = k_min; k <= k_max; ++k) y_.push_back(offset + static_cast<double>(k) * spacing);
  }

  // Along each line, the pieces inside the area (non-zero winding) become segments.
  void pair_up() {
    std::vector<std::vector<std::size_t>> by_line(y_.size());
    for (std::size_t c = 0; c < crossings_.size(); ++c) by_line[crossings_[c].line].push_back(c);
    for (auto& on_line : by_line) {
      std::sort(on_line.begin(), on_line.end(), [&](std::size_t a, std::size_t b) {
        return crossings_[a].x != crossings_[b].x ? crossings_[a].x < crossings_[b].x : a < b;
      });
      // Walking the line left to right, an edge running down is entered (outer loops CCW,
      // the inside on their left), one running up is left.
      int winding = 0;
      std::size_t start = 0;
      for (std::size_t c : on_line) {
        const int before = winding;
        winding -= crossings_[c].winding;
        if (before == 0 && winding != 0) start = c;
        if (before != 0 && winding == 0 &&
            crossings_[c].x - crossings_[start].x >= kMinLine) {
          crossings_[start].segment = crossings_[c].segment =
              static_cast<long>(segments_.size());
          segments_.push_back({start, c, false});
        }
      }
    }
  }

  // Per loop, the crossings that end a segment, in order along the loop.
  void order_rings() {
    rings_.assign(loops_.size(), {});
    for (std::size_t c = 0; c < crossings_.size(); ++c) {
      if (crossings_[c].segment >= 0) rings_[crossings_[c].loop].push_back(c);
    }
    for (auto& ring : rings_) {
      std::sort(ring.begin(), ring.end(), [&](std::size_t a, std::size_t b) {
        return crossings_[a].arc != crossings_[b].arc ? crossings_[a].arc < crossings_[b].arc
                                                      : a < b;
      });
      for (std::size_t i = 0; i < ring.size(); ++i) crossings_[ring[i]].ring = i;
    }
  }

  std::vector<Loop> loops_;
  long first_line_ = 0;
  std::vector<double> lengths_;
  std::vector<double> y_;
  std::vector<Crossing> crossings_;
  std::vector<Segment> segments_;
  std::vector<std::vector<std::size_t>> rings_;
};

// Where the scan lines meet the edge of the area to fill, to carry free line ends on to it.
class Edge {
 public:
  Edge(const Region& area, const ScanLines& lines, const ScanFrame& frame, long first_line)
      : first_(first_line) {
    for (const Loop& loop : area.loops) {
      for (std::size_t i = 0, n = loop.size(); i < n && n >= 3; ++i) {
        const Vec2 p = frame.into(loop[i]), q = frame.into(loop[(i + 1) % n]);
        if (p.y == q.y) continue;
        const double low = std::min(p.y, q.y), high = std::max(p.y, q.y);
        for (long k = static_cast<long>(std::ceil((low - lines.offset) / lines.spacing));; ++k) {
          const double y = lines.offset + static_cast<double>(k) * lines.spacing;
          if (y >= high) break;
          if (y < low || k < first_) continue;
          const auto line = static_cast<std::size_t>(k - first_);
          if (line >= xs_.size()) xs_.resize(line + 1);
          xs_[line].push_back(p.x + (y - p.y) / (q.y - p.y) * (q.x - p.x));
        }
      }
    }
    for (auto& xs : xs_) std::sort(xs.begin(), xs.end());
  }

  // The x where the line of crossing `end` meets the edge beyond it, going away from `from`
  // (the line's other end); the crossing's own x if the edge is not found there.
  double reach(const Crossing& end, double from) const {
    if (end.line < 0 || static_cast<std::size_t>(end.line) >= xs_.size()) return end.x;
    const auto& xs = xs_[static_cast<std::size_t>(end.line)];
    if (end.x >= from) {
      const auto it = std::lower_bound(xs.begin(), xs.end(), end.x);
      return it == xs.end() ? end.x : *it;
    }
    const auto it = std::upper_bound(xs.begin(), xs.end(), end.x);
    return it == xs.begin() ? end.x : *(it - 1);
  }

 private:
  long first_;
  std::vector<std::vector<double>> xs_;  // by line, from the centre area's first line
};

// A connector from one crossing to another along their loop, forward (with the loop's
// direction) or backward.
struct Connector {
  std::size_t to = 0;
  bool forward = true;
  double length = 0;
};

class Chainer {
 public:
  Chainer(const Scan& scan, double max_connector) : scan_(scan), max_(max_connector) {}

  // The best free neighbour along the loop to join crossing `from` to, if any.
  std::optional<Connector> join(std::size_t from) const {
    if (!(max_ > 0)) return std::nullopt;
    const auto& crossings = scan_.crossings();
    const Crossing& c = crossings[from];
    const auto& ring = scan_.rings()[c.loop];
    const double loop_length = scan_.loop_length(c.loop);
    std::optional<Connector> best;
    if (ring.size() < 2) return best;
    for (bool forward : {true, false}) {
      const std::size_t to = ring[forward ? (c.ring + 1) % ring.size()
                                          : (c.ring + ring.size() - 1) % ring.size()];
      const Crossing& d = crossings[to];
      if (scan_.segments()[d.segment].used || std::abs(d.line - c.line) > 1) continue;
      double length = forward ? d.arc - c.arc : c.arc - d.arc;
      if (length < 0) length += loop_length;
      if (length > max_) continue;
      if (!best || length < best->length) best = Connector{to, forward, length};
    }
    return best;
  }

  std::size_t other_end(std::size_t c) const {
    const Segment& s = scan_.segments()[scan_.crossings()[c].segment];
    return s.left == c ? s.right : s.left;
  }

 private:
  const Scan& scan_;
  double max_;
};

// The loop's vertices a connector passes, in the order it passes them.
void connector_points(const Scan& scan, std::size_t from, std::size_t to, bool forward,
                      std::vector<Vec2>& out) {
  const Crossing& a = scan.crossings()[from];
  const Crossing& b = scan.crossings()[to];
  const Loop& loop = scan.loops()[a.loop];
  const std::size_t n = loop.size();
  if (forward) {
    if (a.edge == b.edge && b.t >= a.t) return;
    std::size_t v = (a.edge + 1) % n;
    for (std::size_t count = 0; count < n; ++count) {
      out.push_back(loop[v]);
      if (v == b.edge) break;
      v = (v + 1) % n;
    }
  } else {
    if (a.edge == b.edge && b.t <= a.t) return;
    std::size_t v = a.edge;
    const std::size_t last = (b.edge + 1) % n;
    for (std::size_t count = 0; count < n; ++count) {
      out.push_back(loop[v]);
      if (v == last) break;
      v = (v + n - 1) % n;
    }
  }
}

}  // namespace

std::vector<ExtrusionPath> zigzag(const Region& centre_area, const ScanLines& lines,
                                  double max_connector, const Region* fill_area, PathRole role,
                                  double width) {
  std::vector<ExtrusionPath> paths;
  if (!(lines.spacing > 0) || !std::isfinite(lines.offset) || !std::isfinite(lines.angle)) {
    return paths;
  }
  const ScanFrame frame(lines.angle);
  Scan scan(centre_area, lines, frame);
  std::optional<Edge> fill;
  if (fill_area) fill.emplace(*fill_area, lines, frame, scan.first_line());
  auto& segments = scan.segments();
  // Segments in scan order (line, then along it), so chains start low and the output does
  // not depend on the order of the loops' edges.
  std::vector<std::size_t> order(segments.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto& crossings = scan.crossings();
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Crossing& ca = crossings[segments[a].left];
    const Crossing& cb = crossings[segments[b].left];
    return ca.line != cb.line ? ca.line < cb.line : ca.x < cb.x;
  });
  const Chainer chainer(scan, max_connector);
  for (std::size_t first : order) {
    if (segments[first].used) continue;
    segments[first].used = true;
    // The chain as crossings: (c0, c1) a segment, (c1, c2) a connector, (c2, c3) a segment...
    std::deque<std::size_t> chain{segments[first].left, segments[first].right};
    std::deque<bool> forward;  // direction of each connector, in chain order
    while (auto next = chainer.join(chain.back())) {
      segments[crossings[next->to].segment].used = true;
      forward.push_back(next->forward);
      chain.push_back(next->to);
      chain.push_back(chainer.other_end(next->to));
    }
    while (auto next = chainer.join(chain.front())) {
      segments[crossings[next->to].segment].used = true;
      forward.push_front(!next->forward);  // walked from the new crossing to the old front
      chain.push_front(next->to);
      chain.push_front(chainer.other_end(next->to));
    }
    std::vector<Vec2> points;
    for (std::size_t j = 0; j + 1 < chain.size(); j += 2) {
      points.push_back(scan.point(chain[j]));
      points.push_back(scan.point(chain[j + 1]));
      if (j + 2 < chain.size()) connector_points(scan, chain[j + 1], chain[j + 2], forward[j / 2], points);
    }
    // Ends joined to nothing reach on along their line to the edge of the area to fill.
    if (fill) {
      points.front().x = fill->reach(crossings[chain[0]], crossings[chain[1]].x);
      points.back().x = fill->reach(crossings[chain.back()], crossings[chain[chain.size() - 2]].x);
    }
    ExtrusionPath path;
    path.role = role;
    path.width = width;
    for (Vec2 p : points) {
      const Vec2 q = frame.out(p);
      if (path.points.empty() || !(q == path.points.back())) path.points.push_back(q);
    }
    if (path.points.size() >= 2) paths.push_back(std::move(path));
  }
  return paths;
}

}  // namespace geometry
