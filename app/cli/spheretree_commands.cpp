// `sulcus-cli spheretree ...`: build sphere-trees and measure their fit.

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "app/cli/commands.h"
#include "core/geometry/mesh_io.h"
#include "core/spheretree/builder.h"
#include "core/spheretree/metrics.h"
#include "core/spheretree/octree_builder.h"
#include "core/spheretree/tree_files.h"

namespace sulcus::cli {
namespace {

// A one-line progress bar on a terminal; stage changes only when piped.
BuildProgress ProgressBar() {
  const bool tty = isatty(fileno(stderr));
  auto last_stage = std::make_shared<std::string>();
  return [tty, last_stage](std::string_view stage, double f) {
    if (tty) {
      const int width = 30, filled = static_cast<int>(f * width + 0.5);
      std::fprintf(stderr, "\r  [%-*s] %3d%%  %-28.*s", width,
                   std::string(filled, '#').c_str(), static_cast<int>(f * 100 + 0.5),
                   static_cast<int>(stage.size()), stage.data());
      if (f >= 1.0) std::fprintf(stderr, "\n");
    } else if (*last_stage != stage) {
      *last_stage = stage;
      std::fprintf(stderr, "  %3d%% %.*s\n", static_cast<int>(f * 100 + 0.5),
                   static_cast<int>(stage.size()), stage.data());
    }
    return true;
  };
}

void PrintMetrics(const TreeMetrics& m) {
  const double e = m.largest_extent_mm;
  std::printf(
      "fit (largest extent %.4g mm, volume %.4g mm^3, %zu surface samples, %d points per "
      "sphere)\n",
      e, m.volume_mm3, m.surface_samples, EvalParams{}.points_per_sphere);
  std::printf(
      "  level spheres  protrusion max        mean                 coverage    overlap  "
      "excess vol  children in parent\n");
  for (const LevelMetrics& l : m.levels) {
    std::printf(
        "  %5d %7zu  %8.4f mm %6.3f%%  %8.4f mm %6.3f%%  %9.5f%%  %7.2f  %9.3f%%  "
        "%8.2f%%\n",
        l.level, l.spheres, l.protrusion_max_mm, 100 * l.protrusion_max_mm / e,
        l.protrusion_mean_mm, 100 * l.protrusion_mean_mm / e, 100 * l.coverage, l.overlap,
        100 * l.excess_volume, 100 * l.children_inside);
  }
}

}  // namespace

void AddSphereTreeCommands(CLI::App& app) {
  CLI::App* st =
      app.add_subcommand("spheretree", "Build sphere-trees and measure their fit");
  st->require_subcommand(1);

  struct BuildArgs {
    std::string mesh, out;
    SphereTreeParams params;
    bool eval = false;
    std::string method = "medial";
  };
  auto b = std::make_shared<BuildArgs>();
  CLI::App* build = st->add_subcommand("build", "Build a sphere-tree from a closed mesh");
  build->add_option("MESH", b->mesh, "Closed mesh (.stl, .obj, .ply, .off)")->required();
  build->add_option("-o,--output", b->out, "Tree file (.sph, Bradshaw's format)")
      ->required();
  build->add_option("--levels", b->params.levels, "Levels, counting the root")
      ->capture_default_str();
  build->add_option("--branch", b->params.branching, "Children per node")
      ->capture_default_str();
  build->add_option("--leaves", b->params.leaves, "Leaf budget")->capture_default_str();
  build->add_option(
      "--target-error", b->params.target_error_mm,
      "Instead of a budget: the fewest leaves protruding at most this many mm");
  build
      ->add_option("--spend", b->params.spend,
                   "mean: trade leaves to lower the mean protrusion, none past the worst "
                   "(default); worst: the "
                   "min-max cover only (what tools use)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, SphereTreeParams::Spend>{
          {SpendName(SphereTreeParams::Spend::kMean), SphereTreeParams::Spend::kMean},
          {SpendName(SphereTreeParams::Spend::kWorst),
           SphereTreeParams::Spend::kWorst}}));
  build
      ->add_option("--tighten-passes", b->params.tighten_passes,
                   "Times the leaves are tightened after the cover (worst, target "
                   "error; mean tightens once before trading)")
      ->capture_default_str()
      ->check(CLI::Range(1, 8));
  build
      ->add_option("--samples", b->params.samples,
                   "Surface samples (0: automatic; at most 10,000,000)")
      ->check(WholeNumber() & CLI::Range(0, 10000000));
  build->add_option("--seed", b->params.seed, "Random seed")
      ->capture_default_str()
      ->check(WholeNumber());
  build->add_flag("--eval", b->eval, "Also print the fit metrics");
  build
      ->add_option("--method", b->method,
                   "medial (Sulcus) or octree (the straightforward reference)")
      ->check(CLI::IsMember({"medial", "octree"}))
      ->capture_default_str();
  build->callback([b] {
    const TriangleMesh mesh = LoadMesh(b->mesh);
    std::printf("building %s: %zu faces, %s\n", b->mesh.c_str(), mesh.num_faces(),
                b->params.ToString().c_str());
    std::fflush(stdout);
    SphereTreeBuildStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    const SphereTree tree = b->method == "octree"
                                ? BuildOctreeSphereTree(mesh, b->params.levels)
                                : BuildSphereTree(mesh, b->params, ProgressBar(), &stats);
    stats.seconds_total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    WriteSph(tree, b->out);
    std::printf("wrote %s: %zu nodes, %zu leaves\n", b->out.c_str(), tree.size(),
                tree.NumLeaves());
    std::printf("  time %.2f s (medial axis %.2f s, cover %.2f s, hierarchy %.2f s)\n",
                stats.seconds_total, stats.seconds_medial, stats.seconds_cover,
                stats.seconds_hierarchy);
    std::printf("  %zu surface pieces, %zu medial candidates, protrusion bound %.4g mm\n",
                stats.surface_pieces, stats.medial_candidates, stats.error_bound_mm);
    for (int l = 0; l < tree.levels; ++l) {
      std::printf("  level %d: %zu spheres\n", l, tree.NodesOnLevel(l).size());
    }
    if (b->eval) PrintMetrics(EvaluateSphereTree(mesh, tree));
  });

  auto mesh = std::make_shared<std::string>();
  auto file = std::make_shared<std::string>();
  auto offset = std::make_shared<std::vector<double>>();
  CLI::App* eval =
      st->add_subcommand("eval", "Measure how well a tree fits its mesh, per level");
  eval->add_option("MESH", *mesh, "The mesh the tree was built from")->required();
  eval->add_option("TREE", *file, "Tree file (.sph)")->required();
  eval->add_option(
          "--offset", *offset,
          "Add X Y Z to every centre (for files from a toolkit that recentred the mesh)")
      ->expected(3);
  eval->callback([=] {
    const TriangleMesh m = LoadMesh(*mesh);
    const Vector3 shift = offset->size() == 3
                              ? Vector3((*offset)[0], (*offset)[1], (*offset)[2])
                              : Vector3::Zero();
    const SphereTree tree = ReadSph(*file, shift);
    std::printf("tree %s: %d levels, branch %d, %zu nodes, %zu leaves\n", file->c_str(),
                tree.levels, tree.branching, tree.size(), tree.NumLeaves());
    PrintMetrics(EvaluateSphereTree(m, tree));
  });
}

}  // namespace sulcus::cli
