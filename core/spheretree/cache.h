#pragma once
// On-disk cache of built sphere-trees, keyed by the mesh's content and the build
// parameters: a second load of the same scene builds nothing.

#include <filesystem>
#include <string>

#include "core/spheretree/builder.h"

namespace sulcus {

/// Hash of the mesh's vertices and faces (exact bytes).
std::uint64_t MeshContentHash(const TriangleMesh& mesh);

/// The key of a tree: mesh content, parameters and the builder's version.
std::uint64_t SphereTreeCacheKey(const TriangleMesh& mesh,
                                 const SphereTreeParams& params);

/// $SULCUS_CACHE_DIR, else $XDG_CACHE_HOME/sulcus, else ~/.cache/sulcus.
std::filesystem::path DefaultCacheDir();

struct CacheOutcome {
  enum class Kind { kHit, kBuilt, kRebuiltCorrupt } kind = Kind::kBuilt;
  std::filesystem::path file;
  std::string warning;         // why a cached file was not trusted, when it was not
  SphereTreeBuildStats stats;  // of the build, when one ran
};

/// Returns the cached tree when a valid one exists, else builds, stores and
/// returns it. A corrupt or truncated cache file is rebuilt, with a warning in the
/// outcome. A cache that cannot be written is reported in the warning too; the
/// tree is still returned.
SphereTree LoadOrBuildSphereTree(const TriangleMesh& mesh, const SphereTreeParams& params,
                                 const std::filesystem::path& cache_dir,
                                 const BuildProgress& progress = {},
                                 CacheOutcome* outcome = nullptr);

}  // namespace sulcus
