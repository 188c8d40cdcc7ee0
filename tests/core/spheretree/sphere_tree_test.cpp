#include "core/spheretree/sphere_tree.h"

#include <gtest/gtest.h>

#include <limits>

namespace sulcus {
namespace {

// Root with two children; the second child has one child of its own.
SphereTree Small() {
  SphereTree t;
  t.levels = 3;
  t.branching = 2;
  t.AddNode({0, 0, 0}, 10, 0);
  t.AddNode({-3, 0, 0}, 4, 1);
  t.AddNode({3, 0, 0}, 4, 1);
  t.AddNode({3, 1, 0}, 2, 2);
  t.first_child[0] = 1;
  t.child_count[0] = 2;
  t.first_child[2] = 3;
  t.child_count[2] = 1;
  return t;
}

TEST(SphereTree, LevelsCutsAndLeaves) {
  const SphereTree t = Small();
  EXPECT_NO_THROW(t.Validate());
  EXPECT_EQ(t.NumLeaves(), 2u);
  EXPECT_EQ(t.NodesOnLevel(1), (std::vector<std::int32_t>{1, 2}));
  // The cut at level 2 keeps the shallow leaf 1 and the deep leaf 3.
  EXPECT_EQ(t.CutAtLevel(2), (std::vector<std::int32_t>{1, 3}));
  EXPECT_EQ(t.CutAtLevel(0), (std::vector<std::int32_t>{0}));
}

void ExpectInvalid(const SphereTree& t, const std::string& what) {
  try {
    t.Validate();
    ADD_FAILURE() << "accepted, expected: " << what;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(SphereTree, ValidateFindsEachFault) {
  SphereTree t = Small();
  t.r[3] = 0;
  ExpectInvalid(t, "node 3 has radius 0");
  t = Small();
  t.x[1] = std::numeric_limits<double>::quiet_NaN();
  ExpectInvalid(t, "node 1 has a non-finite value");
  t = Small();
  t.first_child[2] = 9;
  ExpectInvalid(t, "node 2 has children outside the node array");
  t = Small();
  t.level[3] = 1;
  ExpectInvalid(t, "child 3 of node 2 is not one level deeper");
  t = Small();
  t.child_count[2] = 0;
  ExpectInvalid(t, "node 3 is not reached from the root");
  t = Small();
  t.y.pop_back();
  ExpectInvalid(t, "array sizes disagree");
  ExpectInvalid(SphereTree{}, "no nodes");
}

}  // namespace
}  // namespace sulcus
