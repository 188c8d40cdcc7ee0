#include "core/haptics/pose_grid.h"

#include <cmath>

namespace sulcus {

bool EncodePose(const RigidTransform& X, PoseCode* code) noexcept {
  const Vector3& p = X.translation();
  if (!p.allFinite() || !X.rotation().allFinite() || p.cwiseAbs().maxCoeff() > 1e6)
    return false;
  Quaternion q(X.rotation());
  const double n = q.norm();
  if (!(n > 0.5 && n < 2)) return false;  // not a rotation
  q.coeffs() /= n;
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  for (int i = 0; i < 3; ++i) code->p[i] = std::llround(p[i] / kPositionStepMm);
  const double c[4] = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 4; ++i) code->q[i] = std::llround(c[i] / kQuaternionStep);
  return true;
}

RigidTransform DecodePose(const PoseCode& code) noexcept {
  Quaternion q(static_cast<double>(code.q[0]) * kQuaternionStep,
               static_cast<double>(code.q[1]) * kQuaternionStep,
               static_cast<double>(code.q[2]) * kQuaternionStep,
               static_cast<double>(code.q[3]) * kQuaternionStep);
  const double n = q.norm();
  if (n > 0)
    q.coeffs() /= n;
  else
    q = Quaternion::Identity();
  const Vector3 p(static_cast<double>(code.p[0]) * kPositionStepMm,
                  static_cast<double>(code.p[1]) * kPositionStepMm,
                  static_cast<double>(code.p[2]) * kPositionStepMm);
  return RigidTransform(q.toRotationMatrix(), p);
}

}  // namespace sulcus
