#include "core/geometry/mesh_io.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <mutex>
#include <sstream>

#include "core/base/files.h"
#include "core/geometry/mesh_readers.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

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

}  // namespace

bool IsSupportedMeshFile(const fs::path& path) {
  const std::string ext = Lower(path.extension().string());
  return ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".off";
}

TriangleMesh LoadMesh(const fs::path& path, const MeshLoadOptions& options) {
  const std::string name = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw MeshError(name, "no such file");
  if (fs::is_directory(path, ec))
    throw MeshError(name, "is a directory, expected a mesh file");
  // A FIFO or a device would block or never end: refused before it is opened.
  if (const fs::file_status st = fs::status(path, ec); !ec && !fs::is_regular_file(st))
    throw MeshError(name,
                    "is not a regular file (a FIFO or a device?): a mesh is read "
                    "from a file");
  if (!IsSupportedMeshFile(path)) {
    throw MeshError(name, "unsupported extension '" + path.extension().string() +
                              "' (expected .stl, .obj, .ply or .off)");
  }
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw MeshError(name, "cannot be opened for reading (check permissions)");
  }
  if (fs::file_size(path, ec) == 0) throw MeshError(name, "file is empty");
  RawMesh importer =
      ReadMeshFile(path);  // Sulcus's own readers: bounded by the file (mesh_readers.h)
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
                                std::to_string(poly.size()) +
                                " vertices, expected 3 or more");
    }
    for (int v : poly) {
      if (v < 0 || v >= nv) {
        throw MeshError(name, "face " + std::to_string(i) + " refers to vertex " +
                                  std::to_string(v) + ", expected an index below " +
                                  std::to_string(nv));
      }
    }
    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
      faces.push_back({poly[0], poly[k], poly[k + 1]});
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

void SaveMesh(const TriangleMesh& mesh, const fs::path& path,
              const MeshSaveOptions& options) {
  const std::string name = path.string();
  {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!ec && fs::exists(st) && !fs::is_regular_file(st))
      throw MeshError(name, "is not a regular file; a mesh is written to a file");
  }
  if (!IsSupportedMeshFile(path)) {
    throw MeshError(name, "unsupported extension '" + path.extension().string() +
                              "' (expected .stl, .obj, .ply or .off)");
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
  // Into memory first, then the file whole through a temporary beside it (a
  // full disk is an error and the old file survives).
  std::ostringstream bytes(options.binary ? std::ios::out | std::ios::binary
                                          : std::ios::out);
  bool ok;
  {
    std::lock_guard lock(OpenMeshMutex());
    QuietOpenMesh quiet;
    ok = OpenMesh::IO::write_mesh(om, bytes, path.extension().string(), opt, 17);
  }
  if (!ok) throw MeshError(name, "cannot be written in this format");
  try {
    AtomicFile file(path, true);
    const std::string data = bytes.str();
    file.stream().write(data.data(), static_cast<std::streamsize>(data.size()));
    file.Commit();
  } catch (const FileError& e) {
    throw MeshError(name, e.what());
  }
}

}  // namespace sulcus
