#pragma once
// Shapes the soft tissues share, private to core/anatomy's soft-tissue files:
// the arch curve, lofted meshes, the arches' teeth, and the jaw (jaw.cpp) that
// MakeSoftTissue (soft_tissue.cpp) builds among the others.

#include <algorithm>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "core/anatomy/soft_tissue.h"
#include "core/anatomy/tooth.h"

namespace sulcus::soft_tissue {

inline constexpr double kPi = std::numbers::pi;
using Vector2 = Eigen::Vector2d;

// One arch's occlusal curve as a function of signed arc length s (negative on
// the patient's right), with its tangent (toward +s) and outward normal.
class ArchCurve {
 public:
  ArchCurve(bool upper, const ArchParams& params) {
    points_.resize(2 * kHalf + 1);
    for (int i = 0; i <= 2 * kHalf; ++i) {
      const double s = (i - kHalf) * kStep;
      points_[i] = ArchPoint(upper, s < 0, std::abs(s), params);
    }
  }
  Vector3 Point(double s) const {
    const double x = std::clamp(s / kStep + kHalf, 0.0, 2.0 * kHalf - 1e-9);
    const int i = static_cast<int>(x);
    const double t = x - i;
    return (1 - t) * points_[i] + t * points_[i + 1];
  }
  Vector3 Tangent(double s) const {
    return (Point(s + 0.1) - Point(s - 0.1)).normalized();
  }
  Vector3 Normal(double s) const {  // horizontal, out of the arch (buccal)
    const Vector3 t = Tangent(s);
    return Vector3(-t.y(), t.x(), 0).normalized();
  }
  // The s whose curve point is nearest p (in plan), from a starting guess.
  double Project(const Vector3& p, double s0) const {
    double s = s0;
    for (int i = 0; i < 5; ++i) {
      Vector3 d = p - Point(s);
      d.z() = 0;
      s += d.dot(Tangent(s));
    }
    return s;
  }

 private:
  static constexpr int kHalf = 2000;     // samples each side of the midline
  static constexpr double kStep = 0.05;  // mm: the curve to 100 mm from the midline
  std::vector<Vector3> points_;
};

// A closed mesh through rings of equal size (each a closed loop), capped at
// both ends by a vertex at the ring's centroid; made outward.
TriangleMesh Loft(const std::vector<std::vector<Vector3>>& rings);

// A rounded rectangle (superellipse of exponent e) spanning [u0, u1] along
// `u` and [z0, z1] along +z, about `origin`; m points, counter-clockwise.
std::vector<Vector3> Section(const Vector3& origin, const Vector3& u, double u0,
                             double u1, double z0, double z1, int m, double e = 4.0);

// The placed teeth of an arch (no third molars) and their meshes, with each
// tooth's centre on the curve.
struct ArchTeeth {
  std::vector<PlacedTooth> placed;
  std::vector<TriangleMesh> meshes;
  std::vector<double> s;  // signed arc of each tooth's centre
};

// The same arch's teeth are generated once per process: every soft tissue of a
// scene is shaped around them.
const ArchTeeth& Teeth(bool upper, const ArchParams& arch);

// The last tooth's distal end, mm along the arch.
inline double ArchEnd(bool upper) { return ArchCentreMm(upper, 7) + 5.5; }

// 0 below 0, 1 above 1, a cubic between with level ends.
inline double SmoothStep(double x) {
  const double t = std::clamp(x, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// The jaw of one arch: a bar along the curve whose section holds every root
// (1.5 mm of bone around it, 2.5 mm beyond the apex), its top at the crest;
// with the bone between the roots of a tooth whose furcation the scene
// involves (InterradicularBone).
TriangleMesh Jaw(bool upper, const ArchParams& arch, const std::map<int, double>& drops,
                 const std::map<int, std::map<std::string, int>>& furcation);

}  // namespace sulcus::soft_tissue
