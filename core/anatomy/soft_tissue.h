#pragma once
// The rest of the mouth, simply: tongue, palate, cheeks (buccal mucosa) and the
// alveolar bone of each jaw, in the world frame of arch.h, sized to the arches.
// Enough for oral inspection (the tongue hides lingual surfaces, the cheeks bound
// the vestibule); not anatomy to learn from.

#include <string>
#include <vector>

#include "core/anatomy/arch.h"
#include "core/geometry/mesh.h"

namespace sulcus {

/// The names MakeSoftTissue knows: tongue, palate, cheek_left, cheek_right,
/// jaw_lower, jaw_upper.
const std::vector<std::string>& SoftTissueNames();

/// A closed, outward mesh in the world frame. Throws std::invalid_argument for
/// an unknown name.
TriangleMesh MakeSoftTissue(const std::string& name, const ArchParams& arch = {});

}  // namespace sulcus
