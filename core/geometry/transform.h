#pragma once
// Rigid transforms and the paper's 6-vector configuration.
//
// Naming follows frames (docs/architecture.md, "Rules the code keeps"): `X_WT` is the
// pose of frame T in frame W, so `p_W = X_WT * p_T` and `X_WB = X_WT * X_TB`.
//
// Configuration (paper eq. 1): q = (x, y, z, gamma, beta, alpha), with the rotation
// R = Rz(alpha) * Ry(beta) * Rx(gamma) (paper appendix, eq. 7). These Euler angles
// are singular at beta = +/-pi/2; the engine therefore perturbs orientations with
// rotation vectors through the exponential map and uses Euler angles only at the
// boundary (files, the paper's formulas, the CLI).

#include "core/geometry/types.h"

namespace sulcus {

/// Rotation R = Rz(alpha) Ry(beta) Rx(gamma) (paper appendix).
Matrix3 RotationFromEuler(double gamma, double beta, double alpha);

/// Inverse of RotationFromEuler, returning (gamma, beta, alpha) with
/// beta in [-pi/2, pi/2] and gamma, alpha in (-pi, pi]. At the singularity
/// (|cos beta| ~ 0) gamma is set to 0 and alpha carries the whole yaw, so the
/// returned angles always reproduce R. Precondition: R is a rotation.
Vector3 EulerFromRotation(const Matrix3& R);

/// Rotation of angle |w| about w / |w| (Rodrigues). Accurate for tiny |w|.
Matrix3 ExpMap(const Vector3& w);

/// Rotation vector w with ExpMap(w) = R and |w| <= pi. Robust near 0 and pi.
Vector3 LogMap(const Matrix3& R);

/// The nearest rotation to M (polar decomposition by SVD); used to remove drift.
Matrix3 NearestRotation(const Matrix3& M);

/// A proper rigid transform: rotation R and translation p.
class RigidTransform {
 public:
  /// The identity.
  RigidTransform() : R_(Matrix3::Identity()), p_(Vector3::Zero()) {}
  /// Precondition: R is a rotation (orthonormal, det +1); not checked here.
  RigidTransform(const Matrix3& R, const Vector3& p) : R_(R), p_(p) {}
  RigidTransform(const Quaternion& q, const Vector3& p);

  static RigidTransform Identity() { return {}; }
  /// From q = (x, y, z, gamma, beta, alpha) (paper eq. 1 and 7).
  static RigidTransform FromConfiguration(const Vector6& q);
  /// From a homogeneous 4x4 matrix whose bottom row is (0, 0, 0, 1).
  static RigidTransform FromMatrix4(const Matrix4& T);

  const Matrix3& rotation() const { return R_; }
  const Vector3& translation() const { return p_; }
  Quaternion quaternion() const;

  /// (x, y, z, gamma, beta, alpha); see EulerFromRotation for the singular case.
  Vector6 ToConfiguration() const;
  /// Homogeneous matrix, the paper's T with bottom row (0, 0, 0, 1).
  Matrix4 ToMatrix4() const;

  RigidTransform inverse() const;
  /// Composition: X_AC = X_AB * X_BC.
  RigidTransform operator*(const RigidTransform& X_BC) const;
  /// Point transform: p_A = X_AB * p_B.
  Vector3 operator*(const Vector3& p_B) const { return R_ * p_B + p_; }

  /// This pose moved by dp (a translation in the outer frame) and turned by the
  /// rotation vector dtheta (about the origin of this pose, in the outer frame):
  /// R' = Exp(dtheta) R, p' = p + dp. This is the local increment of
  /// docs/architecture.md.
  RigidTransform Perturbed(const Vector3& dp, const Vector3& dtheta) const;

  /// The increment (dp, dtheta) that takes this pose to `other` in the sense of
  /// Perturbed: dp = p_other - p, dtheta = Log(R_other R^T).
  Vector6 DifferenceTo(const RigidTransform& other) const;

 private:
  Matrix3 R_;
  Vector3 p_;
};

}  // namespace sulcus
