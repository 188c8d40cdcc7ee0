#include "core/geometry/mesh_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/geometry/primitives.h"
#include "tests/common/compare.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;
using test::CompareMatrices;
using test::CompareScalars;
using test::ToleranceType;

fs::path OutDir() {
  const fs::path dir = fs::path(SULCUS_TEST_OUTPUT) / "mesh_io";
  fs::create_directories(dir);
  return dir;
}

fs::path Bad(const std::string& name) {
  return fs::path(SULCUS_TEST_DATA) / "bad" / name;
}

// Expects LoadMesh to throw a MeshError whose message names the file and contains
// `fault`.
void ExpectLoadFails(const fs::path& path, const std::string& fault) {
  try {
    LoadMesh(path);
    ADD_FAILURE() << path << " loaded, expected: " << fault;
  } catch (const MeshError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path.string() + ": ", 0), 0u)
        << "message does not start with the file: " << what;
    EXPECT_NE(what.find(fault), std::string::npos)
        << "message: " << what << "\nexpected: " << fault;
    EXPECT_EQ(e.path(), path.string());
  }
}

struct Format {
  const char* name;
  const char* extension;
  bool binary;
  double tolerance;  // OpenMesh's readers parse into float32, whatever the format
};

void PrintTo(const Format& f, std::ostream* os) { *os << f.name; }

class MeshRoundTrip : public ::testing::TestWithParam<Format> {};

TEST_P(MeshRoundTrip, KeepsGeometryAndTopology) {
  const Format& fmt = GetParam();
  // Coordinates not representable in float, so float storage shows.
  TriangleMesh mesh = MakeTorus(10.123456789, 3.3, 24, 12);
  mesh.Transform(Matrix3::Identity(), Vector3(0.1, -0.2, 1.0 / 3.0));
  const fs::path file = OutDir() / (std::string("torus_") + fmt.name + fmt.extension);
  SaveMesh(mesh, file, {.binary = fmt.binary});
  const TriangleMesh back = LoadMesh(file);
  ASSERT_EQ(back.num_vertices(), mesh.num_vertices());
  ASSERT_EQ(back.num_faces(), mesh.num_faces());
  const MeshReport a = mesh.Check(), b = back.Check();
  EXPECT_TRUE(b.IsSolid());
  EXPECT_EQ(b.euler_characteristic, a.euler_characteristic);
  EXPECT_TRUE(
      CompareScalars(b.volume, a.volume, fmt.tolerance, ToleranceType::kRelative));
  // Same faces on the same points, in the same order (STL readers merge equal
  // points, which for a mesh with distinct vertices changes nothing but order).
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(CompareMatrices(back.vertices()[back.faces()[f][k]],
                                  mesh.vertices()[mesh.faces()[f][k]], fmt.tolerance,
                                  ToleranceType::kRelative))
          << "face " << f << " corner " << k;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllFormats, MeshRoundTrip,
    ::testing::Values(Format{"stl_ascii", ".stl", false, test::tol::kFloat32},
                      Format{"stl_binary", ".stl", true, test::tol::kFloat32},
                      Format{"obj", ".obj", false, test::tol::kFloat32},
                      Format{"off", ".off", false, test::tol::kFloat32},
                      Format{"ply_ascii", ".ply", false, test::tol::kFloat32},
                      Format{"ply_binary", ".ply", true, test::tol::kFloat32}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(MeshIo, BinaryAndAsciiStlDiffer) {
  const TriangleMesh box = MakeBox(Vector3(1, 2, 3));
  SaveMesh(box, OutDir() / "box_a.stl", {.binary = false});
  SaveMesh(box, OutDir() / "box_b.stl", {.binary = true});
  std::ifstream a(OutDir() / "box_a.stl"), b(OutDir() / "box_b.stl", std::ios::binary);
  std::string first;
  std::getline(a, first);
  EXPECT_EQ(first.rfind("solid", 0), 0u);
  // Binary: 80-byte header + count + 50 bytes per triangle.
  EXPECT_EQ(fs::file_size(OutDir() / "box_b.stl"), 84u + 50u * box.num_faces());
}

TEST(MeshIo, BadFilesFailWithTheirFault) {
  ExpectLoadFails(Bad("does_not_exist.stl"), "no such file");
  ExpectLoadFails(Bad("empty.stl"), "file is empty");
  ExpectLoadFails(Bad("garbage.off"), "line 1: expected the header 'OFF', found 'this'");
  ExpectLoadFails(Bad("open.obj"),
                  "open: 3 boundary edge(s) (expected a closed, manifold surface)");
  ExpectLoadFails(Bad("nonmanifold_edge.obj"),
                  "non-manifold: 1 edge(s) shared by more than two faces");
  ExpectLoadFails(Bad("pinched_vertex.off"),
                  "non-manifold: 1 vertex(es) where separate sheets touch");
  ExpectLoadFails(Bad("no_faces.obj"), "contains no faces");
  ExpectLoadFails(Bad("nan_vertex.stl"),
                  "triangle 3 corner 1 has a non-finite coordinate (NaN or infinity)");
  ExpectLoadFails(
      Bad("truncated.stl"),
      "truncated binary STL: the header declares 4 triangles (284 bytes) but the "
      "file has 134 bytes");
  ExpectLoadFails(Bad("bad_index.off"),
                  "face 3 refers to vertex 9, expected an index below 4");
  ExpectLoadFails(Bad("mesh.txt"),
                  "unsupported extension '.txt' (expected .stl, .obj, .ply or .off)");
}

TEST(MeshIo, DirectoryIsNotAMesh) {
  const fs::path dir = OutDir() / "a_folder.stl";
  fs::create_directories(dir);
  ExpectLoadFails(dir, "is a directory, expected a mesh file");
}

TEST(MeshIo, OpenMeshLoadsWhenChecksAreRelaxed) {
  // Inspection tools read any well-formed file and report on it.
  const TriangleMesh m = LoadMesh(Bad("open.obj"), {.require_closed_manifold = false});
  const MeshReport r = m.Check();
  EXPECT_EQ(r.num_faces, 3u);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_FALSE(r.IsSolid());
}

TEST(MeshIo, UnwritablePathFails) {
  const TriangleMesh box = MakeBox(Vector3(1, 1, 1));
  EXPECT_THROW(SaveMesh(box, "/nonexistent-folder/box.stl"), MeshError);
  EXPECT_THROW(SaveMesh(box, "/nonexistent-folder/box.obj"), MeshError);
  EXPECT_THROW(SaveMesh(box, OutDir() / "box.xyz"), MeshError);
}

TEST(MeshIo, ShippedMeshesAreValidSolids) {
  int seen = 0;
  for (const auto& entry :
       fs::directory_iterator(fs::path(SULCUS_SOURCE_DIR) / "resources/meshes")) {
    if (!IsSupportedMeshFile(entry.path())) continue;
    ++seen;
    EXPECT_TRUE(LoadMesh(entry.path()).Check().IsSolid()) << entry.path();
  }
  EXPECT_GT(seen, 0);
}

}  // namespace
}  // namespace sulcus
