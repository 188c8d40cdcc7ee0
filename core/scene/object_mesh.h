#pragma once
// Scene objects' meshes, private to core/scene: what generates an object's
// mesh, for the compiler's twins (MakeObjectMesh and MakeObjectMeshCached,
// public, are in scene.h).

#include <string>

#include "core/scene/scene.h"

namespace sulcus {

/// What generates an object's mesh, as text (the cache's key, in a tooth's
/// unmirrored frame); empty for meshes not generated (a mesh file, a shape).
/// Two objects with the same key have the same mesh, up to their mirroring.
std::string GeneratorKey(const ObjectSpec& o);

}  // namespace sulcus
