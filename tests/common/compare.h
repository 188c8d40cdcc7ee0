#pragma once
// Floating-point comparison for tests (docs/architecture.md, "Rules the code keeps"): one
// helper for scalars and matrices, absolute or relative, with tolerances that carry a
// name and a reason. Never EXPECT_EQ a computed double.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace sulcus::test {

enum class ToleranceType {
  kAbsolute,  // |a - b| <= tol
  kRelative,  // |a - b| <= tol * max(1, |a|, |b|)  (absolute near zero)
};

/// Named tolerances, each with the reason for its size.
namespace tol {
// Products of a few rotations in double: round-off grows like 10 ulp per product.
inline constexpr double kRoundTrip = 1e-12;
// Angles recovered through atan2 near the Euler singularity lose ~sqrt(eps).
inline constexpr double kNearSingular = 1e-7;
// float32 storage (STL): 24-bit mantissa, ~6e-8 relative.
inline constexpr double kFloat32 = 1e-6;
// Sums over thousands of triangles: accumulated round-off, still far below 1 ppm.
inline constexpr double kAccumulated = 1e-9;
}  // namespace tol

inline ::testing::AssertionResult CompareScalars(
    double a, double b, double tolerance, ToleranceType type = ToleranceType::kAbsolute) {
  if (!std::isfinite(a) || !std::isfinite(b)) {
    if (a == b) return ::testing::AssertionSuccess();  // same infinity
    return ::testing::AssertionFailure() << a << " vs " << b << ": non-finite";
  }
  const double scale =
      type == ToleranceType::kRelative ? std::max({1.0, std::abs(a), std::abs(b)}) : 1.0;
  const double err = std::abs(a - b);
  if (err <= tolerance * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << a << " vs " << b << ": difference " << err << " exceeds "
         << (type == ToleranceType::kRelative ? "relative " : "absolute ") << "tolerance "
         << tolerance;
}

/// Compares two matrices entry by entry. Fails on a shape mismatch, a NaN, or
/// the first entry outside the tolerance, printing both matrices.
template <typename DerivedA, typename DerivedB>
::testing::AssertionResult CompareMatrices(
    const Eigen::MatrixBase<DerivedA>& a, const Eigen::MatrixBase<DerivedB>& b,
    double tolerance, ToleranceType type = ToleranceType::kAbsolute) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << "shape " << a.rows() << "x" << a.cols()
                                         << " vs " << b.rows() << "x" << b.cols();
  }
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      auto r = CompareScalars(static_cast<double>(a(i, j)), static_cast<double>(b(i, j)),
                              tolerance, type);
      if (!r) {
        std::ostringstream s;
        s << "entry (" << i << ", " << j << "): " << r.message() << "\nfirst:\n"
          << a << "\nsecond:\n"
          << b;
        return ::testing::AssertionFailure() << s.str();
      }
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace sulcus::test
