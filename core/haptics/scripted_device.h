#pragma once
// Scripted devices: trajectories as data (keyframes of a pose over time) played
// back by loop time, so a run is the same on every machine. Named trajectories
// are made around a target on an object's surface; a CSV file gives any other.

#include <filesystem>
#include <string>
#include <vector>

#include "core/haptics/device.h"

namespace sulcus {

struct Keyframe {
  double t_s = 0;
  Vector3 p_W = Vector3::Zero();
  Quaternion q_W = Quaternion::Identity();
  std::uint32_t buttons = 0;
};

/// Keyframes in time order; the pose between two is interpolated (linear
/// position, spherical orientation), held after the last.
class Trajectory {
 public:
  Trajectory() = default;
  explicit Trajectory(
      std::vector<Keyframe> keys);  // throws std::invalid_argument if unordered or empty
  const std::vector<Keyframe>& keys() const { return keys_; }
  double duration_s() const { return keys_.empty() ? 0 : keys_.back().t_s; }
  /// The pose at time t; never allocates.
  DeviceSample Sample(double t_s) const noexcept;

 private:
  std::vector<Keyframe> keys_;
};

/// Where a named trajectory works: a point on a surface, the surface's outward
/// normal there, and the direction the working end should point along (its +z,
/// away from the tip; by default the normal).
struct ScriptTarget {
  Vector3 p_W = Vector3::Zero();
  Vector3 n_W = Vector3::UnitZ();
  Vector3 axis_W = Vector3::Zero();   // zero: use n_W
  Vector3 along_W = Vector3::Zero();  // a tangent for slides (zero: any)
  Vector3 tool_axis_W =
      Vector3::Zero();  // the working end's direction if not axis_W (a tilt)
  Vector3 shank_W =
      Vector3::Zero();           // where the shank leans (the tool frame's -x), zero: any
  double insert_depth_mm = 4.0;  // how far below the target `insert` goes
  double insert_offset_mm = 0.3;  // how far off the target, along n, `insert` moves
  int object = -1;                // the scene object the target is on, when known
};

/// The tool's orientation a trajectory starts from: its +z along the tool axis
/// (tool_axis_W, else axis_W, else n_W), its shank (-x) leaning toward shank_W
/// when given.
Quaternion ScriptOrientation(const ScriptTarget& target);

/// The names the CLI offers.
const std::vector<std::string>& ScriptNames();

/// A named trajectory around the target, `duration_s` long:
///  line   passes 4 mm above the target, 20 mm across, without touching;
///  poke   presses along -n, 1.5 mm into the surface and back, once a second;
///  slide  presses 0.5 mm in and slides +-5 mm along the surface;
///  arc    presses 0.5 mm in and tilts the tool +-30 degrees about the tip;
///  insert moves the tip down along `axis_W` from 3 mm above the target to
///         insert_depth_mm below it in 1.5 s, stays there a second and comes back
///         up in 1.5 s (every 4 s), insert_offset_mm off the target along n;
///  random smooth seeded motion within 3 mm of the target that keeps touching.
/// Throws std::invalid_argument for an unknown name (listing the known ones).
Trajectory MakeScript(const std::string& name, const ScriptTarget& target,
                      double duration_s, std::uint64_t seed = 1);

/// A CSV trajectory: a header line, then `t_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg`
/// with an optional `buttons` column. Throws std::runtime_error naming the file,
/// the line and what was expected.
Trajectory LoadTrajectoryCsv(const std::filesystem::path& file);

class ScriptedDevice final : public Device {
 public:
  explicit ScriptedDevice(Trajectory trajectory, std::string name = "scripted");
  const DeviceCaps& caps() const override { return caps_; }
  bool Read(double t_s, DeviceSample* out) noexcept override;
  void Write(const Vector3& force_W, const Vector3& torque_W) noexcept override;
  bool finished() const noexcept override { return finished_; }
  const Vector3& last_force_W() const { return force_W_; }

 private:
  Trajectory trajectory_;
  DeviceCaps caps_;
  Vector3 force_W_ = Vector3::Zero(), torque_W_ = Vector3::Zero();
  bool finished_ = false;
};

}  // namespace sulcus
