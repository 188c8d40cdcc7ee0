#include <cmath>
#include <numbers>

#include "core/anatomy/probe.h"
#include "core/anatomy/tooth.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/primitives.h"
#include "core/scene/scene.h"
#include "core/spheretree/cache.h"

namespace sulcus {

TriangleMesh MakeObjectMesh(const ObjectSpec& o) {
  switch (o.kind) {
    case ObjectSpec::Kind::kTooth: return GenerateTooth(o.fdi).mesh;
    case ObjectSpec::Kind::kMesh: return LoadMesh(o.mesh);
    case ObjectSpec::Kind::kBox:
      return MakeBox(o.size, std::max(1, static_cast<int>(std::ceil(o.size.maxCoeff() / 2))));
    case ObjectSpec::Kind::kSphere: return MakeIcosphere(o.radius_mm, 4);
    case ObjectSpec::Kind::kCylinder:
      return MakeCylinder(o.radius_mm, o.height_mm, 48, std::max(1, static_cast<int>(o.height_mm / 2)));
  }
  return {};
}

std::unique_ptr<CompiledScene> CompileScene(const SceneSpec& spec, const std::filesystem::path& cache_dir,
                                            const BuildProgress& progress) {
  auto scene = std::make_unique<CompiledScene>();
  scene->spec = spec;
  const int n = static_cast<int>(spec.objects.size());
  auto report = [&](int i, std::string_view stage, double f) {
    if (progress && !progress(stage, (i + f) / (n + 1))) throw BuildCancelled();
  };
  for (int i = 0; i < n; ++i) {
    const ObjectSpec& o = spec.objects[i];
    TriangleMesh mesh = MakeObjectMesh(o);
    report(i, o.name, 0.1);
    const BuildProgress inner = [&](std::string_view stage, double f) {
      return !progress || progress(stage, (i + 0.1 + 0.9 * f) / (n + 1));
    };
    scene->trees.push_back(LoadOrBuildSphereTree(mesh, spec.trees, cache_dir, inner));
    scene->meshes.push_back(std::move(mesh));
  }
  scene->tool_mesh = MakeProbe(spec.probe).collision_mesh;
  scene->tool_tree = LoadOrBuildSphereTree(scene->tool_mesh, SphereTreeParams{}, cache_dir,
                                           [&](std::string_view stage, double f) {
                                             return !progress || progress(stage, (n + f) / (n + 1));
                                           });
  std::vector<CollisionWorld::Object> objects;
  for (int i = 0; i < n; ++i) objects.push_back({&scene->trees[i], spec.objects[i].X_WO});
  scene->model = std::make_unique<EngineModel>(scene->tool_tree, objects, spec.haptics);
  return scene;
}

}  // namespace sulcus
