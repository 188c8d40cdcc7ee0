#include "core/lesson/scripted_student.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/anatomy/arch.h"
#include "core/base/text.h"

namespace sulcus {
namespace {

constexpr double kPi = std::numbers::pi;

struct ToothFrame {
  const LessonGeometry::Tooth* g;
  // Where the shank turns (the tool's -x): away from the arch on a buccal
  // pass, toward the mouth's middle on a lingual one, as a clinician holds the
  // probe; one direction for the whole pass, so the handle never swings round
  // the working end between strokes.
  Vector3 shank_W = Vector3::Zero();
  Vector3 World(const Vector3& p_T) const {
    return g->X_WT * ArchMirror(g->mirrored, p_T);
  }
  Vector3 Axis() const { return g->X_WT.rotation().col(2); }
  int Segments() const { return static_cast<int>(g->margin_z.size()); }
  int SegmentAt(double phi) const {
    const int n = Segments();
    double a = std::fmod(phi, 2 * kPi);
    if (a < 0) a += 2 * kPi;
    return static_cast<int>(std::lround(a / (2 * kPi) * n)) % n;
  }
  // The sulcus' middle at angle phi, `depth` below the margin.
  Vector3 Sulcus(double phi, double depth, double out = 0) const {
    const int k = SegmentAt(phi);
    const double r = g->sulcus_r[k] + out, z = g->margin_z[k] - depth;
    return World(Vector3(r * std::cos(phi), r * std::sin(phi), z));
  }
  double Pocket(double phi) const {
    const int k = SegmentAt(phi);
    return g->margin_z[k] - g->floor_z[k];
  }
  // The working end along the long axis, tilted `tilt_deg` away from the tooth
  // (outward at phi), as the crown's bulge asks.
  // Near a contact, the handle leans away from it so that the tip goes under
  // the contact point into the col (up to kColTiltDeg at the contact).
  Quaternion Tool(double phi, double tilt_deg) const {
    auto dir = [&](const Vector3& v_T) {
      return Vector3(g->X_WT.rotation() * ArchMirror(g->mirrored, v_T));
    };
    const Vector3 out_W = dir(Vector3(std::cos(phi), std::sin(phi), 0));
    const Vector3 tangent_W = dir(Vector3(-std::sin(phi), std::cos(phi), 0));
    const double t = tilt_deg * kPi / 180;
    Vector3 axis = std::cos(t) * Axis() + std::sin(t) * out_W;
    for (const auto& [contact, has] :
         {std::pair{0.0, g->mesial_contact}, std::pair{kPi, g->distal_contact}}) {
      if (!has) continue;
      double d = std::remainder(phi - contact, 2 * kPi);  // signed, -pi..pi
      const double near = 1.0 - std::abs(d) / (kColZoneDeg * kPi / 180);
      if (near <= 0) continue;
      const double lean = kColTiltDeg * kPi / 180 * near;
      axis +=
          std::tan(lean) * (d >= 0 ? 1.0 : -1.0) * tangent_W;  // away from the contact
    }
    const Vector3 z = axis.normalized();
    Vector3 x = -(shank_W - shank_W.dot(z) * z);
    if (x.norm() < 0.1) return Quaternion::FromTwoVectors(Vector3::UnitZ(), z);
    x.normalize();
    Matrix3 R;
    R.col(0) = x;
    R.col(1) = z.cross(x);
    R.col(2) = z;
    return Quaternion(R);
  }
  static constexpr double kColZoneDeg = 35, kColTiltDeg = 25;
};

}  // namespace

const std::vector<std::string>& ScriptedStudentNames() {
  static const std::vector<std::string> names = {
      "careful",  "rough",     "misreading", "spot",     "lazy",  "tremor", "slow",
      "hesitant", "overshoot", "occlusal",   "charting", "human", "keys"};
  return names;
}

ScriptedStudent::ScriptedStudent(const std::string& name, const LessonSpec& spec,
                                 const CompiledScene& scene)
    : name_(name), spec_(spec) {
  const auto& names = ScriptedStudentNames();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    throw std::invalid_argument("unknown scripted student '" + name +
                                "'; known: " + Join(names));
  }
  const LessonGeometry geometry = MakeLessonGeometry(scene, spec.teeth);
  // The teeth and surfaces in path order.
  struct Pass {
    int fdi;
    bool buccal;
  };
  std::vector<Pass> passes;
  for (const SiteRef& s : spec.path) {
    const bool buccal = s.site < 3;
    if (passes.empty() || passes.back().fdi != s.fdi || passes.back().buccal != buccal)
      passes.push_back({s.fdi, buccal});
  }
  std::vector<int> order;
  for (const Pass& p : passes)
    if (std::find(order.begin(), order.end(), p.fdi) == order.end())
      order.push_back(p.fdi);
  if (name == "lazy" && order.size() >= 2) skipped_.push_back(order[1]);
  if (name == "misreading") {
    for (std::size_t i = 0; i < order.size() && misread_.size() < 3; ++i)
      for (const SiteRef& s : spec.path)
        if (s.fdi == order[i] && IsInterdental(s.site)) {
          misread_.push_back(s);
          break;
        }
  }
  // The human hands.
  const bool human = name == "human";
  const bool spot = name == "spot" || name == "occlusal";
  if (name == "tremor") hand_ = {.tremor_mm = 0.06, .tremor_deg = 0.3, .drift_mm = 0.2};
  if (human) hand_ = {.tremor_mm = 0.06, .tremor_deg = 0.3, .drift_mm = 0.15};
  const double slow = name == "slow" ? 3.0 : human ? 1.5 : 1.0;  // moves' durations
  const double stroke_speed = name == "slow" ? 2.0 : human ? 3.0 : 12.0;
  const bool overshoot = name == "overshoot";
  chart_at_rest_ = name == "charting" || human;
  const double target_n = name == "rough" ? 2.0 : overshoot ? 0.36 : 0.20;
  const double past_floor_mm =
      name == "rough" ? 1.5 : 0.5;  // the deepest a stroke goes if it feels nothing
  const double tilt_deg = 4.0;
  const double lift_mm = 12.0;  // above the margin: clear of every crown
  auto move = [&](const Vector3& p, const Quaternion& q, double s) {
    Move m;
    m.X_WH = RigidTransform(q, p);
    m.duration_s = s * slow;
    moves_.push_back(m);
  };
  bool first = true;
  for (const Pass& pass : passes) {
    if (std::find(skipped_.begin(), skipped_.end(), pass.fdi) != skipped_.end()) continue;
    const LessonGeometry::Tooth* g = geometry.Find(pass.fdi);
    if (!g) continue;
    ToothFrame f{g};
    f.shank_W = g->X_WT.rotation() *
                ArchMirror(g->mirrored, Vector3(0, pass.buccal ? 1.0 : -1.0, 0));
    // The surface in the tooth frame: buccal angles 0..pi, lingual pi..2 pi.
    // The tip goes in at the distal line angle (DB, DL), walks distally under
    // the contact into the col, then the whole arc to the mesial col, and back
    // to the mesial line angle (MB, ML) to come out: it never comes down or
    // lifts out under a contact, where the crowns meet above the sulcus.
    const double distal = pass.buccal ? kPi * 172 / 180 : kPi * 188 / 180;
    const double mesial = pass.buccal ? kPi * 8 / 180 : kPi * 352 / 180;
    const double enter = g->site_angle[pass.buccal ? 2 : 5],
                 leave = g->site_angle[pass.buccal ? 0 : 3];
    const double r = g->sulcus_r[f.SegmentAt(kPi / 2)];
    auto arc = [&](double a, double b, double spacing) {
      std::vector<double> v;
      const int n =
          std::max(1, static_cast<int>(std::ceil(std::abs(b - a) * r / spacing)));
      for (int i = 1; i <= n; ++i) v.push_back(a + (b - a) * i / n);
      return v;
    };
    struct Stop {
      double phi;
      bool stroke;
    };
    std::vector<Stop> stops;
    if (spot) {
      for (int s : pass.buccal ? std::array{2, 1, 0} : std::array{5, 4, 3})
        stops.push_back({g->site_angle[s], true});
    } else {
      stops.push_back({enter, true});
      for (double phi : arc(enter, distal, 0.8)) stops.push_back({phi, true});
      // Strokes 0.8 mm apart, and one at each site's own angle (where a clinician reads
      // it).
      std::vector<double> walk = arc(distal, mesial, 0.8);
      for (int s : pass.buccal ? std::array{0, 1, 2} : std::array{3, 4, 5})
        walk.push_back(g->site_angle[s]);
      std::sort(walk.begin(), walk.end(), [&](double a, double b) {
        return std::abs(a - distal) < std::abs(b - distal);
      });
      for (double phi : walk) stops.push_back({phi, true});
      for (double phi : arc(mesial, leave, 0.8)) stops.push_back({phi, false});
    }
    const double phi0 = stops.front().phi;
    const Quaternion q0 = f.Tool(phi0, tilt_deg);
    move(f.Sulcus(phi0, -lift_mm, 2.5), q0, first ? 0.0 : 0.6);
    if (first)
      move(f.Sulcus(phi0, -lift_mm, 2.5), q0, 0.6);  // the ramp-in, away from everything
    first = false;
    move(f.Sulcus(phi0, -1.0), q0, 0.8);
    for (const Stop& stop : stops) {
      const double phi = stop.phi;
      const Quaternion q = f.Tool(phi, tilt_deg);
      // Each stroke starts 1 mm below the margin and goes down the tool's axis;
      // the spot-prober starts above the margin each time, the occlusal
      // approach 2 mm above it (over the crown).
      const double top = name == "occlusal" ? -2.0 : spot ? -1.0 : 1.0;
      move(f.Sulcus(phi, top), q, spot ? 0.5 : 0.15);
      if (!stop.stroke) continue;
      Move stroke;
      stroke.stroke = true;
      stroke.X_WH = moves_.back().X_WH;
      const Vector3 axis = q * Vector3::UnitZ();
      const double cos_tilt = std::max(0.5, axis.dot(f.Axis()));
      stroke.max_depth_mm = (f.Pocket(phi) - top + past_floor_mm) / cos_tilt;
      stroke.target_force_n = target_n;
      stroke.speed_mm_s = stroke_speed;
      // A person rests at the floor and keeps the force there.
      if (overshoot || name == "tremor" || human) {
        stroke.hold_force_n = 0.22;
        stroke.hold_s = 1.0;
      }
      if (name == "hesitant") {
        stroke.pause_at_mm = 0.5 * f.Pocket(phi) - top;
        stroke.pause_s = 0.3;
      }
      // At each site's own angle a charting hand rests and charts.
      const bool own = std::any_of(g->site_angle.begin(), g->site_angle.end(),
                                   [&](double a) { return a == phi; });
      if (chart_at_rest_ && own) {
        stroke.chart_at_rest = true;
        stroke.hold_s = 1.0;
      }
      moves_.push_back(stroke);
    }
    const double phi1 = stops.back().phi;
    move(f.Sulcus(phi1, -1.0), f.Tool(phi1, tilt_deg), 0.5);
    move(f.Sulcus(phi1, -lift_mm, 2.5), f.Tool(phi1, tilt_deg), 0.6);
  }
  if (moves_.empty())
    throw std::invalid_argument("the lesson has no teeth this student can reach");
  move(moves_.back().X_WH.translation(), Quaternion(moves_.back().X_WH.rotation()), 0.5);
}

