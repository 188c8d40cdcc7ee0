// Where a scene's mesh files may come from (core/scene/mesh_paths.h).
#include "core/scene/mesh_paths.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

TEST(MeshPaths, AFileBesideTheSceneIsTakenHoweverTheFolderIsSpelled) {
  const fs::path dir = test::FreshOutputPath("mesh_paths", "beside");
  test::WriteText(dir / "m.stl", "solid m\nendsolid m\n");
  EXPECT_EQ(MeshPathProblem("m.stl", dir), "");
  EXPECT_EQ(MeshPathProblem("m.stl", dir / "."), "");
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  EXPECT_EQ(MeshPathProblem("m.stl", "."), "") << "a scene read as scene.yaml";
  fs::current_path(before);
}

TEST(MeshPaths, OutsideTheFolderOnlyFromALibraryTheEnvironmentNames) {
  const fs::path root = test::FreshOutputPath("mesh_paths", "library");
  fs::create_directories(root / "scene");
  fs::create_directories(root / "lib");
  test::WriteText(root / "lib" / "m.stl", "solid m\nendsolid m\n");
  fs::create_symlink(root / "lib" / "m.stl", root / "scene" / "link.stl");
  ::unsetenv("SULCUS_MESH_LIBRARY");
  EXPECT_NE(MeshPathProblem("link.stl", root / "scene").find("leaves the scene's folder"),
            std::string::npos);
  EXPECT_NE(MeshPathProblem("../lib/m.stl", root / "scene").find("leaves"),
            std::string::npos);
  EXPECT_NE(
      MeshPathProblem((root / "lib" / "m.stl").string(), root / "scene").find("leaves"),
      std::string::npos);
  ::setenv("SULCUS_MESH_LIBRARY", ("/nowhere:" + (root / "lib").string()).c_str(), 1);
  EXPECT_EQ(MeshPathProblem("link.stl", root / "scene"), "");
  EXPECT_EQ(MeshPathProblem((root / "lib" / "m.stl").string(), root / "scene"), "");
  ::unsetenv("SULCUS_MESH_LIBRARY");
}

TEST(MeshPaths, AFileTooLargeForAnyMouthIsRefusedBeforeItIsRead) {
  const fs::path dir = test::FreshOutputPath("mesh_paths", "large");
  { std::ofstream(dir / "huge.stl").flush(); }
  fs::resize_file(dir / "huge.stl", (512ull << 20) + 1);  // sparse: nothing written
  EXPECT_EQ(MeshPathProblem("huge.stl", dir),
            "mesh path 'huge.stl' is 512 MB; a scene's mesh may be at most 512 MB "
            "(reduce its triangles first)");
  fs::resize_file(dir / "huge.stl", 512ull << 20);
  EXPECT_EQ(MeshPathProblem("huge.stl", dir), "");
  fs::remove(dir / "huge.stl");
}

}  // namespace
}  // namespace sulcus
