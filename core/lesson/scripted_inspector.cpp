#include "core/lesson/scripted_inspector.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/soft_tissue.h"
#include "core/base/text.h"
#include "core/collision/collision.h"
#include "core/haptics/scripted_device.h"
#include "core/lesson/scripted_keys.h"

namespace sulcus {
namespace {

// Where the whole instrument can be without meeting anything: the hand plans
// its way with the same sphere-trees the engine feels (every object, soft
// tissues too), as a clinician's hand finds its way without forcing.
class Clearance {
 public:
  explicit Clearance(const CompiledScene& scene) {
    std::vector<CollisionWorld::Object> objects;
    for (std::size_t i = 0; i < scene.trees.size(); ++i)
      if (!scene.trees[i].empty())
        objects.push_back({&scene.trees[i], scene.spec.objects[i].X_WO});
    world_ = std::make_unique<CollisionWorld>(scene.tool_tree, objects);
  }
  // The instrument at a pose is `margin` clear of every tree.
  bool Free(const Vector3& p, const Quaternion& q, double margin) const {
    ContactPair pair;
    QueryLimits limits;
    limits.stop_when_full = true;
    return FindContacts(*world_, RigidTransform(q, p), margin, scratch_.get(), &pair, 1,
                        limits)
               .pairs == 0;
  }
  // Free along the hand's way from one pose to another, position and
  // orientation interpolated as the device plays a move (every 0.5 mm and 3 degrees).
  bool PathFree(const Vector3& a, const Quaternion& qa, const Vector3& b,
                const Quaternion& qb, double margin) const {
    const double turn = qa.angularDistance(qb);
    const int n =
        std::max(1, static_cast<int>(std::ceil(std::max(
                        (b - a).norm() / 0.5, turn / (3 * std::numbers::pi / 180)))));
    for (int i = 0; i <= n; ++i) {
      const double s = static_cast<double>(i) / n;
      if (!Free(a + s * (b - a), qa.slerp(s, qb), margin)) return false;
    }
    return true;
  }
  // A way from one pose to another that keeps the whole instrument clear:
  // straight; up the first pose's axis, across and down the second's; round by
  // a waypoint near the middle, turned partway; or through the middle of the
  // mouth or in front of the lips, turning there. The waypoints between (empty
  // when the straight way is clear); nullopt when none is found.
  std::optional<std::vector<RigidTransform>> Route(const RigidTransform& A,
                                                   const RigidTransform& B,
                                                   const Vector3& hub,
                                                   const Vector3& front,
                                                   double margin) const {
    const Vector3 pa = A.translation(), pb = B.translation();
    const Quaternion qa(A.rotation()), qb(B.rotation());
    if (PathFree(pa, qa, pb, qb, margin)) return std::vector<RigidTransform>{};
    const Vector3 ua = qa * Vector3::UnitZ(), ub = qb * Vector3::UnitZ();
    std::vector<double> la_ok = {0},
                        lb_ok = {0};  // how far each pose goes straight up its axis
    for (double l : {2.0, 4.0, 7.0, 10.0, 15.0}) {
      if (!PathFree(pa, qa, pa + l * ua, qa, margin)) break;
      la_ok.push_back(l);
    }
    for (double l : {2.0, 4.0, 7.0, 10.0, 15.0}) {
      if (!PathFree(pb + l * ub, qb, pb, qb, margin)) break;
      lb_ok.push_back(l);
    }
    auto with_lifts = [&](const Vector3& a1, const Vector3& b1,
                          std::vector<RigidTransform> between) {
      std::vector<RigidTransform> w;
      if ((a1 - pa).norm() > 0) w.emplace_back(qa, a1);
      w.insert(w.end(), between.begin(), between.end());
      if ((b1 - pb).norm() > 0) w.emplace_back(qb, b1);
      return w;
    };
    std::optional<std::vector<RigidTransform>> best;
    double best_len = 1e18;
    for (double la : la_ok)
      for (double lb : lb_ok)
        if (la + lb < best_len && PathFree(pa + la * ua, qa, pb + lb * ub, qb, margin)) {
          best_len = la + lb;
          best = with_lifts(pa + la * ua, pb + lb * ub, {});
        }
    if (best) return best;
    const Vector3 a1 = pa + la_ok.back() * ua, b1 = pb + lb_ok.back() * ub;
    // Waypoints drawn from a fixed sequence: the same lesson plans the same way.
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Vector3 mid = 0.5 * (a1 + b1);
    for (int i = 0; i < 300; ++i) {
      const double r = i < 100 ? 6.0 : i < 200 ? 12.0 : 20.0;
      const Vector3 m = mid + r * Vector3(u(rng), u(rng), u(rng));
      const Quaternion qm = qa.slerp(0.5 + 0.4 * u(rng), qb);
      if (Free(m, qm, margin) && PathFree(a1, qa, m, qm, margin) &&
          PathFree(m, qm, b1, qb, margin))
        return with_lifts(a1, b1, {RigidTransform(qm, m)});
    }
    for (const Vector3& via : {hub, front})
      if (PathFree(a1, qa, via, qa, margin) && PathFree(via, qa, via, qb, margin) &&
          PathFree(via, qb, b1, qb, margin))
        return with_lifts(a1, b1, {RigidTransform(qa, via), RigidTransform(qb, via)});
    return std::nullopt;
  }

