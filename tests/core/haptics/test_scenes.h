#pragma once
// Scenes for engine tests and the hard-case suite, made of hand-placed spheres
// (the engine needs only the trees; the builder has its own tests).

#include <memory>
#include <vector>

#include "core/haptics/engine.h"

namespace sulcus::test {

/// A periodontal probe: tip sphere (r 0.25 mm) at the tool origin, shaft of
/// spheres (r 0.4 mm) along +z every 0.3 mm up to `length` mm.
SphereTree MakeProbe(double length = 15.0);

/// A flat face for the tool: a grid of nx x ny spheres of radius r, spacing s,
/// centres in the plane z = r (so the face's lowest points are at z = 0).
SphereTree MakeFlatFace(int nx, int ny, double spacing, double radius);

/// A slab of spheres: centres on a grid over [-hx, hx] x [-hy, hy] x [z0, z1]
/// (z layers every `spacing`), radius r, in the object's frame.
SphereTree MakeBlock(double hx, double hy, double z0, double z1, double spacing,
                     double radius);

/// A scene: owns its trees, and an engine model on them.
struct Scene {
  std::vector<std::unique_ptr<SphereTree>> trees;
  std::unique_ptr<SphereTree> tool;
  std::vector<CollisionWorld::Object> objects;
  void Add(SphereTree tree, const RigidTransform& X_WO);
  std::unique_ptr<EngineModel> Model(const EngineParams& params = {}) const;
};

}  // namespace sulcus::test
