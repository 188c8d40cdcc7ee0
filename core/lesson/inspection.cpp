#include "core/lesson/inspection.h"

#include <algorithm>
#include <cmath>

#include "core/anatomy/arch.h"
#include "core/anatomy/probe.h"
#include "core/anatomy/soft_tissue.h"
#include "core/haptics/haptic_loop.h"

namespace sulcus {
namespace {

// Whether the segment from the eye a to b passes through a leaf sphere of the
// tree (object frame). Spheres cover the surface from outside: a conservative
// line of sight. A leaf around the eye itself does not hide (a free camera put
// inside a tissue sees past it: what is that near is clipped).
bool SegmentMeetsTree(const SphereTree& tree, const Vector3& a, const Vector3& b) {
  if (tree.empty()) return false;
  const Vector3 ab = b - a;
  const double len2 = ab.squaredNorm();
  auto meets = [&](std::size_t i) {
    const Vector3 c = tree.center(i);
    const double s = len2 > 0 ? std::clamp((c - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (a + s * ab - c).squaredNorm() < tree.r[i] * tree.r[i];
  };
  std::int32_t stack[512];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const auto i = static_cast<std::size_t>(stack[--top]);
    if (!meets(i)) continue;
    if (tree.IsLeaf(i)) {
      if ((a - tree.center(i)).squaredNorm() >= tree.r[i] * tree.r[i]) return true;
      continue;
    }
    for (int k = 0; k < tree.child_count[i]; ++k) {
      if (top == 512) return true;  // deeper than any tree Sulcus builds: call it hidden
      stack[top++] = tree.first_child[i] + k;
    }
  }
  return false;
}

constexpr std::array<const char*, 5> kSurfaceCodes = {"M", "D", "B", "L", "O"};

// The tip's distance to the union of a tree's leaf spheres (negative inside),
// and the centre of the nearest leaf; nodes farther than `reach` are not opened.
struct Nearest {
  double d = 1e9;
  Vector3 centre = Vector3::Zero();
};
void NearestLeaf(const SphereTree& t, std::size_t i, const Vector3& p, double reach,
                 Nearest* out) {
  const Vector3 c = t.center(i);
  const double d = (p - c).norm() - t.r[i];
  if (d > reach || d > out->d) return;
  if (t.IsLeaf(i)) {
    out->d = d;
    out->centre = c;
    return;
  }
  for (int k = 0; k < t.child_count[i]; ++k)
    NearestLeaf(t, static_cast<std::size_t>(t.first_child[i] + k), p, reach, out);
}

}  // namespace

const std::vector<std::string>& InspectionRegionNames() {
  static const std::vector<std::string> names = {"lip_upper",
                                                 "lip_lower",
                                                 "cheek_right",
                                                 "cheek_left",
                                                 "gingiva_upper",
                                                 "gingiva_lower",
                                                 "tongue_dorsum",
                                                 "tongue_lateral_border_right",
                                                 "tongue_lateral_border_left",
                                                 "tongue_ventral",
                                                 "floor_of_mouth",
                                                 "palate",
                                                 "soft_palate"};
  return names;
}

std::string RegionLabel(const std::string& region) {
  static const std::map<std::string, std::string> labels = {
      {"lip_upper", "the upper lip"},
      {"lip_lower", "the lower lip"},
      {"cheek_right", "the right buccal mucosa"},
      {"cheek_left", "the left buccal mucosa"},
      {"gingiva_upper", "the upper gingiva and ridge"},
      {"gingiva_lower", "the lower gingiva and ridge"},
      {"tongue_dorsum", "the tongue's dorsum"},
      {"tongue_lateral_border_right", "the tongue's right lateral border"},
      {"tongue_lateral_border_left", "the tongue's left lateral border"},
      {"tongue_ventral", "the tongue's ventral surface"},
      {"floor_of_mouth", "the floor of the mouth"},
      {"palate", "the hard palate"},
      {"soft_palate", "the soft palate"}};
  const auto it = labels.find(region);
  return it != labels.end() ? it->second : region;
}

std::vector<std::string> SceneRegions(const SceneSpec& scene) {
  std::vector<std::string> have;
  for (const ObjectSpec& o : scene.objects) {
    if (o.kind == ObjectSpec::Kind::kGingiva)
      have.push_back(o.fdi / 10 <= 2 ? "gingiva_upper" : "gingiva_lower");
    if (o.kind != ObjectSpec::Kind::kAnatomy) continue;
    if (o.anatomy == "tongue") {
      for (const char* r : {"tongue_dorsum", "tongue_lateral_border_right",
                            "tongue_lateral_border_left", "tongue_ventral"})
        have.push_back(r);
    } else if (o.anatomy == "jaw_upper" || o.anatomy == "jaw_lower") {
      have.push_back(o.anatomy == "jaw_upper" ? "gingiva_upper" : "gingiva_lower");
    } else {
      have.push_back(o.anatomy);
    }
  }
  std::vector<std::string> out;
  for (const std::string& r : InspectionRegionNames())
    if (std::find(have.begin(), have.end(), r) != have.end()) out.push_back(r);
  return out;
}

std::string LesionRegion(const std::string& anatomy, const std::string& lesion_region) {
  if (anatomy == "tongue") return "tongue_" + lesion_region;
  return anatomy;
}

const char* SurfaceCode(ToothSurface s) {
  return kSurfaceCodes[static_cast<std::size_t>(s)];
}

std::optional<ToothSurface> SurfaceFromCode(const std::string& code) {
  for (std::size_t i = 0; i < kSurfaceCodes.size(); ++i)
    if (code == kSurfaceCodes[i]) return static_cast<ToothSurface>(i);
  return std::nullopt;
}

const char* WhoStatusName(int code) {
  switch (code) {
    case 0:
      return "sound";
    case 1:
      return "decayed";
    case 2:
      return "filled, with decay";
    case 3:
      return "filled, no decay";
    case 4:
      return "missing, due to caries";
    case 5:
      return "missing, any other reason";
    case 6:
      return "fissure sealant";
    case 7:
      return "crown or implant";
    case 8:
      return "unerupted";
    case 9:
      return "not recorded";
  }
  return "?";
}

const char* ToString(Finding::Kind k) {
  switch (k) {
    case Finding::Kind::kStatus:
      return "status";
    case Finding::Kind::kCaries:
      return "caries";
    case Finding::Kind::kCalculus:
      return "calculus";
    case Finding::Kind::kInflamed:
      return "inflamed gingiva";
    case Finding::Kind::kLesion:
      return "lesion";
  }
  return "?";
}

std::string Finding::ToString() const {
  std::string s = present ? "" : "withdrawn: ";
  switch (kind) {
    case Kind::kStatus:
      return s + "status " + std::to_string(status) + " (" + WhoStatusName(status) +
             ") at " + std::to_string(fdi);
    case Kind::kCaries:
      return s + "caries " + std::to_string(fdi) + " " + SurfaceCode(surface);
    case Kind::kCalculus:
      return s + "calculus " + std::to_string(fdi);
    case Kind::kInflamed:
      return s + "inflamed gingiva " + std::to_string(fdi);
    case Kind::kLesion:
      return s + (lesion.empty() ? "lesion" : lesion) + " on " + RegionLabel(region);
  }
  return s;
}

int ToothRecord::Status() const {
  if (status) return *status;
  return std::any_of(caries.begin(), caries.end(), [](bool b) { return b; }) ? 1 : 0;
}

ToothRecord* Odontogram::Find(int fdi) {
  for (ToothRecord& t : teeth)
    if (t.fdi == fdi) return &t;
  return nullptr;
}
const ToothRecord* Odontogram::Find(int fdi) const {
  return const_cast<Odontogram*>(this)->Find(fdi);
}

bool Odontogram::Apply(const Finding& f) {
  if (f.kind == Finding::Kind::kLesion) {
    if (f.present)
      lesions[f.region] = f.lesion;
    else
      lesions.erase(f.region);
    return true;
  }
  ToothRecord* t = Find(f.fdi);
  if (!t) return false;
  switch (f.kind) {
    case Finding::Kind::kStatus:
      if (f.present)
        t->status = f.status;
      else
        t->status.reset();
      break;
    case Finding::Kind::kCaries:
      t->caries[static_cast<std::size_t>(f.surface)] = f.present;
      break;
    case Finding::Kind::kCalculus:
      t->calculus = f.present;
      break;
    case Finding::Kind::kInflamed:
      t->inflamed = f.present;
      break;
    case Finding::Kind::kLesion:
      break;
  }
  return true;
}

Odontogram EmptyOdontogram(const std::vector<int>& teeth) {
  Odontogram o;
  for (int fdi : teeth) {
    ToothRecord t;
    t.fdi = fdi;
    o.teeth.push_back(t);
  }
  return o;
}

Odontogram TrueOdontogram(const SceneSpec& scene, const std::vector<int>& teeth,
                          const std::vector<std::string>& regions) {
  Odontogram o = EmptyOdontogram(teeth);
  for (const ObjectSpec& obj : scene.objects) {
    if (obj.kind == ObjectSpec::Kind::kTooth) {
      ToothRecord* t = o.Find(obj.fdi);
      if (!t) continue;
      for (std::size_t s = 0; s < 5; ++s) t->caries[s] = obj.caries_mm[s] > 0;
      t->calculus = std::any_of(obj.calculus.begin(), obj.calculus.end(),
                                [](int c) { return c > 0; });
      t->inflamed =
          std::any_of(obj.inflamed.begin(), obj.inflamed.end(), [](bool b) { return b; });
      t->status = t->Status();
    } else if (obj.kind == ObjectSpec::Kind::kAnatomy && !obj.lesion_kind.empty()) {
      const std::string r = LesionRegion(obj.anatomy, obj.lesion_region);
      if (std::find(regions.begin(), regions.end(), r) != regions.end())
        o.lesions[r] = obj.lesion_kind;
    }
  }
  return o;
}

std::string InspectionUnit::Name() const {
  return region.empty() ? std::to_string(fdi) + " " + SurfaceCode(surface) : region;
}

InspectionTracker::InspectionTracker(const LessonSpec& spec, const CompiledScene& scene)
    : spec_(spec), scene_(scene), teeth_(spec.teeth) {
  for (const std::string& r : spec.regions) {
    InspectionUnit u;
    u.region = r;
    units_.push_back(u);
  }
  first_tooth_unit_ = static_cast<int>(units_.size());
  for (int fdi : teeth_)
    for (int s = 0; s < 5; ++s) {
      InspectionUnit u;
      u.fdi = fdi;
      u.surface = static_cast<ToothSurface>(s);
      units_.push_back(u);
    }
  dwell_ticks_.assign(units_.size(), 0);
  rate_hz_ = scene.spec.rate_hz > 0 ? scene.spec.rate_hz : 1000;
  dwell_needed_ = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::lround(spec.rubric.touch_dwell_s * rate_hz_)));
  tip_radius_ = MakeProbe(scene.spec.probe).tip_radius_mm;

