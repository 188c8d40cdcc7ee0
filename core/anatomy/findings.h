#pragma once
// Where the scene's findings sit on the generated anatomy, so that they are
// drawn where they are (and, for lessons, found where they are): a caries
// lesion on a named surface of a tooth, inflamed gingiva at named sites.

#include <array>
#include <vector>

#include "core/anatomy/tooth.h"

namespace sulcus {

/// Tooth surfaces in the order of scene files' `caries_mm` keys.
enum class ToothSurface { kMesial, kDistal, kBuccal, kLingual, kOcclusal };

/// The centre of a lesion on `surface`, a vertex of the tooth's mesh (tooth
/// frame): occlusal in the central fossa (molars, premolars) or on the incisal
/// edge's lingual slope (incisors, canines); proximal just cervical of the
/// contact point (where proximal caries starts); buccal and lingual in the
/// cervical third.
Vector3 CariesCentre(const ToothModel& tooth, ToothSurface surface);

/// A point on a tooth's surface with its outward normal (tooth frame).
struct SurfacePoint {
  Vector3 point = Vector3::Zero(), normal = Vector3::UnitZ();
};

/// CariesCentre with the surface's outward normal there (the mean of the
/// normals of the faces around it).
SurfacePoint CariesSpot(const ToothModel& tooth, ToothSurface surface);

/// The deepest cavity a scene may ask for (enamel and the dentine under it).
inline constexpr double kMaxCavityMm = 2.0;

/// Cavitates the lesions that `cavity_mm` names (depth at the centre, 0: none;
/// `caries_mm` their radii): the surface inside each lesion sinks along the
/// surface's normal at its centre: `depth` over the inner half of the lesion
/// (the cavity's floor), then smoothly less to nothing at the rim (its walls).
/// Only vertices facing the same way (normal within 70 degrees) move, so a thin
/// crown's other side stays where it is; the mesh's vertices and faces are
/// otherwise unchanged (it stays closed, the lesions' colouring per vertex
/// still applies).
void CarveCavities(ToothModel* tooth, const std::array<double, 5>& caries_mm,
                   const std::array<double, 5>& cavity_mm);

/// Per vertex of the tooth's mesh: how far inside a lesion it lies, 1 at a
/// lesion's centre falling to 0 at its rim (radius: the lesion's size), the
/// largest over the five surfaces. `caries_mm` as in the scene (0: none).
std::vector<double> CariesCoverage(const ToothModel& tooth,
                                   const std::array<double, 5>& caries_mm);

/// Per vertex of a gingival mesh in its tooth's frame: how inflamed the tissue
/// is, 1 at an inflamed site fading to 0 half way to the next site, by the
/// vertex's angle around the tooth (site angles as in gingiva.h).
std::vector<double> InflammationCoverage(const std::vector<Vector3>& vertices,
                                         const std::array<bool, 6>& inflamed);

/// Per vertex of a mesh: how far inside a round lesion of radius `radius_mm`
/// centred at `centre` it lies (1 at the centre, 0 at the rim and beyond).
std::vector<double> LesionCoverage(const TriangleMesh& mesh, const Vector3& centre,
                                   double radius_mm);

struct GingivaModel;

/// A calculus deposit at probing site `site` (0..5, MB B DB ML L DL) of a tooth,
/// in the tooth frame: a flattened, lumpy ellipsoid (about 2 mm along the
/// surface, 1.2 mm high) on the root or crown surface, standing about 0.3 mm
/// proud of it (the lumps move its surface in or out by up to a sixth).
/// Supragingival: just above the gingival margin; subgingival: in the sulcus,
/// a third of the way from the floor to the margin. Without gingiva
/// (`gingiva` null) the margin is taken 1.5 mm above the CEJ and the floor
/// 2 mm below that.
TriangleMesh MakeCalculus(const ToothModel& tooth, const GingivaModel* gingiva, int site,
                          bool subgingival);

/// Changes whenever MakeCalculus's meshes change: caches of generated meshes key on it.
inline constexpr int kCalculusVersion = 2;

}  // namespace sulcus
