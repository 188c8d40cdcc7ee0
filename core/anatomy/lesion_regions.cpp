// Where a lesion may sit on a soft tissue, and where on its mesh that is.
#include <algorithm>
#include <stdexcept>

#include "core/anatomy/soft_tissue.h"

namespace sulcus {

const std::vector<std::string>& LesionKinds() {
  static const std::vector<std::string> kinds = {"ulcer", "leukoplakia", "erythroplakia"};
  return kinds;
}

std::vector<std::string> LesionRegions(const std::string& anatomy) {
  if (anatomy == "tongue")
    return {"dorsum", "lateral_border_left", "lateral_border_right", "ventral"};
  if (anatomy.rfind("jaw", 0) == 0) return {};
  return {"centre"};
}

Vector3 LesionCentre(const std::string& anatomy, const std::string& region,
                     const TriangleMesh& mesh) {
  return RegionSpot(anatomy, region, mesh).point;
}

SurfacePoint RegionSpot(const std::string& anatomy, const std::string& region,
                        const TriangleMesh& mesh) {
  const auto regions = LesionRegions(anatomy);
  if (std::find(regions.begin(), regions.end(), region) == regions.end())
    throw std::invalid_argument("'" + anatomy + "' has no region '" + region +
                                "' for a lesion");
  const std::vector<Vector3> normals = mesh.VertexNormalSums();
  const Aabb b = mesh.Bounds();
  const Vector3 mid = 0.5 * (b.min + b.max);
  const double length = b.max.y() - b.min.y();
  // The side facing the mouth and a point the lesion is nearest.
  Vector3 facing = Vector3::UnitZ(), anchor = mid;
  if (anatomy == "tongue") {
    if (region == "dorsum") {
      facing = Vector3::UnitZ();
      anchor = Vector3(0, b.max.y() - 0.3 * length, b.max.z());
    } else if (region == "ventral") {
      facing = -Vector3::UnitZ();
      anchor = Vector3(0, b.max.y() - 4, b.max.z() - 5);
    } else {
      const double side =
          region == "lateral_border_left" ? 1 : -1;  // the patient's left is +x
      facing = side * Vector3::UnitX();
      anchor = Vector3(side == 1 ? b.max.x() : b.min.x(), b.max.y() - 0.35 * length,
                       b.max.z() - 3);
    }
  } else if (anatomy == "cheek_left" || anatomy == "cheek_right") {
    const double side = anatomy == "cheek_left" ? 1 : -1;
    facing = -side * Vector3::UnitX();  // toward the midline
    anchor = Vector3(side == 1 ? b.min.x() : b.max.x(), mid.y(), mid.z());
  } else if (anatomy == "lip_upper" || anatomy == "lip_lower") {
    facing = -Vector3::UnitY();  // toward the teeth
    anchor = Vector3(0, b.min.y(), mid.z());
  } else if (anatomy == "palate" || anatomy == "soft_palate") {
    facing = -Vector3::UnitZ();
    anchor = Vector3(0, mid.y(), anatomy == "palate" ? b.max.z() : mid.z());
  } else if (anatomy == "floor_of_mouth") {
    facing = Vector3::UnitZ();
    anchor = Vector3(0, b.max.y(), b.max.z());
  }
  double best = std::numeric_limits<double>::infinity();
  SurfacePoint at{mid, facing};
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (normals[i].norm() == 0 || normals[i].normalized().dot(facing) < 0.5) continue;
    const double d = (mesh.vertices()[i] - anchor).norm();
    if (d < best) {
      best = d;
      at = {mesh.vertices()[i], normals[i].normalized()};
    }
  }
  return at;
}

}  // namespace sulcus
