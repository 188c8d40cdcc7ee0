#include <algorithm>
#include <cmath>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/soft_tissue.h"
#include "core/lesson/inspection.h"

// Where an instrument examines each region and tooth surface from (the
// scripted inspectors go there; the window's view is checked against it).

namespace sulcus {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Target = UnitApproach;

const Vector3 kAnterior = Vector3::UnitY(), kUp = Vector3::UnitZ();

int FindObject(const SceneSpec& s, ObjectSpec::Kind kind, int fdi,
               const std::string& anatomy = "") {
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const ObjectSpec& o = s.objects[i];
    if (o.kind == kind &&
        (kind == ObjectSpec::Kind::kAnatomy ? o.anatomy == anatomy : o.fdi == fdi))
      return static_cast<int>(i);
  }
  return -1;
}

// A point on a tooth's (or its collar's) outer surface at angle phi (tooth
// frame, 0 mesial, 90 degrees buccal) and height z, with its horizontal normal, in the
// world.
bool SideSpot(const CompiledScene& scene, int object, double phi, double z, Vector3* p_W,
              Vector3* n_W) {
  const ObjectSpec& o = scene.spec.objects[static_cast<std::size_t>(object)];
  // A mirrored object's mesh is the tooth frame's mirrored in x: the angle mirrors
  // instead.
  const double r = OuterRadius(scene.meshes[static_cast<std::size_t>(object)],
                               o.mirrored ? kPi - phi : phi, z);
  if (r <= 0) return false;
  const Vector3 dir(std::cos(phi), std::sin(phi), 0);
  *p_W = o.X_WO * ArchMirror(o.mirrored, Vector3(r * dir.x(), r * dir.y(), z));
  *n_W = (o.X_WO.rotation() * ArchMirror(o.mirrored, dir)).normalized();
  return true;
}

Vector3 OcclusalOf(const ObjectSpec& o) {
  return (o.X_WO.rotation() * Vector3::UnitZ()).normalized();
}

std::optional<Target> ToothTarget(const CompiledScene& scene, int fdi, ToothSurface s,
                                  double phi_deg = -1) {
  const int i = FindObject(scene.spec, ObjectSpec::Kind::kTooth, fdi);
  if (i < 0) return std::nullopt;
  const ObjectSpec& o = scene.spec.objects[static_cast<std::size_t>(i)];
  const Vector3 occlusal = OcclusalOf(o);
  const double top = scene.meshes[static_cast<std::size_t>(i)].Bounds().max.z();
  Target t;
  if (s == ToothSurface::kOcclusal) {
    const ToothModel tooth = GenerateTooth(fdi);
    SurfacePoint sp = CariesSpot(tooth, s);
    if (fdi % 10 <= 3) {  // incisors and canines: on the incisal edge (the cusp tip)
      for (const Vector3& v : tooth.mesh.vertices())
        if (v.z() > sp.point.z()) sp.point = v;
      sp.normal = Vector3::UnitZ();
    }
    t.p = o.X_WO * ArchMirror(o.mirrored, sp.point);
    t.n = (o.X_WO.rotation() * ArchMirror(o.mirrored, sp.normal)).normalized();
    t.axis = (occlusal + 0.5 * kAnterior).normalized();
    t.shank =
        -(o.X_WO.rotation() * ArchMirror(o.mirrored, Vector3::UnitY()));  // lingually
    return t;
  }
  const double phi = phi_deg >= 0                  ? phi_deg * kPi / 180
                     : s == ToothSurface::kBuccal  ? kPi / 2
                     : s == ToothSurface::kLingual ? 3 * kPi / 2
                     : s == ToothSurface::kMesial  ? 35 * kPi / 180
                                                   : 145 * kPi / 180;
  if (!SideSpot(scene, i, phi, 0.5 * top, &t.p, &t.n)) return std::nullopt;
  // Up past the crown's bulge; on the buccal side no farther out than the
  // vestibule allows.
  t.axis = (occlusal + (s == ToothSurface::kBuccal ? 0.1 : 0.3) * t.n + 0.4 * kAnterior)
               .normalized();
  t.shank = -t.n;
  return t;
}

