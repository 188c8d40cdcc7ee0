// `sulcus-cli anatomy ...`: generate procedural dental anatomy.

#include <cstdio>
#include <memory>
#include <string>

#include "app/cli/commands.h"
#include "core/anatomy/tooth.h"
#include "core/geometry/mesh_io.h"

namespace sulcus::cli {

void AddAnatomyCommands(CLI::App& app) {
  CLI::App* anatomy = app.add_subcommand("anatomy", "Generate procedural dental anatomy");
  anatomy->require_subcommand(1);
  auto fdi = std::make_shared<int>(36);
  auto out = std::make_shared<std::string>();
  auto resolution = std::make_shared<int>(ToothParams{}.resolution);
  CLI::App* tooth = anatomy->add_subcommand(
      "tooth", "Write one tooth by FDI number (11 to 48), in its tooth frame");
  tooth->add_option("FDI", *fdi, "FDI number, e.g. 36 (lower left first molar)")
      ->required();
  tooth->add_option("-o,--output", *out, "Mesh file (.stl, .obj, .ply, .off)")
      ->required();
  tooth
      ->add_option("--resolution", *resolution,
                   "Icosahedron subdivisions (4: 5,120 triangles, 5: 20,480)")
      ->capture_default_str();
  tooth->callback([=] {
    const ToothModel m = GenerateTooth(*fdi, {.resolution = *resolution});
    SaveMesh(m.mesh, *out, {.binary = true});
    const MeshReport r = m.mesh.Check();
    std::printf("wrote %s: FDI %d, %s %s, %d root(s), %zu triangles, %.1f mm^3, %s\n",
                out->c_str(), *fdi, m.tooth.upper() ? "upper" : "lower",
                ToString(m.tooth.type()).c_str(), m.dimensions.roots, m.mesh.num_faces(),
                r.volume, r.IsSolid() ? "a valid solid" : "NOT a valid solid");
  });
}

}  // namespace sulcus::cli
