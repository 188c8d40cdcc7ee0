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

#include "core/collision/leaf_planes.h"
#include "core/geometry/transform.h"
#include "core/spheretree/sphere_tree.h"

namespace sulcus {

/// One leaf pair. gap = |c_T - c_O| - r_T - r_O at the query pose (negative when
/// the spheres overlap), or, when the object's leaf is clipped by planes, as
/// CollisionWorld::LeafGap gives it. A leaf on a concave crease (the union of
/// its planes' half spaces, leaf_planes.h) makes one pair for each part of the
/// union near the tool sphere, so that the frame keeps the tool out of every
/// part (a constraint on the nearest part alone would let it into the other).
struct ContactPair {
  std::int32_t object = 0;       // index of the object in the world
  std::int32_t object_leaf = 0;  // node index in that object's tree
  std::int32_t tool_leaf = 0;    // node index in the tool's tree
  /// 0: the whole leaf; j + 1: on a concave crease, its part below plane j.
  std::int32_t piece = 0;
  double gap = 0;

  /// Stable identity of the pair across frames (for warm starts).
  std::uint64_t key() const {
    return (static_cast<std::uint64_t>(piece) << 62) |
           (static_cast<std::uint64_t>(object) << 48) |
           (static_cast<std::uint64_t>(object_leaf) << 24) |
           static_cast<std::uint64_t>(tool_leaf);
  }
  /// The object of a pair from its key.
  static int ObjectOfKey(std::uint64_t key) {
    return static_cast<int>((key >> 48) & 0x3fffu);
  }
  /// The tool's leaf of a pair from its key.
  static int ToolLeafOfKey(std::uint64_t key) {
    return static_cast<int>(key & 0xffffffu);
  }
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
    const LeafPlanes* planes =
        nullptr;  // the leaves' clipping planes (none: spheres); copied
  };
  /// Precondition: every tree is valid (SphereTree::Validate). Up to 16,383
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
  /// Within this sphere gap a pair on a clipped leaf is measured on the leaf's
  /// planes; beyond it, as spheres (the same penetration: neither is negative
  /// there), so a fast move's wide margin costs one distance per far pair.
  static constexpr double kPlanesWithinMm = 0.1;
  /// Gap of a tool sphere (centre c_W, radius r) to object i's leaf n, as a
  /// pair's gap is measured (ContactPair::gap). For a plain leaf, or a clipped
  /// one (leaf_planes.h) further than kPlanesWithinMm, the sphere gap. Else
  /// the larger of two lower bounds of the distance to the clipped leaf, less
  /// r: the exact distance to the polyhedron of its planes (to a face, to an
  /// edge where two meet, to the corner of three; inside, minus the depth below
  /// the nearest face), and for each plane the exact distance to the part of the
  /// sphere below it (to the sphere, or to the rim of the disc the plane cuts);
  /// when the polyhedron's nearest point lies in the sphere it is exact alone.
  /// A leaf on a concave crease (LeafPlanes::concave) is the union of the
  /// sphere cut by its other planes and each of the crease's: the smallest of
  /// their gaps.
  /// `normal`, when given, receives the unit direction in which that gap grows
  /// for the tool sphere (zero when the centres coincide).
  ///
  /// Why both: the polyhedron alone reaches beyond the leaf; the sphere pieces
  /// alone bulge at an edge (a tapered tool pushed between two walls would stop
  /// on the bulges, as on plain spheres). Why the rim and not the sphere gap:
  /// a tool sliding on the face toward the leaf meets the sphere's cap (cut away
  /// by the plane) before the rim, and a constraint on the cap would hold it
  /// back at every leaf.
  ///
  /// `piece` (ContactPair::piece): j + 1 for the part of a concave leaf below
  /// its plane j (and its planes outside the crease), 0 for the whole leaf.
  double LeafGap(int i, std::int32_t n, const Vector3& c_W, double r,
                 Vector3* normal = nullptr, int piece = 0) const {
    const std::size_t k = offset_[i] + n;
    const Vector3 away(c_W.x() - ox_[k], c_W.y() - oy_[k], c_W.z() - oz_[k]);
    const double dist = away.norm();
    const double sphere = dist - r - orad_[k];
    if (sphere < kPlanesWithinMm && Clipped(k))
      return ClippedGap(k, c_W, r, normal, piece);
    if (normal) *normal = dist > 1e-12 ? Vector3(away / dist) : Vector3::Zero();
    return sphere;
  }
  /// A pair's gap with the tool at X_WT (LeafGap of its two leaves).
  double PairGap(const RigidTransform& X_WT, const ContactPair& c,
                 Vector3* normal = nullptr) const {
    return LeafGap(c.object, c.object_leaf, X_WT * tool_->center(c.tool_leaf),
                   tool_->r[c.tool_leaf], normal, c.piece);
  }
  /// The planes of object i's leaf n united on a concave crease (bit j: plane
  /// j; LeafPlanes::concave), 0 for any other leaf.
  unsigned UnitedPlanes(int i, std::int32_t n) const { return concave_[offset_[i] + n]; }
  /// Largest distance from the tool origin to a point of a tool leaf sphere.
  double tool_reach() const { return tool_reach_; }

