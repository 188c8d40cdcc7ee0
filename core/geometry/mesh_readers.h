#pragma once
// Sulcus's own readers of mesh files (STL ASCII and binary, OBJ, PLY ASCII and
// binary, OFF): vertices and polygons exactly as the file declares them (STL's
// corners merged where they are equal). Written for input from someone else:
// every count in a header is checked against the file's size before anything
// is allocated or looped over, every number for finiteness, a file that ends
// early is an error naming the line (text) or byte offset (binary), and no
// reader runs longer than linear in its file's size. Errors are MeshError
// naming the file. LoadMesh (mesh_io.h) checks what the engine needs on top.

#include <filesystem>
#include <vector>

#include "core/geometry/types.h"

namespace sulcus {

struct RawMesh {
  std::vector<Vector3> points;
  std::vector<std::vector<int>> polygons;  // indices into points, as declared
};

/// The format from the extension (.stl, .obj, .ply, .off; any case).
RawMesh ReadMeshFile(const std::filesystem::path& path);

}  // namespace sulcus
