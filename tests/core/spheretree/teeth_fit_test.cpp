// Sphere-trees of the generated teeth:
// asserts the guarantees (every surface sample covered, every child inside its
// parent) and the worst-protrusion target (1.5 % of the largest extent)
// on every tooth and probe, and its mean target (0.3 %) on the probes, incisors,
// canines and premolars; records protrusion and build time in the test XML and
// on stdout. The molars' mean is reported, not asserted: they are at 0.35 to
// 0.49 % (docs/engine.md, "Sphere-trees").

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "core/anatomy/gingiva.h"
#include "core/anatomy/probe.h"
#include "core/anatomy/soft_tissue.h"
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
  std::printf(
      "tooth %d (%s): %zu leaves, build %.2f s, protrusion worst %.3f %% mean %.3f %%, "
      "coverage %.4f %%\n",
      GetParam(), ToString(tooth.tooth.type()).c_str(), l.spheres, stats.seconds_total,
      worst, mean, 100 * l.coverage);
  RecordProperty("worst_protrusion_pct", std::to_string(worst));
  RecordProperty("mean_protrusion_pct", std::to_string(mean));
  RecordProperty("build_s", std::to_string(stats.seconds_total));
  EXPECT_EQ(l.uncovered_samples, 0u);
  for (const LevelMetrics& level : m.levels) EXPECT_EQ(level.children_inside, 1.0);
  EXPECT_LE(l.spheres, 512u);
  EXPECT_LE(worst, 1.5);
  if (tooth.tooth.type() < ToothType::kFirstMolar) {
    EXPECT_LE(mean, 0.3);
  }
}

INSTANTIATE_TEST_SUITE_P(Fdi, ToothTree,
                         ::testing::Values(11, 12, 13, 14, 15, 16, 17, 31, 33, 34, 36,
                                           37));

// Trading (Spend::kMean, the default) against the min-max cover alone
// (Spend::kWorst) on a molar, where it matters most: the same leaf count and
// guarantees, a lower mean, the worst leaf about where it was.
TEST(ToothTreeSpend, TradingLowersTheMolarsMean) {
  const ToothModel tooth = GenerateTooth(36);
  SphereTreeParams p;
  p.spend = SphereTreeParams::Spend::kWorst;
  const TreeMetrics even = EvaluateSphereTree(tooth.mesh, BuildSphereTree(tooth.mesh, p));
  p.spend = SphereTreeParams::Spend::kMean;
  const TreeMetrics traded =
      EvaluateSphereTree(tooth.mesh, BuildSphereTree(tooth.mesh, p));
  const LevelMetrics& a = even.leaves();
  const LevelMetrics& b = traded.leaves();
  std::printf(
      "tooth 36, 512 leaves: worst %.3f -> %.3f %%, mean %.3f -> %.3f %%, overlap %.2f "
      "-> %.2f\n",
      100 * a.protrusion_max_mm / even.largest_extent_mm,
      100 * b.protrusion_max_mm / even.largest_extent_mm,
      100 * a.protrusion_mean_mm / even.largest_extent_mm,
      100 * b.protrusion_mean_mm / even.largest_extent_mm, a.overlap, b.overlap);
  EXPECT_EQ(b.spheres, a.spheres);
  EXPECT_EQ(b.uncovered_samples, 0u);
  for (const LevelMetrics& level : traded.levels) EXPECT_EQ(level.children_inside, 1.0);
  EXPECT_LT(b.protrusion_mean_mm, 0.9 * a.protrusion_mean_mm);
  EXPECT_LT(b.overlap, a.overlap);
  EXPECT_LT(b.protrusion_max_mm, 1.1 * a.protrusion_max_mm);
}

// The other shipped anatomy: the probes' collision parts, a gingival collar and
// the soft tissues. Same guarantees, figures reported.
class AnatomyTree : public ::testing::TestWithParam<std::string> {};

TEST_P(AnatomyTree, CoversAndNests) {
  const std::string name = GetParam();
  const bool tool = name.rfind("probe_", 0) == 0;
  TriangleMesh mesh;
  if (tool) {
    mesh = MakeProbe(name.substr(6)).collision_mesh;
  } else if (name == "gingiva_46") {
    GingivaParams p;
    p.pocket_mm = {5, 4, 7, 5, 4, 6};
    mesh = GenerateGingiva(GenerateTooth(46), p).mesh;
  } else {
    mesh = MakeSoftTissue(name);
  }
  SphereTreeBuildStats stats;
  const SphereTree tree =
      BuildSphereTree(mesh, tool ? ToolTreeParams() : SphereTreeParams{}, {}, &stats);
  const TreeMetrics m = EvaluateSphereTree(mesh, tree);
  const LevelMetrics& l = m.leaves();
  const double worst = 100 * l.protrusion_max_mm / m.largest_extent_mm;
  const double mean = 100 * l.protrusion_mean_mm / m.largest_extent_mm;
  std::printf(
      "%s: %zu faces, %zu leaves, build %.2f s, protrusion worst %.3f %% (%.3f mm) mean "
      "%.3f %%, coverage %.4f %%\n",
      name.c_str(), mesh.num_faces(), l.spheres, stats.seconds_total, worst,
      l.protrusion_max_mm, mean, 100 * l.coverage);
  RecordProperty("worst_protrusion_pct", std::to_string(worst));
  RecordProperty("mean_protrusion_pct", std::to_string(mean));
  EXPECT_EQ(l.uncovered_samples, 0u);
  for (const LevelMetrics& level : m.levels) EXPECT_EQ(level.children_inside, 1.0);
  if (tool) {
    EXPECT_LE(worst, 1.5);
    EXPECT_LE(mean, 0.3);
  }
}

INSTANTIATE_TEST_SUITE_P(Shipped, AnatomyTree,
                         ::testing::Values("probe_williams", "probe_unc15", "probe_who",
                                           "gingiva_46", "tongue", "palate", "cheek_left",
                                           "jaw_lower"));

}  // namespace
}  // namespace sulcus
