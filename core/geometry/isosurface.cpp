#include "core/geometry/isosurface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

namespace sulcus {

TriangleMesh Isosurface(const std::function<double(const Vector3&)>& f, const Aabb& box,
                        double cell) {
  if (!(cell > 0)) throw std::invalid_argument("isosurface: the cell must be positive");
  if (box.empty()) return {};
  // One cell beyond the box on every side, held outside, so the surface closes.
  const Vector3 lo = box.min - Vector3::Constant(cell);
  std::array<int, 3> n{};
  for (int a = 0; a < 3; ++a)
    n[a] = static_cast<int>(std::ceil((box.max[a] - box.min[a]) / cell)) + 3;
  const std::int64_t points = static_cast<std::int64_t>(n[0]) * n[1] * n[2];
  if (points > (std::int64_t{1} << 24))
    throw std::invalid_argument("isosurface: a grid of " + std::to_string(points) +
                                " points is too fine");
  auto index = [&](int i, int j, int k) {
    return (static_cast<std::int64_t>(k) * n[1] + j) * n[0] + i;
  };
  auto position = [&](std::int64_t id) {
    const int i = static_cast<int>(id % n[0]), j = static_cast<int>((id / n[0]) % n[1]),
              k = static_cast<int>(id / (static_cast<std::int64_t>(n[0]) * n[1]));
    return Vector3(lo.x() + i * cell, lo.y() + j * cell, lo.z() + k * cell);
  };
  const double nudge = 1e-3 * cell;
  std::vector<double> value(static_cast<std::size_t>(points));
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const bool border =
            i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        double v = border ? cell : f(position(index(i, j, k)));
        if (!(v < -nudge)) v = std::max(v, nudge);  // NaN and near-zero count as outside
        value[static_cast<std::size_t>(index(i, j, k))] = v;
      }

  std::vector<Vector3> vertices;
  std::vector<TriangleMesh::Face> faces;
  std::unordered_map<std::uint64_t, std::int32_t> on_edge;
  auto crossing = [&](std::int64_t a, std::int64_t b) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key =
        static_cast<std::uint64_t>(a) << 32 | static_cast<std::uint64_t>(b);
    auto [it, added] =
        on_edge.try_emplace(key, static_cast<std::int32_t>(vertices.size()));
    if (added) {
      const double fa = value[static_cast<std::size_t>(a)],
                   fb = value[static_cast<std::size_t>(b)];
      const double t = fa / (fa - fb);
      vertices.push_back(position(a) + t * (position(b) - position(a)));
    }
    return it->second;
  };
  // Adds triangle (p, q, r) facing from the inside point `in` toward `out`.
  auto emit = [&](std::int32_t p, std::int32_t q, std::int32_t r, std::int64_t in,
                  std::int64_t out) {
    const Vector3 normal = (vertices[q] - vertices[p]).cross(vertices[r] - vertices[p]);
    if (normal.dot(position(out) - position(in)) < 0) std::swap(q, r);
    faces.push_back({p, q, r});
  };
  // The six tetrahedra of a cube: corner 0 to corner 7 through each order of
  // the three axis steps.
  static constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                        {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i) {
        for (const auto& order : kOrders) {
          std::array<int, 3> c = {i, j, k};
          std::array<std::int64_t, 4> t{};
          t[0] = index(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[order[s]];
            t[s + 1] = index(c[0], c[1], c[2]);
          }
          std::array<std::int64_t, 4> in{}, out{};
          int ni = 0, no = 0;
          for (std::int64_t p : t)
            (value[static_cast<std::size_t>(p)] < 0 ? in[ni++] : out[no++]) = p;
          if (ni == 0 || no == 0) continue;
          if (ni == 1) {
            emit(crossing(in[0], out[0]), crossing(in[0], out[1]),
                 crossing(in[0], out[2]), in[0], out[0]);
          } else if (ni == 3) {
            emit(crossing(in[0], out[0]), crossing(in[1], out[0]),
                 crossing(in[2], out[0]), in[0], out[0]);
          } else {
            // A quad: in0-out0, in0-out1, in1-out1, in1-out0 in order around it.
            const std::int32_t a = crossing(in[0], out[0]), b = crossing(in[0], out[1]),
                               c2 = crossing(in[1], out[1]), d = crossing(in[1], out[0]);
            emit(a, b, c2, in[0], out[0]);
            emit(a, c2, d, in[1], out[1]);
          }
        }
      }
  return TriangleMesh(std::move(vertices), std::move(faces));
}

}  // namespace sulcus