 private:
  bool Clipped(std::size_t k) const {
    return planes_[k * kPlaneStride + 3] < LeafPlanes::kNone;
  }
  // LeafGap of a clipped leaf (flat index k), within kPlanesWithinMm.
  double ClippedGap(std::size_t k, const Vector3& c_W, double r, Vector3* normal,
                    int piece) const;
  // The distance from c_W to the ball (c, R) cut by the planes at pl (as
  // stored: kPlaneStride doubles, the used ones first).
  static double CutBallDistance(const Vector3& c, double R, const double* pl,
                                const Vector3& c_W, Vector3* dir);
  // Signed distance from q to {x : n_j . x <= d_j} for a leaf's used planes
  // (kPlaneStride doubles at pl), the unit direction in which it grows, and
  // the nearest point (q itself inside).
  static double PolyhedronDistance(const double* pl, const Vector3& q, Vector3* dir,
                                   Vector3* nearest);
  // Signed distance from q to the ball (c, R) cut by the plane (nx, ny, nz, d)
  // at pl, and the unit direction in which it grows (zero when undefined).
  static double BallHalfSpaceDistance(const Vector3& c, double R, const double* pl,
                                      const Vector3& q, Vector3* dir);
  friend CollisionStats FindContacts(const CollisionWorld&, const RigidTransform&, double,
                                     CollisionScratch*, ContactPair*, int,
                                     const QueryLimits&) noexcept;
  const SphereTree* tool_;
  std::vector<Object> objects_;
  // All object nodes in W, flat (structure of arrays); object i starts at offset_[i].
  std::vector<std::size_t> offset_;
  std::vector<double> ox_, oy_, oz_, orad_;
  // Leaf clipping planes in W, kPlaneStride per node: (nx, ny, nz, d) for each
  // of kMaxPlanes, the used ones first (n zero, d kNone: none).
  static constexpr int kPlaneStride = 4 * LeafPlanes::kMaxPlanes;
  std::vector<double> planes_;
  std::vector<std::uint8_t> concave_;  // per node: LeafPlanes::concave
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
  int pairs = 0;          // written to the output
  bool overflow = false;  // more pairs existed than the capacity held
  bool stack_overflow = false;
  bool cut_short = false;  // stopped by a QueryLimits (the pairs are a part of the set)
  int node_tests = 0;      // sphere-sphere tests made
};

/// Bounds on one query's work, for callers that must not wait on an unbounded
/// traversal (a tool deep inside an object overlaps many node pairs).
struct QueryLimits {
  bool stop_when_full =
      false;  // stop at the first pair past `capacity` (an overlap test: capacity 1)
  int max_node_tests = 0;  // stop after about this many sphere tests (0: no limit)
};

/// Leaf pairs with gap < margin for the tool at X_WT, written to `out`
/// (capacity entries at most), in traversal order (deterministic; object by
/// object). No allocation; never throws. With limits, the query may stop early
/// (`cut_short`), having done O(capacity + max_node_tests) work.
CollisionStats FindContacts(const CollisionWorld& world, const RigidTransform& X_WT,
                            double margin, CollisionScratch* scratch, ContactPair* out,
                            int capacity, const QueryLimits& limits) noexcept;
inline CollisionStats FindContacts(const CollisionWorld& world,
                                   const RigidTransform& X_WT, double margin,
                                   CollisionScratch* scratch, ContactPair* out,
                                   int capacity) noexcept {
  return FindContacts(world, X_WT, margin, scratch, out, capacity, QueryLimits{});
}

/// The reference: Algorithm 1 as a plain recursion over both trees (descending
/// both sides), no pruning tricks. In its own traversal order.
std::vector<ContactPair> FindContactsReference(const CollisionWorld& world,
                                               const RigidTransform& X_WT, double margin);

}  // namespace sulcus
