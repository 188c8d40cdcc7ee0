#include "core/geometry/transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "tests/common/compare.h"

namespace sulcus {
namespace {

using test::CompareMatrices;
using test::CompareScalars;
namespace tol = test::tol;
constexpr double kPi = std::numbers::pi;

Matrix3 Rx(double a) { return Eigen::AngleAxisd(a, Vector3::UnitX()).toRotationMatrix(); }
Matrix3 Ry(double a) { return Eigen::AngleAxisd(a, Vector3::UnitY()).toRotationMatrix(); }
Matrix3 Rz(double a) { return Eigen::AngleAxisd(a, Vector3::UnitZ()).toRotationMatrix(); }

// Seeded random configurations; every fourth has beta exactly at +/-90 degrees.
std::vector<Vector6> RandomConfigurations(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-100, 100), ang(-kPi, kPi),
      half(-kPi / 2, kPi / 2);
  std::vector<Vector6> out;
  for (int i = 0; i < n; ++i) {
    Vector6 q;
    q << pos(rng), pos(rng), pos(rng), ang(rng), half(rng), ang(rng);
    if (i % 4 == 1) q[4] = kPi / 2;
    if (i % 4 == 2) q[4] = -kPi / 2;
    out.push_back(q);
  }
  return out;
}

TEST(Transform, AppendixMatrixEntryByEntry) {
  const double g = 0.3, b = -0.7, a = 1.9;
  const Matrix3 R = RotationFromEuler(g, b, a);
  const double cg = std::cos(g), sg = std::sin(g), cb = std::cos(b), sb = std::sin(b),
               ca = std::cos(a), sa = std::sin(a);
  // The paper's T, typed from the appendix (its bottom row "1 1 1 1" is a typo
  // for "0 0 0 1").
  Matrix4 T;
  T << ca * cb, ca * sb * sg - sa * cg, ca * sb * cg + sa * sg, 4.0,  //
      sa * cb, sa * sb * sg + ca * cg, sa * sb * cg - ca * sg, 5.0,   //
      -sb, cb * sg, cb * cg, 6.0,                                     //
      0, 0, 0, 1;
  EXPECT_TRUE(CompareMatrices(R, T.topLeftCorner<3, 3>(), tol::kRoundTrip));
  Vector6 q;
  q << 4, 5, 6, g, b, a;
  EXPECT_TRUE(CompareMatrices(RigidTransform::FromConfiguration(q).ToMatrix4(), T,
                              tol::kRoundTrip));
  // And it is Rz(alpha) Ry(beta) Rx(gamma).
  EXPECT_TRUE(CompareMatrices(R, Rz(a) * Ry(b) * Rx(g), tol::kRoundTrip));
}

TEST(Transform, EulerMatrixRoundTripIncludingGimbalLock) {
  for (const Vector6& q : RandomConfigurations(2000, 42)) {
    const Matrix3 R = RotationFromEuler(q[3], q[4], q[5]);
    const Vector3 e = EulerFromRotation(R);
    // The matrix always comes back, even where the angles are not unique.
    ASSERT_TRUE(CompareMatrices(RotationFromEuler(e[0], e[1], e[2]), R, tol::kRoundTrip))
        << "q = " << q.transpose();
    EXPECT_LE(std::abs(e[1]), kPi / 2 + tol::kRoundTrip);
    if (std::abs(std::abs(q[4]) - kPi / 2) > 1e-3) {
      // Away from the singularity the angles are unique.
      EXPECT_TRUE(CompareMatrices(e, q.tail<3>(), tol::kNearSingular)) << q.transpose();
    } else {
      EXPECT_TRUE(CompareScalars(e[1], q[4], tol::kNearSingular));
    }
  }
}

TEST(Transform, GimbalLockKeepsOnlyTheDefinedCombination) {
  // At beta = +90 deg only alpha - gamma matters: (0.4, 0.9) and (0, 0.5) agree.
  const Matrix3 R1 = RotationFromEuler(0.4, kPi / 2, 0.9);
  const Matrix3 R2 = RotationFromEuler(0.0, kPi / 2, 0.5);
  EXPECT_TRUE(CompareMatrices(R1, R2, tol::kRoundTrip));
  const Vector3 e = EulerFromRotation(R1);
  EXPECT_TRUE(CompareScalars(e[0], 0.0, 0.0));
  EXPECT_TRUE(CompareScalars(e[2], 0.5, tol::kRoundTrip));
  // At beta = -90 deg only alpha + gamma matters.
  const Vector3 f = EulerFromRotation(RotationFromEuler(0.4, -kPi / 2, 0.9));
  EXPECT_TRUE(CompareScalars(f[2], 1.3, tol::kRoundTrip));
}

TEST(Transform, QuaternionRoundTrip) {
  for (const Vector6& q : RandomConfigurations(500, 7)) {
    const RigidTransform X = RigidTransform::FromConfiguration(q);
    const RigidTransform Y(X.quaternion(), X.translation());
    ASSERT_TRUE(CompareMatrices(Y.ToMatrix4(), X.ToMatrix4(), tol::kRoundTrip));
    // Configuration -> transform -> configuration -> transform is the identity map.
    const RigidTransform Z = RigidTransform::FromConfiguration(X.ToConfiguration());
    ASSERT_TRUE(CompareMatrices(Z.ToMatrix4(), X.ToMatrix4(), tol::kRoundTrip * 100,
                                test::ToleranceType::kRelative));
  }
}

TEST(Transform, CompositionInverseAndPoints) {
  const auto qs = RandomConfigurations(300, 11);
  for (std::size_t i = 0; i + 2 < qs.size(); i += 3) {
    const RigidTransform X_AB = RigidTransform::FromConfiguration(qs[i]);
    const RigidTransform X_BC = RigidTransform::FromConfiguration(qs[i + 1]);
    const RigidTransform X_CD = RigidTransform::FromConfiguration(qs[i + 2]);
    const Vector3 p_D = qs[i + 2].head<3>() * 0.1;
    // Composition agrees with 4x4 matrix products and with point mapping.
    EXPECT_TRUE(CompareMatrices((X_AB * X_BC).ToMatrix4(),
                                X_AB.ToMatrix4() * X_BC.ToMatrix4(), 1e-12,
                                test::ToleranceType::kRelative));
    EXPECT_TRUE(CompareMatrices((X_AB * X_BC * X_CD) * p_D, X_AB * (X_BC * (X_CD * p_D)),
                                1e-12, test::ToleranceType::kRelative));
    // Associativity.
    EXPECT_TRUE(CompareMatrices(((X_AB * X_BC) * X_CD).ToMatrix4(),
                                (X_AB * (X_BC * X_CD)).ToMatrix4(), 1e-12,
                                test::ToleranceType::kRelative));
    // Through a homogeneous matrix and back.
    EXPECT_TRUE(CompareMatrices(RigidTransform::FromMatrix4(X_AB.ToMatrix4()).ToMatrix4(),
                                X_AB.ToMatrix4(), 0.0));
    // Inverse.
    EXPECT_TRUE(CompareMatrices((X_AB * X_AB.inverse()).ToMatrix4(), Matrix4::Identity(),
                                1e-12, test::ToleranceType::kRelative));
    EXPECT_TRUE(CompareMatrices(X_AB.inverse() * (X_AB * p_D), p_D, 1e-12,
                                test::ToleranceType::kRelative));
  }
}

TEST(Transform, ExpLogRoundTripAcrossAngles) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0, 1);
  // Tiny, ordinary and near-pi angles (where acos-based logs lose precision).
  for (double angle :
       {0.0, 1e-14, 1e-9, 1e-5, 1e-3, 0.5, 2.0, 3.0, kPi - 1e-6, kPi - 1e-9}) {
    for (int k = 0; k < 20; ++k) {
      const Vector3 axis = Vector3(n(rng), n(rng), n(rng)).normalized();
      const Vector3 w = angle * axis;
      const Matrix3 R = ExpMap(w);
      ASSERT_TRUE(
          CompareMatrices(R, Eigen::AngleAxisd(angle, axis).toRotationMatrix(), 1e-14));
      ASSERT_TRUE(CompareScalars(R.determinant(), 1.0, 1e-14));
      // Near pi the axis of R is recovered to ~eps / (pi - angle).
      const double tol = angle > 3.1 ? 1e-6 : 1e-12;
      ASSERT_TRUE(CompareMatrices(ExpMap(LogMap(R)), R, tol)) << "angle " << angle;
      if (angle < 3.0) {
        ASSERT_TRUE(CompareMatrices(LogMap(R), w, 1e-12)) << "angle " << angle;
      }
    }
  }
}

