#include "core/haptics/scripted_device.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include "core/base/files.h"
#include "core/base/text.h"

namespace sulcus {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kKeyRateHz = 200;  // named trajectories are sampled at this rate

Vector3 AnyPerpendicular(const Vector3& n) {
  const Vector3 a = std::abs(n.x()) < 0.9 ? Vector3::UnitX() : Vector3::UnitY();
  return (a - a.dot(n) * n).normalized();
}

// 0 -> 1 -> 0 over one period, smooth at both ends.
double Bump(double phase) { return 0.5 - 0.5 * std::cos(2 * kPi * phase); }

// Reaches 1 at t = ramp_s, smoothly, and stays there.
double Approach(double t, double ramp_s) {
  return t >= ramp_s ? 1.0 : 0.5 - 0.5 * std::cos(kPi * t / ramp_s);
}

}  // namespace

Trajectory::Trajectory(std::vector<Keyframe> keys) : keys_(std::move(keys)) {
  if (keys_.empty())
    throw std::invalid_argument("a trajectory needs at least one keyframe");
  for (std::size_t i = 1; i < keys_.size(); ++i)
    if (!(keys_[i].t_s > keys_[i - 1].t_s))
      throw std::invalid_argument(
          "trajectory keyframes must be in increasing time order");
  for (Keyframe& k : keys_) k.q_W.normalize();
}

DeviceSample Trajectory::Sample(double t) const noexcept {
  DeviceSample s;
  s.time_s = t;
  if (keys_.empty()) return s;
  const auto it = std::upper_bound(keys_.begin(), keys_.end(), t,
                                   [](double v, const Keyframe& k) { return v < k.t_s; });
  if (it == keys_.begin() || it == keys_.end()) {
    const Keyframe& k = it == keys_.begin() ? keys_.front() : keys_.back();
    s.X_WH = RigidTransform(k.q_W, k.p_W);
    s.buttons = k.buttons;
    return s;
  }
  const Keyframe& a = *(it - 1);
  const Keyframe& b = *it;
  const double u = (t - a.t_s) / (b.t_s - a.t_s);
  s.X_WH = RigidTransform(a.q_W.slerp(u, b.q_W), a.p_W + u * (b.p_W - a.p_W));
  s.buttons = a.buttons;
  return s;
}

const std::vector<std::string>& ScriptNames() {
  static const std::vector<std::string> names = {"line", "poke",   "slide",
                                                 "arc",  "insert", "random"};
  return names;
}

Quaternion ScriptOrientation(const ScriptTarget& target) {
  const Vector3 n = target.n_W.normalized();
  const Vector3 axis = target.axis_W.squaredNorm() > 0 ? target.axis_W.normalized() : n;
  const Vector3 z =
      target.tool_axis_W.squaredNorm() > 0 ? target.tool_axis_W.normalized() : axis;
  const Vector3 lean = target.shank_W - target.shank_W.dot(z) * z;
  if (lean.squaredNorm() < 1e-12) return Quaternion::FromTwoVectors(Vector3::UnitZ(), z);
  Matrix3 R;
  R.col(0) = -lean.normalized();
  R.col(2) = z;
  R.col(1) = z.cross(R.col(0));
  return Quaternion(R);
}

Trajectory MakeScript(const std::string& name, const ScriptTarget& target,
                      double duration_s, std::uint64_t seed) {
  if (std::find(ScriptNames().begin(), ScriptNames().end(), name) ==
      ScriptNames().end()) {
    throw std::invalid_argument("unknown scripted trajectory '" + name +
                                "'; known: " + Join(ScriptNames()));
  }
  if (!(duration_s > 0))
    throw std::invalid_argument("a trajectory needs a positive duration");
  const Vector3 n = target.n_W.normalized();
  const Vector3 axis = target.axis_W.squaredNorm() > 0 ? target.axis_W.normalized() : n;
  Vector3 u = target.along_W - target.along_W.dot(n) * n;
  u = u.squaredNorm() > 1e-12 ? u.normalized() : AnyPerpendicular(n);
  const Vector3 tilt_axis = n.cross(u).normalized();
  const Quaternion q0 = ScriptOrientation(target);
  const Vector3& p = target.p_W;

  // Random motion: a few sinusoids per direction, seeded.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> freq(0.15, 0.9), phase(0, 2 * kPi);
  struct Wave {
    double f, phi;
  };
  std::array<std::array<Wave, 3>, 6> waves{};
  for (auto& dir : waves)
    for (Wave& w : dir) w = {freq(rng), phase(rng)};
  auto noise = [&](int dir, double t) {
    double v = 0;
    for (const Wave& w : waves[dir]) v += std::sin(2 * kPi * w.f * t + w.phi);
    return v / 3;  // within [-1, 1]
  };

  std::vector<Keyframe> keys;
  const int count = static_cast<int>(std::ceil(duration_s * kKeyRateHz)) + 1;
  keys.reserve(count);
  for (int i = 0; i < count; ++i) {
    const double t = i / kKeyRateHz;
    Keyframe k;
    k.t_s = t;
    k.q_W = q0;
    if (name == "line") {
      const double s =
          2 * std::abs(std::fmod(t / 4.0 + 0.25, 1.0) * 2 - 1) - 1;  // triangle wave
      k.p_W = p + 4 * n + 10 * s * u;
    } else if (name == "poke") {
      k.p_W = p + (3.0 - 4.5 * Bump(t)) * n;
    } else if (name == "slide") {
      const double h = 3.0 - 3.5 * Approach(t, 0.5);
      k.p_W = p + h * n + 5 * std::sin(2 * kPi * std::max(0.0, t - 0.5) / 2) * u;
    } else if (name == "arc") {
      const double h = 3.0 - 3.5 * Approach(t, 0.5);
      const double angle =
          (30 * kPi / 180) * std::sin(2 * kPi * std::max(0.0, t - 0.5) / 2);
      k.p_W = p + h * n;
      k.q_W = Quaternion(Eigen::AngleAxisd(angle, tilt_axis)) * q0;
    } else if (name == "insert") {
      // Down in 1.5 s, a second at the bottom, up in 1.5 s; every 4 s.
      const double phase = std::fmod(t, 4.0), span = 3.0 + target.insert_depth_mm;
      const double a = phase < 1.5 ? 3.0 - span * Approach(phase, 1.5)
                       : phase < 2.5
                           ? -target.insert_depth_mm
                           : -target.insert_depth_mm + span * Approach(phase - 2.5, 1.5);
      k.p_W = p + target.insert_offset_mm * n + a * axis;
    } else {  // random
      const double approach = Approach(t, 0.5);
      const Vector3 v = AnyPerpendicular(n).cross(n);
      k.p_W = p + 3 * approach * (noise(0, t) * u + noise(1, t) * v) +
              (3.0 - approach * (3.5 - 1.0 * noise(2, t))) * n;
      const double tilt = (20 * kPi / 180) * approach;
      k.q_W = Quaternion(Eigen::AngleAxisd(tilt * noise(3, t), u)) *
              Quaternion(Eigen::AngleAxisd(tilt * noise(4, t), v)) * q0;
    }
    keys.push_back(k);
  }
  return Trajectory(std::move(keys));
}