namespace {

// Plays a student's moves by loop time, feeling the force written back.
class StudentDevice final : public Device {
 public:
  StudentDevice(std::vector<ScriptedStudent::Move> moves, std::string name,
                ScriptedStudent::HandStyle hand)
      : moves_(std::move(moves)), hand_(hand) {
    caps_.name = std::move(name);
    caps_.output_dof = 3;
    caps_.max_force_n = 3.3;
    caps_.max_torque_nmm = 515;
    if (!moves_.empty()) pose_ = moves_.front().X_WH;
  }
  const DeviceCaps& caps() const override { return caps_; }
  bool finished() const noexcept override { return i_ >= moves_.size(); }
  // What the hand feels of a stroke: the force against its way down (the
  // floor), not the gingiva's and the tooth's sideways push.
  void Write(const Vector3& force_W, const Vector3&) noexcept override {
    force_n_ =
        i_ < moves_.size() ? -force_W.dot(top_set_ ? down_ : Down(moves_[i_])) : 0.0;

    force_W_ = force_W;
  }
  bool Read(double t_s, DeviceSample* out) noexcept override {
    const double dt = started_ ? t_s - last_t_ : 0;
    started_ = true;
    last_t_ = t_s;
    // What a hand perceives of the force: low-passed at 3 Hz.
    felt_lp_n_ += (1.0 - std::exp(-2 * kPi * 3.0 * dt)) * (force_n_ - felt_lp_n_);
    while (i_ < moves_.size()) {
      const ScriptedStudent::Move& m = moves_[i_];
      if (!m.stroke) {
        if (phase_t_ == 0) from_ = pose_;
        phase_t_ += dt;
        const double s = m.duration_s > 0 ? std::min(1.0, phase_t_ / m.duration_s) : 1.0;
        const Quaternion q =
            Quaternion(from_.rotation()).slerp(s, Quaternion(m.X_WH.rotation()));
        pose_ = RigidTransform(
            q, from_.translation() + s * (m.X_WH.translation() - from_.translation()));
        if (s < 1.0 && !(m.stop_force_n > 0 && force_W_.norm() >= m.stop_force_n)) break;
        Next();
        break;
      }
      // A stroke: in at its speed until the force is felt, a rest at the bottom, back at
      // 20 mm/s.
      if (!top_set_) {
        const bool aimed = m.aim_W.squaredNorm() > 0;
        top_ = aimed ? pose_ : m.X_WH;
        down_ = Down(m);
        max_depth_ = m.max_depth_mm;
        // Toward the spot it aims at, from wherever the hand stopped, and as far past it.
        if (const Vector3 to = m.aim_W - top_.translation(); aimed && to.norm() > 1e-6) {
          down_ = to.normalized();
          max_depth_ = to.norm() + m.max_depth_mm;
        }
        top_set_ = true;
      }
      const Vector3 down = down_;
      if (phase_ == 0 && m.pause_s > 0 && !paused_ && depth_ >= m.pause_at_mm) {
        pause_t_ += dt;  // a hesitation on the way down
        if (pause_t_ >= m.pause_s) paused_ = true;
      } else if (phase_ == 0) {
        depth_ += m.speed_mm_s * dt;
        if (force_n_ >= m.target_force_n || depth_ >= max_depth_) {
          depth_ = std::min(depth_, max_depth_);
          phase_ = 1;
          phase_t_ = 0;
        }
      } else if (phase_ == 1) {
        phase_t_ += dt;
        // Backing off from an overshoot: up slowly until the force is the one meant.
        if (m.hold_force_n > 0) depth_ += 4.0 * (m.hold_force_n - felt_lp_n_) * dt;
        if (phase_t_ >= m.hold_s) phase_ = 2;
      } else {
        depth_ -= 20.0 * dt;
        if (depth_ <= 0) {
          depth_ = 0;
          pose_ = top_;
          Next();
          break;
        }
      }
      pose_ = RigidTransform(top_.rotation(), top_.translation() + depth_ * down);
      break;
    }
    out->X_WH = Hand(pose_, t_s);
    out->buttons = 0;
    out->time_s = t_s;
    return true;
  }