  const auto& objs = scene.spec.objects;
  roles_.resize(objs.size());
  for (std::size_t i = 0; i < objs.size(); ++i) {
    const ObjectSpec& o = objs[i];
    X_OW_.push_back(o.X_WO.inverse());
    ObjectRole& role = roles_[i];
    if (o.kind == ObjectSpec::Kind::kTooth) {
      const auto it = std::find(teeth_.begin(), teeth_.end(), o.fdi);
      if (it != teeth_.end()) role.tooth = static_cast<int>(it - teeth_.begin());
      if (i < scene.meshes.size()) role.top_z = scene.meshes[i].Bounds().max.z();
    } else if (o.kind == ObjectSpec::Kind::kGingiva) {
      role.unit = UnitOf(o.fdi / 10 <= 2 ? "gingiva_upper" : "gingiva_lower");
    } else if (o.kind == ObjectSpec::Kind::kAnatomy) {
      if (o.anatomy == "tongue")
        role.tongue = true;
      else if (o.anatomy == "jaw_upper")
        role.unit = UnitOf("gingiva_upper");
      else if (o.anatomy == "jaw_lower")
        role.unit = UnitOf("gingiva_lower");
      else
        role.unit = UnitOf(o.anatomy);
      if (!o.lesion_kind.empty() && i < scene.meshes.size()) {
        const std::string where = LesionRegion(o.anatomy, o.lesion_region);
        const SurfacePoint p = RegionSpot(o.anatomy, o.lesion_region, scene.meshes[i]);
        lesions_.push_back({where, static_cast<int>(i), o.X_WO * p.point,
                            (o.X_WO.rotation() * p.normal).normalized(), o.lesion_mm});
      }
    }
  }
  // Where each unit is, for the views (made here, once: not in the window's first frame
  // with a view).
  for (const InspectionUnit& u : units_) spots_.push_back(ApproachOf(scene_, u, teeth_));
  for (const CariesLesion& c : SceneCariesLesions(scene.spec))
    lesions_.push_back({std::to_string(objs[static_cast<std::size_t>(c.tooth)].fdi) +
                            " " + SurfaceCode(static_cast<ToothSurface>(c.surface)),
                        c.tooth, c.centre_W, c.normal_W.normalized(), c.radius_mm});
}

