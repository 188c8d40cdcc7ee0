#include "core/solver/qp.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sulcus {
namespace {

// Weight of the violation in the elastic problem, relative to the scaled distance
// (the violation is squared-penalised 1e8 times harder than the motion).
constexpr double kElasticWeight = 1e8;
// Below this the dual residual is zero: the constraints are inconsistent.
constexpr double kInfeasibleResidual = 1e-13;

// Lawson-Hanson NNLS on R dual rows: minimise |e_R - C u| over u >= 0, where C
// is R x m (column-major in `cols`) and e_R the last unit vector.
template <int R>
class Nnls {
 public:
  using Col = Eigen::Matrix<double, R, 1>;

  Nnls(const double* cols, int m, std::uint8_t* in_set, std::uint8_t* blocked)
      : cols_(cols), m_(m), in_set_(in_set), blocked_(blocked) {
    e_.setZero();
    e_[R - 1] = 1.0;
  }

  // Runs from the warm rows; returns false when the iteration cap was hit.
  bool Run(const std::int32_t* warm, int num_warm, int max_iterations) {
    for (int j = 0; j < m_; ++j) in_set_[j] = blocked_[j] = 0;
    k_ = 0;
    // Warm start: take the previous active rows, then drop those whose
    // least-squares weight is not positive until all are. One factorisation
    // when the rows are independent (the usual case: last frame's set); only
    // when they are not, are they taken one at a time, each kept if the set
    // stays independent.
    for (int i = 0; i < num_warm && k_ < R; ++i) {
      const std::int32_t j = warm[i];
      if (j < 0 || j >= m_ || in_set_[j]) continue;
      passive_[k_++] = j;
      in_set_[j] = 1;
    }
    auto factor = [&] { return k_ == 0 || LeastSquares(z_); };
    bool solved = factor();
    if (!solved) {
      const int taken = k_;
      std::int32_t rows[R];
      std::copy_n(passive_, taken, rows);
      for (int i = 0; i < taken; ++i) in_set_[rows[i]] = 0;
      k_ = 0;
      for (int i = 0; i < taken; ++i) {
        passive_[k_++] = rows[i];
        in_set_[rows[i]] = 1;
        if (!LeastSquares(z_)) Remove(k_ - 1);
      }
      solved = factor();
    }
    while (k_ > 0) {
      if (!solved) {
        Remove(k_ - 1);
        solved = factor();
        continue;
      }
      int worst = -1;
      for (int i = 0; i < k_; ++i) {
        if (z_[i] <= 0 && (worst < 0 || z_[i] < z_[worst])) worst = i;
      }
      if (worst < 0) break;
      Remove(worst);
      solved = factor();
    }
    for (int i = 0; i < k_; ++i) u_[i] = z_[i];
    UpdateResidual();

    for (iterations_ = 0; iterations_ < max_iterations; ++iterations_) {
      // The column most correlated with the residual enters. The same products
      // over every column (passive and blocked ones too) are, at the end, the
      // rows' violations (largest_product()).
      int t = -1;
      double best = 0, largest = 0;
      for (int j = 0; j < m_; ++j) {
        const double w = Column(j).dot(r_);
        largest = std::max(largest, w);
        if (w > best && !in_set_[j] && !blocked_[j]) {
          best = w;
          t = j;
        }
      }
      largest_product_ = largest;
      if (t < 0 || best <= 1e-12 * (1.0 + Column(t).norm()) || k_ == R) return true;
      passive_[k_] = t;
      u_[k_] = 0;
      ++k_;
      in_set_[t] = 1;
      // Inner loop: keep every passive weight positive.
      bool first = true;
      while (true) {
        if (!LeastSquares(z_)) {  // numerically dependent: it cannot enter
          Block(t);
          break;
        }
        if (first && z_[k_ - 1] <= 0) {  // round-off: the entering weight must be > 0
          Block(t);
          break;
        }
        first = false;
        double alpha = 1.0;
        for (int i = 0; i < k_; ++i) {
          if (z_[i] <= 0) alpha = std::min(alpha, u_[i] / (u_[i] - z_[i]));
        }
        if (alpha >= 1.0) {
          for (int i = 0; i < k_; ++i) u_[i] = z_[i];
          break;
        }
        for (int i = 0; i < k_; ++i) u_[i] += alpha * (z_[i] - u_[i]);
        for (int i = k_ - 1; i >= 0; --i) {
          if (u_[i] <= 1e-300) Remove(i);
        }
      }
      UpdateResidual();
    }
    return false;
  }

