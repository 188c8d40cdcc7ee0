// `sulcus-cli scene ...`: validate and export scene files.

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "app/cli/commands.h"
#include "core/base/files.h"
#include "core/geometry/mesh_io.h"
#include "core/scene/scene.h"
#include "core/spheretree/cache.h"

namespace sulcus::cli {

void AddSceneCommands(CLI::App& app) {
  CLI::App* scene = app.add_subcommand("scene", "Validate and export scene files");
  scene->require_subcommand(1);
  auto file = std::make_shared<std::string>();
  CLI::App* validate =
      scene->add_subcommand("validate",
                            "Check a scene file; print every error as file:line:column: "
                            "message (exit 1 on error)");
  validate->add_option("FILE", *file, "Scene file (.yaml)")->required();
  validate->callback([file] {
    try {
      const SceneSpec s = LoadSceneSpec(*file);
      std::string effects;
      for (Effect e : s.effects)
        effects += std::string(effects.empty() ? "" : ", ") + ToString(e);
      std::printf("%s: valid scene '%s': %zu objects, probe %s, effects: %s\n",
                  file->c_str(), s.name.c_str(), s.objects.size(), s.probe.c_str(),
                  effects.c_str());
    } catch (const LoadError& e) {
      std::fprintf(stderr, "%s\n%s\n", e.what(), e.Summary().c_str());
      Finish(1);
    }
  });

  auto build_file = std::make_shared<std::string>();
  auto cache = std::make_shared<std::string>();
  CLI::App* build =
      scene->add_subcommand("build",
                            "Generate every mesh and sphere-tree of a scene (through the "
                            "cache) and say how long each stage took");
  build->add_option("FILE", *build_file, "Scene file (.yaml)")->required();
  build->add_option("--cache", *cache,
                    "Cache folder (default: $SULCUS_CACHE_DIR or ~/.cache/sulcus)");
  auto build_drawn = std::make_shared<bool>(false);
  build->add_flag("--drawn", *build_drawn,
                  "Also build the gingiva as the window draws it (the sulcus closed "
                  "round the teeth), as the window does "
                  "after the scene, and say how long it took");
  build->callback([=] {
    const SceneSpec s = LoadSceneSpec(*build_file);
    const std::filesystem::path dir =
        cache->empty() ? DefaultCacheDir() : std::filesystem::path(*cache);
    int last = -1;
    const auto compiled = CompileScene(s, dir,
                                       [&](std::string_view stage, double f) {
                                         const int pct = static_cast<int>(f * 100);
                                         if (pct != last) {
                                           last = pct;
                                           std::fprintf(stderr, "\r[%3d%%] %-40.40s", pct,
                                                        std::string(stage).c_str());
                                         }
                                         return true;
                                       },
                                       {.seen_gingiva = *build_drawn});
    std::fprintf(stderr, "\n");
    std::size_t spheres = 0, triangles = 0;
    for (const SphereTree& t : compiled->trees) spheres += t.size();
    for (const TriangleMesh& m : compiled->meshes) triangles += m.num_faces();
    // The stages as a window or a lesson meets them (CompileScene, on all cores).
    std::printf(
        "%s: %zu objects, %zu triangles; meshes %.2f s, sphere-trees and model %.2f s, "
        "total %.2f s (%zu spheres); cache %s\n",
        build_file->c_str(), s.objects.size(), triangles, compiled->mesh_seconds,
        compiled->tree_seconds, compiled->mesh_seconds + compiled->tree_seconds, spheres,
        dir.c_str());
    // What was built (the rest came from the cache): a generated case rebuilds
    // only what its pockets change.
    std::string built;
    int hits = 0;
    for (std::size_t i = 0; i < compiled->spec.objects.size(); ++i) {
      if (!compiled->tree_built[i]) {
        ++hits;
        continue;
      }
      char line[160];
      std::snprintf(line, sizeof line, "%s%s (%zu leaves, %.2f s)",
                    built.empty() ? "" : ", ", compiled->spec.objects[i].name.c_str(),
                    compiled->trees[i].NumLeaves(), compiled->object_tree_seconds[i]);
      built += line;
    }
    std::printf("sphere-trees built: %s; %d from the cache\n",
                built.empty() ? "none" : built.c_str(), hits);
    // The felt surface: leaves cut by planes, and of them those on a concave
    // crease (cut by the union of their planes; core/collision/leaf_planes.h).
    std::size_t leaves = 0, clipped = 0, creases = 0;
    for (std::size_t i = 0; i < compiled->planes.size(); ++i) {
      leaves += compiled->trees[i].NumLeaves();
      clipped += static_cast<std::size_t>(compiled->planes[i].count());
      for (const std::uint8_t c : compiled->planes[i].concave) creases += c != 0;
    }
    if (compiled->spec.leaf_planes)
      std::printf(
          "leaf planes: %zu of %zu leaves cut by planes, %zu of them on a concave "
          "crease\n",
          clipped, leaves, creases);
    if (*build_drawn) {
      std::size_t shares = 0, seen_triangles = 0;
      for (const TriangleMesh& m : compiled->seen.meshes) {
        shares += m.num_faces() > 0;
        seen_triangles += m.num_faces();
      }
      std::printf(
          "the gingiva as drawn: %zu shares, %zu triangles (built with the trees)\n",
          shares, seen_triangles);
    }
    std::printf("scene ready in %.2f s\n",
                compiled->mesh_seconds + compiled->tree_seconds);
  });

  auto export_file = std::make_shared<std::string>();
  auto dir = std::make_shared<std::string>();
  CLI::App* exp = scene->add_subcommand(
      "export", "Write every object's mesh, placed in the world frame, as STL");
  exp->add_option("FILE", *export_file, "Scene file (.yaml)")->required();
  exp->add_option("-o,--output", *dir, "Folder for the meshes")->required();
  auto export_drawn = std::make_shared<bool>(false);
  exp->add_flag("--drawn", *export_drawn,
                "The gingiva as the window draws it (the sulcus closed round the teeth) "
                "instead of the surface the probe feels");
  exp->callback([=] {
    const SceneSpec s = LoadSceneSpec(*export_file);
    // Every object's file name first: two objects whose names differ only in
    // what a file name cannot hold ("a b" and "a-b") would write one file.
    std::vector<std::filesystem::path> outs;
    std::map<std::string, std::string> taken;  // file name -> object
    for (const ObjectSpec& o : s.objects) {
      std::string name = o.name;
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      if (const auto it = taken.find(name); it != taken.end())
        throw FileError("objects '" + it->second + "' and '" + o.name +
                        "' would both be written to " + name +
                        ".stl; rename one of them in " + *export_file +
                        " (nothing was written)");
      taken[name] = o.name;
      outs.push_back(std::filesystem::path(*dir) / (name + ".stl"));
    }
    std::vector<KeptFile> inputs = {{*export_file, "the scene file"}};
    for (const ObjectSpec& o : s.objects)
      if (!o.mesh.empty()) inputs.push_back({o.mesh, "a mesh the scene reads"});
    for (const std::filesystem::path& out : outs) RefuseOverwrite(out, inputs);
    std::filesystem::create_directories(*dir);
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const ObjectSpec& o = s.objects[i];
      TriangleMesh mesh =
          MakeObjectMeshCached(o, DefaultCacheDir(), nullptr, *export_drawn);
      mesh.Transform(o.X_WO.rotation(), o.X_WO.translation());
      const std::filesystem::path& out = outs[i];
      SaveMesh(mesh, out, {.binary = true});
      std::printf("wrote %s (%zu triangles)\n", out.c_str(), mesh.num_faces());
    }
  });
}

}  // namespace sulcus::cli
