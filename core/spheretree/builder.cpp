#include "core/spheretree/builder.h"
// The sphere-tree builder's pipeline: each stage is in its own file
// (builder_stages.h lists them).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>

#include "core/spheretree/builder_stages.h"
#include "core/spheretree/mesh_oracle.h"
#include "core/spheretree/random.h"

namespace sulcus {
namespace {

using Clock = std::chrono::steady_clock;
using detail::Uniform;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

}  // namespace

const char* SpendName(SphereTreeParams::Spend spend) {
  return spend == SphereTreeParams::Spend::kMean ? "mean" : "worst";
}

std::optional<SphereTreeParams::Spend> ParseSpend(std::string_view name) {
  for (const auto spend :
       {SphereTreeParams::Spend::kMean, SphereTreeParams::Spend::kWorst})
    if (name == SpendName(spend)) return spend;
  return std::nullopt;
}

std::string SphereTreeParams::ToString() const {
  std::ostringstream s;
  s.precision(17);
  s << "levels=" << levels << " branch=" << branching << " leaves=" << leaves
    << " target_error_mm=" << target_error_mm << " samples=" << samples
    << " seed=" << seed << " spend=" << SpendName(spend);
  // (named only when not the default, so that every tree cached before the
  // passes could be chosen keeps its key)
  if (tighten_passes != 3) s << " passes=" << tighten_passes;
  return s.str();
}

SphereTree BuildSphereTree(const TriangleMesh& mesh, const SphereTreeParams& params,
                           const BuildProgress& progress, SphereTreeBuildStats* stats) {
  using namespace tree_build;  // NOLINT(google-build-using-namespace): its own stages
  const auto t0 = Clock::now();
  const Reporter report(progress);
  if (params.levels < 1 || params.levels > 8) {
    throw SphereTreeError("levels " + std::to_string(params.levels) +
                          " is out of range (expected 1 to 8)");
  }
  if (params.branching < 2 || params.branching > 32) {
    throw SphereTreeError("branching " + std::to_string(params.branching) +
                          " is out of range (expected 2 to 32)");
  }
  if (params.tighten_passes < 1 || params.tighten_passes > 8) {
    throw SphereTreeError("tightening passes " + std::to_string(params.tighten_passes) +
                          " is out of range (expected 1 to 8)");
  }
  const std::size_t capacity =
      std::min<std::size_t>(LeafCapacity(params.levels, params.branching), kMaxLeaves);
  if (params.target_error_mm < 0 || !std::isfinite(params.target_error_mm) ||
      (params.target_error_mm > 0 && params.target_error_mm < kMinTargetErrorMm)) {
    throw SphereTreeError("target error must be 0 (a leaf budget) or at least " +
                          std::to_string(kMinTargetErrorMm) + " mm");
  }
  if (params.target_error_mm == 0 &&
      (params.leaves < 1 || static_cast<std::size_t>(params.leaves) > capacity)) {
    throw SphereTreeError("leaf budget " + std::to_string(params.leaves) +
                          " does not fit in " + std::to_string(params.levels) +
                          " levels of " + std::to_string(params.branching) +
                          " (at most " + std::to_string(capacity) + " leaves)");
  }
  const MeshReport check = mesh.Check();
  if (!check.closed() || !check.manifold()) {
    throw SphereTreeError("the mesh must be a closed, manifold surface (" +
                          std::to_string(check.boundary_edges) + " boundary and " +
                          std::to_string(check.nonmanifold_edges) +
                          " non-manifold edges)");
  }
  const double extent = check.bounds.LargestExtent();
  const double diag = check.bounds.extent().norm();
  if (!(extent > 0) || std::abs(check.volume) <= 1e-9 * extent * extent * extent) {
    throw SphereTreeError("the mesh encloses no volume (it is flat or degenerate)");
  }
  const double orientation = check.volume > 0 ? 1.0 : -1.0;  // inward meshes still work

  // 1. Pieces and samples.
  const std::size_t budget = params.target_error_mm > 0 ? capacity : params.leaves;
  const int wanted = params.samples > 0
                         ? params.samples
                         : std::min(60000, std::max(3000, 8 * static_cast<int>(budget)));
  double h = std::sqrt(check.area / (0.433 * wanted));
  std::vector<Vector3> normals;
  std::vector<Piece> pieces = Subdivide(mesh, h, &normals, orientation);
  // Long thin faces: coarser pieces, down to one per face (a mesh of more faces
  // than that keeps one piece each).
  while (pieces.size() > 4u * static_cast<std::size_t>(wanted) &&
         pieces.size() > mesh.num_faces()) {
    h *= 1.5;
    normals.clear();
    pieces = Subdivide(mesh, h, &normals, orientation);
  }
  report("sampling", 0.02);
  std::uint64_t rng = params.seed;
  std::vector<Vector3> samples;
  samples.reserve(pieces.size());
  for (const Piece& p : pieces) {
    double u = Uniform(rng), v = Uniform(rng);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    samples.push_back(p.v[0] + u * (p.v[1] - p.v[0]) + v * (p.v[2] - p.v[0]));
  }

  // 2. Medial axis candidates.
  const MeshOracle oracle(mesh);
  const Reporter medial_report([&](std::string_view stage, double f) {
    return !progress || progress(stage, 0.02 + 0.38 * f);
  });
  const std::vector<Candidate> cands =
      MedialCandidates(samples, normals, diag, 0.25 * h, oracle, medial_report);
  if (cands.empty())
    throw SphereTreeError("no point of the medial axis was found inside the mesh");
  const double seconds_medial = Seconds(t0);

  // 3. Cover. With a budget: the smallest bound whose greedy cover fits it,
  // pieces no candidate encloses that well held at (nearly) their own best, so
  // that one hard spot does not hold the whole surface to its bound; one round
  // splits those pieces and covers again.
  const auto t_cover = Clock::now();
  int runs = 0;
  auto tick = [&] { report("cover", 0.4 + 0.3 * std::min(1.0, runs++ / 40.0)); };
  MinMaxCover cover;
  const std::size_t max_pieces = 6 * static_cast<std::size_t>(wanted);
  // Pieces whose best possible bound is above `limit` are split.
  auto refine_binding = [&](const CoverLists& lists, double limit) {
    const std::vector<float> floor = PieceFloors(lists, pieces.size());
    std::vector<char> split(pieces.size(), 0);
    std::size_t n_split = 0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      split[i] = floor[i] > limit;
      n_split += split[i];
    }
    if (n_split == 0 || pieces.size() + 3 * n_split > max_pieces) return false;
    pieces = SplitPieces(pieces, split);
    return true;
  };
  if (params.target_error_mm > 0) {
    const double eps = params.target_error_mm;
    cover.eps = eps;
    for (int round = 0;; ++round) {
      tick();
      cover.lists = ComputeCovers(cands, PieceBvh(pieces), eps);
      if (round == 3 || !refine_binding(cover.lists, 0.6 * eps)) break;
    }
    cover.chosen = GreedyCover(cover.lists, eps, pieces.size(), capacity);
    if (cover.chosen.empty()) {
      throw SphereTreeError(
          "a protrusion of at most " + std::to_string(eps) +
          " mm needs more leaves than " + std::to_string(params.levels) + " levels of " +
          std::to_string(params.branching) + " hold (" + std::to_string(capacity) +
          "); allow more levels or a larger error");
    }
  } else {
    cover = CoverWithBudget(cands, pieces, budget, 0.02 * h, 0.0, diag, tick);
    if (refine_binding(cover.lists, 0.6 * cover.eps)) {
      cover =
          CoverWithBudget(cands, pieces, budget, 0.02 * h, cover.lists_eps, diag, tick);
    }
  }

