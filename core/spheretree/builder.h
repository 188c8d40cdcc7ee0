#pragma once
// Builds a sphere-tree from a closed mesh by a medial-axis method (docs/engine.md,
// "Sphere-trees"): Voronoi poles of dense surface samples approximate the medial
// axis; leaves are chosen among medial spheres by a greedy set cover of the
// surface that bounds each leaf's protrusion, then tightened (the surface
// pieces at each leaf's rim are split and handed to the neighbour that already
// holds them, and leaves re-centred) and traded where they lower the sum of
// protrusions most (a leaf whose pieces its neighbours take cheaply is removed,
// one that gains most from a cut is cut); leaves are grouped into a B-ary
// hierarchy whose parents are smallest enclosing spheres of their children.
//
// Guarantees, independent of any sampling density:
// - every point of the surface lies inside some leaf (each leaf encloses whole
//   surface triangles, and a sphere enclosing a triangle's corners encloses it);
// - every child lies inside its parent.

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/spheretree/sphere_tree.h"

namespace sulcus {

struct SphereTreeParams {
  int levels = 4;     // counting the root: 4 levels of 8 hold 512 leaves
  int branching = 8;  // children per node, at most
  int leaves = 512;   // leaf budget, used when target_error_mm is 0
  /// When > 0: the fewest leaves whose protrusion bound is at most this (mm), as
  /// long as they fit in branching^(levels-1) leaves.
  double target_error_mm = 0;
  /// Surface samples for the medial axis and the cover; 0 picks
  /// max(3000, 8 * leaves), capped at 60000.
  int samples = 0;
  std::uint64_t seed = 1;
  /// What a budget is spent on. kMean (default): after the min-max cover, leaves
  /// are traded to where they lower the sum of protrusion bounds most (the mean
  /// the fit is judged by), no leaf past the worst one; more leaves end up near
  /// that worst bound, and thin parts get more leaves. kWorst: the min-max cover
  /// only, tightened; what tools use (ToolTreeParams). With a target error
  /// there is no budget to trade, and this is ignored.
  enum class Spend { kMean, kWorst } spend = Spend::kMean;
  /// How many times the leaves are tightened after the cover (the pieces at
  /// each leaf's rim split, each piece given to the leaf that holds it with
  /// the widest margin, the leaves re-centred), 1 to 8: the last step of
  /// kWorst and of a target error. kMean tightens once before it trades,
  /// whatever this is. Each pass costs about a sixth of a build; on a case's
  /// jaw (2,048 leaves) one pass against three left the worst leaf 0.49
  /// against 0.48 mm and the mean 0.25 against 0.24 mm, in 3.9 against 5.7 s.
  int tighten_passes = 3;

  /// Text that identifies these parameters (for cache keys and reports).
  std::string ToString() const;
};

/// The parameters a tool's tree is built with: the default budget, spent evenly
/// (Spend::kWorst). A tool's tip is in every contact; trading would crowd
/// leaves there and multiply the engine's contact pairs.
/// A spend's name, "mean" or "worst", as scene files, the command line and
/// the cache keys write it.
const char* SpendName(SphereTreeParams::Spend spend);
/// The spend of that name, or nothing for another word.
std::optional<SphereTreeParams::Spend> ParseSpend(std::string_view name);

inline SphereTreeParams ToolTreeParams() {
  SphereTreeParams p;
  p.spend = SphereTreeParams::Spend::kWorst;
  return p;
}

/// The most leaves a tree may have, by budget or by target error (the shipped
/// scenes use 512 to 3,072; a build's time and memory grow with the leaves,
/// and a million took over 300 s and 2 GB).
inline constexpr int kMaxLeaves = 16384;

/// The smallest target error a scene may ask for, mm: the sampled surface
/// cannot be followed closer than this.
inline constexpr double kMinTargetErrorMm = 0.005;

/// How many leaves `levels` levels (counting the root) of `branching` hold:
/// branching^(levels - 1).
std::size_t LeafCapacity(int levels, int branching);

/// What a build did and measured.
struct SphereTreeBuildStats {
  std::size_t surface_pieces = 0;  // sub-triangles the cover is computed on
  std::size_t medial_candidates = 0;
  std::size_t leaves = 0;
  double error_bound_mm = 0;  // max over leaves of (radius - depth of centre)
  double seconds_total = 0;
  double seconds_medial = 0;  // sampling, Delaunay, poles, depths
  double seconds_cover = 0;   // set cover and refinement
  double seconds_hierarchy = 0;
};

/// Progress callback: stage name and overall fraction in [0, 1]. Return false to
/// cancel; the build then throws BuildCancelled.
using BuildProgress = std::function<bool(std::string_view stage, double fraction)>;

class BuildCancelled : public std::runtime_error {
 public:
  BuildCancelled() : std::runtime_error("sphere-tree build cancelled") {}
};

/// Bad input for a build: a mesh that is not a solid, or parameters out of range.
class SphereTreeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Builds the tree. Deterministic for a given mesh and parameters. Throws
/// SphereTreeError for an open, non-manifold or volumeless mesh or bad
/// parameters, BuildCancelled when the progress callback returns false.
SphereTree BuildSphereTree(const TriangleMesh& mesh, const SphereTreeParams& params,
                           const BuildProgress& progress = {},
                           SphereTreeBuildStats* stats = nullptr);

/// Groups given leaf spheres into a hierarchy of `levels` levels (counting the
/// root) with up to `branching` children per node: top-down bisection along the
/// longest axis, parents the smallest spheres enclosing their children (so every
/// child lies inside its parent). For trees made by hand (tools, test scenes).
/// Throws SphereTreeError when the leaves do not fit.
SphereTree BuildTreeFromLeaves(const std::vector<Vector3>& centers,
                               const std::vector<double>& radii, int levels = 4,
                               int branching = 8);

}  // namespace sulcus
