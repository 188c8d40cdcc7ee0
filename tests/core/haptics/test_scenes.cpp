#include "tests/core/haptics/test_scenes.h"

#include <cmath>

#include "core/spheretree/builder.h"

namespace sulcus::test {
namespace {

SphereTree FromLeaves(const std::vector<Vector3>& c, const std::vector<double>& r) {
  int levels = 1;
  std::size_t capacity = 1;
  while (capacity < c.size()) {
    capacity *= 8;
    ++levels;
  }
  return BuildTreeFromLeaves(c, r, std::max(levels, 2), 8);
}

}  // namespace

SphereTree MakeProbe(double length) {
  std::vector<Vector3> c = {Vector3::Zero()};
  std::vector<double> r = {0.25};
  for (double z = 0.45; z <= length; z += 0.3) {
    c.emplace_back(0, 0, z);
    r.push_back(0.4);
  }
  return FromLeaves(c, r);
}

SphereTree MakeFlatFace(int nx, int ny, double spacing, double radius) {
  std::vector<Vector3> c;
  std::vector<double> r;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      c.emplace_back((i - (nx - 1) / 2.0) * spacing, (j - (ny - 1) / 2.0) * spacing,
                     radius);
      r.push_back(radius);
    }
  }
  return FromLeaves(c, r);
}

SphereTree MakeBlock(double hx, double hy, double z0, double z1, double spacing,
                     double radius) {
  std::vector<Vector3> c;
  std::vector<double> r;
  const int nx = static_cast<int>(std::round(2 * hx / spacing)),
            ny = static_cast<int>(std::round(2 * hy / spacing));
  const int nz = std::max(0, static_cast<int>(std::round((z1 - z0) / spacing)));
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      for (int k = 0; k <= nz; ++k) {
        c.emplace_back(-hx + i * spacing, -hy + j * spacing, z0 + k * spacing);
        r.push_back(radius);
      }
    }
  }
  return FromLeaves(c, r);
}

void Scene::Add(SphereTree tree, const RigidTransform& X_WO) {
  trees.push_back(std::make_unique<SphereTree>(std::move(tree)));
  objects.push_back({trees.back().get(), X_WO});
}

std::unique_ptr<EngineModel> Scene::Model(const EngineParams& params) const {
  return std::make_unique<EngineModel>(*tool, objects, params);
}

}  // namespace sulcus::test
