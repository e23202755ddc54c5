// The layer stack: layer bounds, and cross-sections at any height from an index of the faces
// by height (equal-height buckets, each listing the faces whose z-range meets it), so that a
// query reads one bucket instead of the whole mesh. Read-only after construction, so const
// calls are safe from any number of threads.
#include "geometry/slicing/layer_stack.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "geometry/core/error.h"
#include "geometry/slicing/plane_section.h"

namespace geometry {

std::vector<Layer> uniform_layers(double part_height, double thickness, double first_layer) {
  if (!(part_height > 0) || !(thickness > 0) || !(first_layer >= 0) ||
      !std::isfinite(part_height) || !std::isfinite(thickness) || !std::isfinite(first_layer)) {
    return {};
  }
  const double first = first_layer > 0 ? first_layer : thickness;
  // Layers after the first; the tolerance keeps 30 mm at 0.15 mm at 200 layers, not 201.
  const double more = std::max(0.0, std::ceil((part_height - first) / thickness - 1e-9));
  std::vector<Layer> layers;
  layers.reserve(static_cast<std::size_t>(more) + 1);
  layers.push_back({0, first});
  for (std::size_t i = 1; i <= static_cast<std::size_t>(more); ++i) {
    // From the first top, not accumulated, so that rounding does not drift over many layers.
    layers.push_back({layers.back().z_hi, first + static_cast<double>(i) * thickness});
  }
  return layers;
}

std::vector<Layer> layers_from_tops(std::span<const double> tops) {
  std::vector<Layer> layers;
  layers.reserve(tops.size());
  double previous = 0;
  for (std::size_t i = 0; i < tops.size(); ++i) {
    if (!std::isfinite(tops[i]) || !(tops[i] > previous)) {
      throw InputError(fmt::format(
          "layer heights: top {} ({} mm) is not above {} ({} mm); give positive, strictly "
          "increasing layer tops",
          i + 1, tops[i], i == 0 ? std::string("the bed") : fmt::format("top {}", i), previous));
    }
    layers.push_back({previous, tops[i]});
    previous = tops[i];
  }
  return layers;
}

struct LayerStack::Index {
  double z_min = 0, z_max = 0;  // of all faces
  double bucket_height = 1;
  std::size_t buckets = 0;
  std::vector<std::size_t> bucket_begin;     // faces of bucket b: bucket_faces[begin[b], begin[b+1])
  std::vector<std::uint32_t> bucket_faces;   // ascending within each bucket
  std::vector<std::uint32_t> first_bucket;   // of every indexed face
  std::vector<double> face_low, face_high;   // z-range of every face (NaN: not indexed)
  std::vector<double> vertex_heights;        // sorted, distinct

