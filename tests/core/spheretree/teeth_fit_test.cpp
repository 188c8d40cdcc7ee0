// Sphere-trees of the generated teeth (issue 4 measured on issue 3's anatomy):
// asserts the guarantees (every surface sample covered, every child inside its
// parent) and records protrusion and build time per tooth in the test XML and on
// stdout. The protrusion targets (worst <= 1.5 %, mean <= 0.3 % of the
// largest extent) are reported, not asserted: molars do not meet the mean yet.

#include <gtest/gtest.h>

#include <cstdio>

#include "core/anatomy/tooth.h"
#include "core/spheretree/builder.h"
#include "core/spheretree/metrics.h"

namespace sulcus {
namespace {

class ToothTree : public ::testing::TestWithParam<int> {};

TEST_P(ToothTree, CoversTheToothAndNests) {
  const ToothModel tooth = GenerateTooth(GetParam());
  SphereTreeBuildStats stats;
  const SphereTree tree = BuildSphereTree(tooth.mesh, SphereTreeParams{}, {}, &stats);
  const TreeMetrics m = EvaluateSphereTree(tooth.mesh, tree);
  const LevelMetrics& l = m.leaves();
  const double worst = 100 * l.protrusion_max_mm / m.largest_extent_mm;
  const double mean = 100 * l.protrusion_mean_mm / m.largest_extent_mm;
  std::printf("tooth %d (%s): %zu leaves, build %.2f s, protrusion worst %.3f %% mean %.3f %%, coverage %.4f %%\n",
              GetParam(), ToString(tooth.tooth.type()).c_str(), l.spheres, stats.seconds_total, worst, mean,
              100 * l.coverage);
  RecordProperty("worst_protrusion_pct", std::to_string(worst));
  RecordProperty("mean_protrusion_pct", std::to_string(mean));
  RecordProperty("build_s", std::to_string(stats.seconds_total));
  EXPECT_EQ(l.uncovered_samples, 0u);
  for (const LevelMetrics& level : m.levels) EXPECT_EQ(level.children_inside, 1.0);
  EXPECT_LE(l.spheres, 512u);
}

INSTANTIATE_TEST_SUITE_P(Fdi, ToothTree, ::testing::Values(11, 12, 13, 14, 15, 16, 17, 31, 33, 34, 36, 37));

}  // namespace
}  // namespace sulcus