 private:
  static Vector3 Down(const ScriptedStudent::Move& m) {
    return m.direction_W.squaredNorm() > 0
               ? m.direction_W.normalized()
               : Vector3(-(m.X_WH.rotation() * Vector3::UnitZ()));
  }
  void Next() {
    ++i_;
    phase_ = 0;
    phase_t_ = 0;
    depth_ = 0;
    top_set_ = false;
    paused_ = false;
    pause_t_ = 0;
  }
  // The pose the hand holds for the pose it means: tremor, drift, key steps.
  RigidTransform Hand(const RigidTransform& X, double t) {
    const ScriptedStudent::HandStyle& h = hand_;
    Vector3 p = X.translation();
    Quaternion q(X.rotation());
    if (h.tremor_mm > 0 || h.drift_mm > 0) {
      constexpr double k2Pi = 2 * kPi;
      const Vector3 u1 = Vector3(0.6, 0.3, 0.74).normalized(),
                    u2 = Vector3(-0.4, 0.8, 0.45).normalized(),
                    u3 = Vector3(0.2, -0.5, 0.84).normalized();
      p += h.tremor_mm *
           (std::sin(k2Pi * 9.5 * t) * u1 + 0.7 * std::sin(k2Pi * 11.3 * t + 1.0) * u2);
      p += h.drift_mm * std::sin(k2Pi * 0.07 * t) * u3;
      const double a = h.tremor_deg * kPi / 180 * std::sin(k2Pi * 9.5 * t + 0.5);
      q = Quaternion(Eigen::AngleAxisd(a, u2)) * q;
    }
    if (h.step_mm > 0) {
      if (!keys_set_) {
        keys_ = p;
        keys_set_ = true;
        last_step_t_ = t;
      }
      // One key step per axis at most every step_s, toward where the hand means to be.
      if (t - last_step_t_ >= h.step_s) {
        last_step_t_ = t;
        for (int k = 0; k < 3; ++k) {
          const double d = p[k] - keys_[k];
          if (std::abs(d) >= 0.5 * h.step_mm) keys_[k] += d > 0 ? h.step_mm : -h.step_mm;
        }
      }
      p = keys_;
    }
    return RigidTransform(q, p);
  }
  std::vector<ScriptedStudent::Move> moves_;
  ScriptedStudent::HandStyle hand_;
  bool paused_ = false, keys_set_ = false;
  double pause_t_ = 0, last_step_t_ = 0;
  Vector3 keys_ = Vector3::Zero();
  DeviceCaps caps_;
  std::size_t i_ = 0;
  int phase_ = 0;
  double phase_t_ = 0, depth_ = 0, last_t_ = 0, force_n_ = 0, felt_lp_n_ = 0;
  Vector3 force_W_ = Vector3::Zero();
  bool started_ = false;
  bool top_set_ = false;
  Vector3 down_ = Vector3::UnitZ();
  double max_depth_ = 0;
  RigidTransform pose_, from_, top_;
};

}  // namespace

