#include "core/spheretree/cache.h"

#include <cstdio>
#include <cstdlib>

#include "core/spheretree/tree_files.h"

namespace sulcus {
namespace {
// Bump when the builder's output changes for the same input.
constexpr char kBuilderVersion[] = "sulcus-spheretree-builder-5";
}  // namespace

std::uint64_t MeshContentHash(const TriangleMesh& mesh) {
  std::uint64_t h =
      Fnv1a(mesh.vertices().data(), mesh.vertices().size() * sizeof(Vector3));
  return Fnv1a(mesh.faces().data(), mesh.faces().size() * sizeof(TriangleMesh::Face), h);
}

std::uint64_t SphereTreeCacheKey(const TriangleMesh& mesh,
                                 const SphereTreeParams& params) {
  const std::string text = params.ToString() + " " + kBuilderVersion;
  return Fnv1a(text.data(), text.size(), MeshContentHash(mesh));
}

std::filesystem::path DefaultCacheDir() {
  if (const char* dir = std::getenv("SULCUS_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "sulcus";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache/sulcus";
  return std::filesystem::temp_directory_path() / "sulcus-cache";
}

SphereTree LoadOrBuildSphereTree(const TriangleMesh& mesh, const SphereTreeParams& params,
                                 const std::filesystem::path& cache_dir,
                                 const BuildProgress& progress, CacheOutcome* outcome) {
  CacheOutcome local;
  CacheOutcome& out = outcome ? *outcome : local;
  const std::uint64_t key = SphereTreeCacheKey(mesh, params);
  char name[40];
  std::snprintf(name, sizeof name, "tree-%016llx.bin",
                static_cast<unsigned long long>(key));
  out.file = cache_dir / name;
  out.warning.clear();
  std::error_code ec;
  if (std::filesystem::exists(out.file, ec)) {
    try {
      SphereTree tree = ReadTreeBinary(out.file, key);
      out.kind = CacheOutcome::Kind::kHit;
      return tree;
    } catch (const TreeFileError& e) {
      out.kind = CacheOutcome::Kind::kRebuiltCorrupt;
      out.warning = std::string("ignored the cached tree: ") + e.what() + "; rebuilding";
    }
  } else {
    out.kind = CacheOutcome::Kind::kBuilt;
  }
  SphereTree tree = BuildSphereTree(mesh, params, progress, &out.stats);
  try {
    std::filesystem::create_directories(cache_dir);
    WriteTreeBinary(tree, key, out.file);
  } catch (const std::exception& e) {
    out.warning += (out.warning.empty() ? "" : "; ") +
                   std::string("could not cache the tree: ") + e.what();
  }
  return tree;
}

}  // namespace sulcus
