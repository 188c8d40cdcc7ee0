#include "core/lesson/scripted_inspector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/soft_tissue.h"
#include "core/haptics/scripted_device.h"

namespace sulcus {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Where the tip goes to examine one unit: the surface point, its outward
// normal, the tool's axis while there (the way out of the mouth) and where the
// shank leans.
struct Target {
  int unit = -1;
  Vector3 p = Vector3::Zero(), n = Vector3::UnitZ(), axis = Vector3::UnitZ(), shank = Vector3::Zero();
  Vector3 pre = Vector3::Zero();  // where the tip starts its way in (zero: off the surface and up the tool's axis)
  bool region = false;
  double press_n = 0.2;  // how hard the hand rests the tip on it
};

const Vector3 kAnterior = Vector3::UnitY(), kUp = Vector3::UnitZ();

int FindObject(const SceneSpec& s, ObjectSpec::Kind kind, int fdi, const std::string& anatomy = "") {
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const ObjectSpec& o = s.objects[i];
    if (o.kind == kind && (kind == ObjectSpec::Kind::kAnatomy ? o.anatomy == anatomy : o.fdi == fdi))
      return static_cast<int>(i);
  }
  return -1;
}

// A point on a tooth's (or its collar's) outer surface at angle phi (tooth
// frame, 0 mesial, 90 degrees buccal) and height z, with its horizontal normal, in the world.
bool SideSpot(const CompiledScene& scene, int object, double phi, double z, Vector3* p_W, Vector3* n_W) {
  const ObjectSpec& o = scene.spec.objects[static_cast<std::size_t>(object)];
  const TriangleMesh mesh = ArchMirror(o.mirrored, scene.meshes[static_cast<std::size_t>(object)]);
  const double r = OuterRadius(mesh, phi, z);
  if (r <= 0) return false;
  const Vector3 dir(std::cos(phi), std::sin(phi), 0);
  *p_W = o.X_WO * ArchMirror(o.mirrored, Vector3(r * dir.x(), r * dir.y(), z));
  *n_W = (o.X_WO.rotation() * ArchMirror(o.mirrored, dir)).normalized();
  return true;
}

Vector3 OcclusalOf(const ObjectSpec& o) { return (o.X_WO.rotation() * Vector3::UnitZ()).normalized(); }

std::optional<Target> ToothTarget(const CompiledScene& scene, int fdi, ToothSurface s) {
  const int i = FindObject(scene.spec, ObjectSpec::Kind::kTooth, fdi);
  if (i < 0) return std::nullopt;
  const ObjectSpec& o = scene.spec.objects[static_cast<std::size_t>(i)];
  const Vector3 occlusal = OcclusalOf(o);
  const ToothModel tooth = GenerateTooth(fdi);
  const double top = tooth.mesh.Bounds().max.z();
  Target t;
  if (s == ToothSurface::kOcclusal) {
    SurfacePoint sp = CariesSpot(tooth, s);
    if (fdi % 10 <= 3) {  // incisors and canines: on the incisal edge (the cusp tip)
      for (const Vector3& v : tooth.mesh.vertices())
        if (v.z() > sp.point.z()) sp.point = v;
      sp.normal = Vector3::UnitZ();
    }
    t.p = o.X_WO * ArchMirror(o.mirrored, sp.point);
    t.n = (o.X_WO.rotation() * ArchMirror(o.mirrored, sp.normal)).normalized();
    t.axis = (occlusal + 0.5 * kAnterior).normalized();
    t.shank = -(o.X_WO.rotation() * ArchMirror(o.mirrored, Vector3::UnitY()));  // lingually
    return t;
  }
  const double phi = s == ToothSurface::kBuccal    ? kPi / 2
                     : s == ToothSurface::kLingual ? 3 * kPi / 2
                     : s == ToothSurface::kMesial  ? 35 * kPi / 180
                                                   : 145 * kPi / 180;
  if (!SideSpot(scene, i, phi, 0.5 * top, &t.p, &t.n)) return std::nullopt;
  // Up past the crown's bulge; on the buccal side no farther out than the
  // vestibule allows.
  t.axis = (occlusal + (s == ToothSurface::kBuccal ? 0.1 : 0.3) * t.n + 0.4 * kAnterior).normalized();
  t.shank = -t.n;
  return t;
}

