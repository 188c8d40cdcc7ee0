#pragma once
// The small dense QP of the haptic frame (paper eq. 2 and V-B):
//
//   minimise 1/2 (q - q0)^T G (q - q0)   subject to   A q >= b,
//
// with 6 variables, G = diag(g) positive, and up to a few thousand constraints.
//
// Method. With x = G^(1/2) (q - q0) the problem is a least-distance problem
// (LDP): the point of the polyhedron {x : E x >= f} nearest the origin, where
// E = A G^(-1/2) row-normalised. This removes the bad scaling of G (1 N/mm
// against 1000 N*mm/rad). The LDP is solved through its dual, a non-negative
// least-squares problem of 7 rows, by the Lawson-Hanson active-set method
// (Lawson & Hanson, "Solving Least Squares Problems", ch. 23):
// - the active ("passive") set never holds more than 7 linearly independent
//   constraints, so duplicate, near-parallel and more-than-6-active (degenerate)
//   sets are handled by construction, and every inner solve is a fixed 7x7 QR;
// - it starts from the previous frame's active set (warm start);
// - an infeasible set is detected exactly (zero dual residual) and then solved
//   as an elastic problem that minimises the violation, so the answer is the
//   least-violating pose, never garbage.
// The solver allocates only in its constructor and never throws.

#include <array>
#include <cstdint>
#include <vector>

#include "core/geometry/types.h"

namespace sulcus {

enum class QpStatus : std::uint8_t {
  kSolved,             // optimal; KKT residual checked
  kInfeasibleRelaxed,  // no q satisfies every row: least-violating q returned
  kIterationLimit,  // stopped at the cap; q is the last iterate (feasible for the active
                    // set)
  kTooManyConstraints,  // m above the capacity given at construction; q = q0
  kBadInput,            // a non-finite or non-positive input; q = q0
};

const char* ToString(QpStatus status);

constexpr int kQpVars = 6;
constexpr int kQpMaxActive = kQpVars + 2;  // elastic problem: 7 variables, 8 dual rows

struct QpSolution {
  QpStatus status = QpStatus::kSolved;
  Vector6 q = Vector6::Zero();
  int iterations = 0;  // columns added to the active set (outer iterations)
  int num_active = 0;
  std::array<std::int32_t, kQpMaxActive> active{};  // rows with a positive multiplier
  std::array<double, kQpMaxActive> lambda{};  // their multipliers, for A q >= b as given
  double kkt_residual =
      0;  // max of stationarity, complementarity, dual infeasibility (relative)
  double max_violation = 0;  // max over rows of (b - A q) / |row of A G^-1/2|, >= 0
};

class QpSolver {
 public:
  /// Preallocates for up to `max_constraints` rows.
  explicit QpSolver(int max_constraints);

  /// Solves the QP. A is m x 6, row-major; b has m entries; g are the diagonal
  /// entries of G (all > 0). `warm_rows` (may be null) are rows believed active,
  /// e.g. last frame's active constraints; order does not matter. No allocation,
  /// no exception. The returned reference stays valid until the next call.
  const QpSolution& Solve(const double* A, const double* b, int m, const Vector6& g,
                          const Vector6& q0, const std::int32_t* warm_rows = nullptr,
                          int num_warm = 0) noexcept;

  int capacity() const { return capacity_; }

 private:
  int capacity_;
  std::vector<double> columns_;  // dual columns, (rows x m) column-major, rows = 7 or 8
  std::vector<double> scale_;    // |row of A G^-1/2|
  std::vector<std::uint8_t> in_set_;
  std::vector<std::uint8_t> blocked_;
  QpSolution solution_;
};

}  // namespace sulcus
