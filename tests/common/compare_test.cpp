#include "tests/common/compare.h"

#include <limits>

namespace sulcus::test {
namespace {

TEST(CompareScalars, AbsoluteAndRelative) {
  EXPECT_TRUE(CompareScalars(1.0, 1.0 + 5e-13, tol::kRoundTrip));
  EXPECT_FALSE(CompareScalars(1.0, 1.0 + 5e-12, tol::kRoundTrip));
  // 1e6 vs 1e6 + 1e-7: absolute error 1e-7 fails 1e-12, relative error 1e-13 passes.
  EXPECT_FALSE(
      CompareScalars(1e6, 1e6 + 1e-7, tol::kRoundTrip, ToleranceType::kAbsolute));
  EXPECT_TRUE(CompareScalars(1e6, 1e6 + 1e-7, tol::kRoundTrip, ToleranceType::kRelative));
}

TEST(CompareScalars, NonFinite) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(CompareScalars(nan, nan, 1.0));
  EXPECT_FALSE(CompareScalars(1.0, inf, 1e300));
  EXPECT_TRUE(CompareScalars(inf, inf, 0.0));
}

TEST(CompareMatrices, ShapeEntryAndMessage) {
  const Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d b = a;
  EXPECT_TRUE(CompareMatrices(a, b, 0.0));
  b(1, 2) = 1e-3;
  const auto r = CompareMatrices(a, b, 1e-6);
  ASSERT_FALSE(r);
  EXPECT_NE(std::string(r.message()).find("entry (1, 2)"), std::string::npos);
  EXPECT_FALSE(CompareMatrices(a, Eigen::Vector3d::Zero(), 1.0));
}

}  // namespace
}  // namespace sulcus::test
