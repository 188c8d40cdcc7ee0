// Leaf spheres clipped by planes fitted to the mesh: the planes bound the
// surface (nothing of it is cut away), a flat face is felt flat, and the fast
// query and the reference agree on clipped leaves.
#include "core/collision/leaf_planes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/collision/collision.h"
#include "core/geometry/primitives.h"
#include "core/haptics/engine.h"
#include "core/haptics/haptic_loop.h"
#include "core/spheretree/builder.h"

namespace sulcus {
namespace {

// Points spread over every face (barycentric samples).
std::vector<Vector3> SurfaceSamples(const TriangleMesh& mesh, int per_face,
                                    unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vector3> out;
  for (const auto& f : mesh.faces()) {
    const Vector3 a = mesh.vertices()[f[0]], b = mesh.vertices()[f[1]],
                  c = mesh.vertices()[f[2]];
    for (int k = 0; k < per_face; ++k) {
      double s = u(rng), t = u(rng);
      if (s + t > 1) s = 1 - s, t = 1 - t;
      out.push_back(a + s * (b - a) + t * (c - a));
    }
  }
  return out;
}

SphereTree Tree(const TriangleMesh& mesh, int leaves) {
  SphereTreeParams p;
  p.leaves = leaves;
  p.levels = 4;
  return BuildSphereTree(mesh, p);
}

// Every surface point inside a leaf sphere is on or below that leaf's plane,
// and every surface point is inside some clipped leaf (the clipped tree still
// covers the whole surface).
void ExpectPlanesBoundTheSurface(const TriangleMesh& mesh, const SphereTree& tree,
                                 const LeafPlanes& planes) {
  const std::vector<Vector3> samples = SurfaceSamples(mesh, 6, 7);
  int uncovered = 0, cut = 0;
  for (const Vector3& p : samples) {
    bool covered = false;
    for (std::size_t n = 0; n < tree.size(); ++n) {
      if (!tree.IsLeaf(n) || (p - tree.center(n)).norm() > tree.r[n] + 1e-9) continue;
      const bool below = planes.Below(n, p, 1e-9);
      if (!below) ++cut;
      covered = covered || below;
    }
    if (!covered) ++uncovered;
  }
  EXPECT_EQ(cut, 0) << "surface points cut away by a leaf's plane";
  EXPECT_EQ(uncovered, 0) << "surface points outside every clipped leaf";
}

TEST(LeafPlanes, BoundTheSurfaceOfACurvedAndAFlatMesh) {
  TriangleMesh ellipsoid = MakeIcosphere(1.0, 4);
  ellipsoid.Transform(Vector3(4, 3.5, 10).asDiagonal(), Vector3::Zero());
  const SphereTree et = Tree(ellipsoid, 128);
  const LeafPlanes ep = FitLeafPlanes(ellipsoid, et);
  // A smooth convex surface: every leaf that meets it is clipped.
  EXPECT_GT(ep.count(), static_cast<int>(et.NumLeaves()) * 9 / 10);
  ExpectPlanesBoundTheSurface(ellipsoid, et, ep);

  const TriangleMesh box = MakeBox(Vector3(16, 16, 4), 8);
  const SphereTree bt = Tree(box, 128);
  const LeafPlanes bp = FitLeafPlanes(box, bt);
  ExpectPlanesBoundTheSurface(box, bt, bp);
  // A leaf meeting only the top face has the top face as its plane, exactly.
  int on_top = 0;
  for (std::size_t n = 0; n < bt.size(); ++n) {
    if (!bt.IsLeaf(n)) continue;
    for (int j = 0; j < LeafPlanes::kMaxPlanes; ++j) {
      if (bp.d[n][j] < LeafPlanes::kNone && bp.n[n][j].z() > 1 - 1e-12) {
        EXPECT_NEAR(bp.d[n][j], 2.0, 1e-9);
        ++on_top;
      }
    }
  }
  EXPECT_GT(on_top, 0);
}

TEST(LeafPlanes, AThinWallIsCutByBothItsFaces) {
  // A 0.2 mm sheet: leaves much larger than it meet both faces; each such leaf
  // is cut by both (normals +z and -z, offsets 0.1), to the sheet itself.
  const TriangleMesh sheet = MakeBox(Vector3(10, 10, 0.2), 4);
  const SphereTree t = Tree(sheet, 32);
  const LeafPlanes p = FitLeafPlanes(sheet, t);
  int both = 0;
  for (std::size_t n = 0; n < t.size(); ++n) {
    if (!t.IsLeaf(n)) continue;
    bool up = false, down = false;
    for (int j = 0; j < LeafPlanes::kMaxPlanes; ++j) {
      if (p.d[n][j] >= LeafPlanes::kNone) continue;
      if (p.n[n][j].z() > 1 - 1e-12) up = std::abs(p.d[n][j] - 0.1) < 1e-9;
      if (p.n[n][j].z() < -1 + 1e-12) down = std::abs(p.d[n][j] - 0.1) < 1e-9;
    }
    both += up && down;
  }
  EXPECT_GT(both, 16);
  ExpectPlanesBoundTheSurface(sheet, t, p);
}

// A block with a V groove along y: faces inclined 35 degrees meeting at
// x = 0, z = 0 (an interior angle of 110 degrees), 10 mm wide, 20 mm long,
// 4 mm below the crease.
TriangleMesh VGroove() {
  const double t = std::tan(35 * M_PI / 180);
  const double prof[5][2] = {{-5, 5 * t}, {0, 0}, {5, 5 * t}, {5, -4}, {-5, -4}};
  std::vector<Vector3> v;
  for (const double y : {-10.0, 10.0})
    for (const auto& p : prof) v.emplace_back(p[0], y, p[1]);
  std::vector<std::array<int, 3>> f;
  for (const auto& k : {std::array<int, 3>{1, 2, 3}, {1, 3, 4}, {1, 4, 0}}) {
    f.push_back({k[2], k[1], k[0]});
    f.push_back({k[0] + 5, k[1] + 5, k[2] + 5});
  }
  for (int i = 0; i < 5; ++i) {
    const int j = (i + 1) % 5;
    f.push_back({i, j, j + 5});
    f.push_back({i, j + 5, i + 5});
  }
  return TriangleMesh(std::move(v), std::move(f));
}

// In the groove, a leaf across the crease meets both faces, each rising above
// the other's plane. Cut by the intersection of the two planes (each lifted
// over the other face) it would hold a tool off the crease; cut by their union
// (each plane bounding its own face) it is the groove itself: a ball that
// touches both faces has gap 0 to the leaves there, and the space just above
// the crease is outside them.
TEST(LeafPlanes, AConcaveCreaseIsCutByTheUnionOfItsTwoFaces) {
  const TriangleMesh block = VGroove();
  ASSERT_TRUE(block.Check().IsSolid());
  SphereTreeParams fine;
  fine.levels = 5;
  fine.leaves = 1024;
  const SphereTree tree = BuildSphereTree(block, fine);
  const LeafPlanes planes = FitLeafPlanes(block, tree);
  ExpectPlanesBoundTheSurface(block, tree, planes);
  LeafPlaneParams never;
  never.concave_lift_mm = 0;
  const LeafPlanes lifted = FitLeafPlanes(block, tree, never);
  ExpectPlanesBoundTheSurface(block, tree, lifted);
  const CollisionWorld world(tree, {{&tree, RigidTransform::Identity(), &planes}});
  const CollisionWorld world_lifted(tree, {{&tree, RigidTransform::Identity(), &lifted}});
  const double r = 0.1, h = r / std::sin(55 * M_PI / 180);
  int crease_leaves = 0;
  for (double y = -3; y <= 3; y += 0.5) {
    const Vector3 ball(0, y, h);  // touching both faces
    double gap = 1e9, gap_lifted = 1e9;
    for (std::size_t n = 0; n < tree.size(); ++n) {
      if (!tree.IsLeaf(n)) continue;
      gap = std::min(gap, world.LeafGap(0, static_cast<std::int32_t>(n), ball, r));
      gap_lifted = std::min(
          gap_lifted, world_lifted.LeafGap(0, static_cast<std::int32_t>(n), ball, r));
      // Across the crease, away from the block's ends (a leaf there meets four
      // groups of faces, and holds three planes).
      const Vector3 c = tree.center(n);
      if ((c - Vector3(0, y, 0)).norm() >= tree.r[n] || std::abs(c.y()) + tree.r[n] >= 10)
        continue;
      ++crease_leaves;
      EXPECT_TRUE(planes.concave[n]) << "leaf " << n << " across the crease at y " << y;
      EXPECT_FALSE(planes.Below(n, Vector3(0, y, 0.002), 0)) << "above the crease";
      EXPECT_TRUE(planes.Below(n, Vector3(0, y, -0.002), 0)) << "below it";
    }
    EXPECT_NEAR(gap, 0, 1e-9) << "y " << y;
    EXPECT_LT(gap_lifted, -0.02) << "y " << y << ": lifted planes push the ball off";
  }
  EXPECT_GT(crease_leaves, 8);
  // A convex edge stays an intersection: the box's leaves are not concave.
  const TriangleMesh box = MakeBox(Vector3(16, 16, 4), 8);
  const SphereTree bt = Tree(box, 128);
  const LeafPlanes bp = FitLeafPlanes(box, bt);
  EXPECT_EQ(std::count(bp.concave.begin(), bp.concave.end(), 1), 0);
}

TEST(LeafPlanes, FastQueryMatchesTheReferenceOnClippedLeaves) {
  TriangleMesh ellipsoid = MakeIcosphere(1.0, 3);
  ellipsoid.Transform(Vector3(4, 3.5, 10).asDiagonal(), Vector3::Zero());
  const SphereTree obj = Tree(ellipsoid, 64);
  const LeafPlanes planes = FitLeafPlanes(ellipsoid, obj);
  const SphereTree tool = Tree(MakeCylinder(0.4, 8, 12, 8), 32);
  const RigidTransform X_WO(
      Eigen::AngleAxisd(0.3, Vector3(1, 1, 0).normalized()).toRotationMatrix(),
      Vector3(1, -2, 3));
  const CollisionWorld world(tool, {{&obj, X_WO, &planes}});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  CollisionScratch scratch;
  std::vector<ContactPair> out(20000);
  int compared = 0, clipped_pairs = 0;
  for (int k = 0; k < 200; ++k) {
    const Vector3 axis = Vector3(u(rng), u(rng), u(rng)).normalized();
    const RigidTransform X(Eigen::AngleAxisd(3 * u(rng), axis).toRotationMatrix(),
                           X_WO * Vector3(5 * u(rng), 4.5 * u(rng), 11 * u(rng)));
    const double margin = 0.5 * (1 + u(rng));
    const auto ref = FindContactsReference(world, X, margin);
    const CollisionStats s = FindContacts(world, X, margin, &scratch, out.data(),
                                          static_cast<int>(out.size()));
    ASSERT_EQ(static_cast<std::size_t>(s.pairs), ref.size());
    std::vector<std::pair<std::uint64_t, double>> a, b;
    for (int i = 0; i < s.pairs; ++i) a.emplace_back(out[i].key(), out[i].gap);
    for (const ContactPair& c : ref) b.emplace_back(c.key(), c.gap);
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].first, b[i].first);
      EXPECT_NEAR(a[i].second, b[i].second, 1e-9);
    }
    for (const ContactPair& c : ref) {
      // A clipped leaf's gap is never below its sphere gap (each of its pieces
      // bounds the distance to a part of the sphere).
      const Vector3 cT = X * tool.center(c.tool_leaf);
      const double sphere = (cT - world.ObjectCenter(0, c.object_leaf)).norm() -
                            tool.r[c.tool_leaf] - world.ObjectRadius(0, c.object_leaf);
      EXPECT_GE(c.gap, sphere - 1e-12);
      if (std::abs(c.gap - sphere) > 1e-12) ++clipped_pairs;
    }
    compared += static_cast<int>(ref.size());
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(clipped_pairs, 100);  // the planes decided many of them
}

