// All error metrics of one layer's region in one call (DESIGN.md §3), independent of the
// strategy that made the region, so that strategies can be compared layer by layer.
//
// Input: a layer stack and a layer index, prepared once as a LayerReference (the slab, its
// footprint's islands, its columns, its surface, its volume limit: everything that does not
// depend on the region), then any number of regions, mm. The footprint itself is not kept:
// nothing measures against it, and its Region would cost a conversion of every loop per layer
// (slab_islands, slab.h). One LayerReference serves every strategy on its layer: best builds
// one and hands its islands to ma (best_contour.cpp), so a layer's footprint is computed once
// (callgrind of `mahost slice` on the bunny at 0.15 mm, --contour best: 333 footprints for 333
// layers, 1.65 G of 14.2 G instructions).
// Output per region: area (mm^2); volume deviation and the layer's volume limit (mm^3;
// volume_deviation.h, volume_limit.h); forward, reverse and Hausdorff distance (mm;
// distance_error.h); the missed features (missed_features.h).
// Out-of-range layer: an empty reference, whose metrics are all 0 except the region's area.
// A LayerReference caches search state in its grids: use each one from one thread at a time.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/slab/boundary_pair.h"
#include "geometry/metrics/distance_error.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/slab.h"
#include "geometry/slab/slab_columns.h"

namespace geometry {

struct MetricOptions {
  DistanceOptions distance;
  // false: no columns, volume limit or volume deviation (they stay 0), for callers that only
  // compare distance errors (mahost advise, analyze's thicker layers).
  bool volumes = true;
};

struct LayerMetrics {
  double z_lo = 0, thickness = 0;
  double area = 0;                // of the region, mm^2
  double volume_deviation = 0;    // ΔV, mm^3
  double volume_limit = 0;        // the least ΔV any region can have on this layer, mm^3
  double distance = 0;            // D: surface to walls (the paper's), mm
  double reverse_distance = 0;    // walls to surface, mm
  double hausdorff = 0;           // max of both, mm
  std::size_t missed_features = 0;
};

struct LayerReference {
  Layer layer;
  Slab slab;
  std::vector<BoundaryPair> islands;  // of the slab's footprint (slab_islands)
  bool volumes = false;  // columns and volume_limit computed (MetricOptions::volumes)
  SlabColumns columns;
  SlabSurface surface;
  double volume_limit = 0;
};

LayerReference layer_reference(const LayerStack& stack, std::size_t layer,
                               const MetricOptions& options = {});
// The same from the layer's slab, built already (slab_of(stack, layer)).
LayerReference layer_reference(const LayerStack& stack, std::size_t layer, Slab slab,
                               const MetricOptions& options = {});

LayerMetrics layer_metrics(const LayerReference& reference, const Region& region,
                           const MetricOptions& options = {});

LayerMetrics layer_metrics(const LayerStack& stack, std::size_t layer, const Region& region,
                           const MetricOptions& options = {});

}  // namespace geometry
