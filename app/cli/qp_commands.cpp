// `sulcus-cli qp-bench FILE` and `sulcus-cli qp-gen KIND ...`.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "app/cli/commands.h"
#include "core/solver/qp.h"
#include "core/solver/qp_instances.h"

namespace sulcus::cli {
namespace {

struct BenchResult {
  std::vector<double> us;
  std::vector<double> q;  // every frame's solution, n per frame, in the file's order
  long iterations = 0;
  long active = 0;  // rows active at the solution, summed over frames
  int max_iterations = 0;
  int failures = 0;
  int infeasible = 0;
};

// Independent check of one answer, from the file's own A, b, G and q_h and the
// solver's multipliers: violation max(b - A q), and the KKT residual (stationarity
// G (q - q_h) = sum lambda_i a_i, complementarity, dual feasibility), relative.
void Check(const QpInstances& qp, int s, int t, const QpSolution& sol, double* violation,
           double* kkt) {
  const double* A = qp.A(s, t);
  const double* b = qp.B(s, t);
  const double* qh = qp.QH(s, t);
  *violation = 0;
  for (int i = 0; i < qp.m; ++i) {
    double ax = 0;
    for (int k = 0; k < 6; ++k) ax += A[6 * i + k] * sol.q[k];
    *violation = std::max(*violation, b[i] - ax);
  }
  double stat[6], scale = 1;
  for (int k = 0; k < 6; ++k) {
    stat[k] = qp.g[k] * (sol.q[k] - qh[k]);
    scale = std::max(scale, std::abs(stat[k]));
  }
  double comp = 0, dual = 0;
  for (int j = 0; j < sol.num_active; ++j) {
    const double* a = A + 6 * sol.active[j];
    double ax = 0;
    for (int k = 0; k < 6; ++k) {
      stat[k] -= sol.lambda[j] * a[k];
      ax += a[k] * sol.q[k];
    }
    comp = std::max(comp, std::abs(sol.lambda[j] * (ax - b[sol.active[j]])));
    dual = std::max(dual, -sol.lambda[j]);
  }
  double st = 0;
  for (double v : stat) st = std::max(st, std::abs(v));
  *kkt = std::max({st / scale, comp / scale, dual});
}

BenchResult Run(const QpInstances& qp, bool warm) {
  BenchResult r;
  QpSolver solver(qp.m);
  r.us.reserve(static_cast<std::size_t>(qp.sequences) * qp.frames);
  r.q.reserve(static_cast<std::size_t>(qp.sequences) * qp.frames * kQpVars);
  std::vector<std::int32_t> active(kQpMaxActive);
  // Each frame's rows are copied here before the clock starts: the engine
  // writes its rows just before it solves (they are in cache), and the DAQP
  // harness (scripts/daqp_bench.py) hands DAQP a fresh copy too.
  std::vector<double> A(static_cast<std::size_t>(qp.m) * kQpVars), b(qp.m);
  Vector6 g;
  for (int k = 0; k < 6; ++k) g[k] = qp.g[k];
  for (int s = 0; s < qp.sequences; ++s) {
    int num_active = 0;
    for (int t = 0; t < qp.frames; ++t) {
      const Vector6 qh = Eigen::Map<const Vector6>(qp.QH(s, t));
      std::copy_n(qp.A(s, t), A.size(), A.begin());
      std::copy_n(qp.B(s, t), b.size(), b.begin());
      const auto t0 = std::chrono::steady_clock::now();
      const QpSolution& sol =
          solver.Solve(A.data(), b.data(), qp.m, g, qh, warm ? active.data() : nullptr,
                       warm ? num_active : 0);
      r.us.push_back(
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0)
              .count());
      num_active = sol.num_active;
      std::copy_n(sol.active.begin(), num_active, active.begin());
      for (int k = 0; k < kQpVars; ++k) r.q.push_back(sol.q[k]);
      r.iterations += sol.iterations;
      r.active += sol.num_active;
      r.max_iterations = std::max(r.max_iterations, sol.iterations);
      double violation, kkt;
      Check(qp, s, t, sol, &violation, &kkt);
      const bool ok = sol.status == QpStatus::kSolved && violation <= 1e-6 && kkt <= 1e-6;
      r.failures += !ok;
      r.infeasible += sol.status == QpStatus::kInfeasibleRelaxed;
    }
  }
  std::sort(r.us.begin(), r.us.end());
  return r;
}

double Pct(const std::vector<double>& v, double q) {
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

}  // namespace

void AddQpCommands(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto cold = std::make_shared<bool>(false);
  auto solutions = std::make_shared<std::string>();
  CLI::App* bench = app.add_subcommand("qp-bench",
                                       "Solve every QP of a file in order, warm-starting "
                                       "along each sequence, and time it");
  bench->add_option("FILE", *file, "QP instances (see `qp-gen --help` for the format)")
      ->required();
  bench->add_flag("--compare-cold", *cold,
                  "Also solve every frame cold (no warm start), side by side");
  bench->add_option("--solutions", *solutions,
                    "Write every frame's warm-started solution here (float64 q[n] per "
                    "frame, little-endian, in the "
                    "file's order), to compare with another solver");
  bench->callback([=] {
    const QpInstances qp = ReadQpInstances(*file);
    if (qp.n != kQpVars) {
      throw QpFileError(*file + ": n = " + std::to_string(qp.n) + ", this solver has " +
                        std::to_string(kQpVars) + " variables");
    }
    std::printf("%s: n=%d m=%d, %d sequences of %d frames\n", file->c_str(), qp.n, qp.m,
                qp.sequences, qp.frames);
    auto report = [&](const char* label, const BenchResult& r) {
      const double n = static_cast<double>(r.us.size());
      std::printf(
          "  %-5s median %.2f us, p99 %.2f us, max %.2f us; iterations mean %.2f, max "
          "%d; failures %d"
          " (%d infeasible, relaxed)\n",
          label, Pct(r.us, 0.5), Pct(r.us, 0.99), r.us.back(), r.iterations / n,
          r.max_iterations, r.failures, r.infeasible);
    };
    if (*cold) report("cold", Run(qp, false));
    const BenchResult warm = Run(qp, true);
    report("warm", warm);
    if (!solutions->empty()) {
      std::FILE* f = std::fopen(solutions->c_str(), "wb");
      const bool ok = f && std::fwrite(warm.q.data(), sizeof(double), warm.q.size(), f) ==
                               warm.q.size();
      if (f) std::fclose(f);
      if (!ok) throw QpFileError(*solutions + ": cannot write the solutions");
    }
    std::printf(
        "qp-bench frames=%zu median_us=%.3f p99_us=%.3f max_us=%.3f mean_iters=%.3f "
        "max_iters=%d failures=%d "
        "mean_active=%.2f\n",
        warm.us.size(), Pct(warm.us, 0.5), Pct(warm.us, 0.99), warm.us.back(),
        static_cast<double>(warm.iterations) / warm.us.size(), warm.max_iterations,
        warm.failures, static_cast<double>(warm.active) / warm.us.size());
    Finish(warm.failures ? 1 : 0);
  });

  auto kind = std::make_shared<std::string>();
  auto m = std::make_shared<int>(64);
  auto seqs = std::make_shared<int>(20);
  auto frames = std::make_shared<int>(200);
  auto seed = std::make_shared<std::uint64_t>(1);
  auto out = std::make_shared<std::string>();
  CLI::App* gen = app.add_subcommand(
      "qp-gen",
      "Write contact-like QP sequences. Format (little-endian): int32 n, m, S, T; "
      "float64 G_diag[n]; then S "
      "sequences of T frames, each float64 q_h[n], A[m*n] row-major, b[m]; each frame is "
      "min 1/2 (q-q_h)^T G (q-q_h) s.t. A q >= b");
  gen->add_option("KIND", *kind, "slot, wedge, plane, cluster or random")
      ->required()
      ->check(CLI::IsMember({"slot", "wedge", "plane", "cluster", "random"}));
  gen->add_option("--m", *m, "Constraints per frame")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  gen->add_option("--sequences", *seqs, "Sequences")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  gen->add_option("--frames", *frames, "Frames per sequence")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  gen->add_option("--seed", *seed, "Random seed")->capture_default_str();
  gen->add_option("-o,--output", *out, "Output file")->required();
  gen->callback([=] {
    WriteQpInstances(GenerateQpInstances(*kind, *m, *seqs, *frames, *seed), *out);
    std::printf("wrote %s: %s, m=%d, %d sequences of %d frames\n", out->c_str(),
                kind->c_str(), *m, *seqs, *frames);
  });
}

}  // namespace sulcus::cli