  // 4. Leaves: each piece to the leaf that encloses it best, leaves re-centred,
  // then tightened (and, with a budget, the leaves that frees spent).
  const CandidateIndex index(cands, 0.5 * h);
  auto make_leaves = [&](const std::vector<std::int32_t>& chosen,
                         std::vector<Piece>* work) {
    std::vector<Leaf> out;
    out.reserve(budget);
    for (std::int32_t i : chosen) out.push_back({cands[i].c, cands[i].depth, {}});
    AssignPieces(&out, *work);
    RefineLeaves(&out, *work, index, oracle);
    AssignPieces(&out, *work);
    const bool budgeted = params.target_error_mm == 0;
    const bool trade = budgeted && params.spend == SphereTreeParams::Spend::kMean;
    // The passes asked for, or one before trading.
    for (int pass = 0; pass < (trade ? 1 : params.tighten_passes); ++pass) {
      ShrinkLeaves(&out, work, index, oracle, 4 * max_pieces, 2);
      if (budgeted) SplitLeavesInTwo(&out, budget, *work, index, oracle);
    }
    if (!trade) return out;
    // Then trade leaves, and the pieces at their borders, where that lowers the
    // sum of bounds most, no leaf beyond the worst one now.
    double worst = 0;
    for (const Leaf& l : out)
      worst = std::max(worst, CoverError(l.c, l.depth, *work, l.pieces));
    SwapLeaves(&out, *work, index, oracle, worst, budget, 40);
    TradePieces(&out, *work, index, oracle, worst, 10);
    SwapLeaves(&out, *work, index, oracle, worst, budget, 40);
    RefineLeaves(&out, *work, index, oracle);
    return out;
  };
  report("tighten", 0.72);
  const std::vector<Piece> cover_pieces = pieces;
  std::vector<Leaf> leaves = make_leaves(cover.chosen, &pieces);
  // When every piece is covered at (nearly) its own best bound with leaves to
  // spare, the pieces are what limits the fit (smooth, coarsely meshed solids):
  // cover again on pieces a quarter the size, if that gives more leaves.
  if (params.target_error_mm == 0 && leaves.size() < budget * 9 / 10 &&
      cover_pieces.size() <= max_pieces) {
    report("tighten", 0.85);
    std::vector<Piece> work =
        SplitPieces(cover_pieces, std::vector<char>(cover_pieces.size(), 1));
    const MinMaxCover finer =
        CoverWithBudget(cands, work, budget, 0.02 * h, cover.lists_eps, diag, tick);
    std::vector<Leaf> trial = make_leaves(finer.chosen, &work);
    if (trial.size() > leaves.size()) {
      leaves = std::move(trial);
      pieces = std::move(work);
    }
  }
  std::vector<Vector3> centers;
  std::vector<double> radii;
  double bound = 0;
  for (const Leaf& l : leaves) {
    const double r = CoverError(l.c, 0.0, pieces, l.pieces) * (1 + 1e-12) +
                     1e-12 * extent;  // at depth 0: the radius
    centers.push_back(l.c);
    radii.push_back(r);
    bound = std::max(bound, r - l.depth);
  }
  const double seconds_cover = Seconds(t_cover);
  // 4. Hierarchy.
  report("hierarchy", 0.95);
  const auto t_tree = Clock::now();
  SphereTree tree = BuildTreeFromLeaves(centers, radii, params.levels, params.branching);
  tree.Validate();
  report("done", 1.0);
  if (stats != nullptr) {
    stats->surface_pieces = pieces.size();
    stats->medial_candidates = cands.size();
    stats->leaves = leaves.size();
    stats->error_bound_mm = bound;
    stats->seconds_medial = seconds_medial;
    stats->seconds_cover = seconds_cover;
    stats->seconds_hierarchy = Seconds(t_tree);
    stats->seconds_total = Seconds(t0);
  }
  return tree;
}

}  // namespace sulcus
