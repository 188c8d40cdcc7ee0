#include "core/spheretree/cache.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/geometry/primitives.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

SphereTreeParams Params() {
  SphereTreeParams p;
  p.levels = 3;
  p.leaves = 24;
  p.samples = 1500;
  return p;
}

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::path(SULCUS_TEST_OUTPUT) / "cache" / name;
  fs::remove_all(dir);
  return dir;
}

TEST(Cache, SecondLoadBuildsNothing) {
  const TriangleMesh mesh = MakeTorus(10, 3, 32, 16);
  const fs::path dir = FreshDir("hit");
  CacheOutcome first, second;
  int progress_calls = 0;
  const SphereTree a = LoadOrBuildSphereTree(mesh, Params(), dir, {}, &first);
  const SphereTree b = LoadOrBuildSphereTree(
      mesh, Params(), dir,
      [&](std::string_view, double) {
        ++progress_calls;
        return true;
      },
      &second);
  EXPECT_EQ(first.kind, CacheOutcome::Kind::kBuilt);
  EXPECT_EQ(second.kind, CacheOutcome::Kind::kHit);
  EXPECT_EQ(progress_calls, 0);  // no build ran
  EXPECT_EQ(a.r, b.r);
  EXPECT_TRUE(first.warning.empty()) << first.warning;
}

TEST(Cache, KeyDependsOnMeshAndParameters) {
  const TriangleMesh a = MakeTorus(10, 3, 32, 16);
  TriangleMesh b = a;
  b.Transform(Matrix3::Identity(), Vector3(1e-9, 0, 0));
  SphereTreeParams p = Params();
  EXPECT_NE(SphereTreeCacheKey(a, p), SphereTreeCacheKey(b, p));
  const auto key = SphereTreeCacheKey(a, p);
  p.seed = 2;
  EXPECT_NE(SphereTreeCacheKey(a, p), key);
}

TEST(Cache, CorruptFileIsRebuiltWithAWarning) {
  const TriangleMesh mesh = MakeTorus(10, 3, 32, 16);
  const fs::path dir = FreshDir("corrupt");
  CacheOutcome out;
  const SphereTree good = LoadOrBuildSphereTree(mesh, Params(), dir, {}, &out);
  // Truncate the cached file.
  const auto size = fs::file_size(out.file);
  fs::resize_file(out.file, size / 2);
  CacheOutcome again;
  const SphereTree rebuilt = LoadOrBuildSphereTree(mesh, Params(), dir, {}, &again);
  EXPECT_EQ(again.kind, CacheOutcome::Kind::kRebuiltCorrupt);
  EXPECT_NE(again.warning.find("ignored the cached tree"), std::string::npos)
      << again.warning;
  EXPECT_NE(again.warning.find("truncated"), std::string::npos) << again.warning;
  EXPECT_EQ(rebuilt.r, good.r);
  EXPECT_EQ(fs::file_size(out.file), size);  // replaced by a good one
}

TEST(Cache, UnwritableCacheStillReturnsTheTree) {
  const TriangleMesh mesh = MakeTorus(10, 3, 32, 16);
  const fs::path blocker = FreshDir("blocked");
  fs::create_directories(blocker.parent_path());
  std::ofstream(blocker) << "a file where the cache folder should be";
  CacheOutcome out;
  const SphereTree tree =
      LoadOrBuildSphereTree(mesh, Params(), blocker / "sub", {}, &out);
  EXPECT_GT(tree.size(), 0u);
  EXPECT_NE(out.warning.find("could not cache the tree"), std::string::npos)
      << out.warning;
  fs::remove(blocker);
}

}  // namespace
}  // namespace sulcus
