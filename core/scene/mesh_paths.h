#pragma once
// Where a scene's mesh files may come from: inside the scene's folder (links
// followed), or a library folder the environment names.

#include <filesystem>
#include <string>

namespace sulcus {

/// Why a scene's `mesh:` path `rel`, written in a scene file in `folder`, cannot
/// be used ("" when it can): it must name a regular, non-empty file of at most
/// 512 MB inside `folder` (links resolved, however the folder is spelled) or in
/// a folder of the environment variable SULCUS_MESH_LIBRARY (':'-separated).
std::string MeshPathProblem(const std::string& rel, const std::filesystem::path& folder);

}  // namespace sulcus
