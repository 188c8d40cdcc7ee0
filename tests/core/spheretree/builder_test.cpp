#include "core/spheretree/builder.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "core/geometry/primitives.h"
#include "core/spheretree/builder_stages.h"
#include "core/spheretree/metrics.h"
#include "tests/common/compare.h"

namespace sulcus {
namespace {

SphereTreeParams Small(int leaves = 64) {
  SphereTreeParams p;
  p.levels = 3;
  p.branching = 8;
  p.leaves = leaves;
  p.samples = 3000;
  return p;
}

// Coarse evaluation: enough for coverage and containment, which the builder
// guarantees at any density.
EvalParams Quick() {
  EvalParams e;
  e.surface_samples = 20000;
  e.points_per_sphere = 96;
  e.volume_samples_per_sphere = 64;
  return e;
}

TriangleMesh Joined(const TriangleMesh& a, const TriangleMesh& b) {
  std::vector<Vector3> v = a.vertices();
  std::vector<TriangleMesh::Face> f = a.faces();
  const int offset = static_cast<int>(v.size());
  v.insert(v.end(), b.vertices().begin(), b.vertices().end());
  for (auto t : b.faces()) f.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return TriangleMesh(v, f);
}

// Every leaf-level surface sample covered and every child inside its parent.
void ExpectGuarantees(const TriangleMesh& mesh, const SphereTree& tree) {
  const TreeMetrics m = EvaluateSphereTree(mesh, tree, Quick());
  for (const LevelMetrics& l : m.levels) {
    EXPECT_EQ(l.children_inside, 1.0) << "level " << l.level;
  }
  EXPECT_EQ(m.leaves().uncovered_samples, 0u);
  EXPECT_EQ(m.leaves().coverage, 1.0);
}

struct Shape {
  const char* name;
  TriangleMesh (*make)();
};

class BuilderOnShapes : public ::testing::TestWithParam<Shape> {};

TEST_P(BuilderOnShapes, CoversEverythingAndNests) {
  const TriangleMesh mesh = GetParam().make();
  SphereTreeBuildStats stats;
  const SphereTree tree = BuildSphereTree(mesh, Small(), {}, &stats);
  EXPECT_NO_THROW(tree.Validate());
  EXPECT_LE(tree.NumLeaves(), 64u);
  EXPECT_GT(stats.medial_candidates, 0u);
  ExpectGuarantees(mesh, tree);
}

INSTANTIATE_TEST_SUITE_P(
    Calibration, BuilderOnShapes,
    ::testing::Values(
        Shape{"box_sharp_edges", [] { return MakeBox(Vector3(20, 8, 4), 2); }},
        Shape{"torus_genus_one", [] { return MakeTorus(10, 3, 48, 24); }},
        Shape{"thin_plate", [] { return MakeBox(Vector3(20, 20, 0.4), 4); }},
        Shape{"two_parts",
              [] {
                TriangleMesh b = MakeIcosphere(3, 3);
                b.Transform(Matrix3::Identity(), Vector3(12, 0, 0));
                return Joined(MakeIcosphere(4, 3), b);
              }},
        Shape{"long_cylinder", [] { return MakeCylinder(0.5, 30, 24, 12); }}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(Builder, ScaleInvariant) {
  // A tiny (micrometre) and a huge (metre) torus give the same relative fit.
  double relative[2];
  int i = 0;
  for (double scale : {1e-3, 1e3}) {
    TriangleMesh mesh = MakeTorus(10, 3, 32, 16);
    mesh.Transform(scale * Matrix3::Identity(), Vector3::Zero());
    const SphereTree tree = BuildSphereTree(mesh, Small(32));
    ExpectGuarantees(mesh, tree);
    const TreeMetrics m = EvaluateSphereTree(mesh, tree, Quick());
    relative[i++] = m.leaves().protrusion_max_mm / m.largest_extent_mm;
  }
  EXPECT_NEAR(relative[0], relative[1], 0.05 * relative[0]);
}

TEST(Builder, MoreLeavesFitBetter) {
  const TriangleMesh mesh = MakeTorus(10, 3, 48, 24);
  const EvalParams e = Quick();
  const double coarse = EvaluateSphereTree(mesh, BuildSphereTree(mesh, Small(8)), e)
                            .leaves()
                            .protrusion_max_mm;
  const double fine = EvaluateSphereTree(mesh, BuildSphereTree(mesh, Small(64)), e)
                          .leaves()
                          .protrusion_max_mm;
  EXPECT_LT(fine, 0.5 * coarse);
}

TEST(Builder, AMeshOfMoreFacesThanSamplesStillBuilds) {
  // 16 leaves want 3,000 samples; a sphere of 20,480 faces has more than four
  // times that many even at one piece per face. It builds, one piece a face
  // (the sampling once grew its piece size without end here).
  const TriangleMesh mesh = MakeIcosphere(5.0, 5);
  ASSERT_GT(mesh.num_faces(), 4u * 3000u);
  const SphereTree tree = BuildSphereTree(mesh, Small(16));
  EXPECT_GT(tree.NumLeaves(), 0u);
  EXPECT_LT(EvaluateSphereTree(mesh, tree, Quick()).leaves().protrusion_max_mm, 5.0);
}

TEST(Builder, TargetErrorMode) {
  const TriangleMesh mesh = MakeTorus(10, 3, 48, 24);
  SphereTreeParams p = Small();
  p.levels = 4;  // up to 512 leaves
  p.target_error_mm = 0.3;
  SphereTreeBuildStats stats;
  const SphereTree tree = BuildSphereTree(mesh, p, {}, &stats);
  EXPECT_LE(stats.error_bound_mm, 0.3 + 1e-9);
  // The bound holds for the measured protrusion (it is an upper bound).
  EXPECT_LE(EvaluateSphereTree(mesh, tree, Quick()).leaves().protrusion_max_mm,
            0.3 + 1e-9);
  // A looser target needs fewer leaves.
  p.target_error_mm = 0.6;
  EXPECT_LT(BuildSphereTree(mesh, p).NumLeaves(), tree.NumLeaves());
  p.target_error_mm = 1e-6;
  EXPECT_THROW(BuildSphereTree(mesh, p), SphereTreeError);
}

TEST(Builder, DeterministicForASeed) {
  const TriangleMesh mesh = MakeTorus(10, 3, 32, 16);
  const SphereTree a = BuildSphereTree(mesh, Small(32));
  const SphereTree b = BuildSphereTree(mesh, Small(32));
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.r, b.r);
  SphereTreeParams other = Small(32);
  other.seed = 99;
  EXPECT_NE(BuildSphereTree(mesh, other).x, a.x);
}

TEST(Builder, ProgressIsMonotoneAndCancellable) {
  const TriangleMesh mesh = MakeTorus(10, 3, 32, 16);
  double last = -1;
  int calls = 0;
  BuildSphereTree(mesh, Small(32), [&](std::string_view, double f) {
    EXPECT_GE(f, last);
    last = f;
    ++calls;
    return true;
  });
  EXPECT_GT(calls, 5);
  EXPECT_DOUBLE_EQ(last, 1.0);
  int seen = 0;
  EXPECT_THROW(BuildSphereTree(mesh, Small(32),
                               [&](std::string_view, double) { return ++seen < 3; }),
               BuildCancelled);
}

void ExpectBuildError(const TriangleMesh& mesh, const SphereTreeParams& p,
                      const std::string& what) {
  try {
    BuildSphereTree(mesh, p);
    ADD_FAILURE() << "built, expected: " << what;
  } catch (const SphereTreeError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(Builder, BadInputIsRejectedClearly) {
  const TriangleMesh box = MakeBox(Vector3(1, 1, 1));
  auto faces = box.faces();
  faces.pop_back();
  ExpectBuildError(TriangleMesh(box.vertices(), faces), Small(),
                   "the mesh must be a closed, manifold surface (3 boundary and 0 "
                   "non-manifold edges)");
  // Flat: a closed surface of zero volume (a box squashed to a plane).
  TriangleMesh flat = MakeBox(Vector3(1, 1, 1));
  flat.Transform(Vector3(1, 1, 0).asDiagonal(), Vector3::Zero());
  ExpectBuildError(flat, Small(),
                   "the mesh encloses no volume (it is flat or degenerate)");
  SphereTreeParams p = Small();
  p.leaves = 100;  // 3 levels of 8 hold 64
  ExpectBuildError(box, p,
                   "leaf budget 100 does not fit in 3 levels of 8 (at most 64 leaves)");
  p = Small();
  p.levels = 0;
  ExpectBuildError(box, p, "levels 0 is out of range (expected 1 to 8)");
  p = Small();
  p.branching = 1;
  ExpectBuildError(box, p, "branching 1 is out of range (expected 2 to 32)");
  p = Small();
  p.tighten_passes = 0;
  ExpectBuildError(box, p, "tightening passes 0 is out of range (expected 1 to 8)");
}

// The candidates' k-d tree finds every ball that can reach a point within a
// bound, |x - c| - depth <= bound, exactly as a scan of all of them does and in
// the same (index) order: the cover's search for its hardest pieces relies on
// it to list the same entries as the scan it replaced.
TEST(CentreKdTree, WithinFindsWhatAScanFinds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(-20, 20), deep(0, 3);
  std::vector<tree_build::Candidate> balls(5000);
  for (auto& b : balls) b = {Vector3(at(rng), at(rng), 0.2 * at(rng)), deep(rng)};
  const tree_build::CentreKdTree<tree_build::Candidate> tree(balls);
  std::vector<std::int32_t> found;
  std::size_t total = 0;
  for (int q = 0; q < 200; ++q) {
    const Vector3 x(at(rng), at(rng), 0.2 * at(rng));
    const double bound = 0.05 * (q % 40);
    tree.Within(x, bound, &found);
    std::vector<std::int32_t> scan;
    for (std::size_t i = 0; i < balls.size(); ++i)
      if ((x - balls[i].c).norm() - balls[i].depth <= bound)
        scan.push_back(static_cast<std::int32_t>(i));
    EXPECT_EQ(found, scan) << "query " << q;
    total += scan.size();
  }
  EXPECT_GT(total, 200u) << "the queries find balls";
  const std::vector<tree_build::Candidate> no_balls;
  const tree_build::CentreKdTree<tree_build::Candidate> none(no_balls);
  none.Within(Vector3::Zero(), 1.0, &found);
  EXPECT_TRUE(found.empty());
}

// The min-max cover tightened once instead of three times: every guarantee
// holds, the same leaves are spent, and the fit is nearly as close (each pass
// only splits pieces at the leaves' rims and hands them to the leaf that holds
// them best, so none can loosen it).
TEST(Builder, OneTighteningPassKeepsEveryGuarantee) {
  const TriangleMesh mesh = MakeTorus(10, 3, 48, 24);
  SphereTreeParams p = Small();
  p.spend = SphereTreeParams::Spend::kWorst;
  const SphereTree three = BuildSphereTree(mesh, p);
  p.tighten_passes = 1;
  const SphereTree once = BuildSphereTree(mesh, p);
  ExpectGuarantees(mesh, once);
  EXPECT_EQ(once.NumLeaves(), three.NumLeaves());
  const double worst_three =
      EvaluateSphereTree(mesh, three, Quick()).leaves().protrusion_max_mm;
  const double worst_once =
      EvaluateSphereTree(mesh, once, Quick()).leaves().protrusion_max_mm;
  std::printf("figure: worst protrusion %.4f mm tightened once, %.4f mm three times\n",
              worst_once, worst_three);
  EXPECT_LE(worst_three, worst_once + 1e-9);
  EXPECT_LT(worst_once, 1.15 * worst_three);
}

TEST(Builder, InwardOrientedMeshStillWorks) {
  TriangleMesh torus = MakeTorus(10, 3, 32, 16);
  torus.FlipOrientation();
  ExpectGuarantees(torus, BuildSphereTree(torus, Small(32)));
}

}  // namespace
}  // namespace sulcus