 private:
  std::unique_ptr<CollisionWorld> world_;
  std::unique_ptr<CollisionScratch> scratch_ = std::make_unique<CollisionScratch>();
};

}  // namespace

const std::vector<std::string>& ScriptedInspectorNames() {
  static const std::vector<std::string> names = {"thorough", "skipping", "mistaken",
                                                 "rough"};
  return names;
}

ScriptedInspector::ScriptedInspector(const std::string& name, const LessonSpec& spec,
                                     const CompiledScene& scene)
    : name_(name) {
  const auto& names = ScriptedInspectorNames();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    throw std::invalid_argument("unknown scripted inspector '" + name +
                                "'; known: " + Join(names));
  }
  if (!spec.inspection())
    throw std::invalid_argument("a scripted inspector takes inspection lessons only");
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
    for (auto it = truth_.teeth.rbegin(); it != truth_.teeth.rend() && missed_.empty();
         ++it)
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
  // The steps in the lesson's order, each unit once. Within a step of teeth the
  // hand keeps one way of holding the instrument as long as it can, as a
  // clinician does: along the arch on the buccal side (distal, buccal, mesial
  // of each tooth), back along the occlusal surfaces, then along the lingual
  // side; turning the instrument between buccal and lingual at every tooth
  // would sweep its shank across the teeth and cheeks 28 times.
  std::vector<int> order;
  for (const StepSpec& st : spec.steps) {
    std::vector<int> step;
    for (int u : units.StepUnits(st))
      if (std::find(order.begin(), order.end(), u) == order.end() &&
          std::find(step.begin(), step.end(), u) == step.end())
        step.push_back(u);
    std::vector<int> buccal, occlusal, lingual, rest;
    // Toward the midline (17 to 11) each tooth's distal comes first; away from it, its
    // mesial.
    const bool to_midline =
        st.teeth.size() > 1 && st.teeth.back() % 10 < st.teeth.front() % 10;
    const ToothSurface first = to_midline ? ToothSurface::kDistal : ToothSurface::kMesial,
                       last = to_midline ? ToothSurface::kMesial : ToothSurface::kDistal;
    for (int fdi : st.teeth) {
      for (ToothSurface s : {first, ToothSurface::kBuccal, last})
        if (const int u = units.UnitOf(fdi, s);
            std::find(step.begin(), step.end(), u) != step.end())
          buccal.push_back(u);
      if (const int u = units.UnitOf(fdi, ToothSurface::kOcclusal);
          std::find(step.begin(), step.end(), u) != step.end())
        occlusal.insert(occlusal.begin(), u);
      if (const int u = units.UnitOf(fdi, ToothSurface::kLingual);
          std::find(step.begin(), step.end(), u) != step.end())
        lingual.push_back(u);
    }
    for (int u : step)
      if (std::find(buccal.begin(), buccal.end(), u) == buccal.end() &&
          std::find(occlusal.begin(), occlusal.end(), u) == occlusal.end() &&
          std::find(lingual.begin(), lingual.end(), u) == lingual.end())
        rest.push_back(u);
    for (const std::vector<int>* part : {&rest, &buccal, &occlusal, &lingual})
      order.insert(order.end(), part->begin(), part->end());
  }
  bool rough_tongue = false, rough_lesion = false;
  auto move = [&](const Vector3& p, const Quaternion& q, double s) {
    ScriptedStudent::Move m;
    m.X_WH = RigidTransform(q, p);
    m.duration_s = s;
    moves_.push_back(m);
  };
  const Clearance clearance(scene);
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
  // In front of the lips: where the hand takes the instrument out to turn it.
  double front_y = hub.y();
  for (std::size_t i = 0; i < scene.meshes.size(); ++i)
    for (const Vector3& v : scene.meshes[i].vertices())
      front_y = std::max(front_y, (scene.spec.objects[i].X_WO * v).y());
  const Vector3 front(hub.x(), front_y + 25.0, hub.z());
  for (int u : order) {
    const InspectionUnit& unit = units.units()[static_cast<std::size_t>(u)];
    if (std::find(skipped_.begin(), skipped_.end(), unit.Name()) != skipped_.end())
      continue;
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
    // Off the surface before going in (clear of the cusps around an occlusal
    // fossa), coming to it down the tool's axis.
    const double clear =
        unit.surface == ToothSurface::kOcclusal && unit.region.empty() ? 2.5 : 1.0;
    // The way of holding the instrument: the surface's own approach turned
    // about the working end's axis (roll), leaning toward the front of the
    // mouth or the tooth, tilted off the normal; of these, those from which the
    // instrument comes down its axis to the surface without meeting anything,
    // preferring one the hand can turn to straight from where it is, then a
    // long free way in (at least 3 mm), then the least turn. Where nothing is
    // free at a proximal surface's spot (the neighbour in the way), another
    // spot of that surface; where nothing is free at all, less clearance.
    std::vector<UnitApproach> spots = {*t};
    if (!t->region && (name != "rough" || !rough_lesion))
      for (const UnitApproach& a : ProximalSpots(scene, unit.fdi, unit.surface))
        spots.push_back(a);
    struct Candidate {
      UnitApproach spot;
      Quaternion q;
      Vector3 above;
      double d, turn;
      bool straight;
    };
    std::vector<Candidate> cands;
    const bool have_prev = !moves_.empty();
    const Vector3 prev_p =
        have_prev ? Vector3(moves_.back().X_WH.translation()) : Vector3::Zero();
    const Quaternion prev_q =
        have_prev ? Quaternion(moves_.back().X_WH.rotation()) : Quaternion::Identity();
    for (double margin : {0.3, 0.1, 0.02}) {
      for (const UnitApproach& spot : spots) {
        const Vector3 off = spot.p + clear * spot.n;
        for (double roll : {0.0, 0.8, -0.8, 1.57, -1.57})
          for (double tilt : {0.0, -0.15, -0.3})
            for (double lean : {0.0, 0.4, 0.8, 1.2, -0.4, -0.8}) {
              ScriptTarget st;
              st.n_W = spot.n;
              st.tool_axis_W =
                  (spot.axis + lean * Vector3::UnitY() + tilt * spot.n).normalized();
              st.shank_W = Eigen::AngleAxisd(roll, st.tool_axis_W) * spot.shank;
              const Quaternion qc = ScriptOrientation(st);
              if (!clearance.Free(off, qc, margin)) continue;
              double d = 1.0;
              for (double c : {8.0, 6.0, 4.0, 3.0, 2.0})
                if (clearance.PathFree(off, qc, off + c * st.tool_axis_W, qc, margin)) {
                  d = c;
                  break;
                }
              const Vector3 ab = off + d * st.tool_axis_W;
              const bool straight =
                  have_prev && clearance.PathFree(prev_p, prev_q, ab, qc, 0.1);
              cands.push_back({spot, qc, ab, d,
                               have_prev ? prev_q.angularDistance(qc) : 0.0, straight});
            }
        if (!cands.empty()) break;
      }
      if (!cands.empty()) break;
    }
    std::stable_sort(cands.begin(), cands.end(),
                     [](const Candidate& a, const Candidate& b) {
                       if (a.straight != b.straight) return a.straight;
                       if ((a.d >= 3) != (b.d >= 3)) return a.d >= 3;
                       return a.turn < b.turn;
                     });
    // The first of them the hand can get to with the whole instrument clear.
    const Candidate* pick = cands.empty() ? nullptr : &cands.front();
    std::optional<std::vector<RigidTransform>> route;
    if (have_prev && !first)
      for (std::size_t k = 0; k < cands.size() && k < 40; ++k)
        if ((route = clearance.Route(moves_.back().X_WH,
                                     RigidTransform(cands[k].q, cands[k].above), hub,
                                     front, 0.05))) {
          pick = &cands[k];
          break;
        }
    Quaternion q;
    Vector3 above;
    if (pick) {
      q = pick->q;
      above = pick->above;
      *t = pick->spot;
    } else {  // nowhere free: as the surface's own approach says
      ScriptTarget st;
      st.n_W = t->n;
      st.tool_axis_W = t->axis;
      st.shank_W = t->shank;
      q = ScriptOrientation(st);
      above = t->pre.squaredNorm() > 0 ? t->pre
                                       : Vector3(t->p + clear * t->n + 8.0 * t->axis);
    }
    const Vector3 off = t->p + clear * t->n, in = t->p - 0.5 * t->n;
    if (first) {
      // The first pose: up the instrument's axis, or in front of the mouth,
      // where the whole instrument is clear of everything and comes straight
      // to the surface.
      const Vector3 up = q * Vector3::UnitZ();
      Vector3 start = above + 10.0 * up;
      for (const Vector3& dir : {up, Vector3(Vector3::UnitY()),
                                 Vector3((up + Vector3::UnitY()).normalized())}) {
        bool found = false;
        for (double l : {10.0, 15.0, 20.0, 30.0, 40.0})
          if (clearance.PathFree(above + l * dir, q, above, q, 0.3)) {
            start = above + l * dir;
            found = true;
            break;
          }
        if (found) break;
      }
      move(start, q, 0.0);
      move(start, q, 0.6);  // the ramp-in, away from everything
      first = false;
    } else {
      // The way there (Clearance::Route); where none is found, straight, or
      // between regions through the middle of the mouth.
      if (!pick)
        route = clearance.Route(moves_.back().X_WH, RigidTransform(q, above), hub, front,
                                0.05);
      if (route)
        for (const RigidTransform& w : *route) {
          const double len = (w.translation() - moves_.back().X_WH.translation()).norm();
          move(w.translation(), Quaternion(w.rotation()), std::max(0.25, len / 60.0));
        }
      else if (t->region || last_region)
        move(hub, q,
             std::max(0.25, (hub - moves_.back().X_WH.translation()).norm() / 60.0));
    }
    last_region = t->region;
    const double travel = (above - moves_.back().X_WH.translation()).norm();
    move(above, q, std::max(0.25, travel / 60.0));
    move(off, q, std::max(0.2, (off - above).norm() / 40.0));
    // Soft tissue bulges where its sphere-tree says it does not quite: coming
    // down to a region the hand stops where it first feels the tissue (0.1 N),
    // and presses from there toward the spot, as a hand does.
    if (t->region) moves_.back().stop_force_n = 0.1;
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
    if (t->region) {
      stroke.aim_W = t->p;
      stroke.max_depth_mm = 1.0;
    }
    moves_.push_back(stroke);
    move(above, q, std::max(0.2, (off - above).norm() / 40.0));
  }
  if (moves_.empty())
    throw std::invalid_argument("the lesson has nothing this inspector can reach");
  move(moves_.back().X_WH.translation(), Quaternion(moves_.back().X_WH.rotation()), 0.3);
}