  const Col& residual() const { return r_; }
  int size() const { return k_; }
  std::int32_t passive(int i) const { return passive_[i]; }
  double weight(int i) const { return u_[i]; }
  int iterations() const { return iterations_; }
  // The largest product of a column with the final residual (>= 0), after a
  // Run that returned true: with the LDP's x = -r[0..R-2] / r[R-1], a column's
  // slack is -product / r[R-1], so this over r[R-1] is the largest violation.
  double largest_product() const { return largest_product_; }

 private:
  Eigen::Map<const Col> Column(int j) const {
    return Eigen::Map<const Col>(cols_ + static_cast<std::size_t>(j) * R);
  }

  // z = argmin |e - C_P z| (e the last unit vector) by a QR of C_P made with
  // classical Gram-Schmidt applied twice (as stable as Householder's for these
  // at most R columns of R rows, and with fixed-size storage and no blocking,
  // several times cheaper); false when C_P is rank deficient.
  bool LeastSquares(double* z) const {
    double q[R][R];   // orthonormal columns q[i][0..R)
    double rr[R][R];  // upper triangle: rr[j][i], j <= i
    for (int i = 0; i < k_; ++i) {
      const double* c = cols_ + static_cast<std::size_t>(passive_[i]) * R;
      double v[R];
      double cn = 0;
      for (int t = 0; t < R; ++t) {
        v[t] = c[t];
        cn += c[t] * c[t];
      }
      for (int j = 0; j < i; ++j) rr[j][i] = 0;
      for (int pass = 0; pass < 2; ++pass) {
        for (int j = 0; j < i; ++j) {
          double h = 0;
          for (int t = 0; t < R; ++t) h += q[j][t] * v[t];
          for (int t = 0; t < R; ++t) v[t] -= h * q[j][t];
          rr[j][i] += h;
        }
      }
      double vn = 0;
      for (int t = 0; t < R; ++t) vn += v[t] * v[t];
      vn = std::sqrt(vn);
      if (!(vn > 1e-10 * std::sqrt(cn))) return false;
      rr[i][i] = vn;
      const double inv = 1.0 / vn;
      for (int t = 0; t < R; ++t) q[i][t] = v[t] * inv;
    }
    // R z = Q^T e, whose entries are the last components of the q's.
    for (int i = k_ - 1; i >= 0; --i) {
      double acc = q[i][R - 1];
      for (int j = i + 1; j < k_; ++j) acc -= rr[i][j] * z[j];
      z[i] = acc / rr[i][i];
      if (!std::isfinite(z[i])) return false;
    }
    return true;
  }

  void UpdateResidual() {
    r_ = e_;
    for (int i = 0; i < k_; ++i) r_ -= u_[i] * Column(passive_[i]);
  }

  void Remove(int i) {
    in_set_[passive_[i]] = 0;
    for (int a = i; a + 1 < k_; ++a) {
      passive_[a] = passive_[a + 1];
      u_[a] = u_[a + 1];
      z_[a] = z_[a + 1];
    }
    --k_;
  }

  void Block(std::int32_t t) {
    for (int i = 0; i < k_; ++i) {
      if (passive_[i] == t) {
        Remove(i);
        break;
      }
    }
    blocked_[t] = 1;
  }

