#include "core/scene/mesh_paths.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/base/files.h"
#include "core/base/text.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

// The largest mesh file a scene may name (a full-arch intraoral scan is tens of
// megabytes).
constexpr std::uintmax_t kMaxMeshBytes = 512ull << 20;

// Folders besides the scene's own that its meshes may come from: the
// environment variable SULCUS_MESH_LIBRARY, folders separated by ':'.
std::vector<fs::path> MeshLibraryFolders() {
  std::vector<fs::path> folders;
  const char* env = std::getenv("SULCUS_MESH_LIBRARY");
  if (!env) return folders;
  std::string all(env);
  for (std::size_t start = 0; start <= all.size();) {
    const std::size_t end = std::min(all.find(':', start), all.size());
    if (end > start) folders.emplace_back(all.substr(start, end - start));
    start = end + 1;
  }
  return folders;
}

}  // namespace

std::string MeshPathProblem(const std::string& rel, const fs::path& folder) {
  const fs::path full = (folder / rel).lexically_normal();
  const std::string shown = "mesh path '" + Shorten(rel) + "'";
  if (rel.find('\0') != std::string::npos)
    return shown + " holds a NUL character; give a file name";
  if (rel.empty() || rel == "." || rel == "..")
    return "mesh path '" + rel + "' names no file; give the mesh file's name";
  bool inside = !fs::path(rel).is_absolute() && IsInsideFolder(full, folder);
  for (const fs::path& lib : MeshLibraryFolders())
    inside = inside || IsInsideFolder(full, lib);  // (for an absolute rel, full is rel)
  if (!inside)
    return shown +
           " leaves the scene's folder (after following links); put the mesh beside "
           "the scene file, or name its folder in SULCUS_MESH_LIBRARY";
  if (const std::string why = UnreadableReason(full); !why.empty())
    return why == "no such file"
               ? shown + " not found (looked for " + Shorten(full.string(), 300) + ")"
               : shown + " " + why;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(full, ec);
  if (ec) return shown + " cannot be read: " + ec.message();
  if (size == 0) return shown + " is an empty file";
  if (size > kMaxMeshBytes)
    return shown + " is " + std::to_string(size >> 20) +
           " MB; a scene's mesh may be at most 512 MB (reduce its triangles first)";
  return {};
}

}  // namespace sulcus