std::optional<Target> RegionTarget(const CompiledScene& scene, const std::string& region,
                                   const std::vector<int>& teeth) {
  Target t;
  if (region == "gingiva_upper" || region == "gingiva_lower") {
    // The attached gingiva: palatal of the upper first molars (open to the
    // middle of the mouth), lingual of the lower central incisors (the lower
    // lip lies over their labial gingiva: a probe reaching it presses the lip).
    const bool upper = region == "gingiva_upper";
    for (int fdi :
         upper ? std::vector<int>{16, 26, 15, 25} : std::vector<int>{41, 31, 42, 32}) {
      const int i = FindObject(scene.spec, ObjectSpec::Kind::kGingiva, fdi);
      if (i < 0 ||
          (!teeth.empty() && std::find(teeth.begin(), teeth.end(), fdi) == teeth.end()))
        continue;
      // The attached gingiva 1 mm below the CEJ, above the bone crest (below
      // it the gingiva draws into the jaw), or 0.5 mm below where the floor is
      // shallower; the working end leaning out past the crown's bulge.
      const auto spot = [&](double z) {
        return SideSpot(scene, i, 3 * kPi / 2, z, &t.p, &t.n);
      };
      if (!spot(-1.0) && !spot(-0.5)) continue;
      const Vector3 occlusal =
          OcclusalOf(scene.spec.objects[static_cast<std::size_t>(i)]);
      t.axis = (occlusal + 0.35 * t.n).normalized();
      t.shank = kAnterior;
      t.region = true;
      return t;
    }
    return std::nullopt;
  }
  std::string anatomy = region, part = "centre";
  if (region.rfind("tongue_", 0) == 0) {
    anatomy = "tongue";
    part = region.substr(7);
  }
  const int i = FindObject(scene.spec, ObjectSpec::Kind::kAnatomy, 0, anatomy);
  if (i < 0) return std::nullopt;
  const ObjectSpec& o = scene.spec.objects[static_cast<std::size_t>(i)];
  SurfacePoint sp = RegionSpot(anatomy, part, scene.meshes[static_cast<std::size_t>(i)]);
  // The lips at the height of the incisors' crowns (their centre may face the
  // alveolar mucosa above the vestibule's fold); the cheeks between the arches
  // by the first molars.
  auto crown_mid = [&](int fdi) -> std::optional<Vector3> {
    const int k = FindObject(scene.spec, ObjectSpec::Kind::kTooth, fdi);
    if (k < 0) return std::nullopt;
    const ObjectSpec& tooth = scene.spec.objects[static_cast<std::size_t>(k)];
    const double top = scene.meshes[static_cast<std::size_t>(k)].Bounds().max.z();
    return tooth.X_WO * Vector3(0, 0, 0.55 * top);
  };
  std::optional<Vector3> aim;
  Vector3 facing = Vector3::Zero();
  if (anatomy == "lip_upper" || anatomy == "lip_lower") {
    aim = crown_mid(anatomy == "lip_upper" ? 11 : 41);
    if (aim) aim->x() = 0;
    facing = -kAnterior;
  } else if (anatomy == "cheek_left" || anatomy == "cheek_right") {
    const bool left = anatomy == "cheek_left";
    const auto up = crown_mid(left ? 26 : 16), down = crown_mid(left ? 36 : 46);
    if (up && down) aim = 0.5 * (*up + *down);
    facing = left ? Vector3(-Vector3::UnitX()) : Vector3(Vector3::UnitX());
  } else if (anatomy == "floor_of_mouth" || part == "ventral") {
    // Behind the central incisors' lingual gingiva (the gap in front of the
    // tongue's tip): the floor's top there, the tongue's underside just behind.
    const int g = FindObject(scene.spec, ObjectSpec::Kind::kGingiva, 41);
    const int k = g >= 0 ? g : FindObject(scene.spec, ObjectSpec::Kind::kTooth, 41);
    const int tongue = FindObject(scene.spec, ObjectSpec::Kind::kAnatomy, 0, "tongue");
    if (k >= 0 && tongue >= 0) {
      const auto world_bounds = [&](int obj) {
        Aabb b;
        const ObjectSpec& oo = scene.spec.objects[static_cast<std::size_t>(obj)];
        for (const Vector3& v : scene.meshes[static_cast<std::size_t>(obj)].vertices())
          b.Extend(oo.X_WO * v);
        return b;
      };
      const Aabb gum = world_bounds(k), tg = world_bounds(tongue);
      const double gap_y = 0.5 * (gum.min.y() + tg.max.y());
      aim = anatomy == "floor_of_mouth" ? Vector3(0, gap_y, -1e3)
                                        : Vector3(0, tg.max.y() - 1.0, -1e3);
      facing = anatomy == "floor_of_mouth" ? kUp : Vector3(-kUp);
    }
  }
  if (aim) {
    const TriangleMesh& mesh = scene.meshes[static_cast<std::size_t>(i)];
    const std::vector<Vector3> normals = mesh.VertexNormalSums();
    double best = 1e18;
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      if (normals[v].norm() == 0) continue;
      const Vector3 nW = (o.X_WO.rotation() * normals[v]).normalized();
      if (nW.dot(facing) < 0.7) continue;
      const Vector3 pW = o.X_WO * mesh.vertices()[v];
      // Nearest in height and along the arch; across it the surface decides.
      const Vector3 d = pW - *aim;
      const double cost = anatomy.rfind("lip", 0) == 0 ? d.x() * d.x() + d.z() * d.z()
                          : aim->z() < -100
                              ? d.x() * d.x() + d.y() * d.y() - 1e-3 * nW.dot(facing)
                              : d.y() * d.y() + d.z() * d.z();
      if (cost < best) {
        best = cost;
        sp = {mesh.vertices()[v], normals[v].normalized()};
      }
    }
  }
  t.p = o.X_WO * sp.point;
  t.n = (o.X_WO.rotation() * sp.normal).normalized();
  t.shank = kAnterior;
  t.region = true;
  if (anatomy == "lip_lower" || anatomy == "lip_upper") {
    // Down (up) the vestibule between the lip and the incisors.
    t.axis = anatomy == "lip_lower" ? kUp : Vector3(-kUp);
  } else if (anatomy == "cheek_left" || anatomy == "cheek_right") {
    t.axis = (kAnterior + t.n).normalized();
    t.pre = t.p + 6.0 * t.n;
  } else if (anatomy == "palate" || anatomy == "soft_palate") {
    t.axis = (-kUp + (anatomy == "palate" ? 0.4 : 0.6) * kAnterior).normalized();
    t.pre = t.p + 5.0 * t.n;
  } else if (part == "lateral_border_left" || part == "lateral_border_right") {
    // Down between the tongue and the lower teeth.
    t.axis = kUp;
    t.shank = t.n;
  } else if (part == "ventral" || anatomy == "floor_of_mouth") {
    // Down the gap between the lower incisors' lingual gingiva and the tongue's
    // tip, leaning forward so that the working end clears the tip: the floor
    // just behind the incisors, the ventral surface under the tongue's tip.
    t.axis = (kUp + 0.36 * kAnterior).normalized();
  } else {  // the dorsum
    t.axis = (kUp + 0.5 * kAnterior).normalized();
    t.pre = t.p + 5.0 * t.n;
  }
  return t;
}

}  // namespace

std::vector<UnitApproach> ProximalSpots(const CompiledScene& scene, int fdi,
                                        ToothSurface s) {
  std::vector<UnitApproach> out;
  if (s != ToothSurface::kMesial && s != ToothSurface::kDistal) return out;
  // Toward the buccal, toward the contact, then the same from the lingual side
  // (inside the proximal sector, within 45 degrees of the mesial or distal).
  const std::vector<double> mesial = {28, 42, 325, 332, 318},
                            distal = {152, 138, 215, 208, 222};
  for (double phi : s == ToothSurface::kMesial ? mesial : distal)
    if (auto t = ToothTarget(scene, fdi, s, phi)) out.push_back(*t);
  return out;
}

std::optional<UnitApproach> ApproachOf(const CompiledScene& scene,
                                       const InspectionUnit& unit,
                                       const std::vector<int>& teeth) {
  return unit.region.empty() ? ToothTarget(scene, unit.fdi, unit.surface)
                             : RegionTarget(scene, unit.region, teeth);
}

}  // namespace sulcus
