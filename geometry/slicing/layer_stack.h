// The layer stack: a part's layers with their bounds and cross-sections at any height.
//
// Every contour strategy (DESIGN.md §2) and every metric (§3) reads the model through this:
// a layer i has z_lo, z_hi, thickness t = z_hi - z_lo; the slab S_i is the solid between them.
// Heights in mm; cross-sections follow slicer.h's conventions (limit from above).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"

namespace geometry {

struct Layer {
  double z_lo = 0, z_hi = 0;
  double thickness() const { return z_hi - z_lo; }
  double z_mid() const { return 0.5 * (z_lo + z_hi); }
};

// Layers from z = 0 up to and including the one that reaches part_height: the first is
// first_layer thick (0 means `thickness`), the rest `thickness`. A 50 mm part at 0.15 mm
// gives 334 layers, the last ending at 50.1 mm. Non-positive sizes give no layers.
std::vector<Layer> uniform_layers(double part_height, double thickness, double first_layer = 0);

// Layers from a list of increasing layer tops (z_hi values), the first starting at z = 0.
// Throws InputError if the list is not strictly increasing and positive.
std::vector<Layer> layers_from_tops(std::span<const double> tops);

class LayerStack {
 public:
  // Indexes the mesh's faces by height once; the mesh must outlive the stack.
  LayerStack(const Mesh& mesh, std::vector<Layer> layers);
  // The same mesh and face index with other layers (any bounds, even overlapping: a layer
  // plan measures candidate slabs this way without indexing the mesh again).
  LayerStack(const LayerStack& other, std::vector<Layer> layers);
  ~LayerStack();
  LayerStack(LayerStack&&) noexcept;
  LayerStack& operator=(LayerStack&&) noexcept;

  const Mesh& mesh() const { return *mesh_; }
  const std::vector<Layer>& layers() const { return layers_; }
  std::size_t size() const { return layers_.size(); }

  // Cross-section at any height; touches only the faces that span z.
  Region cross_section(double z) const;

  Region lower(std::size_t layer) const { return cross_section(layers_[layer].z_lo); }
  Region mid(std::size_t layer) const { return cross_section(layers_[layer].z_mid()); }
  Region upper(std::size_t layer) const { return cross_section(layers_[layer].z_hi); }

  // Indices of the faces whose z-range meets [z_lo, z_hi] (closed interval), ascending.
  std::vector<std::uint32_t> faces_between(double z_lo, double z_hi) const;

  // Sorted, distinct heights of the mesh's vertices inside [z_lo, z_hi]: between two of them
  // every cross-section changes linearly with z (what exact slab integrals break on).
  std::vector<double> vertex_heights_between(double z_lo, double z_hi) const;

 private:
  struct Index;
  const Mesh* mesh_;
  std::vector<Layer> layers_;
  std::shared_ptr<const Index> index_;
};

}  // namespace geometry