TEST(Transform, IncrementIsLocalAndNonSingularAtGimbalLock) {
  // At beta = 90 deg, a small rotation about the world x axis: Euler angles
  // cannot express it smoothly (their Jacobian is singular), the increment can.
  Vector6 q;
  q << 1, 2, 3, 0.2, kPi / 2, -0.3;
  const RigidTransform X = RigidTransform::FromConfiguration(q);
  const Vector3 dtheta(1e-6, 0, 0), dp(0.1, 0, 0);
  const RigidTransform Y = X.Perturbed(dp, dtheta);
  EXPECT_TRUE(CompareMatrices(Y.rotation(), Rx(1e-6) * X.rotation(), 1e-15));
  EXPECT_TRUE(CompareMatrices(Y.translation(), X.translation() + dp, 1e-15));
  Vector6 expected;
  expected << dp, dtheta;
  EXPECT_TRUE(CompareMatrices(X.DifferenceTo(Y), expected, 1e-15));
}

TEST(Transform, NearestRotationRemovesDrift) {
  Matrix3 R = RotationFromEuler(0.1, 0.2, 0.3);
  R(0, 1) += 1e-6;
  const Matrix3 Q = NearestRotation(R);
  EXPECT_TRUE(CompareMatrices(Q * Q.transpose(), Matrix3::Identity(), 1e-14));
  EXPECT_TRUE(CompareScalars(Q.determinant(), 1.0, 1e-14));
  EXPECT_TRUE(CompareMatrices(Q, R, 1e-6));
}

}  // namespace
}  // namespace sulcus