  // Monotone in z, so a face indexed in buckets bucket(low)..bucket(high) is found from any
  // z in its range.
  std::size_t bucket(double z) const {
    const double b = std::floor((z - z_min) / bucket_height);
    if (!(b > 0)) return 0;
    return std::min(static_cast<std::size_t>(std::min(b, 1e18)), buckets - 1);
  }
};

LayerStack::LayerStack(const Mesh& mesh, std::vector<Layer> layers)
    : mesh_(&mesh), layers_(std::move(layers)) {
  auto built = std::make_shared<Index>();
  index_ = built;
  Index& index = *built;
  const std::size_t face_count = mesh.faces.size();
  index.face_low.assign(face_count, NAN);
  index.face_high.assign(face_count, NAN);

  std::vector<char> used(mesh.vertices.size(), 0);  // vertices of indexed faces
  bool any = false;
  double extent_sum = 0;
  std::size_t sloped = 0;
  for (std::size_t f = 0; f < face_count; ++f) {
    const auto& face = mesh.faces[f];
    if (face[0] >= mesh.vertices.size() || face[1] >= mesh.vertices.size() ||
        face[2] >= mesh.vertices.size()) {
      continue;
    }
    const double a = mesh.vertices[face[0]].z, b = mesh.vertices[face[1]].z,
                 c = mesh.vertices[face[2]].z;
    if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c)) continue;
    const double low = std::min({a, b, c}), high = std::max({a, b, c});
    index.face_low[f] = low;
    index.face_high[f] = high;
    index.z_min = any ? std::min(index.z_min, low) : low;
    index.z_max = any ? std::max(index.z_max, high) : high;
    any = true;
    if (high > low) extent_sum += high - low, ++sloped;
    for (std::uint32_t v : face) used[v] = 1;
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (used[v]) index.vertex_heights.push_back(mesh.vertices[v].z);
  }
  std::sort(index.vertex_heights.begin(), index.vertex_heights.end());
  index.vertex_heights.erase(
      std::unique(index.vertex_heights.begin(), index.vertex_heights.end()),
      index.vertex_heights.end());
  if (!any) return;

  // About two buckets per typical face height: a face sits in two or three buckets, and a
  // query filters little more than the faces that actually cross its plane.
  const double range = index.z_max - index.z_min;
  std::size_t buckets = 1;
  if (range > 0 && sloped > 0) {
    const double typical = extent_sum / static_cast<double>(sloped);
    const double wanted = 2 * range / typical;
    buckets = static_cast<std::size_t>(
        std::clamp(wanted, 1.0, static_cast<double>(std::max<std::size_t>(face_count, 1))));
  }
  index.buckets = buckets;
  index.bucket_height = range > 0 ? range / static_cast<double>(buckets) : 1;

  // Counting sort of (bucket, face) pairs into one flat array.
  index.bucket_begin.assign(buckets + 1, 0);
  index.first_bucket.assign(face_count, 0);
  for (std::size_t f = 0; f < face_count; ++f) {
    if (std::isnan(index.face_low[f])) continue;
    index.first_bucket[f] = static_cast<std::uint32_t>(index.bucket(index.face_low[f]));
    for (std::size_t b = index.first_bucket[f], e = index.bucket(index.face_high[f]); b <= e; ++b) {
      ++index.bucket_begin[b + 1];
    }
  }
  for (std::size_t b = 0; b < buckets; ++b) index.bucket_begin[b + 1] += index.bucket_begin[b];
  index.bucket_faces.resize(index.bucket_begin[buckets]);
  std::vector<std::size_t> fill(index.bucket_begin.begin(), index.bucket_begin.end() - 1);
  for (std::size_t f = 0; f < face_count; ++f) {
    if (std::isnan(index.face_low[f])) continue;
    for (std::size_t b = index.first_bucket[f], e = index.bucket(index.face_high[f]); b <= e; ++b) {
      index.bucket_faces[fill[b]++] = static_cast<std::uint32_t>(f);
    }
  }
}

LayerStack::LayerStack(const LayerStack& other, std::vector<Layer> layers)
    : mesh_(other.mesh_), layers_(std::move(layers)), index_(other.index_) {}

LayerStack::~LayerStack() = default;
LayerStack::LayerStack(LayerStack&&) noexcept = default;
LayerStack& LayerStack::operator=(LayerStack&&) noexcept = default;

Region LayerStack::cross_section(double z) const {
  const Index& index = *index_;
  // Limit from above: nothing at or above the top, nothing below the bottom (or NaN).
  if (index.buckets == 0 || !(z >= index.z_min && z < index.z_max)) return {};
  const std::size_t b = index.bucket(z);
  std::vector<std::uint32_t> crossing;
  crossing.reserve(index.bucket_begin[b + 1] - index.bucket_begin[b]);
  for (std::size_t i = index.bucket_begin[b]; i < index.bucket_begin[b + 1]; ++i) {
    const std::uint32_t f = index.bucket_faces[i];
    if (index.face_low[f] <= z && z < index.face_high[f]) crossing.push_back(f);
  }
  return plane_section(*mesh_, crossing, z);
}

std::vector<std::uint32_t> LayerStack::faces_between(double z_lo, double z_hi) const {
  const Index& index = *index_;
  if (index.buckets == 0 || !(z_lo <= z_hi) || z_hi < index.z_min || z_lo > index.z_max) {
    return {};
  }
  const std::size_t first = index.bucket(z_lo), last = index.bucket(z_hi);
  std::vector<std::uint32_t> faces;
  for (std::size_t b = first; b <= last; ++b) {
    const std::size_t run = faces.size();
    for (std::size_t i = index.bucket_begin[b]; i < index.bucket_begin[b + 1]; ++i) {
      const std::uint32_t f = index.bucket_faces[i];
      if (!(index.face_low[f] <= z_hi && index.face_high[f] >= z_lo)) continue;
      // A face listed in several buckets of the range is taken from the first of them only.
      if (b != std::max<std::size_t>(first, index.first_bucket[f])) continue;
      faces.push_back(f);
    }
    // Each bucket's faces are ascending: merged into those of the buckets before.
    std::inplace_merge(faces.begin(), faces.begin() + static_cast<std::ptrdiff_t>(run), faces.end());
  }
  return faces;
}

std::vector<double> LayerStack::vertex_heights_between(double z_lo, double z_hi) const {
  const auto& heights = index_->vertex_heights;
  if (!(z_lo <= z_hi)) return {};
  return {std::lower_bound(heights.begin(), heights.end(), z_lo),
          std::upper_bound(heights.begin(), heights.end(), z_hi)};
}

}  // namespace geometry