  const double* cols_;
  int m_;
  std::uint8_t* in_set_;
  std::uint8_t* blocked_;
  Col e_, r_;
  std::int32_t passive_[R];
  double u_[R], z_[R];
  int k_ = 0;
  int iterations_ = 0;
  double largest_product_ = 0;
};

}  // namespace

const char* ToString(QpStatus status) {
  switch (status) {
    case QpStatus::kSolved:
      return "solved";
    case QpStatus::kInfeasibleRelaxed:
      return "infeasible (least violation)";
    case QpStatus::kIterationLimit:
      return "iteration limit";
    case QpStatus::kTooManyConstraints:
      return "too many constraints";
    case QpStatus::kBadInput:
      return "bad input";
  }
  return "?";
}

QpSolver::QpSolver(int max_constraints)
    : capacity_(std::max(1, max_constraints)),
      columns_(static_cast<std::size_t>(capacity_ + 1) * 8),
      scale_(capacity_),
      in_set_(capacity_ + 1),
      blocked_(capacity_ + 1) {}

const QpSolution& QpSolver::Solve(const double* A, const double* b, int m,
                                  const Vector6& g, const Vector6& q0,
                                  const std::int32_t* warm, int num_warm) noexcept {
  QpSolution& s = solution_;
  s = QpSolution{};
  s.q = q0;
  if (m > capacity_) {
    s.status = QpStatus::kTooManyConstraints;
    return s;
  }
  if (!(g.array() > 0).all() || !g.allFinite() || !q0.allFinite()) {
    s.status = QpStatus::kBadInput;
    return s;
  }
  const Vector6 inv_sqrt_g = g.cwiseSqrt().cwiseInverse();
  // Dual columns of the LDP, [e_i; f_i] with e_i = a_i G^-1/2 / s_i and
  // f_i = (b_i - a_i q0) / s_i; rows with a zero gradient are skipped (always
  // satisfied or never satisfiable: the latter is reported as a violation).
  bool finite = true;
  double zero_rows = 0;  // the most a row of zeros asks (0 >= b_i), when positive
  for (int i = 0; i < m; ++i) {
    const Eigen::Map<const Vector6> a(A + 6 * i);
    const Vector6 e = a.cwiseProduct(inv_sqrt_g);
    const double norm = std::sqrt(e.squaredNorm());
    double* col = columns_.data() + static_cast<std::size_t>(i) * 7;
    scale_[i] = norm;
    // (A NaN or infinite norm or b fails the test below, checked once after the loop.)
    finite = finite && norm < std::numeric_limits<double>::infinity() &&
             std::abs(b[i]) < std::numeric_limits<double>::infinity();
    const double inv = norm >= 1e-300 ? 1.0 / norm : 0.0;
    if (norm < 1e-300) zero_rows = std::max(zero_rows, b[i]);
    Eigen::Map<Vector6> column(col);
    column = e * inv;
    col[6] = (b[i] - a.dot(q0)) * inv;
  }
  if (!finite) {
    s.status = QpStatus::kBadInput;
    return s;
  }

  const int max_iterations = 3 * m + 30;
  Nnls<7> nnls(columns_.data(), m, in_set_.data(), blocked_.data());
  const bool converged = nnls.Run(warm, num_warm, max_iterations);
  s.iterations = nnls.iterations();
  Vector6 x = Vector6::Zero();
  const double r_last = nnls.residual()[6];
  bool violation_known = false;  // from the last scan of the columns
  double violation = 0;
  if (r_last > kInfeasibleResidual) {
    if (converged) {
      violation = std::max(zero_rows, nnls.largest_product() / r_last);
      violation_known = true;
    }
    x = -nnls.residual().head<6>() / r_last;
    s.num_active = nnls.size();
    for (int i = 0; i < nnls.size(); ++i) {
      s.active[i] = nnls.passive(i);
      s.lambda[i] = nnls.weight(i) / r_last;
    }
    s.status = converged ? QpStatus::kSolved : QpStatus::kIterationLimit;
  } else {
    // Inconsistent rows: minimise |x|^2 + w t^2 subject to E x + t >= f, t >= 0.
    // Columns become [e_i; 1/sqrt(w); f_i] and [0; 1; 0] for t >= 0.
    const double c = 1.0 / std::sqrt(kElasticWeight);
    double* cols8 = columns_.data();
    // Re-pack in place from the back (8 > 7 entries per column).
    for (int i = m - 1; i >= 0; --i) {
      double tmp[7];
      std::copy_n(columns_.data() + static_cast<std::size_t>(i) * 7, 7, tmp);
      double* col = cols8 + static_cast<std::size_t>(i) * 8;
      std::copy_n(tmp, 6, col);
      col[6] = scale_[i] < 1e-300 ? 0.0 : c;
      col[7] = tmp[6];
    }
    double* last = cols8 + static_cast<std::size_t>(m) * 8;
    std::fill_n(last, 8, 0.0);
    last[6] = 1.0;
    Nnls<8> elastic(cols8, m + 1, in_set_.data(), blocked_.data());
    const bool ok = elastic.Run(nullptr, 0, max_iterations + 30);
    s.iterations += elastic.iterations();
    const double rl = elastic.residual()[7];
    if (rl > kInfeasibleResidual) {
      x = -elastic.residual().head<6>() / rl;
      for (int i = 0; i < elastic.size(); ++i) {
        if (elastic.passive(i) >= m) continue;
        s.active[s.num_active] = elastic.passive(i);
        s.lambda[s.num_active++] = elastic.weight(i) / rl;
      }
    }
    s.status = ok ? QpStatus::kInfeasibleRelaxed : QpStatus::kIterationLimit;
    // Restore the 7-row columns for the checks below.
    for (int i = 0; i < m; ++i) {
      double tmp[8];
      std::copy_n(cols8 + static_cast<std::size_t>(i) * 8, 8, tmp);
      double* col = columns_.data() + static_cast<std::size_t>(i) * 7;
      std::copy_n(tmp, 6, col);
      col[6] = tmp[7];
    }
  }
  s.q = q0 + inv_sqrt_g.cwiseProduct(x);

  // KKT check in the scaled space: x = sum lambda_i e_i, lambda >= 0, e_i x >= f_i,
  // lambda_i (e_i x - f_i) = 0.
  Vector6 stationarity = x;
  double complementarity = 0;
  for (int i = 0; i < s.num_active; ++i) {
    const double* col = columns_.data() + static_cast<std::size_t>(s.active[i]) * 7;
    const Eigen::Map<const Vector6> e(col);
    stationarity -= s.lambda[i] * e;
    complementarity =
        std::max(complementarity, std::abs(s.lambda[i] * (e.dot(x) - col[6])));
  }
  for (int i = 0; i < m && !violation_known; ++i) {
    const double* col = columns_.data() + static_cast<std::size_t>(i) * 7;
    const double slack = Eigen::Map<const Vector6>(col).dot(x) - col[6];
    if (scale_[i] < 1e-300) {  // a row of zeros: 0 >= b_i or never
      violation = std::max(violation, b[i]);
      continue;
    }
    violation = std::max(violation, -slack);
  }
  const double size = 1.0 + x.lpNorm<Eigen::Infinity>();
  s.max_violation = std::max(0.0, violation);
  s.kkt_residual =
      std::max(stationarity.lpNorm<Eigen::Infinity>(), complementarity) / size;
  for (int i = 0; i < s.num_active; ++i) {
    // Report multipliers for the rows as given: lambda_orig = lambda / s_i.
    s.lambda[i] /= scale_[s.active[i]];
  }
  if (!s.q.allFinite()) {
    s.q = q0;
    s.status = QpStatus::kBadInput;
  }
  return s;
}

}  // namespace sulcus