// Slides the flat end of an upright 0.4 mm cylinder at a constant device depth
// of 0.3 mm over the top of a 16 x 16 x 4 mm box, 12 mm at 4 mm/s (1 kHz).
struct Slide {
  double ripple_pct = 0, height_ripple_mm = 0, lowest_gap_mm = 1e9, highest_gap_mm = -1e9,
         worst_pop_n = 0;
  std::uint64_t faults = 0;
};
Slide SlideOnTheBox(const LeafPlanes* planes, const SphereTree& plate,
                    const SphereTree& probe, double probe_bottom) {
  const EngineModel model(probe, {{&plate, RigidTransform::Identity(), planes}},
                          EngineParams{});
  EngineData d(model);
  auto at = [](double x) {
    return RigidTransform(Matrix3::Identity(), Vector3(x, 0, 2 - 0.3));
  };
  ResetTool(RigidTransform(Matrix3::Identity(), Vector3(-6, 0, 3)), &d);
  Slide s;
  double fmin = 1e9, fmax = -1e9, fsum = 0, gmin = 1e9, gmax = -1e9;
  Vector3 last_f = Vector3::Zero(), last_h = at(-6).translation();
  const int warmup = 300, frames = 3000;
  for (int i = 0; i < warmup + frames; ++i) {
    const RigidTransform X = at(-6 + 12.0 * std::max(0, i - warmup) / frames);
    Step(model, X, &d);
    if (i >= warmup) {
      const double fz = d.force_W.z(), gz = d.X_WG.translation().z();
      fmin = std::min(fmin, fz), fmax = std::max(fmax, fz), fsum += fz;
      gmin = std::min(gmin, gz), gmax = std::max(gmax, gz);
      const double gap =
          gz + probe_bottom - 2.0;  // the probe's true end over the true face
      s.lowest_gap_mm = std::min(s.lowest_gap_mm, gap);
      s.highest_gap_mm = std::max(s.highest_gap_mm, gap);
      const double pop =
          UnexplainedForceChange(last_f, d.force_W, last_h, X.translation(), 1.0);
      s.worst_pop_n = std::max(s.worst_pop_n, pop);
    }
    last_f = d.force_W;
    last_h = X.translation();
  }
  s.ripple_pct = 100 * (fmax - fmin) / (fsum / frames);
  s.height_ripple_mm = gmax - gmin;
  s.faults = d.faults.total();
  return s;
}

