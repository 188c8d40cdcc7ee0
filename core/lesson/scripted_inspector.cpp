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
    std::optional<UnitApproach> t = ApproachOf(scene, unit, spec.teeth);
    if (!t) continue;
    double press_n = 0.2;  // how hard the hand rests the tip on it
    if (name == "rough" && !rough_tongue && unit.region == "tongue_dorsum") {
      press_n = 1.0;
      rough_tongue = true;
    }
    if (name == "rough" && !rough_lesion && unit.region.empty()) {
      const ToothRecord* r = truth_.Find(unit.fdi);
      if (r && r->caries[static_cast<std::size_t>(unit.surface)]) {
        // Right on the lesion's centre.
        for (const CariesLesion& c : SceneCariesLesions(scene.spec))
          if (scene.spec.objects[static_cast<std::size_t>(c.tooth)].fdi == unit.fdi &&
              c.surface == static_cast<int>(unit.surface)) {
            t->p = c.centre_W;
            t->n = c.normal_W.normalized();
          }
        press_n = 1.5;
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
    stroke.target_force_n = press_n;
    stroke.speed_mm_s = 25;
    stroke.hold_s = 0.3;
    moves_.push_back(stroke);
    move(above, q, std::max(0.2, (off - above).norm() / 40.0));
  }
  if (moves_.empty()) throw std::invalid_argument("the lesson has nothing this inspector can reach");
  move(moves_.back().X_WH.translation(), Quaternion(moves_.back().X_WH.rotation()), 0.3);
}

std::unique_ptr<ScriptedHand> MakeScriptedHand(const std::string& name, const LessonSpec& spec, const CompiledScene& scene) {
  if (spec.inspection()) return std::make_unique<ScriptedInspector>(name, spec, scene);
  return std::make_unique<ScriptedStudent>(name, spec, scene);
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
