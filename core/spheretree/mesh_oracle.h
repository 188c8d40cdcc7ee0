#pragma once
// Inside tests and distances to a closed mesh, for building and evaluating
// sphere-trees. Backed by CGAL's AABB tree; no CGAL type in this header (CGAL
// stays in .cpp files, docs/architecture.md).

#include <memory>

#include "core/geometry/mesh.h"

namespace sulcus {

class MeshOracle {
 public:
  /// Precondition: the mesh is closed (checked by the callers' validation).
  explicit MeshOracle(const TriangleMesh& mesh);
  ~MeshOracle();
  MeshOracle(const MeshOracle&) = delete;
  MeshOracle& operator=(const MeshOracle&) = delete;

  /// True when p is inside the solid (or on its boundary).
  bool Inside(const Vector3& p) const;
  /// Unsigned distance from p to the surface.
  double Distance(const Vector3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sulcus
