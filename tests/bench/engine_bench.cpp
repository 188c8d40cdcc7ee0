// What the haptic frame costs: collision with the reference Algorithm 1
// against the fast traversal, side by side on the same poses; and the whole frame
// at 10, 100, 200 and 1,000 pairs and for the probe in the full mouth. Reports
// median, p99 and max per frame as counters. Nothing passes or fails on time.
//   build/release/tests/bench/engine_bench --benchmark_counters_tabular=true

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/haptics/engine.h"
#include "tests/bench/mouth_proxy.h"
#include "tests/core/haptics/test_scenes.h"

namespace sulcus {
namespace {

using Clock = std::chrono::steady_clock;

void Percentiles(benchmark::State& state, std::vector<double> us) {
  if (us.empty()) return;
  std::sort(us.begin(), us.end());
  state.counters["p50_us"] = us[us.size() / 2];
  state.counters["p99_us"] = us[std::min(us.size() - 1, us.size() * 99 / 100)];
  state.counters["max_us"] = us.back();
}

// Collision: probe against one tooth (range 0) or the full mouth (range 1).
void CollisionBench(benchmark::State& state, bool reference) {
  const bench::MouthProxy& m = bench::Mouth();
  const bool full = state.range(0) == 1;
  const std::vector<CollisionWorld::Object> objects =
      full ? m.objects : std::vector<CollisionWorld::Object>{m.objects[5]};
  const CollisionWorld world(m.probe, objects);
  CollisionScratch scratch;
  std::vector<ContactPair> out(100000);
  const auto poses = m.ContactPoses(256, 1, full ? -1 : 5);
  std::size_t i = 0, pairs = 0, queries = 0, tests = 0;
  std::vector<double> us;
  us.reserve(1 << 16);
  for (auto _ : state) {
    const RigidTransform& X = poses[i++ % poses.size()];
    const auto t0 = Clock::now();
    int found;
    if (reference) {
      found = static_cast<int>(FindContactsReference(world, X, 0.05).size());
    } else {
      const CollisionStats cs = FindContacts(world, X, 0.05, &scratch, out.data(),
                                             static_cast<int>(out.size()));
      found = cs.pairs;
      tests += cs.node_tests;
    }
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    pairs += found;
    ++queries;
  }
  state.counters["pairs"] = static_cast<double>(pairs) / queries;
  if (!reference) state.counters["node_tests"] = static_cast<double>(tests) / queries;
  Percentiles(state, us);
}
void BM_CollisionReference(benchmark::State& s) { CollisionBench(s, true); }
void BM_CollisionFast(benchmark::State& s) { CollisionBench(s, false); }
BENCHMARK(BM_CollisionReference)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CollisionFast)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The whole frame with a flat face of n x n spheres pressed on a plate and
// sliding: the pair count grows with n (range 0 is n).
void BM_FrameByPairs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  test::Scene s;
  s.tool = std::make_unique<SphereTree>(test::MakeFlatFace(n, n, 0.5, 0.5));
  s.Add(test::MakeBlock(12, 12, -0.5, -0.5, 0.5, 0.5), RigidTransform::Identity());
  const auto model = s.Model();
  EngineData d(*model);
  ResetTool(RigidTransform(Matrix3::Identity(), Vector3(0, 0, 0.5)), &d);
  for (int i = 0; i < 200; ++i)
    Step(*model, RigidTransform(Matrix3::Identity(), Vector3(0, 0, 0.5 - 0.005 * i)), &d);
  std::vector<double> us;
  us.reserve(1 << 16);
  double pairs = 0;
  long frame = 0;
  for (auto _ : state) {
    const double t = frame++ * 0.001;
    const RigidTransform X(
        Eigen::AngleAxisd(0.02 * std::sin(3 * t), Vector3::UnitZ()).toRotationMatrix(),
        Vector3(2 * std::sin(t), std::cos(0.7 * t), -0.5));
    const auto t0 = Clock::now();
    Step(*model, X, &d);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    pairs += d.num_pairs;
  }
  state.counters["pairs"] = pairs / static_cast<double>(frame);
  state.counters["faults"] = static_cast<double>(d.faults.total());
  state.counters["sweep_faults"] = static_cast<double>(d.faults.sweep);
  state.counters["pen_faults"] = static_cast<double>(d.faults.penetration);
  Percentiles(state, us);
}
BENCHMARK(BM_FrameByPairs)
    ->Arg(2)
    ->Arg(5)
    ->Arg(7)
    ->Arg(16)
    ->Arg(19)
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(1.0);

// The probe in the full mouth: sliding over a tooth, pressing 0.3 mm.
void BM_FrameProbeInFullMouth(benchmark::State& state) {
  const bench::MouthProxy& m = bench::Mouth();
  const EngineModel model(m.probe, m.objects, EngineParams{});
  EngineData d(model);
  // Over tooth 5's buccal face (+y of the tooth frame), shaft along +y.
  const RigidTransform X_WO = m.tooth_poses[5];
  const Matrix3 R =
      X_WO.rotation() *
      Quaternion::FromTwoVectors(Vector3::UnitZ(), Vector3::UnitY()).toRotationMatrix();
  // The probe's end face (its origin) 0.3 mm under the ellipsoid's buccal surface.
  auto device = [&](long f) {
    const double t = f * 0.001, x = 1.5 * std::sin(t), z = 4 * std::sin(0.5 * t);
    const double y = 3.5 * std::sqrt(1 - x * x / 16 - z * z / 100) - 0.3;
    return RigidTransform(R, X_WO * Vector3(x, y, z));
  };
  ResetTool(RigidTransform(R, X_WO * Vector3(0, 8, 0)), &d);
  for (int i = 0; i < 300; ++i) Step(model, device(0), &d);
  std::vector<double> us;
  us.reserve(1 << 16);
  double pairs = 0, active = 0;
  long frame = 0;
  for (auto _ : state) {
    const RigidTransform X = device(frame++);
    const auto t0 = Clock::now();
    const auto before = d.faults.sweep;
    Step(model, X, &d);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    pairs += d.num_pairs;
    active += d.active_contacts;
    if (std::getenv("SULCUS_DEBUG_SWEEPS") && d.faults.sweep != before) {
      std::fprintf(stderr, "frame %ld: status %s lin %d pairs %d;", frame,
                   ToString(d.qp_status), d.linearizations, d.num_pairs);
      for (int k = 0; k < d.sweeps; ++k)
        std::fprintf(stderr, " [margin %.4f move %.4f]", d.sweep_margin_mm[k],
                     d.sweep_move_mm[k]);
      std::fprintf(stderr, "\n");
    }
  }
  state.counters["pairs"] = pairs / static_cast<double>(frame);
  state.counters["active"] = active / static_cast<double>(frame);
  state.counters["faults"] = static_cast<double>(d.faults.total());
  state.counters["pen_faults"] = static_cast<double>(d.faults.penetration);
  state.counters["sweep_faults"] = static_cast<double>(d.faults.sweep);
  state.counters["solver_faults"] = static_cast<double>(d.faults.solver);
  state.counters["ovf_faults"] = static_cast<double>(d.faults.pair_overflow);
  Percentiles(state, us);
}
BENCHMARK(BM_FrameProbeInFullMouth)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

}  // namespace
}  // namespace sulcus

BENCHMARK_MAIN();
