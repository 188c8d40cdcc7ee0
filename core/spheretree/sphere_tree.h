#pragma once
// The sphere-tree model the engine traverses: flat arrays in breadth-first order
// (structure of arrays, no pointers), so that the haptic thread reads it without
// indirection and it can be written to disk as is.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/types.h"

namespace sulcus {

/// A sphere-tree. Node 0 is the root. The children of node i are the
/// child_count[i] consecutive nodes starting at first_child[i], all one level
/// deeper. A node without children is a leaf (leaves may sit above the last
/// level, e.g. in trees read from Bradshaw's files). Coordinates are in the
/// object's frame, in mm.
struct SphereTree {
  int levels = 0;     // counting the root level
  int branching = 8;  // most children a node may have
  std::vector<double> x, y, z, r;
  std::vector<std::int32_t> first_child;
  std::vector<std::uint8_t> child_count;
  std::vector<std::uint8_t> level;

  std::size_t size() const { return r.size(); }
  bool empty() const { return r.empty(); }
  Vector3 center(std::size_t i) const { return {x[i], y[i], z[i]}; }
  bool IsLeaf(std::size_t i) const { return child_count[i] == 0; }
  std::size_t NumLeaves() const;
  /// Nodes on level l.
  std::vector<std::int32_t> NodesOnLevel(int l) const;
  /// The cut of the tree at level l: nodes on level l plus leaves above it. The
  /// spheres a traversal stopped at level l would test.
  std::vector<std::int32_t> CutAtLevel(int l) const;
  /// Appends a node and returns its index; used by builders and readers.
  std::int32_t AddNode(const Vector3& c, double radius, int node_level);

  /// Throws std::runtime_error describing the first structural fault: sizes that
  /// disagree, a child index out of range or not one level deeper, a non-finite
  /// value, a non-positive radius, a node not reached from the root.
  void Validate() const;
};

}  // namespace sulcus
