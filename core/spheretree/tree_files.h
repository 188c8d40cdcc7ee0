#pragma once
// Sphere-tree files: Bradshaw's `.sph` text format (his Sphere-Tree Construction
// Toolkit reads and writes it) and Sulcus's compact binary cache format.

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "core/spheretree/sphere_tree.h"

namespace sulcus {

/// A tree file that cannot be used; what() reads "FILE:LINE: what is wrong" (LINE
/// omitted for binary files).
class TreeFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes Bradshaw's format: a first line `levels branch` (levels counting the
/// root), then `x y z r occupancy` for every slot of the full B-ary array in
/// breadth-first order (children of slot N at N*B+1 .. N*B+B); an unused slot has
/// radius -1. Coordinates stay in the object's frame, with 17 significant digits.
void WriteSph(const SphereTree& tree, const std::filesystem::path& path);

/// Reads Bradshaw's format: 4, 5 or 10 numbers per line (his optional auxiliary
/// sphere is ignored); slots with a radius <= 0, and everything below them, are
/// unused. `offset` is added to every centre: his toolkit can recentre a model on
/// its bounding box, so to read such a file back in the mesh's frame, pass the
/// centre of the mesh's bounding box. Throws TreeFileError naming file and line.
SphereTree ReadSph(const std::filesystem::path& path,
                   const Vector3& offset = Vector3::Zero());

/// The binary cache format: magic, version, the cache key, the arrays, and a
/// checksum; written to a temporary file and renamed, so a crash leaves no
/// half-written tree. Reading verifies everything and throws TreeFileError on any
/// mismatch (corrupt, truncated, other version, other key).
void WriteTreeBinary(const SphereTree& tree, std::uint64_t key,
                     const std::filesystem::path& path);
SphereTree ReadTreeBinary(const std::filesystem::path& path, std::uint64_t expected_key);

/// 64-bit FNV-1a over bytes; used for mesh content hashes and checksums.
std::uint64_t Fnv1a(const void* data, std::size_t size,
                    std::uint64_t seed = 0xcbf29ce484222325ull);

}  // namespace sulcus
