// Surface pieces: the flat sub-triangles the sphere-tree builder covers.
#include <algorithm>
#include <cmath>

#include "core/spheretree/builder_stages.h"

namespace sulcus::tree_build {

Piece MakePiece(const Vector3& a, const Vector3& b, const Vector3& c) {
  Piece p;
  p.v[0] = a;
  p.v[1] = b;
  p.v[2] = c;
  p.centroid = (a + b + c) / 3.0;
  return p;
}

std::vector<Piece> Subdivide(const TriangleMesh& mesh, double h,
                             std::vector<Vector3>* normals, double orientation) {
  std::vector<Piece> pieces;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces()[f];
    const Vector3 a = mesh.vertices()[face[0]], b = mesh.vertices()[face[1]],
                  c = mesh.vertices()[face[2]];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / h)));
    const Vector3 normal = orientation * mesh.FaceNormal(f);
    auto at = [&](int i, int j) {
      return Vector3(a + (b - a) * i / n + (c - a) * j / n);
    };
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        pieces.push_back(MakePiece(at(i, j), at(i + 1, j), at(i, j + 1)));
        normals->push_back(normal);
        if (i + j + 1 < n) {
          pieces.push_back(MakePiece(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)));
          normals->push_back(normal);
        }
      }
    }
  }
  return pieces;
}

}  // namespace sulcus::tree_build