int InspectionTracker::UnitOf(const std::string& region) const {
  for (int i = 0; i < first_tooth_unit_; ++i)
    if (units_[static_cast<std::size_t>(i)].region == region) return i;
  return -1;
}

int InspectionTracker::UnitOf(int fdi, ToothSurface s) const {
  const auto it = std::find(teeth_.begin(), teeth_.end(), fdi);
  if (it == teeth_.end()) return -1;
  return first_tooth_unit_ + 5 * static_cast<int>(it - teeth_.begin()) +
         static_cast<int>(s);
}

std::vector<int> InspectionTracker::StepUnits(const StepSpec& step) const {
  std::vector<int> out;
  for (const std::string& r : step.regions)
    if (const int u = UnitOf(r); u >= 0) out.push_back(u);
  for (int fdi : step.teeth)
    for (int s = 0; s < 5; ++s)
      if (step.surfaces & (1u << s))
        if (const int u = UnitOf(fdi, static_cast<ToothSurface>(s)); u >= 0)
          out.push_back(u);
  return out;
}

void InspectionTracker::OnTick(const TickRecord& r,
                               const std::vector<std::uint8_t>& in_contact) {
  const Vector3 tip_W = r.X_WG.translation();
  const double reach = tip_radius_ + 0.5;
  tip_unit_ = -1;
  double best = reach;
  for (std::size_t i = 0; i < roles_.size() && i < in_contact.size(); ++i) {
    const ObjectRole& role = roles_[i];
    if (!in_contact[i] || (role.tooth < 0 && role.unit < 0 && !role.tongue)) continue;
    if (i >= scene_.trees.size() || scene_.trees[i].empty()) continue;
    const ObjectSpec& o = scene_.spec.objects[i];
    const Vector3 p_O = X_OW_[i] * tip_W;
    Nearest n;
    NearestLeaf(scene_.trees[i], 0, p_O, reach, &n);
    if (n.d >= best) continue;
    Vector3 normal_O = p_O - n.centre;
    if (normal_O.norm() < 1e-9) continue;
    normal_O.normalize();
    int unit = role.unit;
    if (role.tooth >= 0) {
      // In the tooth's own frame (+x mesial, +y buccal, +z occlusal).
      const Vector3 p = ArchMirror(o.mirrored, p_O),
                    nrm = ArchMirror(o.mirrored, normal_O);
      ToothSurface s;
      if (nrm.z() > 0.6 || p.z() > role.top_z - 1.0) {
        s = ToothSurface::kOcclusal;
      } else {
        const double phi = std::atan2(p.y(), p.x()), c = std::cos(phi);
        s = c > std::sqrt(0.5)    ? ToothSurface::kMesial
            : c < -std::sqrt(0.5) ? ToothSurface::kDistal
            : p.y() >= 0          ? ToothSurface::kBuccal
                                  : ToothSurface::kLingual;
      }
      unit = first_tooth_unit_ + 5 * role.tooth + static_cast<int>(s);
    } else if (role.tongue) {
      const Vector3 n_W = o.X_WO.rotation() * normal_O;
      const std::string part = TongueRegion(n_W);
      unit =
          UnitOf(part == "dorsum"            ? "tongue_dorsum"
                 : part == "ventral surface" ? "tongue_ventral"
                 : n_W.x() > 0 ? "tongue_lateral_border_left"  // +x: the patient's left
                               : "tongue_lateral_border_right");
    }
    if (unit < 0) continue;
    best = n.d;
    tip_unit_ = unit;
  }
  // Examined: the tip rested on it for the dwell without a break (a brush in
  // passing is not an examination).
  run_ = tip_unit_ >= 0 && tip_unit_ == run_unit_ ? run_ + 1 : 1;
  run_unit_ = tip_unit_;
  if (tip_unit_ >= 0) {
    const auto u = static_cast<std::size_t>(tip_unit_);
    ++dwell_ticks_[u];
    units_[u].dwell_s = static_cast<double>(dwell_ticks_[u]) / rate_hz_;
    if (!units_[u].touched && run_ >= dwell_needed_) {
      units_[u].touched = true;
      units_[u].first_tick = r.tick;
    }
  }
  // Lesions pressed harder than the limit: the push back along the lesion's
  // normal while the tip is on it and its object is touched.
  const double limit = spec_.rubric.lesion_force_n;
  for (Lesion& l : lesions_) {
    const bool on = l.object >= 0 &&
                    static_cast<std::size_t>(l.object) < in_contact.size() &&
                    in_contact[static_cast<std::size_t>(l.object)] &&
                    (tip_W - l.centre_W).norm() <= l.radius_mm + tip_radius_ + 0.3;
    const double press = on ? r.force_W.dot(l.normal_W) : 0.0;
    if (press > limit) {
      if (!l.pressing || press > l.peak) {
        l.peak = press;
        l.peak_tick = r.tick;
      }
      l.pressing = true;
    } else if (l.pressing && press < 0.8 * limit) {
      presses_.push_back({l.where, l.peak, l.peak_tick});
      l.pressing = false;
      l.peak = 0;
    }
  }
}

