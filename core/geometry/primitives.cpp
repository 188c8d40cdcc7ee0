#include "core/geometry/primitives.h"

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace sulcus {

TriangleMesh MakeBox(const Vector3& size, int divisions) {
  const int n = std::max(1, divisions);
  std::vector<Vector3> v;
  std::vector<TriangleMesh::Face> f;
  std::map<std::array<int, 3>, int> index;  // lattice point -> vertex, shared by faces
  auto vertex = [&](std::array<int, 3> key) {
    auto [it, inserted] = index.try_emplace(key, static_cast<int>(v.size()));
    if (inserted) {
      v.emplace_back((static_cast<double>(key[0]) / n - 0.5) * size.x(),
                     (static_cast<double>(key[1]) / n - 0.5) * size.y(),
                     (static_cast<double>(key[2]) / n - 0.5) * size.z());
    }
    return it->second;
  };
  // For each axis and side: the two in-plane axes ordered so that u x w points out.
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      int u = (axis + 1) % 3, w = (axis + 2) % 3;
      if (side == 0) std::swap(u, w);
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto at = [&](int a, int b) {
            std::array<int, 3> k{};
            k[axis] = side * n;
            k[u] = a;
            k[w] = b;
            return vertex(k);
          };
          const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1),
                    d = at(i, j + 1);
          f.push_back({a, b, c});
          f.push_back({a, c, d});
        }
      }
    }
  }
  return TriangleMesh(std::move(v), std::move(f));
}

TriangleMesh MakeIcosphere(double radius, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vector3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                            {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                            {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<TriangleMesh::Face> f = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vector3& p : v) p.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = mid.try_emplace(key, static_cast<int>(v.size()));
      if (inserted) v.push_back((v[a] + v[b]).normalized());
      return it->second;
    };
    std::vector<TriangleMesh::Face> next;
    next.reserve(f.size() * 4);
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]),
                c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  for (Vector3& p : v) p *= radius;
  return TriangleMesh(std::move(v), std::move(f));
}

TriangleMesh MakeTorus(double R, double r, int nu, int nv) {
  std::vector<Vector3> v;
  std::vector<TriangleMesh::Face> f;
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * std::numbers::pi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double w = 2 * std::numbers::pi * j / nv;
      v.emplace_back((R + r * std::cos(w)) * std::cos(u),
                     (R + r * std::cos(w)) * std::sin(u), r * std::sin(w));
    }
  }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return TriangleMesh(std::move(v), std::move(f));
}

TriangleMesh MakeCylinder(double radius, double height, int segments, int stacks) {
  stacks = std::max(1, stacks);
  std::vector<Vector3> v;
  std::vector<TriangleMesh::Face> f;
  for (int k = 0; k <= stacks; ++k) {
    for (int i = 0; i < segments; ++i) {
      const double a = 2 * std::numbers::pi * i / segments;
      v.emplace_back(radius * std::cos(a), radius * std::sin(a), height * k / stacks);
    }
  }
  const int bottom = static_cast<int>(v.size());
  v.emplace_back(0, 0, 0);
  const int top = static_cast<int>(v.size());
  v.emplace_back(0, 0, height);
  auto id = [&](int k, int i) { return k * segments + (i % segments); };
  for (int k = 0; k < stacks; ++k) {
    for (int i = 0; i < segments; ++i) {
      f.push_back({id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      f.push_back({id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  }
  for (int i = 0; i < segments; ++i) {
    f.push_back({bottom, id(0, i + 1), id(0, i)});
    f.push_back({top, id(stacks, i), id(stacks, i + 1)});
  }
  return TriangleMesh(std::move(v), std::move(f));
}

TriangleMesh MakeSweep(const std::vector<Vector3>& path, const std::vector<double>& radii,
                       int segments) {
  const int n = static_cast<int>(path.size());
  std::vector<Vector3> v;
  std::vector<TriangleMesh::Face> f;
  v.push_back(path.front());  // pole at the start
  // Frames transported along the path so rings do not twist.
  Vector3 t0 = (path[1] - path[0]).normalized();
  Vector3 u = t0.unitOrthogonal();
  for (int k = 1; k + 1 < n; ++k) {
    const Vector3 t = (path[k + 1] - path[k - 1]).normalized();
    u = (u - u.dot(t) * t).normalized();  // parallel transport (projection)
    const Vector3 w = t.cross(u);
    for (int i = 0; i < segments; ++i) {
      const double a = 2 * std::numbers::pi * i / segments;
      v.push_back(path[k] + radii[k] * (std::cos(a) * u + std::sin(a) * w));
    }
  }
  const int last = static_cast<int>(v.size());
  v.push_back(path.back());  // pole at the end
  const int rings = n - 2;
  auto id = [&](int ring, int i) { return 1 + (ring - 1) * segments + (i % segments); };
  // Orientation: rings go counter-clockwise about +t, so faces below wind outward.
  for (int i = 0; i < segments; ++i) f.push_back({0, id(1, i + 1), id(1, i)});
  for (int k = 1; k < rings; ++k) {
    for (int i = 0; i < segments; ++i) {
      f.push_back({id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      f.push_back({id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  }
  for (int i = 0; i < segments; ++i) f.push_back({last, id(rings, i), id(rings, i + 1)});
  return TriangleMesh(std::move(v), std::move(f));
}

}  // namespace sulcus
