#include "core/geometry/mesh_io.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <cstdint>
#include <mutex>
#include <sstream>

namespace sulcus {
namespace {

namespace fs = std::filesystem;
using OpenMesh::IO::BaseImporter;
using OpenMesh::VertexHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::EdgeHandle;

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// Collects exactly what a reader declares: vertices and polygons by index. Unlike
// OpenMesh's own mesh importer it never "repairs" a non-manifold face by
// duplicating vertices, so the checks see the file as it is.
class RawImporter final : public BaseImporter {
 public:
  std::vector<Vector3> points;
  std::vector<std::vector<int>> polygons;

  VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
    return add_vertex(OpenMesh::Vec3d(p[0], p[1], p[2]));
  }
  VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
    points.emplace_back(p[0], p[1], p[2]);
    return VertexHandle(static_cast<int>(points.size()) - 1);
  }
  VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3d(0, 0, 0)); }
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(const VHandles& indices) override {
    std::vector<int> poly;
    poly.reserve(indices.size());
    for (const auto& vh : indices) poly.push_back(vh.idx());
    polygons.push_back(std::move(poly));
    return FaceHandle(static_cast<int>(polygons.size()) - 1);
  }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_point(VertexHandle vh, const OpenMesh::Vec3f& p) override {
    if (vh.idx() >= 0 && static_cast<std::size_t>(vh.idx()) < points.size()) {
      points[vh.idx()] = Vector3(p[0], p[1], p[2]);
    }
  }
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  bool is_triangle_mesh() const override { return false; }
  size_t n_vertices() const override { return points.size(); }
  size_t n_faces() const override { return polygons.size(); }
  size_t n_edges() const override { return 0; }
};

// OpenMesh reports through global streams; keep them quiet (we report ourselves)
// and serialise its use, since its IOManager is a process-wide singleton.
std::mutex& OpenMeshMutex() {
  static std::mutex m;
  return m;
}

struct QuietOpenMesh {
  QuietOpenMesh() {
    omerr().disable();
    omlog().disable();
  }
  ~QuietOpenMesh() {
    omerr().enable();
    omlog().enable();
  }
};

std::string Describe(const MeshReport& r) {
  std::ostringstream s;
  if (r.boundary_edges) s << "open: " << r.boundary_edges << " boundary edge(s)";
  if (r.nonmanifold_edges) {
    s << (s.tellp() > 0 ? "; " : "") << "non-manifold: " << r.nonmanifold_edges
      << " edge(s) shared by more than two faces";
  }
  if (r.nonmanifold_vertices) {
    s << (s.tellp() > 0 ? "; " : "") << "non-manifold: " << r.nonmanifold_vertices
      << " vertex(es) where separate sheets touch";
  }
  return s.str();
}

// OpenMesh's STL reader merges equal points through an ordered map, where a NaN
// compares equal to anything and vanishes, and it accepts a short file. Binary STL
// is simple enough to check first: size against the declared count, and every
// coordinate finite. An ASCII STL starts with "solid" and is left to the reader.
void CheckBinaryStl(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char header[80] = {};
  in.read(header, sizeof header);
  if (in.gcount() >= 5 && std::string(header, 5) == "solid") {
    // "solid" may still begin a binary header; the size test below tells.
    const auto size = fs::file_size(path);
    std::uint32_t n = 0;
    if (size < 84 || !in.read(reinterpret_cast<char*>(&n), 4) || 84 + 50ull * n != size) return;
  } else {
    in.clear();
  }
  in.seekg(80);
  std::uint32_t count = 0;
  if (!in.read(reinterpret_cast<char*>(&count), 4)) {
    throw MeshError(path.string(), "truncated binary STL: no triangle count after the 80-byte header");
  }
  const std::uintmax_t expected = 84 + 50ull * count, size = fs::file_size(path);
  if (size < expected) {
    throw MeshError(path.string(), "truncated binary STL: the header declares " +
                                       std::to_string(count) + " triangles (" +
                                       std::to_string(expected) + " bytes) but the file has " +
                                       std::to_string(size) + " bytes");
  }
  for (std::uint32_t t = 0; t < count; ++t) {
    float record[12];
    std::uint16_t attribute;
    in.read(reinterpret_cast<char*>(record), sizeof record);
    in.read(reinterpret_cast<char*>(&attribute), sizeof attribute);
    for (int k = 3; k < 12; ++k) {  // skip the stored normal; check the corners
      if (!std::isfinite(record[k])) {
        throw MeshError(path.string(), "triangle " + std::to_string(t) + " corner " +
                                           std::to_string((k - 3) / 3) +
                                           " has a non-finite coordinate (NaN or infinity)");
      }
    }
  }
}

}  // namespace