Trajectory LoadTrajectoryCsv(const std::filesystem::path& file) {
  if (const std::string why = UnreadableReason(file); !why.empty())
    throw std::runtime_error(file.string() + ": " + why);
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the trajectory file");
  const std::string expected = "t_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg[,buttons]";
  std::string line;
  int line_no = 0;
  std::vector<Keyframe> keys;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(file.string() + ":" + std::to_string(line_no) + ": " +
                             ShortenQuoted(what));
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // A spreadsheet's UTF-8 byte order mark before the header.
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (line.empty() || line[0] == '#') continue;
    if (line_no == 1 || (keys.empty() && line.rfind("t_s", 0) == 0)) {
      if (line.rfind("t_s", 0) != 0) fail("expected the header line '" + expected + "'");
      continue;
    }
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      std::size_t used = 0;
      double x = 0;
      try {
        x = std::stod(cell, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      while (used < cell.size() && std::isspace(static_cast<unsigned char>(cell[used])))
        ++used;
      if (used == 0 || used != cell.size() || !std::isfinite(x))
        fail("column " + std::to_string(v.size() + 1) + " is '" + cell +
             "', expected a finite number");
      v.push_back(x);
    }
    if (v.size() != 7 && v.size() != 8)
      fail("expected 7 or 8 columns (" + expected + "), got " + std::to_string(v.size()));
    Keyframe k;
    k.t_s = v[0];
    if (k.t_s < 0 || k.t_s > 1e6)
      fail("time " + std::to_string(k.t_s) + " s is out of range (0 to 1000000 s)");
    if (!keys.empty() && !(k.t_s > keys.back().t_s))
      fail("time " + std::to_string(k.t_s) + " s must be after the previous row's " +
           std::to_string(keys.back().t_s) + " s");
    for (int c = 1; c <= 3; ++c)
      if (std::abs(v[static_cast<std::size_t>(c)]) > 1e4)
        fail("column " + std::to_string(c + 1) + ": " +
             std::to_string(v[static_cast<std::size_t>(c)]) +
             " mm is out of range (a device moves within +-10000 mm)");
    for (int c = 4; c <= 6; ++c)
      if (std::abs(v[static_cast<std::size_t>(c)]) > 36000)
        fail("column " + std::to_string(c + 1) + ": " +
             std::to_string(v[static_cast<std::size_t>(c)]) +
             " degrees is out of range (+-36000)");
    k.p_W = {v[1], v[2], v[3]};
    const double deg = kPi / 180;
    k.q_W = Quaternion(RotationFromEuler(v[4] * deg, v[5] * deg, v[6] * deg));
    if (v.size() == 8) {
      if (v[7] < 0 || v[7] != std::floor(v[7]) || v[7] > 4294967295.0)
        fail("buttons must be a whole number from 0 to 4294967295 (a bit per button)");
      k.buttons = static_cast<std::uint32_t>(v[7]);
    }
    keys.push_back(k);
  }
  if (keys.empty())
    throw std::runtime_error(file.string() + ": no keyframes; expected rows of " +
                             expected);
  return Trajectory(std::move(keys));
}

ScriptedDevice::ScriptedDevice(Trajectory trajectory, std::string name)
    : trajectory_(std::move(trajectory)) {
  caps_.name = std::move(name);
  caps_.input_dof = 6;
  caps_.output_dof = 6;
  caps_.max_force_n = 1e9;  // the scene's limits apply
  caps_.max_torque_nmm = 1e9;
}

bool ScriptedDevice::Read(double t_s, DeviceSample* out) noexcept {
  *out = trajectory_.Sample(t_s);
  finished_ = t_s >= trajectory_.duration_s();
  return true;
}

void ScriptedDevice::Write(const Vector3& force_W, const Vector3& torque_W) noexcept {
  force_W_ = force_W;
  torque_W_ = torque_W;
}

}  // namespace sulcus
