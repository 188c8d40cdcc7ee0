#pragma once
// Scenes for engine tests and the hard-case suite, made of hand-placed spheres
// (the engine needs only the trees; the builder has its own tests).

#include <memory>
#include <vector>

#include "core/haptics/device.h"
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

inline RigidTransform At(double x, double y, double z) {
  return {Matrix3::Identity(), Vector3(x, y, z)};
}

/// A device whose pose the test sets; it can stop answering or report NaN.
class PuppetDevice final : public Device {
 public:
  PuppetDevice() {
    caps_.name = "puppet";
    caps_.output_dof = 6;
    caps_.max_force_n = 2.0;
    caps_.max_torque_nmm = 100;
  }
  const DeviceCaps& caps() const override { return caps_; }
  bool Read(double t, DeviceSample* out) noexcept override {
    out->X_WH = pose;
    out->time_s = t;
    return answering;
  }
  bool lost() const noexcept override { return gone; }
  void Write(const Vector3& f, const Vector3& t) noexcept override {
    force = f;
    torque = t;
  }
  RigidTransform pose = At(0, 0, 3);
  bool answering = true;
  bool gone = false;  // says it is gone (unplugged), as a driver can
  Vector3 force = Vector3::Zero(), torque = Vector3::Zero();

 private:
  DeviceCaps caps_;
};

/// A scene: owns its trees, and an engine model on them.
struct Scene {
  std::vector<std::unique_ptr<SphereTree>> trees;
  std::unique_ptr<SphereTree> tool;
  std::vector<CollisionWorld::Object> objects;
  void Add(SphereTree tree, const RigidTransform& X_WO);
  std::unique_ptr<EngineModel> Model(const EngineParams& params = {}) const;
};

}  // namespace sulcus::test