std::unique_ptr<ScriptedHand> MakeScriptedHand(const std::string& name,
                                               const LessonSpec& spec,
                                               const CompiledScene& scene) {
  if (spec.inspection()) return std::make_unique<ScriptedInspector>(name, spec, scene);
  if (name == "keys") return MakeScriptedKeys(spec, scene);
  return std::make_unique<ScriptedStudent>(name, spec, scene);
}

LessonDevice MakeLessonDevice(const std::string& spelling, const LessonSpec& spec,
                              const CompiledScene& scene, double seconds) {
  LessonDevice out;
  const DeviceName name = ParseDeviceName(spelling);
  if (name.kind == DeviceName::Kind::kMouse) {
    out.device.name = spelling;
  } else if (name.kind == DeviceName::Kind::kStudent) {
    out.student = MakeScriptedHand(name.what, spec, scene);
    out.device.device = out.student->MakeDevice();
    out.device.name = spelling;
  } else {
    out.device = MakeDevice(spelling, scene, seconds);
  }
  return out;
}

std::unique_ptr<Device> ScriptedInspector::MakeDevice() const {
  return MakeHandDevice(moves_, "student:" + name_);
}

void ScriptedInspector::OnTick(const TickRecord& r) {
  last_tick_ = r.tick;
  if (!lesson_ || !lesson_->inspection()) return;
  const auto& units = lesson_->inspection()->units();
  auto is = [](const Finding& a, const Finding& b) {
    return a.kind == b.kind && a.fdi == b.fdi && a.surface == b.surface;
  };
  auto record = [&](Finding f) {
    if (std::any_of(missed_.begin(), missed_.end(),
                    [&](const Finding& m) { return is(m, f); }))
      return;
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
            unit.fdi, unit.surface == ToothSurface::kBuccal ? ToothSurface::kLingual
                                                            : ToothSurface::kBuccal);
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