std::optional<Target> RegionTarget(const CompiledScene& scene, const std::string& region, const std::vector<int>& teeth) {
  Target t;
  if (region == "gingiva_upper" || region == "gingiva_lower") {
    // The attached gingiva labial of the first incisor of the arch the lesson has.
    const bool upper = region == "gingiva_upper";
    for (int fdi : upper ? std::vector<int>{11, 21, 12, 22} : std::vector<int>{41, 31, 42, 32}) {
      const int i = FindObject(scene.spec, ObjectSpec::Kind::kGingiva, fdi);
      if (i < 0 || (!teeth.empty() && std::find(teeth.begin(), teeth.end(), fdi) == teeth.end())) continue;
      // The attached gingiva, 1.5 mm below the CEJ, the working end leaning
      // out past the crown's bulge.
      if (!SideSpot(scene, i, kPi / 2, -1.5, &t.p, &t.n)) continue;
      const Vector3 occlusal = OcclusalOf(scene.spec.objects[static_cast<std::size_t>(i)]);
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
        for (const Vector3& v : scene.meshes[static_cast<std::size_t>(obj)].vertices()) b.Extend(oo.X_WO * v);
        return b;
      };
      const Aabb gum = world_bounds(k), tg = world_bounds(tongue);
      const double gap_y = 0.5 * (gum.min.y() + tg.max.y());
      aim = anatomy == "floor_of_mouth" ? Vector3(0, gap_y, -1e3) : Vector3(0, tg.max.y() - 1.0, -1e3);
      facing = anatomy == "floor_of_mouth" ? kUp : Vector3(-kUp);
    }
  }
  if (aim) {
    const TriangleMesh& mesh = scene.meshes[static_cast<std::size_t>(i)];
    std::vector<Vector3> normals(mesh.num_vertices(), Vector3::Zero());
    for (const auto& f : mesh.faces()) {
      const Vector3 nf = (mesh.vertices()[f[1]] - mesh.vertices()[f[0]]).cross(mesh.vertices()[f[2]] - mesh.vertices()[f[0]]);
      for (int k = 0; k < 3; ++k) normals[f[k]] += nf;
    }
    double best = 1e18;
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      if (normals[v].norm() == 0) continue;
      const Vector3 nW = (o.X_WO.rotation() * normals[v]).normalized();
      if (nW.dot(facing) < 0.7) continue;
      const Vector3 pW = o.X_WO * mesh.vertices()[v];
      // Nearest in height and along the arch; across it the surface decides.
      const Vector3 d = pW - *aim;
      const double cost = anatomy.rfind("lip", 0) == 0 ? d.x() * d.x() + d.z() * d.z()
                          : aim->z() < -100         ? d.x() * d.x() + d.y() * d.y() - 1e-3 * nW.dot(facing)
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

const std::vector<std::string>& ScriptedInspectorNames() {
  static const std::vector<std::string> names = {"thorough", "skipping", "mistaken", "rough"};
  return names;
}

ScriptedInspector::ScriptedInspector(const std::string& name, const LessonSpec& spec, const CompiledScene& scene)
    : name_(name) {
  const auto& names = ScriptedInspectorNames();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown scripted inspector '" + name + "'; known: " + known);
  }
  if (!spec.inspection()) throw std::invalid_argument("a scripted inspector takes inspection lessons only");
  const InspectionTracker units(spec, scene);
  seen_.assign(units.units().size(), false);
  truth_ = TrueOdontogram(scene.spec, spec.teeth, spec.regions);
  if (name == "skipping") {
    skipped_.push_back("cheek_left");
    for (int fdi : {36, 37, 38, 46, 47, 48})
      if (std::find(spec.teeth.begin(), spec.teeth.end(), fdi) != spec.teeth.end())
        skipped_.push_back(std::to_string(fdi) + " L");
  }
  if (name == "mistaken") {
    for (const ToothRecord& t : truth_.teeth) {
      if (t.Status() != 0) continue;
      Finding f;
      f.kind = Finding::Kind::kCaries;
      f.fdi = t.fdi;
      f.surface = ToothSurface::kOcclusal;
      false_.push_back(f);
      break;
    }
    for (auto it = truth_.teeth.rbegin(); it != truth_.teeth.rend() && missed_.empty(); ++it)
      for (int s = 4; s >= 0; --s)
        if (it->caries[static_cast<std::size_t>(s)]) {
          Finding f;
          f.kind = Finding::Kind::kCaries;
          f.fdi = it->fdi;
          f.surface = static_cast<ToothSurface>(s);
          missed_.push_back(f);
          break;
        }
  }
  // The units in the lesson's order, each once.
  std::vector<int> order;
  for (const StepSpec& st : spec.steps)
    for (int u : units.StepUnits(st))
      if (std::find(order.begin(), order.end(), u) == order.end()) order.push_back(u);
  bool rough_tongue = false, rough_lesion = false;
  auto move = [&](const Vector3& p, const Quaternion& q, double s) {
    ScriptedStudent::Move m;
    m.X_WH = RigidTransform(q, p);
    m.duration_s = s;
    moves_.push_back(m);
  };
  bool first = true, last_region = false;
  // The middle of the mouth, between the arches: the way between regions.
  Vector3 hub = Vector3::Zero();
  int hub_n = 0;
  for (const ObjectSpec& o : scene.spec.objects)
    if (o.kind == ObjectSpec::Kind::kTooth) {
      hub += o.X_WO.translation();
      ++hub_n;
    }
  if (hub_n > 0) hub /= hub_n;
  for (int u : order) {
    const InspectionUnit& unit = units.units()[static_cast<std::size_t>(u)];
    if (std::find(skipped_.begin(), skipped_.end(), unit.Name()) != skipped_.end()) continue;
    std::optional<Target> t = unit.region.empty() ? ToothTarget(scene, unit.fdi, unit.surface)
                                                  : RegionTarget(scene, unit.region, spec.teeth);
    if (!t) continue;
    if (name == "rough" && !rough_tongue && unit.region == "tongue_dorsum") {
      t->press_n = 1.0;
      rough_tongue = true;
    }
    if (name == "rough" && !rough_lesion && unit.region.empty()) {
      const ToothRecord* r = truth_.Find(unit.fdi);
      if (r && r->caries[static_cast<std::size_t>(unit.surface)]) {
        // Right on the lesion's centre.
        const int i = FindObject(scene.spec, ObjectSpec::Kind::kTooth, unit.fdi);
        const ObjectSpec& o = scene.spec.objects[static_cast<std::size_t>(i)];
        const SurfacePoint sp = CariesSpot(GenerateTooth(unit.fdi), unit.surface);
        t->p = o.X_WO * ArchMirror(o.mirrored, sp.point);
        t->n = (o.X_WO.rotation() * ArchMirror(o.mirrored, sp.normal)).normalized();
        t->press_n = 1.5;
        rough_lesion = true;
      }
    }
    ScriptTarget st;
    st.n_W = t->n;
    st.tool_axis_W = t->axis;
    st.shank_W = t->shank;
    const Quaternion q = ScriptOrientation(st);
    // Off the surface before going in (clear of the cusps around an occlusal
    // fossa), coming to it down the tool's axis.
    const double clear = unit.surface == ToothSurface::kOcclusal && unit.region.empty() ? 2.5 : 1.0;
    const Vector3 off = t->p + clear * t->n, in = t->p - 0.5 * t->n;
    const Vector3 above = t->pre.squaredNorm() > 0 ? t->pre : Vector3(off + 8.0 * t->axis);
    if (first) {
      move(above + 10.0 * t->axis, q, 0.0);
      move(above + 10.0 * t->axis, q, 0.6);  // the ramp-in, away from everything
      first = false;
    } else if (t->region || last_region) {
      // Between regions, and from them to the teeth: through the middle of the mouth.
      const Vector3 at = moves_.back().X_WH.translation();
      move(hub, q, std::max(0.25, (hub - at).norm() / 60.0));
    }
    last_region = t->region;
    const double travel = (above - moves_.back().X_WH.translation()).norm();
    move(above, q, std::max(0.25, travel / 60.0));
    move(off, q, std::max(0.2, (off - above).norm() / 40.0));
    // In along the normal until the hand feels the press (or half a
    // millimetre past the surface), resting there, then back out and up.
    ScriptedStudent::Move stroke;
    stroke.stroke = true;
    stroke.X_WH = moves_.back().X_WH;
    stroke.direction_W = in - off;
    stroke.max_depth_mm = stroke.direction_W.norm() + 1.5;
    stroke.target_force_n = t->press_n;
    stroke.speed_mm_s = 25;
    stroke.hold_s = 0.3;
    moves_.push_back(stroke);
    move(above, q, std::max(0.2, (off - above).norm() / 40.0));
  }
  if (moves_.empty()) throw std::invalid_argument("the lesson has nothing this inspector can reach");
  move(moves_.back().X_WH.translation(), Quaternion(moves_.back().X_WH.rotation()), 0.3);
}

