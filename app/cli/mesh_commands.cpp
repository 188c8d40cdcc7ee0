// `sulcus-cli mesh ...`: inspect, convert and generate meshes.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "app/cli/commands.h"
#include "core/base/files.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/primitives.h"
#include "core/geometry/simplify.h"

namespace sulcus::cli {
namespace {

const char* Mark(bool ok) { return ok ? "ok  " : "FAIL"; }

int MeshInfo(const std::string& file) {
  MeshLoadOptions options;
  options.require_closed_manifold = false;  // report on any readable mesh
  const TriangleMesh mesh = LoadMesh(file, options);
  const MeshReport r = mesh.Check();
  const Vector3 e = r.bounds.extent();
  std::printf("mesh %s\n", file.c_str());
  std::printf("  vertices   %zu (%zu unreferenced)\n", r.num_vertices,
              r.unreferenced_vertices);
  std::printf("  faces      %zu\n", r.num_faces);
  std::printf("  edges      %zu\n", r.num_edges);
  std::printf("  components %zu, Euler characteristic %d\n", r.components,
              r.euler_characteristic);
  std::printf("  volume     %.6g mm^3\n", r.volume);
  std::printf("  area       %.6g mm^2\n", r.area);
  std::printf("  bounds     [%.6g, %.6g, %.6g] .. [%.6g, %.6g, %.6g] mm\n",
              r.bounds.min.x(), r.bounds.min.y(), r.bounds.min.z(), r.bounds.max.x(),
              r.bounds.max.y(), r.bounds.max.z());
  std::printf("  size       %.6g x %.6g x %.6g mm\n", e.x(), e.y(), e.z());
  std::printf("checks\n");
  std::printf("  [%s] closed (watertight): %zu boundary edge(s)\n", Mark(r.closed()),
              r.boundary_edges);
  std::printf("  [%s] manifold: %zu edge(s) with 3+ faces, %zu pinched vertex(es)\n",
              Mark(r.manifold()), r.nonmanifold_edges, r.nonmanifold_vertices);
  std::printf("  [%s] consistently oriented: %zu flipped edge(s)\n", Mark(r.oriented()),
              r.misoriented_edges);
  std::printf("  [%s] normals point outward (signed volume > 0)\n", Mark(r.outward()));
  std::printf("  [%s] no degenerate faces: %zu\n", Mark(r.degenerate_faces == 0),
              r.degenerate_faces);
  std::printf("result: %s\n", r.IsSolid() ? "a valid solid: usable by the engine"
                                          : "NOT a valid solid: fix the failed checks");
  return r.IsSolid() ? 0 : 1;
}

// Simplifies `in` with Sulcus's decimation and, side by side, with OpenMesh's
// under the same rules: faces kept, time, the largest distance of the result's
// vertices from the input's planes is bounded by construction and not printed.
void MeshSimplify(const std::string& in, const std::string& out, double error_mm,
                  bool compare) {
  const TriangleMesh mesh = LoadMesh(in, {.require_closed_manifold = false});
  using Clock = std::chrono::steady_clock;
  auto timed = [&](auto&& simplify, const char* who) {
    const auto t0 = Clock::now();
    TriangleMesh m = simplify(mesh, error_mm);
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    const MeshReport r = m.Check();
    std::printf("  %-33s %7zu faces (%.1f %% of %zu), %.3f s; %s, %s\n", who,
                m.num_faces(),
                100.0 * m.num_faces() / std::max<std::size_t>(1, mesh.num_faces()),
                mesh.num_faces(), s, r.closed() ? "closed" : "open",
                r.manifold() ? "manifold" : "NOT manifold");
    return m;
  };
  std::printf("simplify %s within %.3g mm\n", in.c_str(), error_mm);
  const TriangleMesh result = timed(Simplify, "sulcus");
  if (compare) {
    const TriangleMesh fast =
        timed([](const TriangleMesh& m, double e) { return SimplifyWithOpenMesh(m, e); },
              "openmesh");
    const TriangleMesh own = timed(
        [](const TriangleMesh& m, double e) { return SimplifyWithOpenMesh(m, e, true); },
        "openmesh, its own collapse check");
    const bool same = fast.vertices() == own.vertices() && fast.faces() == own.faces();
    std::printf(
        "  OpenMesh's decimation with Sulcus's collapse check and with its own: %s\n",
        same ? "the same mesh" : "DIFFERENT meshes");
  }
  if (!out.empty()) {
    SaveMesh(result, out);
    std::printf("wrote %s\n", out.c_str());
  }
}

}  // namespace

void AddMeshCommands(CLI::App& app) {
  CLI::App* mesh = app.add_subcommand("mesh", "Inspect, convert and generate meshes");
  mesh->require_subcommand(1);

  auto file = std::make_shared<std::string>();
  CLI::App* info = mesh->add_subcommand("info",
                                        "Print counts, volume, area, bounding box and "
                                        "every check; exit 1 if a check fails");
  info->add_option("FILE", *file, "Mesh file (.stl, .obj, .ply, .off)")->required();
  info->callback([file] { Finish(MeshInfo(*file)); });

  auto in = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto binary = std::make_shared<bool>(false);
  CLI::App* convert = mesh->add_subcommand("convert", "Convert a mesh between formats");
  convert->add_option("IN", *in, "Input mesh")->required();
  convert->add_option("OUT", *out, "Output mesh; format from the extension")->required();
  convert->add_flag("--binary", *binary, "Binary STL or PLY");
  convert->callback([in, out, binary] {
    RefuseOverwrite(*out, {{*in, "the mesh being converted"}});
    const TriangleMesh mesh = LoadMesh(*in);
    SaveMesh(mesh, *out, {.binary = *binary});
    std::printf("wrote %s: %zu vertices, %zu faces\n", out->c_str(), mesh.num_vertices(),
                mesh.num_faces());
  });

  auto simplify_in = std::make_shared<std::string>();
  auto simplify_out = std::make_shared<std::string>();
  auto error_mm = std::make_shared<double>(0.02);
  auto compare = std::make_shared<bool>(false);
  CLI::App* simplify = mesh->add_subcommand(
      "simplify", "Collapse edges within a quadric error bound; time it");
  simplify->add_option("IN", *simplify_in, "Input mesh")->required();
  simplify->add_option("-o,--output", *simplify_out, "Output mesh (optional)");
  simplify->add_option("--error", *error_mm, "Largest distance from the planes, mm")
      ->check(Finite() & CLI::Range(1e-6, 10.0));
  simplify->add_flag("--compare", *compare,
                     "Also run OpenMesh's decimater under the same rules, side by side");
  simplify->callback([=] {
    if (!simplify_out->empty())
      RefuseOverwrite(*simplify_out, {{*simplify_in, "the mesh being simplified"}});
    MeshSimplify(*simplify_in, *simplify_out, *error_mm, *compare);
  });

  auto shape = std::make_shared<std::string>();
  auto size = std::make_shared<double>(10.0);
  auto detail = std::make_shared<int>(3);
  auto make_out = std::make_shared<std::string>();
  CLI::App* make = mesh->add_subcommand("make", "Write a calibration solid");
  make->add_option("SHAPE", *shape, "box, sphere, torus or cylinder")
      ->required()
      ->check(CLI::IsMember({"box", "sphere", "torus", "cylinder"}));
  make->add_option("--size", *size,
                   "Characteristic size in mm (edge, radius, ring radius), 0.01 to 1000")
      ->check(Finite() & CLI::Range(0.01, 1000.0));
  make->add_option("--detail", *detail, "Resolution (subdivisions or segments / 8)")
      ->check(CLI::Range(1, 8));
  make->add_option("-o,--output", *make_out, "Output mesh file")->required();
  make->callback([=] {
    TriangleMesh mesh;
    const double s = *size;
    const int d = *detail;
    if (*shape == "box") mesh = MakeBox(Vector3::Constant(s), d);
    if (*shape == "sphere") mesh = MakeIcosphere(s, d);
    if (*shape == "torus") mesh = MakeTorus(s, s / 3, 16 * d, 8 * d);
    if (*shape == "cylinder") mesh = MakeCylinder(s, 2 * s, 16 * d, d);
    SaveMesh(mesh, *make_out);
    std::printf("wrote %s: %s, %zu vertices, %zu faces\n", make_out->c_str(),
                shape->c_str(), mesh.num_vertices(), mesh.num_faces());
  });
}

}  // namespace sulcus::cli