bool InspectionTracker::Hidden(int fdi, const Vector3& eye_W,
                               const Vector3& spot_W) const {
  const bool upper = fdi / 10 == 1 || fdi / 10 == 2;
  for (std::size_t i = 0; i < scene_.spec.objects.size() && i < scene_.trees.size();
       ++i) {
    const ObjectSpec& o = scene_.spec.objects[i];
    // The arch's teeth, deposits, gingiva and jaw; the lips, cheeks and tongue
    // do not hide (retracted, as the window shows them see-through when in
    // the way), nor does the other arch (faded in the window's occlusal views).
    bool hides = false;
    if (o.kind == ObjectSpec::Kind::kTooth || o.kind == ObjectSpec::Kind::kGingiva ||
        o.kind == ObjectSpec::Kind::kCalculus)
      hides = (o.fdi / 10 == 1 || o.fdi / 10 == 2) == upper;
    else if (o.kind == ObjectSpec::Kind::kAnatomy)
      hides = o.anatomy == (upper ? "jaw_upper" : "jaw_lower");
    if (!hides) continue;
    const RigidTransform X_OW = o.X_WO.inverse();
    if (SegmentMeetsTree(scene_.trees[i], X_OW * eye_W, X_OW * spot_W)) return true;
  }
  return false;
}