std::unique_ptr<Device> MakeHandDevice(std::vector<ScriptedStudent::Move> moves,
                                       std::string name,
                                       ScriptedStudent::HandStyle hand) {
  return std::make_unique<StudentDevice>(std::move(moves), std::move(name), hand);
}

std::unique_ptr<Device> ScriptedStudent::MakeDevice() const {
  return MakeHandDevice(moves_, "student:" + name_, hand_);
}

void ScriptedStudent::OnTick(const TickRecord& r) {
  last_tick_ = r.tick;
  // Charting at rest: a site the tip has rested in for 0.5 s (within 0.15 mm,
  // a trembling hand's stillness) is charted there, the probe still in it.
  if (chart_at_rest_ && lesson_) {
    const auto site = lesson_->tip_site();
    const auto depth = lesson_->tip_depth_mm();
    if (!site || !depth || site != rest_site_ || std::abs(*depth - rest_depth_) > 0.15) {
      rest_site_ = site;
      rest_since_s_ = r.time_s;
      rest_depth_ = depth.value_or(0);
    } else if (r.time_s - rest_since_s_ >= 0.5 && *depth >= 0.5 &&
               std::find(charted_.begin(), charted_.end(), *site) == charted_.end() &&
               std::find(spec_.path.begin(), spec_.path.end(), *site) !=
                   spec_.path.end()) {
      ChartEntry e;
      e.site = *site;
      e.tick = r.tick + 1;
      e.pd_mm = static_cast<int>(std::lround(*depth));
      lesson_->Enter(e);
      charted_.push_back(*site);
    }
  }
  for (int i = 0; i < r.num_events; ++i) {
    const HapticEvent& e = r.events[i];
    if (e.kind != EventKind::kProbeReading && e.kind != EventKind::kBleeding) continue;
    const SiteRef s = e.kind == EventKind::kProbeReading
                          ? SiteRef{e.payload.reading.fdi, e.payload.reading.site}
                          : SiteRef{e.payload.bleeding.fdi, e.payload.bleeding.site};
    auto it = std::find_if(seen_.begin(), seen_.end(),
                           [&](const Seen& x) { return x.site == s; });
    if (it == seen_.end()) it = seen_.insert(seen_.end(), {s, 0, false, 0});
    if (e.kind == EventKind::kBleeding) {
      it->bled = true;
    } else if (e.payload.reading.depth_mm > it->deepest) {
      it->deepest = e.payload.reading.depth_mm;
    }
    it->tick = e.tick;
  }
}