bool IsSupportedMeshFile(const fs::path& path) {
  const std::string ext = Lower(path.extension().string());
  return ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".off";
}

TriangleMesh LoadMesh(const fs::path& path, const MeshLoadOptions& options) {
  const std::string name = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw MeshError(name, "no such file");
  if (fs::is_directory(path, ec)) throw MeshError(name, "is a directory, expected a mesh file");
  if (!IsSupportedMeshFile(path)) {
    throw MeshError(name, "unsupported extension '" + path.extension().string() +
                              "' (expected .stl, .obj, .ply or .off)");
  }
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw MeshError(name, "cannot be opened for reading (check permissions)");
  }
  if (fs::file_size(path, ec) == 0) throw MeshError(name, "file is empty");
  if (Lower(path.extension().string()) == ".stl") CheckBinaryStl(path);

  RawImporter importer;
  bool ok;
  {
    std::lock_guard lock(OpenMeshMutex());
    QuietOpenMesh quiet;
    OpenMesh::IO::Options opt;
    // OpenMesh picks its reader by extension, lower case only.
    ok = OpenMesh::IO::IOManager().read(name, importer, opt);
  }
  if (!ok) {
    const std::string ext = Lower(path.extension().string()).substr(1);
    throw MeshError(name, "not a readable " + ext + " file (the " + ext +
                              " reader rejected it)");
  }
  if (importer.polygons.empty()) throw MeshError(name, "contains no faces");

  for (std::size_t i = 0; i < importer.points.size(); ++i) {
    if (!importer.points[i].allFinite()) {
      throw MeshError(name, "vertex " + std::to_string(i) +
                                " has a non-finite coordinate (NaN or infinity)");
    }
  }
  // Polygons with more than three sides (OBJ, OFF, PLY) become fans.
  std::vector<TriangleMesh::Face> faces;
  faces.reserve(importer.polygons.size());
  const int nv = static_cast<int>(importer.points.size());
  for (std::size_t i = 0; i < importer.polygons.size(); ++i) {
    const auto& poly = importer.polygons[i];
    if (poly.size() < 3) {
      throw MeshError(name, "face " + std::to_string(i) + " has " +
                                std::to_string(poly.size()) + " vertices, expected 3 or more");
    }
    for (int v : poly) {
      if (v < 0 || v >= nv) {
        throw MeshError(name, "face " + std::to_string(i) + " refers to vertex " +
                                  std::to_string(v) + ", expected an index below " +
                                  std::to_string(nv));
      }
    }
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) faces.push_back({poly[0], poly[k], poly[k + 1]});
  }
  TriangleMesh mesh(std::move(importer.points), std::move(faces));
  if (options.require_closed_manifold) {
    const MeshReport report = mesh.Check();
    if (!report.closed() || !report.manifold()) {
      throw MeshError(name, Describe(report) + " (expected a closed, manifold surface)");
    }
  }
  return mesh;
}

void SaveMesh(const TriangleMesh& mesh, const fs::path& path, const MeshSaveOptions& options) {
  const std::string name = path.string();
  if (!IsSupportedMeshFile(path)) {
    throw MeshError(name, "unsupported extension '" + path.extension().string() +
                              "' (expected .stl, .obj, .ply or .off)");
  }
  {
    // OpenMesh reports success for some formats even when the file cannot be created.
    std::ofstream probe(path, std::ios::binary | std::ios::trunc);
    if (!probe) throw MeshError(name, "cannot be opened for writing (check the folder exists and is writable)");
  }
  using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
  OmMesh om;
  std::vector<OmMesh::VertexHandle> vh;
  vh.reserve(mesh.num_vertices());
  for (const Vector3& v : mesh.vertices()) {
    vh.push_back(om.add_vertex(OmMesh::Point(v.x(), v.y(), v.z())));
  }
  for (const auto& f : mesh.faces()) {
    if (!om.add_face(vh[f[0]], vh[f[1]], vh[f[2]]).is_valid()) {
      throw MeshError(name, "cannot be written: the mesh is not manifold");
    }
  }
  OpenMesh::IO::Options opt;
  if (options.binary) opt += OpenMesh::IO::Options::Binary;
  bool ok;
  {
    std::lock_guard lock(OpenMeshMutex());
    QuietOpenMesh quiet;
    ok = OpenMesh::IO::write_mesh(om, name, opt, 17);
  }
  if (!ok) throw MeshError(name, "cannot be written (check the folder exists and is writable)");
}

}  // namespace sulcus
