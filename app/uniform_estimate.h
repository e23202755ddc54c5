// Print-time estimates of layer stacks that are not sliced in full: the plan
// line's "estimated 57 min against 1 h 21 min at uniform 0.15 mm (333 layers)", and the
// --max-time search's estimate of each candidate plan.
//
// Both plan the toolpaths of a sample of the stack's layers (mid sections straightened within
// 25 um, supports and raft as the profiles say): one pair of neighbouring layers in so many
// (3 for estimated_seconds, 12 for uniform_seconds), and every layer unlike the sampled one of its
// parity below it (its part's or its support's area more than 10% different, support
// interface or bridges on either), or within the skins' reach (in layers: the top and bottom
// layers and thicknesses, at the thinnest layer) of a change of the part's area, of the bed
// or of the stack's top. Infill and support lines alternate their direction layer by layer,
// so a layer is compared with one of its parity.
//
// estimated_seconds: a layer not sampled prints the paths of the sampled one of its parity
// below it, their time scaled to its own area (its part's and its support's) by the time per
// mm^2 of the sampled layers of its parity below and above it, interpolated by height in
// layers (the one below alone where the one above was sampled for a change of what it prints
// other than its part's area: supports, skins). The copied paths alone are biased where the
// part narrows or widens steadily: frustums from radius 4 to 16 mm and from 16 to 4 mm over
// 30 mm at 0.25 mm, -1.9% and +1.7% against their program; scaled, -0.01% and -0.08%. It is
// what the --max-time search estimates candidate plans by: no plan has been printed yet.
//
// uniform_seconds, once a plan of the same part has been printed: a layer not sampled takes
// as long as the printed layer holding its middle, times the ratio of sampled to printed
// time interpolated between the sampled layers of its parity on either side (only the one
// below where the one above was sampled for a change, and neither where the printed layers
// differ by more than 10% from this one's: then the sampled one below's own time). The
// printed program follows the part's shape layer by layer, and the ratio carries what
// thinner layers change (more lines a fill, other skins and supports). Against slicing
// uniformly with the same contour, tests/bench/estimate_accuracy.sh (3 December 2026): within
// 1.8% (mean 0.57%) on the bunny with and without supports and raft, a sphere, a T, stepped
// tiers, a dome, a vase and a frustum. What the rules buy, on the bunny at --tolerance 0.3
// (its uniform 0.15 and 0.2 mm, 4884 and 3706 s sliced): without the 10% rule for the part's
// area the two samples cost 3% less wall time and are 0.9% and 3.1% off (with it 0.1% and 0.1%);
// without the skins' reach of a change they cost no less (those layers are few and small)
// and are 2.7% and 4.4% off.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/slicing/layer_stack.h"
#include "printer/gcode_writer.h"
#include "printer/profile.h"

namespace app {

// `layers` of the part in `index` (a layer stack of the placed mesh), the profiles' print.
double estimated_seconds(const geometry::LayerStack& index, const std::vector<geometry::Layer>& layers,
                         const printer::Profiles& profiles);

// A uniform stack's sampled layers, each timed on its own.
struct LayerSample {
  std::vector<geometry::Layer> layers;
  std::vector<double> seconds;   // per layer: its print time where sampled, else negative
  std::vector<char> changed;     // per layer: sampled for being unlike the sampled one below
  double before = 0;             // the start G-code and the raft, s
};
LayerSample sample_layers(const geometry::LayerStack& index, const std::vector<geometry::Layer>& layers,
                          const printer::Profiles& profiles);

// The sample's whole print time, s, with the printed program's layers (`printed`, and their
// times in `summary`, raft layers first) filling in the layers not sampled.
double uniform_seconds(const LayerSample& sample, const std::vector<geometry::Layer>& printed,
                       const printer::GcodeSummary& summary);

}  // namespace app
