#pragma once
// A full-mouth stand-in for the engine benchmarks (simple, reproducible shapes):
// 32 tooth-sized ellipsoids (8 x 7 x 20 mm) on two parabolic arches and a jaw,
// 33 objects of up to 512 leaves each, and a 512-leaf probe. Trees are built once
// with the real builder and cached in the build tree.

#include <memory>
#include <vector>

#include "core/collision/collision.h"
#include "core/geometry/mesh.h"

namespace sulcus::bench {

struct MouthProxy {
  TriangleMesh tooth_mesh, jaw_mesh, probe_mesh;
  SphereTree tooth, jaw, probe;
  std::vector<CollisionWorld::Object> objects;  // 33: 32 teeth and the jaw
  std::vector<RigidTransform> tooth_poses;
  /// Poses of the probe touching tooth surfaces: tip 0.2 mm into the surface,
  /// shaft along the outward normal (seeded).
  /// Poses of the probe resting on buccal or lingual tooth surfaces: end face 0.02 mm
  /// into the surface, shaft along the outward normal (seeded). `only_tooth` >= 0
  /// keeps them on that tooth.
  std::vector<RigidTransform> ContactPoses(int n, unsigned seed,
                                           int only_tooth = -1) const;
};

/// Built on first use (a few seconds cold, instant from the cache).
const MouthProxy& Mouth();

}  // namespace sulcus::bench
