#pragma once
// The rest of the mouth, in the world frame of arch.h, shaped around the placed
// teeth: the jaws (alveolar bone under its mucosa, holding every root, its crest
// 1.5 mm apical to the CEJ in health and lower where attachment is lost), the
// lips, the cheeks (buccal mucosa, a vestibule's width outside the teeth), the
// tongue (dorsum, lateral borders, ventral surface), the floor of the mouth and
// the hard and soft palate. Each is one named region an inspection lesson can
// ask for; the scene gives each its own tissue.

#include <map>
#include <string>
#include <vector>

#include "core/anatomy/arch.h"
#include "core/anatomy/findings.h"
#include "core/geometry/mesh.h"

namespace sulcus {

/// Changes whenever MakeSoftTissue's meshes change: caches of generated meshes
/// key on it.
inline constexpr int kSoftTissueVersion = 24;

/// The names MakeSoftTissue knows: jaw_lower, jaw_upper, lip_upper, lip_lower,
/// cheek_left, cheek_right, tongue, floor_of_mouth, palate, soft_palate.
const std::vector<std::string>& SoftTissueNames();

/// How far below the CEJ the bone crest lies at a tooth (mm, along its axis):
/// 1.5 in health, 1 mm below the deepest pocket floor where attachment is lost
/// (horizontal bone loss). `pocket_plus_recession_mm` is the largest of the
/// tooth's six sites; the pocket floor lies that far minus the 1.5 mm the margin
/// stands above the CEJ.
double CrestDropMm(double pocket_plus_recession_mm);

/// How far below its CEJ a multi-rooted tooth's roots part (the roof of its
/// furcation, mm), measured on the generated tooth between its roots; 0 for a
/// tooth with one root.
double FurcationRoofMm(int fdi);

/// Whether the jaw models the bone between a tooth's roots at this crest: a
/// multi-rooted tooth whose crest lies below its furcation's roof, far enough
/// for that bone (up to 0.3 mm under the roof) to stand above it. False for a
/// number that is not a tooth.
bool FurcationAboveCrest(int fdi, double crest_drop_mm);

/// A closed, outward mesh in the world frame. `crest_drop_mm` gives the crest
/// per FDI tooth for the jaws (CrestDropMm; teeth not named: 1.5 mm);
/// `furcation` each multi-rooted tooth's Hamp class (0 to 3) by entrance (as a
/// scene's `furcation`): where the crest has dropped below the furcation, the
/// jaw keeps the bone between the roots up to 0.3 mm under the furcation's
/// roof, missing 2 mm in from a class 1 entrance and 4 mm from a class 2 one
/// (never leaving less than 1 mm), none at all when an entrance is class 3,
/// and all of it for a tooth not named there (class 0: not involved).
/// Throws std::invalid_argument for an unknown name.
TriangleMesh MakeSoftTissue(
    const std::string& name, const ArchParams& arch = {},
    const std::map<int, double>& crest_drop_mm = {},
    const std::map<int, std::map<std::string, int>>& furcation = {});

/// Per vertex of a lip's mesh as MakeSoftTissue made it, how much of it is
/// skin (1) rather than the vermilion at the free edge or the mucosa facing the
/// teeth (0): the outer face from the vermilion border, a third of the way
/// from the free edge to the vestibule's fold, on. Empty for a mesh that is not
/// a generated lip.
std::vector<double> LipSkinCoverage(const TriangleMesh& lip);

/// The part of the tongue a point on it belongs to, from the surface's normal
/// there: "dorsum" (facing up), "ventral surface" (facing down) or "lateral
/// border" (facing sideways).
std::string TongueRegion(const Vector3& normal_W);

/// Soft-tissue lesions a scene may place on a named region.
const std::vector<std::string>& LesionKinds();  // ulcer, leukoplakia, erythroplakia
/// The regions of a soft tissue a lesion may sit on: the tongue's "dorsum",
/// "lateral_border_left", "lateral_border_right", "ventral"; "centre" for the
/// lips, cheeks, palates and the floor of the mouth; none for the jaws.
std::vector<std::string> LesionRegions(const std::string& anatomy);

/// Where a lesion on `region` of the tissue `anatomy` is centred: a vertex of
/// its mesh (`mesh`, as MakeSoftTissue made it) on the side that faces the
/// mouth. Throws std::invalid_argument for a region the tissue does not have.
Vector3 LesionCentre(const std::string& anatomy, const std::string& region,
                     const TriangleMesh& mesh);
/// LesionCentre with the surface's outward normal there (unit; toward the mouth).
SurfacePoint RegionSpot(const std::string& anatomy, const std::string& region,
                        const TriangleMesh& mesh);

}  // namespace sulcus