std::unique_ptr<Device> ScriptedInspector::MakeDevice() const { return MakeHandDevice(moves_, "student:" + name_); }

void ScriptedInspector::OnTick(const TickRecord& r) {
  last_tick_ = r.tick;
  if (!lesson_ || !lesson_->inspection()) return;
  const auto& units = lesson_->inspection()->units();
  auto is = [](const Finding& a, const Finding& b) {
    return a.kind == b.kind && a.fdi == b.fdi && a.surface == b.surface;
  };
  auto record = [&](Finding f) {
    if (std::any_of(missed_.begin(), missed_.end(), [&](const Finding& m) { return is(m, f); })) return;
    f.tick = r.tick;
    lesson_->Record(f);
  };
  for (std::size_t u = 0; u < units.size(); ++u) {
    if (seen_[u] || !units[u].touched) continue;
    seen_[u] = true;
    const InspectionUnit& unit = units[u];
    if (!unit.region.empty()) {
      const auto it = truth_.lesions.find(unit.region);
      if (it == truth_.lesions.end()) continue;
      Finding f;
      f.kind = Finding::Kind::kLesion;
      f.region = unit.region;
      f.lesion = it->second;
      record(f);
      continue;
    }
    const ToothRecord* t = truth_.Find(unit.fdi);
    if (!t) continue;
    Finding f;
    f.fdi = unit.fdi;
    if (t->caries[static_cast<std::size_t>(unit.surface)]) {
      f.kind = Finding::Kind::kCaries;
      f.surface = unit.surface;
      record(f);
    }
    // Calculus and the gingiva's colour are seen from the buccal or lingual side.
    if (unit.surface == ToothSurface::kBuccal || unit.surface == ToothSurface::kLingual) {
      const bool other_seen = [&] {
        const int other = lesson_->inspection()->UnitOf(
            unit.fdi, unit.surface == ToothSurface::kBuccal ? ToothSurface::kLingual : ToothSurface::kBuccal);
        return other >= 0 && seen_[static_cast<std::size_t>(other)];
      }();
      if (other_seen) continue;  // recorded already
      if (t->calculus) {
        f.kind = Finding::Kind::kCalculus;
        record(f);
      }
      if (t->inflamed) {
        f.kind = Finding::Kind::kInflamed;
        record(f);
      }
    }
  }
}

void ScriptedInspector::OnEnd() {
  if (!lesson_) return;
  for (Finding f : false_) {  // written in from memory at the end, examined or not
    f.tick = last_tick_;
    lesson_->Record(f);
  }
  lesson_->Submit(last_tick_);
}

}  // namespace sulcus
