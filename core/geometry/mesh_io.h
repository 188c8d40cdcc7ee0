#pragma once
// Mesh files: STL (ASCII and binary), OBJ, PLY and OFF, read by Sulcus's own
// readers (mesh_readers.h: bounded by the file, for input from someone else) and
// written through OpenMesh. Loading either returns a complete mesh or throws
// MeshError naming the file and the fault; nothing is half-loaded.

#include <filesystem>

#include "core/geometry/mesh.h"

namespace sulcus {

struct MeshLoadOptions {
  /// Reject meshes that are open or non-manifold (what the engine needs). Off for
  /// inspection tools that report on any readable mesh.
  bool require_closed_manifold = true;
};

/// Reads a mesh; the format comes from the extension (.stl, .obj, .ply, .off). Throws
/// MeshError when the file is missing, unreadable, empty, not in its format, has no
/// triangles, has a non-finite coordinate, or (with require_closed_manifold) is open or
/// non-manifold.
TriangleMesh LoadMesh(const std::filesystem::path& path,
                      const MeshLoadOptions& options = {});

struct MeshSaveOptions {
  /// Binary STL or PLY; OBJ and OFF are always text.
  bool binary = false;
};

/// Writes the mesh; the format comes from the extension. Coordinates survive a
/// round trip to float32 precision (about 1e-7 relative, 2e-6 mm on a tooth): STL
/// and binary PLY store float32, and OpenMesh writes text formats at float precision.
/// Throws MeshError when the file cannot be written.
void SaveMesh(const TriangleMesh& mesh, const std::filesystem::path& path,
              const MeshSaveOptions& options = {});

/// True when the extension is one LoadMesh/SaveMesh understand.
bool IsSupportedMeshFile(const std::filesystem::path& path);

}  // namespace sulcus
