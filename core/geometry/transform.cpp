#include "core/geometry/transform.h"

#include <Eigen/SVD>
#include <cmath>

namespace sulcus {

Matrix3 RotationFromEuler(double gamma, double beta, double alpha) {
  const double cg = std::cos(gamma), sg = std::sin(gamma);
  const double cb = std::cos(beta), sb = std::sin(beta);
  const double ca = std::cos(alpha), sa = std::sin(alpha);
  Matrix3 R;
  // Paper appendix, entry by entry.
  R << ca * cb, ca * sb * sg - sa * cg, ca * sb * cg + sa * sg,  //
      sa * cb, sa * sb * sg + ca * cg, sa * sb * cg - ca * sg,   //
      -sb, cb * sg, cb * cg;
  return R;
}

Vector3 EulerFromRotation(const Matrix3& R) {
  const double cb = std::hypot(R(0, 0), R(1, 0));
  const double beta = std::atan2(-R(2, 0), cb);
  // Below this, (R21, R22) and (R10, R00) are round-off and carry no angle.
  constexpr double kSingular = 1e-12;
  if (cb > kSingular) {
    return {std::atan2(R(2, 1), R(2, 2)), beta, std::atan2(R(1, 0), R(0, 0))};
  }
  // beta = +/-pi/2: only alpha -/+ gamma is defined; take gamma = 0. Then for both
  // signs R01 = -sin(alpha) and R11 = cos(alpha).
  return {0.0, beta, std::atan2(-R(0, 1), R(1, 1))};
}

Matrix3 ExpMap(const Vector3& w) {
  const double theta = w.norm();
  // Series for sin(t)/t and (1-cos t)/t^2 below this angle; exact to double.
  constexpr double kSmall = 1e-4;
  double a, b;
  if (theta < kSmall) {
    const double t2 = theta * theta;
    a = 1.0 - t2 / 6.0;
    b = 0.5 - t2 / 24.0;
  } else {
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / (theta * theta);
  }
  Matrix3 W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return Matrix3::Identity() + a * W + b * W * W;
}

Vector3 LogMap(const Matrix3& R) {
  // Through the quaternion: robust at 0 and at pi, unlike acos((tr R - 1) / 2).
  Quaternion q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Vector3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v;  // angle ~ 2 s, direction v / s
  const double angle = 2.0 * std::atan2(s, q.w());
  return v * (angle / s);
}

Matrix3 NearestRotation(const Matrix3& M) {
  Eigen::JacobiSVD<Matrix3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3 U = svd.matrixU();
  const Matrix3 V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) = -U.col(2);
  return U * V.transpose();
}

RigidTransform::RigidTransform(const Quaternion& q, const Vector3& p)
    : R_(q.normalized().toRotationMatrix()), p_(p) {}

RigidTransform RigidTransform::FromConfiguration(const Vector6& q) {
  return {RotationFromEuler(q[3], q[4], q[5]), q.head<3>()};
}

RigidTransform RigidTransform::FromMatrix4(const Matrix4& T) {
  return {T.topLeftCorner<3, 3>(), T.topRightCorner<3, 1>()};
}

Quaternion RigidTransform::quaternion() const {
  Quaternion q(R_);
  q.normalize();
  return q;
}

Vector6 RigidTransform::ToConfiguration() const {
  Vector6 q;
  q << p_, EulerFromRotation(R_);
  return q;
}

Matrix4 RigidTransform::ToMatrix4() const {
  Matrix4 T = Matrix4::Identity();
  T.topLeftCorner<3, 3>() = R_;
  T.topRightCorner<3, 1>() = p_;
  return T;
}

RigidTransform RigidTransform::inverse() const {
  const Matrix3 Rt = R_.transpose();
  return {Rt, -(Rt * p_)};
}

RigidTransform RigidTransform::operator*(const RigidTransform& X_BC) const {
  return {R_ * X_BC.R_, R_ * X_BC.p_ + p_};
}

RigidTransform RigidTransform::Perturbed(const Vector3& dp, const Vector3& dtheta) const {
  return {ExpMap(dtheta) * R_, p_ + dp};
}

Vector6 RigidTransform::DifferenceTo(const RigidTransform& other) const {
  Vector6 d;
  d << other.p_ - p_, LogMap(other.R_ * R_.transpose());
  return d;
}

}  // namespace sulcus
