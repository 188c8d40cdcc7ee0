#pragma once
// Tool sphere-tree against the scene's object sphere-trees (paper, Algorithm 1):
// the pairs of leaf spheres, one of the tool and one of an object, whose gap is
// below a margin. The margin covers the motion of a frame, so that a fast push
// cannot pass through a thin wall between two queries.
//
// Two implementations with the same output: FindContactsReference, the plain
// recursion of Algorithm 1 kept as the obviously correct reference, and
// FindContacts, the one the haptic thread calls (flat arrays, a fixed stack,
// children tested in one loop in the frame of the node they are tested against,
// so no per-node transform; no allocation, no virtual call).

#include <cstdint>
#include <vector>

#include "core/geometry/transform.h"
#include "core/spheretree/sphere_tree.h"

namespace sulcus {

/// One leaf pair. gap = |c_T - c_O| - r_T - r_O at the query pose (negative when
/// the spheres overlap).
struct ContactPair {
  std::int32_t object = 0;       // index of the object in the world
  std::int32_t object_leaf = 0;  // node index in that object's tree
  std::int32_t tool_leaf = 0;    // node index in the tool's tree
  double gap = 0;

  /// Stable identity of the pair across frames (for warm starts).
  std::uint64_t key() const {
    return (static_cast<std::uint64_t>(object) << 48) |
           (static_cast<std::uint64_t>(object_leaf) << 24) | static_cast<std::uint64_t>(tool_leaf);
  }
  /// The object of a pair from its key.
  static int ObjectOfKey(std::uint64_t key) { return static_cast<int>(key >> 48); }
  /// The tool's leaf of a pair from its key.
  static int ToolLeafOfKey(std::uint64_t key) { return static_cast<int>(key & 0xffffffu); }
};

struct CollisionScratch;
struct CollisionStats;
struct QueryLimits;

/// The immutable collision scene: the tool's tree in the tool frame T and every
/// object's tree moved into the world frame W once (objects do not move).
class CollisionWorld {
 public:
  struct Object {
    const SphereTree* tree;  // not owned; must outlive the world
    RigidTransform X_WO;
  };
  /// Precondition: every tree is valid (SphereTree::Validate). Up to 65,535
  /// objects and 2^24 nodes per tree.
  CollisionWorld(const SphereTree& tool, const std::vector<Object>& objects);

  const SphereTree& tool() const { return *tool_; }
  int num_objects() const { return static_cast<int>(objects_.size()); }
  const SphereTree& object_tree(int i) const { return *objects_[i].tree; }
  /// Centre of object i's node n, in W.
  Vector3 ObjectCenter(int i, std::int32_t n) const {
    const std::size_t k = offset_[i] + n;
    return {ox_[k], oy_[k], oz_[k]};
  }
  double ObjectRadius(int i, std::int32_t n) const { return orad_[offset_[i] + n]; }
  /// Largest distance from the tool origin to a point of a tool leaf sphere.
  double tool_reach() const { return tool_reach_; }

 private:
  friend CollisionStats FindContacts(const CollisionWorld&, const RigidTransform&, double,
                                     CollisionScratch*, ContactPair*, int, const QueryLimits&) noexcept;
  const SphereTree* tool_;
  std::vector<Object> objects_;
  // All object nodes in W, flat (structure of arrays); object i starts at offset_[i].
  std::vector<std::size_t> offset_;
  std::vector<double> ox_, oy_, oz_, orad_;
  std::vector<std::int32_t> ofirst_;
  std::vector<std::uint8_t> ocount_;
  double tool_reach_ = 0;
};

/// Per-query scratch space, fixed size (part of the engine's Data).
struct CollisionScratch {
  static constexpr int kStackCapacity = 1024;
  std::int32_t stack_tool[kStackCapacity];
  std::int32_t stack_obj[kStackCapacity];
};

/// Result counters of a fast query.
struct CollisionStats {
  int pairs = 0;             // written to the output
  bool overflow = false;     // more pairs existed than the capacity held
  bool stack_overflow = false;
  bool cut_short = false;    // stopped by a QueryLimits (the pairs are a part of the set)
  int node_tests = 0;        // sphere-sphere tests made
};

/// Bounds on one query's work, for callers that must not wait on an unbounded
/// traversal (a tool deep inside an object overlaps many node pairs).
struct QueryLimits {
  bool stop_when_full = false;  // stop at the first pair past `capacity` (an overlap test: capacity 1)
  int max_node_tests = 0;       // stop after about this many sphere tests (0: no limit)
};

/// Leaf pairs with gap < margin for the tool at X_WT, written to `out`
/// (capacity entries at most), in traversal order (deterministic; object by
/// object). No allocation; never throws. With limits, the query may stop early
/// (`cut_short`), having done O(capacity + max_node_tests) work.
CollisionStats FindContacts(const CollisionWorld& world, const RigidTransform& X_WT, double margin,
                            CollisionScratch* scratch, ContactPair* out, int capacity,
                            const QueryLimits& limits) noexcept;
inline CollisionStats FindContacts(const CollisionWorld& world, const RigidTransform& X_WT, double margin,
                                   CollisionScratch* scratch, ContactPair* out, int capacity) noexcept {
  return FindContacts(world, X_WT, margin, scratch, out, capacity, QueryLimits{});
}

/// The reference: Algorithm 1 as a plain recursion over both trees (descending
/// both sides), no pruning tricks. In its own traversal order.
std::vector<ContactPair> FindContactsReference(const CollisionWorld& world, const RigidTransform& X_WT,
                                               double margin);

}  // namespace sulcus
