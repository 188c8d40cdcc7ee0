#pragma once
// What the probing tests share: the sphere-tree cache they build into, a
// scripted probe played on a scene offline, and a scene's exact meshes (what
// the felt surface is measured against).

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/anatomy/mesh_contact.h"
#include "core/haptics/scripted_device.h"
#include "core/scene/scene.h"
#include "core/session/session.h"

namespace sulcus::probing_test {

inline std::filesystem::path Cache() {
  return std::filesystem::path(SULCUS_TEST_OUTPUT) / "probing-cache";
}

// Plays `keys` on `scene` offline for `ticks` ticks; `consumer`, if given, sees
// every tick. The session is returned for its loop's state after the run.
inline std::unique_ptr<Session> PlayOffline(const CompiledScene& scene,
                                            std::vector<Keyframe> keys,
                                            std::uint64_t ticks, const std::string& name,
                                            TickConsumer* consumer = nullptr) {
  DeviceSpec d;
  d.device = std::make_unique<ScriptedDevice>(Trajectory(std::move(keys)), name);
  SessionOptions so;
  so.max_ticks = ticks;
  auto session = std::make_unique<Session>(scene, std::move(d), so);
  if (consumer) session->AddConsumer(consumer);
  session->RunOffline();
  return session;
}

// A compiled scene's objects as their exact meshes, placed in the world (those
// `keep` accepts; every one by default), and the probe's exact mesh at a pose:
// what the engine's felt surface is measured against.
struct ExactScene {
  explicit ExactScene(const CompiledScene& scene,
                      const std::function<bool(const ObjectSpec&)>& keep = {})
      : tool(scene.tool_mesh) {
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
      const ObjectSpec& o = scene.spec.objects[i];
      if (keep && !keep(o)) continue;
      TriangleMesh m = scene.meshes[i];
      m.Transform(o.X_WO.rotation(), o.X_WO.translation());
      objects.push_back(std::move(m));
    }
  }
  TriangleMesh Probe(const RigidTransform& X) const {
    TriangleMesh probe = tool;
    probe.Transform(X.rotation(), X.translation());
    return probe;
  }
  // Whether the probe at X meets none of the objects (exact triangle tests).
  bool ProbeFree(const RigidTransform& X) const {
    const TriangleMesh probe = Probe(X);
    for (const TriangleMesh& m : objects)
      if (MeshesIntersect(probe, m)) return false;
    return true;
  }
  std::vector<TriangleMesh> objects;
  const TriangleMesh& tool;
};

// Bisection between a value where `free_at` is false and one where it is true,
// to within `tolerance`: the free end.
inline double FreeEnd(const std::function<bool(double)>& free_at, double touching,
                      double free, double tolerance) {
  while (std::abs(free - touching) > tolerance) {
    const double mid = 0.5 * (touching + free);
    (free_at(mid) ? free : touching) = mid;
  }
  return free;
}

}  // namespace sulcus::probing_test
