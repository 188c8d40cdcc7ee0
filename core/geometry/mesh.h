#pragma once
// A triangle mesh as flat arrays (what the rest of the engine consumes), with the
// checks a mesh must pass before anything is built from it. File I/O and the
// half-edge checks go through OpenMesh in mesh_io.cpp and mesh.cpp; no OpenMesh
// type appears in this header.

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/types.h"

namespace sulcus {

/// Axis-aligned box; empty when min > max.
struct Aabb {
  Vector3 min = Vector3::Constant(std::numeric_limits<double>::infinity());
  Vector3 max = Vector3::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const { return (min.array() > max.array()).any(); }
  Vector3 extent() const { return empty() ? Vector3::Zero() : Vector3(max - min); }
  double LargestExtent() const { return extent().maxCoeff(); }
  void Extend(const Vector3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

/// Results of TriangleMesh::Check(). A mesh fit for sphere-tree building is
/// `IsSolid()`: closed, edge-manifold and vertex-manifold, consistently oriented,
/// with outward normals and no degenerate faces.
struct MeshReport {
  std::size_t num_vertices = 0;
  std::size_t num_faces = 0;
  std::size_t num_edges = 0;
  std::size_t boundary_edges = 0;        // used by one face: the mesh is open
  std::size_t nonmanifold_edges = 0;     // used by three or more faces
  std::size_t nonmanifold_vertices = 0;  // fan of faces around it is not one disk
  std::size_t misoriented_edges = 0;     // two faces traverse it in the same direction
  std::size_t degenerate_faces = 0;      // repeated index or (near) zero area
  std::size_t unreferenced_vertices = 0;
  std::size_t components = 0;    // connected through shared edges
  int euler_characteristic = 0;  // V - E + F; 2 per closed genus-0 component
  double volume = 0;             // signed, mm^3; > 0 when normals point out
  double area = 0;               // mm^2
  Aabb bounds;

  bool closed() const { return boundary_edges == 0; }
  bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  bool oriented() const { return misoriented_edges == 0; }
  bool outward() const { return volume > 0; }
  bool IsSolid() const {
    return num_faces > 0 && closed() && manifold() && oriented() && outward() &&
           degenerate_faces == 0;
  }
};

/// A triangle soup with shared vertices. Faces are counter-clockwise seen from
/// outside (normals point out of the solid).
class TriangleMesh {
 public:
  using Face = std::array<std::int32_t, 3>;

  TriangleMesh() = default;
  /// Precondition: every index is in [0, vertices.size()).
  TriangleMesh(std::vector<Vector3> vertices, std::vector<Face> faces);

  const std::vector<Vector3>& vertices() const { return vertices_; }
  const std::vector<Face>& faces() const { return faces_; }
  std::size_t num_vertices() const { return vertices_.size(); }
  std::size_t num_faces() const { return faces_.size(); }

  Aabb Bounds() const;
  /// Signed volume by the divergence theorem; positive for an outward closed mesh.
  double Volume() const;
  double SurfaceArea() const;
  /// Unit normal of face f (zero for a degenerate face).
  Vector3 FaceNormal(std::size_t f) const;
  /// Per vertex, the area-weighted sum of its faces' normals, not normalised
  /// (zero for a vertex no face uses).
  std::vector<Vector3> VertexNormalSums() const;
  /// Every structural check; O(F log F).
  MeshReport Check() const;

  /// Applies p -> R p + t to every vertex.
  void Transform(const Matrix3& R, const Vector3& t);
  /// Reverses every face (turns inward normals outward).
  void FlipOrientation();

 private:
  std::vector<Vector3> vertices_;
  std::vector<Face> faces_;
};

/// Error raised for a mesh file that cannot be used. what() reads
/// "FILE: what is wrong (what was expected)".
class MeshError : public std::runtime_error {
 public:
  MeshError(const std::string& path, const std::string& message)
      : std::runtime_error(path + ": " + message), path_(path) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace sulcus
