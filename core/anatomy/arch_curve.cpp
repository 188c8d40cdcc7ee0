// The arch's shapes every soft tissue is built from: lofted rings, rounded
// sections, and the arches' teeth, generated once per process.
#include <cmath>
#include <mutex>
#include <tuple>

#include "core/anatomy/soft_tissue_parts.h"

namespace sulcus::soft_tissue {
namespace {

ArchTeeth MakeTeeth(bool upper, const ArchParams& arch) {
  ArchTeeth t;
  t.placed = PlaceArch(upper, arch);
  for (const PlacedTooth& p : t.placed) {
    t.meshes.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi, {.resolution = 3}).mesh));
    const bool right = p.tooth.quadrant == 1 || p.tooth.quadrant == 4;
    t.s.push_back((right ? -1 : 1) * ArchCentreMm(upper, p.tooth.position));
  }
  return t;
}

}  // namespace

TriangleMesh Loft(const std::vector<std::vector<Vector3>>& rings) {
  const int n = static_cast<int>(rings.size()),
            m = static_cast<int>(rings.front().size());
  std::vector<Vector3> v;
  std::vector<TriangleMesh::Face> f;
  auto centroid = [&](const std::vector<Vector3>& r) {
    Vector3 c = Vector3::Zero();
    for (const Vector3& p : r) c += p;
    return Vector3(c / static_cast<double>(r.size()));
  };
  v.push_back(centroid(rings.front()));
  for (const auto& r : rings) v.insert(v.end(), r.begin(), r.end());
  v.push_back(centroid(rings.back()));
  const int last = static_cast<int>(v.size()) - 1;
  auto id = [&](int ring, int i) { return 1 + ring * m + (i % m); };
  for (int i = 0; i < m; ++i) f.push_back({0, id(0, i + 1), id(0, i)});
  for (int k = 0; k + 1 < n; ++k) {
    for (int i = 0; i < m; ++i) {
      f.push_back({id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      f.push_back({id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  }
  for (int i = 0; i < m; ++i) f.push_back({last, id(n - 1, i), id(n - 1, i + 1)});
  TriangleMesh mesh(std::move(v), std::move(f));
  if (mesh.Volume() < 0) mesh.FlipOrientation();
  return mesh;
}

std::vector<Vector3> Section(const Vector3& origin, const Vector3& u, double u0,
                             double u1, double z0, double z1, int m, double e) {
  std::vector<Vector3> ring;
  const double cu = 0.5 * (u0 + u1), hu = 0.5 * (u1 - u0), cz = 0.5 * (z0 + z1),
               hz = 0.5 * (z1 - z0);
  for (int i = 0; i < m; ++i) {
    const double a = 2 * kPi * i / m, c = std::cos(a), s = std::sin(a);
    const double x = std::copysign(std::pow(std::abs(c), 2 / e), c),
                 y = std::copysign(std::pow(std::abs(s), 2 / e), s);
    ring.push_back(origin + (cu + hu * x) * u + Vector3(0, 0, cz + hz * y));
  }
  return ring;
}

const ArchTeeth& Teeth(bool upper, const ArchParams& arch) {
  static std::mutex mutex;
  static std::map<std::tuple<bool, double, double, double, double, bool>, ArchTeeth> made;
  const auto key = std::tuple(upper, arch.k_lower, arch.k_upper,
                              arch.upper_lift_mm + arch.occlusion_mm,
                              arch.lower_setback_mm, arch.third_molars);
  std::lock_guard lock(mutex);
  auto it = made.find(key);
  if (it == made.end()) it = made.emplace(key, MakeTeeth(upper, arch)).first;
  return it->second;
}

}  // namespace sulcus::soft_tissue