TEST(LeafPlanes, AFlatFaceIsFeltFlatWhereSpheresAreBumps) {
  const TriangleMesh box = MakeBox(Vector3(16, 16, 4), 8);
  const TriangleMesh probe_mesh = MakeCylinder(0.4, 16, 24, 24);
  const SphereTree probe = BuildSphereTree(probe_mesh, ToolTreeParams());
  const double probe_bottom = probe_mesh.Bounds().min.z();
  const SphereTree plate = Tree(box, 512);
  const LeafPlanes planes = FitLeafPlanes(box, plate);
  const Slide spheres = SlideOnTheBox(nullptr, plate, probe, probe_bottom);
  const Slide clipped = SlideOnTheBox(&planes, plate, probe, probe_bottom);
  std::printf(
      "spheres: ripple %.2f %% height %.4f gap %.4f..%.4f pop %.3f; clipped: ripple %.3f "
      "%% height %.5f gap %.4f..%.4f pop %.3f\n",
      spheres.ripple_pct, spheres.height_ripple_mm, spheres.lowest_gap_mm,
      spheres.highest_gap_mm, spheres.worst_pop_n, clipped.ripple_pct,
      clipped.height_ripple_mm, clipped.lowest_gap_mm, clipped.highest_gap_mm,
      clipped.worst_pop_n);
  // The spheres: tens of percent (what the accuracy-cost table shows).
  EXPECT_GT(spheres.ripple_pct, 10.0);
  // Clipped: below what a hand tells apart (7 %), far below in fact; the tool
  // level, never in the true face, and the gap left only the probe's own tree.
  EXPECT_LT(clipped.ripple_pct, 1.0);
  EXPECT_LT(clipped.height_ripple_mm, 0.01);
  EXPECT_GE(clipped.lowest_gap_mm, -1e-3);
  EXPECT_LT(clipped.highest_gap_mm, spheres.lowest_gap_mm);
  EXPECT_LT(clipped.worst_pop_n, kPopN);
  EXPECT_EQ(clipped.faults, 0u);
}

}  // namespace
}  // namespace sulcus