void ScriptedStudent::OnEnd() {
  if (!lesson_) return;
  // The chart in path order, then the diagnosis of that chart (its own, by the
  // 2017 rules: the student does not need the lesson's score for it).
  // What the examiner is given (the history, mobility, furcation), then the readings.
  PerioChart chart = lesson_->GivenChart();
  for (const SiteRef& s : spec_.path) {
    const auto it = std::find_if(seen_.begin(), seen_.end(),
                                 [&](const Seen& x) { return x.site == s; });
    if (it == seen_.end() || it->deepest <= 0) continue;
    // Bleeding as it showed at the margin (not the scene's truth, nor the
    // moment the effect reported it).
    it->bled = lesson_->blood_seen(s);
    // Charted at rest already: only its bleeding, seen since, is added.
    if (std::find(charted_.begin(), charted_.end(), s) != charted_.end()) {
      if (it->bled) {
        ChartEntry b;
        b.site = s;
        b.tick = last_tick_ + 1;
        b.bleeding = true;
        lesson_->Enter(b);
      }
      if (ToothChart* t = chart.Find(s.fdi)) {
        const auto x =
            std::find_if(lesson_->entries().rbegin(), lesson_->entries().rend(),
                         [&](const ChartEntry& c) { return c.site == s && c.pd_mm; });
        if (x != lesson_->entries().rend())
          t->sites[s.site] = {*x->pd_mm, lesson_->recession_mm(s), it->bled};
      }
      continue;
    }
    // Stamped when it is entered (the end), as the window stamps an entry: a
    // replay with these answers applies it at the same moment.
    ChartEntry e;
    e.site = s;
    e.tick = last_tick_ + 1;
    int pd = static_cast<int>(std::lround(it->deepest));
    if (std::find(misread_.begin(), misread_.end(), s) != misread_.end()) pd += 2;
    e.pd_mm = pd;
    e.bleeding = it->bled;
    lesson_->Enter(e);
    if (ToothChart* t = chart.Find(s.fdi))
      t->sites[s.site] = {pd, lesson_->recession_mm(s), it->bled};
  }
  lesson_->Declare(DiagnosisOfChart(chart, last_tick_));
}

DeclaredDiagnosis DiagnosisOfChart(const PerioChart& chart, std::uint64_t tick) {
  const Diagnosis mine = Classify2017(chart);
  DeclaredDiagnosis d;
  d.tick = tick;
  d.periodontitis = mine.kind == Diagnosis::Kind::kPeriodontitis;
  d.stage = mine.stage;
  d.extent = mine.extent;
  d.grade = mine.grade;
  return d;
}

}  // namespace sulcus
