#include "core/collision/collision.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/geometry/primitives.h"
#include "core/spheretree/builder.h"
#include "tests/common/alloc_guard.h"
#include "tests/core/haptics/test_scenes.h"

namespace sulcus {
namespace {

RigidTransform RandomPose(std::mt19937_64& rng, double spread) {
  std::normal_distribution<double> n(0, 1);
  Vector6 q;
  q << spread * n(rng), spread * n(rng), spread * n(rng), 3 * n(rng), 3 * n(rng),
      3 * n(rng);
  return RigidTransform::FromConfiguration(q);
}

void ExpectSamePairs(std::vector<ContactPair> ref, const ContactPair* fast_begin, int n) {
  ASSERT_EQ(static_cast<int>(ref.size()), n);
  // Each returns its own traversal order: compare as sets, by key.
  auto by_key = [](const ContactPair& x, const ContactPair& y) {
    return x.key() < y.key();
  };
  std::vector<ContactPair> fast(fast_begin, fast_begin + n);
  std::sort(ref.begin(), ref.end(), by_key);
  std::sort(fast.begin(), fast.end(), by_key);
  for (int i = 0; i < n; ++i) {
    ASSERT_EQ(ref[i].key(), fast[i].key()) << i;
    // Same formula on the same doubles up to the order of a 3-term sum.
    ASSERT_NEAR(ref[i].gap, fast[i].gap, 1e-12) << i;
  }
}

TEST(Collision, FastMatchesReferenceOnRandomPoses) {
  test::Scene scene;
  scene.tool = std::make_unique<SphereTree>(test::MakeProbe());
  SphereTreeParams p;
  p.leaves = 512;
  p.samples = 3000;
  scene.Add(BuildSphereTree(MakeTorus(6, 2.5, 40, 20), p), RigidTransform::Identity());
  scene.Add(test::MakeBlock(5, 5, -1, 0, 0.5, 0.4),
            RigidTransform(Matrix3::Identity(), Vector3(0, 0, -4)));
  const CollisionWorld world(*scene.tool, scene.objects);
  CollisionScratch scratch;
  std::vector<ContactPair> out(20000);
  std::mt19937_64 rng(3);
  int with_contacts = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const RigidTransform X = RandomPose(rng, 6);
    for (double margin : {0.0, 0.3}) {
      const auto ref = FindContactsReference(world, X, margin);
      const CollisionStats s =
          FindContacts(world, X, margin, &scratch, out.data(), 20000);
      EXPECT_FALSE(s.overflow);
      ExpectSamePairs(ref, out.data(), s.pairs);
      with_contacts += !ref.empty();
    }
  }
  EXPECT_GT(with_contacts, 100);  // the poses do exercise contact
}

TEST(Collision, MarginReportsNearPairsWithTheirGap) {
  test::Scene scene;
  scene.tool = std::make_unique<SphereTree>(test::MakeProbe());
  scene.Add(test::MakeBlock(2, 2, -0.5, -0.5, 0.5, 0.5),
            RigidTransform::Identity());  // top at z = 0
  const CollisionWorld world(*scene.tool, scene.objects);
  CollisionScratch scratch;
  std::vector<ContactPair> out(1000);
  // Tip (r 0.25) 0.1 mm above the block top: no contact at margin 0, one within 0.2.
  const RigidTransform X(Matrix3::Identity(), Vector3(0, 0, 0.35));
  EXPECT_EQ(FindContacts(world, X, 0.0, &scratch, out.data(), 1000).pairs, 0);
  const CollisionStats s = FindContacts(world, X, 0.2, &scratch, out.data(), 1000);
  ASSERT_GE(s.pairs, 1);
  double nearest = 1e9;
  for (int i = 0; i < s.pairs; ++i) nearest = std::min(nearest, out[i].gap);
  EXPECT_NEAR(nearest, 0.1, 1e-12);
}

TEST(Collision, OverflowIsReportedNotWritten) {
  test::Scene scene;
  scene.tool = std::make_unique<SphereTree>(test::MakeFlatFace(10, 10, 0.5, 0.5));
  scene.Add(test::MakeBlock(5, 5, -0.5, -0.5, 0.5, 0.5), RigidTransform::Identity());
  const CollisionWorld world(*scene.tool, scene.objects);
  CollisionScratch scratch;
  std::vector<ContactPair> out(50);
  const CollisionStats s =
      FindContacts(world, RigidTransform(Matrix3::Identity(), Vector3(0, 0, -0.1)), 0.0,
                   &scratch, out.data(), 50);
  EXPECT_EQ(s.pairs, 50);
  EXPECT_TRUE(s.overflow);
}

TEST(Collision, FastQueryAllocatesNothing) {
  test::Scene scene;
  scene.tool = std::make_unique<SphereTree>(test::MakeProbe());
  scene.Add(test::MakeBlock(5, 5, -1, 0, 0.5, 0.4), RigidTransform::Identity());
  const CollisionWorld world(*scene.tool, scene.objects);
  CollisionScratch scratch;
  std::vector<ContactPair> out(5000);
  const RigidTransform X(Matrix3::Identity(), Vector3(0, 0, 0.2));
  test::AllocationGuard guard;
  const CollisionStats s = FindContacts(world, X, 0.5, &scratch, out.data(), 5000);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_GT(s.pairs, 0);
}

}  // namespace
}  // namespace sulcus
