// The builder on public meshes of different character: smooth with
// thin parts (elephant), sharp edges (fandisk), a thin tube of genus 1 (knot1),
// many holes (couplingdown, genus 9), many disconnected parts (bones, 26).
// Scaled to 20 mm, the size of a tooth. Prints the figures; asserts the
// guarantees and the comparison with the octree reference.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "core/geometry/mesh_io.h"
#include "core/spheretree/builder.h"
#include "core/spheretree/metrics.h"
#include "core/spheretree/octree_builder.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

TriangleMesh LoadScaled(const std::string& name) {
  TriangleMesh mesh = LoadMesh(fs::path(SULCUS_PUBLIC_MESHES) / (name + ".off"));
  const double scale = 20.0 / mesh.Bounds().LargestExtent();
  mesh.Transform(scale * Matrix3::Identity(), Vector3::Zero());
  return mesh;
}

class PublicMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(PublicMesh, FullCoverageNestingAndBetterThanOctree) {
  const TriangleMesh mesh = LoadScaled(GetParam());
  SphereTreeBuildStats stats;
  const SphereTree tree = BuildSphereTree(mesh, SphereTreeParams{}, {}, &stats);
  const TreeMetrics m = EvaluateSphereTree(mesh, tree);
  const TreeMetrics ref = EvaluateSphereTree(mesh, BuildOctreeSphereTree(mesh, 4));
  const LevelMetrics& l = m.leaves();
  std::printf(
      "%-13s %6zu faces  %5.2f s  %3zu leaves  protrusion max %.3f%% mean %.3f%%  "
      "coverage %.4f%%  excess %.1f%%  | octree: %zu leaves, max %.2f%% mean %.2f%%\n",
      GetParam(), mesh.num_faces(), stats.seconds_total, l.spheres,
      100 * l.protrusion_max_mm / m.largest_extent_mm,
      100 * l.protrusion_mean_mm / m.largest_extent_mm, 100 * l.coverage,
      100 * l.excess_volume, ref.leaves().spheres,
      100 * ref.leaves().protrusion_max_mm / ref.largest_extent_mm,
      100 * ref.leaves().protrusion_mean_mm / ref.largest_extent_mm);
  EXPECT_EQ(l.uncovered_samples, 0u);
  for (const LevelMetrics& level : m.levels) EXPECT_EQ(level.children_inside, 1.0);
  EXPECT_LE(l.spheres, 512u);
  // The medial tree sticks out far less than the straightforward one.
  EXPECT_LT(l.protrusion_max_mm, 0.25 * ref.leaves().protrusion_max_mm);
  EXPECT_LT(l.protrusion_mean_mm, 0.25 * ref.leaves().protrusion_mean_mm);
}

INSTANTIATE_TEST_SUITE_P(Cgal, PublicMesh,
                         ::testing::Values("elephant", "fandisk", "knot1", "couplingdown",
                                           "bones"));

// The default evaluation density is dense enough: doubling it moves no figure by
// more than 5 %.
TEST(PublicMeshEval, DefaultDensityHasConverged) {
  const TriangleMesh mesh = LoadScaled("elephant");
  const SphereTree tree = BuildSphereTree(mesh, SphereTreeParams{});
  EvalParams dense;
  dense.surface_samples *= 2;
  dense.points_per_sphere *= 2;
  dense.volume_samples_per_sphere *= 2;
  dense.seed = 11;
  const TreeMetrics a = EvaluateSphereTree(mesh, tree),
                    b = EvaluateSphereTree(mesh, tree, dense);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (std::size_t i = 0; i < a.levels.size(); ++i) {
    const LevelMetrics &x = a.levels[i], &y = b.levels[i];
    EXPECT_NEAR(y.protrusion_max_mm, x.protrusion_max_mm, 0.05 * x.protrusion_max_mm)
        << i;
    EXPECT_NEAR(y.protrusion_mean_mm, x.protrusion_mean_mm, 0.05 * x.protrusion_mean_mm)
        << i;
    EXPECT_NEAR(y.coverage, x.coverage, 0.05 * x.coverage) << i;
    EXPECT_NEAR(y.excess_volume, x.excess_volume, 0.05 * x.excess_volume) << i;
  }
}

}  // namespace
}  // namespace sulcus
