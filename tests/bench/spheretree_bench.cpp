// What building a sphere-tree costs, against the straightforward octree reference
// on the same mesh in the same run. Numbers only; nothing passes or fails on time.
//   build/release/tests/bench/spheretree_bench --benchmark_counters_tabular=true

#include <benchmark/benchmark.h>

#include "core/geometry/primitives.h"
#include "core/spheretree/builder.h"
#include "core/spheretree/metrics.h"
#include "core/spheretree/octree_builder.h"

namespace sulcus {
namespace {

// A 5,000-triangle smooth solid of tooth size (the benchmark case).
const TriangleMesh& Mesh5k() {
  static const TriangleMesh mesh = MakeTorus(8, 3, 50, 50);  // 5,000 triangles
  return mesh;
}

void Report(benchmark::State& state, const SphereTree& tree) {
  EvalParams e;
  e.surface_samples = 30000;
  e.points_per_sphere = 128;
  e.volume_samples_per_sphere = 128;
  const TreeMetrics m = EvaluateSphereTree(Mesh5k(), tree, e);
  state.counters["leaves"] = static_cast<double>(tree.NumLeaves());
  state.counters["prot_max_%"] = 100 * m.leaves().protrusion_max_mm / m.largest_extent_mm;
  state.counters["prot_mean_%"] =
      100 * m.leaves().protrusion_mean_mm / m.largest_extent_mm;
  state.counters["coverage_%"] = 100 * m.leaves().coverage;
}

void BM_BuildMedial(benchmark::State& state) {
  SphereTreeParams p;
  p.leaves = static_cast<int>(state.range(0));
  SphereTree tree;
  for (auto _ : state) {
    tree = BuildSphereTree(Mesh5k(), p);
    benchmark::DoNotOptimize(tree.r.data());
  }
  Report(state, tree);
}
BENCHMARK(BM_BuildMedial)
    ->Arg(64)
    ->Arg(512)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

void BM_BuildOctreeReference(benchmark::State& state) {
  SphereTree tree;
  for (auto _ : state) {
    tree = BuildOctreeSphereTree(Mesh5k(), static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(tree.r.data());
  }
  Report(state, tree);
}
BENCHMARK(BM_BuildOctreeReference)->Arg(3)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace sulcus

BENCHMARK_MAIN();
