#include <cmath>
#include <numbers>

#include "core/anatomy/probe.h"
#include "core/anatomy/tooth.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/primitives.h"
#include "core/scene/scene.h"
#include "core/spheretree/cache.h"
#include "core/spheretree/tree_files.h"

#include <fstream>
#include <iterator>

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

namespace sulcus {

ScriptTarget FindScriptTarget(const CompiledScene& scene, const std::string& script, int object) {
  const auto& objects = scene.spec.objects;
  if (objects.empty()) throw std::invalid_argument("the scene has no objects to touch");
  if (object < 0) {
    object = 0;
    for (std::size_t i = 0; i < objects.size(); ++i)
      if (objects[i].kind == ObjectSpec::Kind::kTooth) {
        object = static_cast<int>(i);
        break;
      }
  }
  if (object >= static_cast<int>(objects.size())) throw std::invalid_argument("no object " + std::to_string(object));
  const ObjectSpec& o = objects[object];
  const TriangleMesh& mesh = scene.meshes[object];
  const Matrix3& R = o.X_WO.rotation();
  ScriptTarget t;
  if (o.kind == ObjectSpec::Kind::kTooth) {
    // Tooth frame: +z occlusal, +y buccal, +x mesial.
    Vector3 best = Vector3::Zero();
    double best_score = -1e300;
    const bool insert = script == "insert";
    for (const Vector3& v : mesh.vertices()) {
      const double score = insert ? (std::abs(v.z()) < 0.6 ? v.y() : -1e300) : v.z() - 0.2 * v.norm();
      if (score > best_score) {
        best_score = score;
        best = v;
      }
    }
    t.p_W = o.X_WO * best;
    t.n_W = R * (insert ? Vector3::UnitY() : Vector3::UnitZ());
    t.axis_W = R * Vector3::UnitZ();
    t.along_W = R * Vector3::UnitX();
  } else {
    Vector3 top = o.X_WO * mesh.vertices().front();
    for (const Vector3& v : mesh.vertices()) {
      const Vector3 w = o.X_WO * v;
      if (w.z() > top.z()) top = w;
    }
    t.p_W = top;
    t.n_W = Vector3::UnitZ();
  }
  return t;
}

std::uint64_t HashFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return Fnv1a(bytes.data(), bytes.size());
}

}  // namespace sulcus
