#include "core/solver/qp.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <limits>
#include <random>

#include "tests/common/alloc_guard.h"
#include "tests/common/compare.h"

namespace sulcus {
namespace {

using test::CompareMatrices;
using Rows = std::vector<Vector6>;

// Named tolerances: the solver's own KKT check is relative to 1 + |x|; solutions
// of well-posed random problems agree with the reference to ~1e-9.
constexpr double kKkt = 1e-9;
constexpr double kAgree = 1e-7;

struct Problem {
  Rows a;
  std::vector<double> b;
  Vector6 g, q0;
  std::vector<double> Flat() const {
    std::vector<double> f;
    for (const Vector6& r : a) f.insert(f.end(), r.data(), r.data() + 6);
    return f;
  }
};

// Exact reference for small m: try every active set of up to 6 rows, solve the
// equality-constrained QP, keep the feasible point with non-negative multipliers
// and the least objective.
Vector6 Reference(const Problem& p) {
  const int m = static_cast<int>(p.a.size());
  const Matrix6 G = p.g.asDiagonal();
  double best = std::numeric_limits<double>::infinity();
  Vector6 best_q = p.q0;
  for (int mask = 0; mask < (1 << m); ++mask) {
    std::vector<int> act;
    for (int i = 0; i < m; ++i) {
      if (mask & (1 << i)) act.push_back(i);
    }
    if (act.size() > 6) continue;
    const int k = static_cast<int>(act.size());
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(6 + k, 6 + k);
    Eigen::VectorXd rhs(6 + k);
    K.topLeftCorner(6, 6) = G;
    rhs.head(6) = G * p.q0;
    for (int j = 0; j < k; ++j) {
      K.block(0, 6 + j, 6, 1) = -p.a[act[j]];
      K.block(6 + j, 0, 1, 6) = p.a[act[j]].transpose();
      rhs[6 + j] = p.b[act[j]];
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
    if (lu.rank() < 6 + k) continue;
    const Eigen::VectorXd sol = lu.solve(rhs);
    const Vector6 q = sol.head(6);
    bool ok = (sol.tail(k).array() >= -1e-12).all();
    for (int i = 0; i < m && ok; ++i) ok = p.a[i].dot(q) >= p.b[i] - 1e-9;
    if (!ok) continue;
    const double obj = 0.5 * (q - p.q0).dot(G * (q - p.q0));
    if (obj < best) {
      best = obj;
      best_q = q;
    }
  }
  return best_q;
}

Problem RandomFeasible(std::mt19937_64& rng, int m, double g_ratio) {
  std::normal_distribution<double> n(0, 1);
  Problem p;
  p.g << 1, 1, 1, g_ratio, g_ratio, g_ratio;
  // Rows are distance-form constraints: [normal, lever x normal].
  const Vector6 q_feasible = Vector6::Zero();
  for (int i = 0; i < m; ++i) {
    const Vector3 normal = Vector3(n(rng), n(rng), n(rng)).normalized();
    const Vector3 lever = 10 * Vector3(n(rng), n(rng), n(rng));
    Vector6 row;
    row << normal, lever.cross(normal);
    p.a.push_back(row);
    p.b.push_back(row.dot(q_feasible) - std::abs(n(rng)));  // zero is strictly feasible
  }
  for (int k = 0; k < 6; ++k) p.q0[k] = 3 * n(rng) / (k < 3 ? 1 : 30);
  return p;
}

const QpSolution& Solve(QpSolver& solver, const Problem& p,
                        const std::vector<std::int32_t>& warm = {}) {
  const auto flat = p.Flat();
  return solver.Solve(flat.data(), p.b.data(), static_cast<int>(p.b.size()), p.g, p.q0,
                      warm.empty() ? nullptr : warm.data(),
                      static_cast<int>(warm.size()));
}

TEST(Qp, AgreesWithExhaustiveReference) {
  std::mt19937_64 rng(1);
  QpSolver solver(64);
  for (int trial = 0; trial < 300; ++trial) {
    const Problem p = RandomFeasible(rng, 1 + trial % 9, trial % 3 == 0 ? 1000.0 : 1.0);
    const QpSolution& s = Solve(solver, p);
    ASSERT_EQ(s.status, QpStatus::kSolved) << trial;
    EXPECT_LT(s.kkt_residual, kKkt) << trial;
    EXPECT_LT(s.max_violation, kKkt) << trial;
    ASSERT_TRUE(
        CompareMatrices(s.q, Reference(p), kAgree, test::ToleranceType::kRelative))
        << trial;
  }
}

TEST(Qp, UnconstrainedOptimumWhenNothingIsActive) {
  QpSolver solver(4);
  Problem p;
  p.g << 1, 1, 1, 1000, 1000, 1000;
  p.q0 << 1, 2, 3, 0.1, 0.2, 0.3;
  Vector6 row = Vector6::Zero();
  row[0] = 1;
  p.a = {row};
  p.b = {-5};  // x >= -5: inactive at q0
  const QpSolution& s = Solve(solver, p);
  EXPECT_EQ(s.status, QpStatus::kSolved);
  EXPECT_EQ(s.num_active, 0);
  EXPECT_TRUE(CompareMatrices(s.q, p.q0, 0.0));
}

TEST(Qp, DuplicateNearParallelAndManyActiveAtOnePoint) {
  // 40 planes through the point z = 1 (a cone apex): the optimum pushes q0 below
  // the apex onto it; far more than 6 rows are active, many duplicate.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(0, 6.283185307179586);
  Problem p;
  p.g << 1, 1, 1, 1000, 1000, 1000;
  p.q0 << 0, 0, -3, 0, 0, 0;
  for (int i = 0; i < 40; ++i) {
    const double a =
        i < 20 ? angle(rng) : 0.3 + (i % 2) * 1e-12;  // duplicates, near-parallel
    Vector3 n(0.3 * std::cos(a), 0.3 * std::sin(a), 1.0);
    n.normalize();
    Vector6 row = Vector6::Zero();
    row.head<3>() = n;
    p.a.push_back(row);
    p.b.push_back(n.z() * 1.0);  // n . (q - apex) >= 0 with apex (0, 0, 1)
  }
  QpSolver solver(64);
  const QpSolution& s = Solve(solver, p);
  ASSERT_EQ(s.status, QpStatus::kSolved);
  EXPECT_LE(s.num_active, 7);
  EXPECT_LT(s.kkt_residual, kKkt);
  Vector6 apex = Vector6::Zero();
  apex[2] = 1;
  EXPECT_TRUE(CompareMatrices(s.q, apex, 1e-9));
}

TEST(Qp, InfeasibleSlotReturnsTheLeastViolatingAnswer) {
  // x >= 1 and x <= -1 (a slot narrower than the probe): no solution. The least
  // violating answer is x = 0 (violation 1 on each side), y and the rest free.
  Problem p;
  p.g << 1, 1, 1, 1000, 1000, 1000;
  p.q0 << 0.4, 2, 0, 0.01, 0, 0;
  Vector6 r1 = Vector6::Zero(), r2 = Vector6::Zero();
  r1[0] = 1;
  r2[0] = -1;
  p.a = {r1, r2, r1};
  p.b = {1, 1, 1};
  QpSolver solver(8);
  const QpSolution& s = Solve(solver, p);
  EXPECT_EQ(s.status, QpStatus::kInfeasibleRelaxed);
  EXPECT_NEAR(s.q[0], 0.0, 1e-6);
  EXPECT_NEAR(s.q[1], 2.0, 1e-6);
  EXPECT_NEAR(s.max_violation, 1.0, 1e-6);
  EXPECT_TRUE(s.q.allFinite());
}

TEST(Qp, WarmStartIsFasterAndGivesTheSameAnswer) {
  std::mt19937_64 rng(9);
  QpSolver solver(600);
  for (int trial = 0; trial < 20; ++trial) {
    const Problem p = RandomFeasible(rng, 500, 1000.0);
    const QpSolution cold = Solve(solver, p);
    ASSERT_EQ(cold.status, QpStatus::kSolved);
    std::vector<std::int32_t> warm(cold.active.begin(),
                                   cold.active.begin() + cold.num_active);
    // The exact active set: one pass confirms it, no column enters.
    const QpSolution hot = Solve(solver, p, warm);
    ASSERT_EQ(hot.status, QpStatus::kSolved);
    EXPECT_EQ(hot.iterations, 0);
    EXPECT_TRUE(CompareMatrices(hot.q, cold.q, 1e-9, test::ToleranceType::kRelative));
    // A stale guess (an inactive row added) still gives the same answer.
    warm.push_back((cold.active[0] + 1) % 500);
    const QpSolution& stale = Solve(solver, p, warm);
    ASSERT_EQ(stale.status, QpStatus::kSolved);
    EXPECT_LE(stale.iterations, cold.iterations + 2);
    EXPECT_TRUE(CompareMatrices(stale.q, cold.q, 1e-9, test::ToleranceType::kRelative));
  }
}

TEST(Qp, NoAllocationAndBadInputsAreReported) {
  std::mt19937_64 rng(2);
  const Problem p = RandomFeasible(rng, 200, 1000.0);
  const auto flat = p.Flat();
  QpSolver solver(256);
  std::vector<std::int32_t> warm = {1, 2, 3};
  {
    test::AllocationGuard guard;
    solver.Solve(flat.data(), p.b.data(), 200, p.g, p.q0, warm.data(), 3);
    EXPECT_EQ(guard.allocations(), 0u);
  }
  Vector6 bad_g = p.g;
  bad_g[4] = 0;
  EXPECT_EQ(solver.Solve(flat.data(), p.b.data(), 200, bad_g, p.q0).status,
            QpStatus::kBadInput);
  std::vector<double> nan_b = p.b;
  nan_b[7] = std::numeric_limits<double>::quiet_NaN();
  const QpSolution& s = solver.Solve(flat.data(), nan_b.data(), 200, p.g, p.q0);
  EXPECT_EQ(s.status, QpStatus::kBadInput);
  EXPECT_TRUE(CompareMatrices(s.q, p.q0, 0.0));  // safe answer: no motion
  EXPECT_EQ(solver.Solve(flat.data(), p.b.data(), 257, p.g, p.q0).status,
            QpStatus::kTooManyConstraints);
}

TEST(Qp, ExtremeStiffnessRatios) {
  std::mt19937_64 rng(4);
  QpSolver solver(64);
  for (double ratio : {1e-3, 1e-1, 1e1, 1e3, 1e6}) {
    for (int trial = 0; trial < 30; ++trial) {
      const Problem p = RandomFeasible(rng, 8, ratio);
      const QpSolution& s = Solve(solver, p);
      ASSERT_EQ(s.status, QpStatus::kSolved);
      EXPECT_LT(s.kkt_residual, kKkt);
      ASSERT_TRUE(
          CompareMatrices(s.q, Reference(p), kAgree, test::ToleranceType::kRelative))
          << "ratio " << ratio;
    }
  }
}

}  // namespace
}  // namespace sulcus