void InspectionTracker::OnView(const ViewSample& v) {
  const Vector3 ahead = v.focal - v.eye;
  if (ahead.norm() < 1e-9) return;
  const double half = 0.5 * v.view_angle_deg * 3.14159265358979323846 / 180;
  for (std::size_t i = 0; i < units_.size(); ++i) {
    if (units_[i].seen || !spots_[i]) continue;
    const Vector3 to = spots_[i]->p - v.eye;
    const double d = to.norm();
    if (d < 1e-9 || d > 150) continue;
    // Inside the cone (the window is wider than tall: the vertical angle is the
    // narrower), facing the camera.
    if (std::acos(std::clamp(to.dot(ahead) / (d * ahead.norm()), -1.0, 1.0)) > half)
      continue;
    if (spots_[i]->n.dot(-to) <= 0) continue;
    if (units_[i].region.empty() &&
        Hidden(units_[i].fdi, v.eye, spots_[i]->p + kViewClearMm * spots_[i]->n))
      continue;
    units_[i].seen = true;
    units_[i].seen_tick = v.tick;
  }
}

std::vector<LesionPress> InspectionTracker::presses() const {
  std::vector<LesionPress> out = presses_;
  for (const Lesion& l : lesions_)
    if (l.pressing) out.push_back({l.where, l.peak, l.peak_tick});
  std::sort(out.begin(), out.end(),
            [](const LesionPress& a, const LesionPress& b) { return a.tick < b.tick; });
  return out;
}

}  // namespace sulcus
