#include "core/lesson/lesson.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/tooth.h"
#include "core/lesson/scoring_parts.h"

namespace sulcus {
using namespace lesson_detail;  // the helpers the state machine and scorers share

const char* ToString(RubricLine::Status s) {
  switch (s) {
    case S::kPass:
      return "pass";
    case S::kPartial:
      return "partial";
    case S::kFail:
      return "fail";
    case S::kInfo:
      return "info";
  }
  return "?";
}

RubricLine::Status AngleStatus(double angle_deg, const RubricSpec& rubric) {
  return angle_deg <= rubric.angle_full_deg   ? S::kPass
         : angle_deg <= rubric.angle_pass_deg ? S::kPartial
                                              : S::kFail;
}

std::string DeclaredDiagnosis::Summary() const {
  if (!periodontitis) return "no periodontitis";
  std::string s =
      std::string("periodontitis stage ") + ToString(stage) + ", " + ToString(extent);
  if (grade != Grade::kNone) s += std::string(", grade ") + ToString(grade);
  return s;
}

const LessonGeometry::Tooth* LessonGeometry::Find(int fdi) const {
  for (const Tooth& t : teeth)
    if (t.fdi == fdi) return &t;
  return nullptr;
}

LessonGeometry MakeLessonGeometry(const CompiledScene& scene,
                                  const std::vector<int>& teeth) {
  LessonGeometry g;
  const auto& objs = scene.spec.objects;
  auto has_tooth = [&](int fdi) {
    return std::any_of(objs.begin(), objs.end(), [&](const ObjectSpec& o) {
      return o.kind == ObjectSpec::Kind::kTooth && o.fdi == fdi;
    });
  };
  for (int fdi : teeth) {
    LessonGeometry::Tooth t;
    t.fdi = fdi;
    const ObjectSpec* gum = nullptr;
    for (int i = 0; i < static_cast<int>(objs.size()); ++i) {
      if (objs[i].kind == ObjectSpec::Kind::kTooth && objs[i].fdi == fdi) {
        t.object = i;
        t.X_WT = objs[i].X_WO;
        t.mirrored = objs[i].mirrored;
      }
      if (objs[i].kind == ObjectSpec::Kind::kGingiva && objs[i].fdi == fdi)
        gum = &objs[i];
    }
    if (t.object < 0 || !gum) continue;
    GingivaParams p;
    p.pocket_mm = gum->pocket_mm;
    p.recession_mm = gum->recession_mm;
    const GingivaModel m = GenerateGingiva(GenerateTooth(fdi), p);
    t.margin_z = m.margin_z;
    t.floor_z = m.floor_z;
    t.sulcus_r = m.sulcus_r;
    t.site_angle = m.site_angle;
    const int q = fdi / 10, pos = fdi % 10;
    t.mesial_contact = pos == 1 ? has_tooth((q % 2 == 1 ? q + 1 : q - 1) * 10 + 1)
                                : has_tooth(q * 10 + pos - 1);
    t.distal_contact = has_tooth(q * 10 + pos + 1);
    g.teeth.push_back(std::move(t));
  }
  return g;
}

LessonRun::LessonRun(const LessonSpec& spec, const CompiledScene& scene,
                     std::string student, std::uint64_t case_seed)
    : spec_(spec),
      scene_(scene),
      geometry_(spec.inspection() ? LessonGeometry{}
                                  : MakeLessonGeometry(scene, spec.teeth)),
      student_(std::move(student)),
      case_seed_(case_seed),
      rate_hz_(scene.spec.rate_hz > 0 ? scene.spec.rate_hz : 1000),
      locator_(scene.effects.sites),
      tracker_(rate_hz_) {
  const PerioChart truth = TrueChart(scene.spec, spec.teeth);
  for (const SiteRef& s : spec.path) {
    SiteResult r;
    r.site = s;
    if (const ToothChart* t = truth.Find(s.fdi)) {
      r.truth_mm = t->sites[s.site].pd_mm.value_or(0);
      r.recession_mm = t->sites[s.site].recession_mm;
      r.truth_bleeding = t->sites[s.site].bleeding;
    }
    const LessonGeometry::Tooth* g = geometry_.Find(s.fdi);
    r.interproximal_contact = g && IsInterdental(s.site) &&
                              (IsMesial(s.site) ? g->mesial_contact : g->distal_contact);
    sites_.push_back(r);
  }
  for (const StepSpec& st : spec.steps) step_results_.push_back({st.id, st.instruction});
  for (const ProbingSite& p : scene.effects.sites)
    path_index_.push_back(SiteIndex({p.fdi, p.site}));
  visit_deepest_.assign(sites_.size(), -1e9);
  near_other_.assign(sites_.size(), 0);
  in_contact_.assign(scene.spec.objects.size(), 0);
  surfaces_.resize(geometry_.teeth.size());
  // The surfaces' arcs: the tooth's own sulcus, from the col's midline on one
  // side to the other's (tip_locator.h), short of each by kColMarginMm.
  arcs_.assign(geometry_.teeth.size(),
               {std::pair{kArcFromDeg, kArcToDeg}, std::pair{kArcFromDeg, kArcToDeg}});
  for (std::size_t i = 0; i < geometry_.teeth.size(); ++i) {
    const ProbingSite* site = nullptr;
    for (const ProbingSite& p : scene.effects.sites)
      if (p.fdi == geometry_.teeth[i].fdi && p.ring) site = &p;
    if (!site) continue;
    const SulcusRing& g = *site->ring;
    auto deg = [&](int s) {
      const double phi = g.col_phi[static_cast<std::size_t>(s)];
      const double r =
          std::max(0.5, g.sulcus_r[static_cast<std::size_t>(g.SegmentAt(phi))]);
      double d = std::fmod(phi * 180 / kPi, 360.0);
      if (d < 0) d += 360;
      return std::pair{d, kColMarginMm / r * 180 / kPi};
    };
    const auto [mb, mb_m] = deg(0);
    const auto [db, db_m] = deg(2);
    const auto [ml, ml_m] = deg(3);
    const auto [dl, dl_m] = deg(5);
    const double ml_d = ml < 1e-9 ? 0.0 : 360.0 - ml;  // 0 stays 0
    arcs_[i][0] = {std::max(kArcFromDeg, mb + mb_m), std::min(kArcToDeg, db - db_m)};
    arcs_[i][1] = {std::max(kArcFromDeg, ml_d + ml_m),
                   std::min(kArcToDeg, 360.0 - dl - dl_m)};
  }
  for (std::size_t i = 0; i < geometry_.teeth.size(); ++i)
    for (SurfaceTrack& s : surfaces_[i])
      s.bins.assign(geometry_.teeth[i].margin_z.size(), false);
  if (spec.inspection()) {
    inspection_.emplace(spec_, scene);
    for (const StepSpec& st : spec_.steps)
      step_units_.push_back(inspection_->StepUnits(st));
    odontogram_ = EmptyOdontogram(spec_.teeth);
    truth_ = TrueOdontogram(scene.spec, spec_.teeth, spec_.regions);
  }
}

PerioChart LessonRun::GivenChart() const {
  PerioChart chart = TrueChart(scene_.spec, spec_.teeth);
  for (ToothChart& t : chart.teeth)
    for (SiteValues& v : t.sites) {
      v.pd_mm.reset();
      v.bleeding = false;
    }
  return chart;
}

double LessonRun::recession_mm(const SiteRef& s) const {
  const int i = SiteIndex(s);
  return i >= 0 ? sites_[static_cast<std::size_t>(i)].recession_mm : 0.0;
}

int LessonRun::SiteIndex(const SiteRef& s) const {
  for (std::size_t i = 0; i < sites_.size(); ++i)
    if (sites_[i].site == s) return static_cast<int>(i);
  return -1;
}

bool LessonRun::SiteInStep(const StepSpec& st, const SiteRef& s) const {
  if (!st.teeth.empty() &&
      std::find(st.teeth.begin(), st.teeth.end(), s.fdi) == st.teeth.end())
    return false;
  const bool buccal = s.site < 3;
  if (st.surface == StepSpec::Surface::kBuccal && !buccal) return false;
  if (st.surface == StepSpec::Surface::kLingual && buccal) return false;
  return true;
}

bool LessonRun::StepComplete(const StepSpec& st) const {
  if (st.complete == StepSpec::Complete::kDiagnosis) return declared_.has_value();
  if (st.complete == StepSpec::Complete::kRecorded) return submitted_.has_value();
  if (st.complete == StepSpec::Complete::kTouched) {
    const std::size_t i = static_cast<std::size_t>(&st - spec_.steps.data());
    for (int u : step_units_[i])
      if (!inspection_->units()[static_cast<std::size_t>(u)].touched) return false;
    return true;
  }
  for (const SiteResult& r : sites_) {
    if (!SiteInStep(st, r.site)) continue;
    if (st.complete == StepSpec::Complete::kRead && !r.reached_mm) return false;
    if (st.complete == StepSpec::Complete::kCharted && !(r.entry && r.entry->pd_mm))
      return false;
  }
  return true;
}

void LessonRun::Advance(std::uint64_t tick) {
  if (spec_.time_limit_s > 0 &&
      static_cast<double>(tick - first_tick_) > spec_.time_limit_s * rate_hz_) {
    if (!timed_out_)
      feedback_.push_back(Format("%.0f s: the lesson's time is up", spec_.time_limit_s));
    timed_out_ = true;
  }
  while (!timed_out_ && step_ < static_cast<int>(spec_.steps.size())) {
    const StepSpec& st = spec_.steps[step_];
    StepResult& res = step_results_[step_];
    if (StepComplete(st)) {
      res.completed = true;
      res.ended_tick =
          std::max(tick, res.started_tick);  // entries may carry earlier ticks
      ++step_;
      if (step_ < static_cast<int>(spec_.steps.size()))
        step_results_[step_].started_tick = tick;
      continue;
    }
    if (st.time_limit_s > 0 &&
        static_cast<double>(tick - res.started_tick) > st.time_limit_s * rate_hz_) {
      res.timed_out = true;
      res.ended_tick = tick;
      feedback_.push_back("step '" + st.id + "': time is up, on to the next");
      ++step_;
      if (step_ < static_cast<int>(spec_.steps.size()))
        step_results_[step_].started_tick = tick;
      continue;
    }
    break;
  }
}

bool LessonRun::ReadAtFloor(const SiteResult& s) {
  return s.reached_mm && s.held_force_n >= kFloorForceN;
}

std::optional<SiteRef> LessonRun::next_site() const {
  if (done()) return std::nullopt;
  const StepSpec& st = spec_.steps[step_];
  // From the site the student read last (they may have moved on past one),
  // round the path: the first the step still asks for.
  const std::size_t n = sites_.size();
  const std::size_t from = last_read_ < 0 ? 0 : static_cast<std::size_t>(last_read_);
  for (std::size_t k = 0; k < n; ++k) {
    const SiteResult& r = sites_[(from + k) % n];
    if (!SiteInStep(st, r.site)) continue;
    if (st.complete == StepSpec::Complete::kRead && !ReadAtFloor(r)) return r.site;
    if (st.complete == StepSpec::Complete::kCharted && !(r.entry && r.entry->pd_mm))
      return r.site;
  }
  return std::nullopt;
}

void LessonRun::Track(const TickRecord& r) {
  const Vector3 p_W = r.X_WG.translation();
  // The walking stroke's coverage (where the tip is for a reading, and whether
  // it is under a contact, is the tip locator's answer, Locate()). Under a
  // contact the two neighbours' sulci meet (the col): the tip may be in both.
  // Each tooth whose sulcus holds it has the arc marked; the stroke goes to
  // the tooth it is closest to.
  double best_radial = 1e9;
  int best = -1;
  double best_depth = 0, best_phi = 0;
  for (std::size_t i = 0; i < geometry_.teeth.size(); ++i) {
    const LessonGeometry::Tooth& t = geometry_.teeth[i];
    const Vector3 p = ArchMirror(t.mirrored, t.X_WT.inverse() * p_W);
    const int n = static_cast<int>(t.margin_z.size());
    if (n == 0) continue;
    double phi = std::atan2(p.y(), p.x());
    if (phi < 0) phi += 2 * kPi;
    const int k = static_cast<int>(std::lround(phi / (2 * kPi) * n)) % n;
    const double depth = t.margin_z[k] - p.z();
    const double pocket = t.margin_z[k] - t.floor_z[k];
    const double radial = std::abs(std::hypot(p.x(), p.y()) - t.sulcus_r[k]);
    if (radial > 0.9 || depth < 0.3 || depth > pocket + 0.6) continue;
    const bool buccal = p.y() >= 0;
    if (depth >= 0.5)
      surfaces_[i][buccal ? 0 : 1].bins[static_cast<std::size_t>(k)] = true;
    if (radial < best_radial) {
      best_radial = radial;
      best = static_cast<int>(i);
      best_depth = depth;
      best_phi = phi;
    }
  }
  if (best < 0) return;
  const LessonGeometry::Tooth& t = geometry_.teeth[static_cast<std::size_t>(best)];
  const bool buccal = std::sin(best_phi) >= 0;
  SurfaceTrack& st = surfaces_[static_cast<std::size_t>(best)][buccal ? 0 : 1];
  const double depth = best_depth;
  if (!st.any) {
    st.any = true;
    st.first = r.tick;
    st.ext_depth = st.turn_depth = depth;
  }
  st.last = r.tick;
  ++st.in_ticks;
  if (t.object >= 0 && in_contact_[static_cast<std::size_t>(t.object)]) ++st.touch_ticks;
  // Up-and-down strokes: turns of the depth with a little hysteresis.
  const double h = kStrokeHysteresisMm;
  if (st.direction == 0) {
    if (depth > st.ext_depth + h)
      st.direction = 1;
    else if (depth < st.ext_depth - h)
      st.direction = -1;
    if (st.direction != 0) st.ext_depth = depth;
  } else if ((st.direction > 0 && depth > st.ext_depth) ||
             (st.direction < 0 && depth < st.ext_depth)) {
    st.ext_depth = depth;
  } else if (std::abs(depth - st.ext_depth) > h) {
    st.swing_sum += std::abs(st.ext_depth - st.turn_depth);
    ++st.strokes;
    st.turn_depth = st.ext_depth;
    st.ext_depth = depth;
    st.direction = -st.direction;
  }
}

void LessonRun::OnTick(const TickRecord& r) {
  // Entries scheduled for this tick apply before it, as the window's do (it
  // stamps an entry with the tick after the last one the lesson has seen).
  while (!scheduled_.empty() && scheduled_.front().tick <= r.tick) {
    const ChartEntry e = scheduled_.front();
    scheduled_.erase(scheduled_.begin());
    Enter(e);
  }
  if (ticks_ == 0) {
    first_tick_ = r.tick;
    if (!step_results_.empty()) step_results_[0].started_tick = r.tick;
  }
  ++ticks_;
  last_tick_ = r.tick;
  // The probing force: along the probe's axis, as the readings score it.
  if (r.tick % LessonResult::kTraceEvery == 0)
    force_trace_.push_back({r.tick, static_cast<float>(std::max(
                                        0.0, r.force_W.dot(r.X_WG.rotation().col(2))))});
  for (int i = 0; i < r.num_events; ++i) {
    const HapticEvent& e = r.events[i];
    switch (e.kind) {
      case EventKind::kContactBegan:
      case EventKind::kContactEnded:
        if (e.object >= 0 && static_cast<std::size_t>(e.object) < in_contact_.size())
          in_contact_[static_cast<std::size_t>(e.object)] =
              e.kind == EventKind::kContactBegan;
        break;
      case EventKind::kBleeding: {
        const int idx = SiteIndex({e.payload.bleeding.fdi, e.payload.bleeding.site});
        if (idx < 0) break;
        SiteResult& s = sites_[static_cast<std::size_t>(idx)];
        if (!s.bled) {
          s.bled = true;
          s.bleed_force_n = e.payload.bleeding.force_n;
          s.bleed_tick = e.tick;
        }
        break;
      }
      case EventKind::kDeviceLost:
        if (!device_lost()) interruptions_.push_back({r.tick, 0});
        break;
      case EventKind::kDeviceBack:
        if (device_lost()) interruptions_.back().back_tick = r.tick;
        break;
      case EventKind::kCalculusTouched: {
        const CalculusPayload& c = e.payload.calculus;
        const std::string where = std::to_string(c.fdi) + " " + SiteCode(c.site);
        if (std::none_of(felt_.begin(), felt_.end(), [&](const RubricLine& l) {
              return l.fdi == c.fdi && l.message.find(where) != std::string::npos;
            }))
          felt_.push_back(Line(
              "findings", nullptr, c.fdi, S::kInfo, 0,
              Format("calculus felt at %s (%.2f N)", where.c_str(), c.force_n), e.tick));
        break;
      }
      case EventKind::kTissueDamage:
        damage_.push_back({Line("damage", nullptr, 0, S::kFail, 0,
                                Format("%.2f N on %s, above its limit of %.2f N",
                                       e.payload.damage.force_n,
                                       ObjectName(scene_.spec, e.object).c_str(),
                                       e.payload.damage.limit_n),
                                e.tick),
                           -1});
        break;
      default:
        break;
    }
  }
  if (inspection_) {
    FollowInspection(r);
  } else {
    Locate(r);
    Track(r);
  }
  Advance(r.tick);
}

void LessonRun::Locate(const TickRecord& r) {
  const TipLocation at = locator_.Locate(r.X_WG, tracker_.held());
  ProbeReading reading;
  if (tracker_.Update(r.tick, at, TipLocator::ProbingForce(r.force_W, r.X_WG), &reading))
    Read(reading);
  tip_at_ = at;
  if (at.site < 0) return;
  // What the report says of a site without a reading.
  if (const int idx = path_index_[static_cast<std::size_t>(at.site)]; idx >= 0) {
    double& d = visit_deepest_[static_cast<std::size_t>(idx)];
    d = std::max(d, at.depth_mm);
    // Interproximal sites: the col under the contact (the one rule, the
    // panel's too).
    if (TipLocator::UnderContact(at, spec_.rubric.col_reach_mm))
      sites_[static_cast<std::size_t>(idx)].col_reached = true;
  }
  for (int i = 0; i < locator_.size(); ++i) {
    const int idx = path_index_[static_cast<std::size_t>(i)];
    if (i != at.site && idx >= 0 && !near_other_[static_cast<std::size_t>(idx)] &&
        locator_.Near(r.X_WG, i))
      near_other_[static_cast<std::size_t>(idx)] = 1;
  }
}

SiteResult* LessonRun::ApplyReading(const ProbeReading& p,
                                    std::vector<SiteResult>* sites) const {
  const int idx = path_index_[static_cast<std::size_t>(p.site)];
  if (idx < 0) return nullptr;
  SiteResult& s = (*sites)[static_cast<std::size_t>(idx)];
  if (!p.update) ++s.insertions;
  if (s.reached_mm && p.depth_mm <= *s.reached_mm) {
    s.left_tick = p.left_tick;
    return nullptr;
  }
  s.reached_mm = p.depth_mm;
  s.held_force_n = p.held_force_n;
  s.peak_force_n = p.peak_force_n;
  s.angle_deg = p.angle_deg;
  s.reading_tick = p.deepest_tick;
  s.entered_tick = p.entered_tick;
  s.left_tick = p.left_tick;
  return &s;
}

void LessonRun::Read(const ProbeReading& p) {
  if (const int idx = path_index_[static_cast<std::size_t>(p.site)]; idx >= 0)
    last_read_ = idx;
  const SiteResult* s = ApplyReading(p, &sites_);
  if (!s) return;
  if (spec_.practice())
    feedback_.push_back(
        Format("%s: the tip reached %.1f mm (%.2f N held); the true "
               "depth is %d mm",
               s->site.ToString().c_str(), p.depth_mm, p.held_force_n, s->truth_mm));
  else
    feedback_.push_back(s->site.ToString() + ": read");
}

void LessonRun::OnEnd() {
  ended_ = true;
  std::vector<ChartEntry> rest;
  rest.swap(scheduled_);
  for (const ChartEntry& e : rest) Enter(e);
}

void LessonRun::Schedule(const ChartEntry& e) {
  if (e.tick == kAfterReading || (ticks_ > 0 && e.tick <= last_tick_)) {
    Enter(e);
    return;
  }
  const auto at =
      std::upper_bound(scheduled_.begin(), scheduled_.end(), e.tick,
                       [](std::uint64_t t, const ChartEntry& x) { return t < x.tick; });
  scheduled_.insert(at, e);
}

std::optional<SiteRef> LessonRun::tip_site() const {
  if (tip_at_.site < 0) return std::nullopt;
  const ProbingSite& p = locator_.sites()[static_cast<std::size_t>(tip_at_.site)];
  return SiteRef{p.fdi, p.site};
}

std::vector<BloodMark> LessonRun::blood_shown() const {
  std::vector<BloodMark> out;
  for (const SiteResult& s : sites_) {
    if (!s.bled || last_tick_ < s.bleed_tick) continue;
    const double age = static_cast<double>(last_tick_ - s.bleed_tick) / rate_hz_;
    if (age < BloodMark::kBloodFirstS) continue;
    if (age >= BloodMark::kBloodFullS) {
      // Kept until the quadrant is charted.
      const int quadrant = s.site.fdi / 10;
      const bool charted =
          std::all_of(sites_.begin(), sites_.end(), [&](const SiteResult& x) {
            return x.site.fdi / 10 != quadrant || (x.entry && x.entry->pd_mm);
          });
      if (charted) continue;
    }
    out.push_back(
        {s.site, std::clamp((age - BloodMark::kBloodFirstS) /
                                (BloodMark::kBloodFullS - BloodMark::kBloodFirstS),
                            0.0, 1.0)});
  }
  return out;
}

bool LessonRun::blood_seen(const SiteRef& site) const {
  const int idx = SiteIndex(site);
  if (idx < 0) return false;
  const SiteResult& s = sites_[static_cast<std::size_t>(idx)];
  return s.bled && last_tick_ >= s.bleed_tick &&
         static_cast<double>(last_tick_ - s.bleed_tick) / rate_hz_ >=
             BloodMark::kBloodFirstS;
}

void LessonRun::Enter(const ChartEntry& e) {
  // Charting the site the tip is in completes its reading now (a clinician
  // reads the marking with the probe still at the floor).
  if (e.pd_mm && e.tick != kAfterReading && ticks_ > 0 && e.tick > last_tick_ &&
      tracker_.site() >= 0) {
    const ProbingSite& p = locator_.sites()[static_cast<std::size_t>(tracker_.site())];
    ProbeReading reading;
    if (SiteRef{p.fdi, p.site} == e.site && tracker_.Complete(last_tick_, &reading))
      Read(reading);
  }
  entries_.push_back(e);
  const int idx = SiteIndex(e.site);
  if (idx >= 0) {
    SiteResult& s = sites_[static_cast<std::size_t>(idx)];
    ChartEntry merged = e;
    if (!merged.pd_mm && s.entry)
      merged.pd_mm = s.entry->pd_mm;  // bleeding alone keeps the depth
    s.entry = merged;
  }
  Advance(e.tick == kAfterReading ? last_tick_ : e.tick);
}

void LessonRun::Declare(const DeclaredDiagnosis& d) {
  declared_ = d;
  const std::uint64_t tick = d.tick == kAfterReading ? last_tick_ : d.tick;
  // Declaring the diagnosis says the examination is over: the steps still
  // open before the diagnosis step are left, skipped, with the sites they
  // missed (the steps follow what the student did).
  if (!inspection_ && !done()) {
    int dx = -1;
    for (int k = step_; k < static_cast<int>(spec_.steps.size()) && dx < 0; ++k)
      if (spec_.steps[static_cast<std::size_t>(k)].complete ==
          StepSpec::Complete::kDiagnosis)
        dx = k;
    while (dx > step_ && !StepComplete(spec_.steps[static_cast<std::size_t>(step_)])) {
      const StepSpec& st = spec_.steps[static_cast<std::size_t>(step_)];
      StepResult& res = step_results_[static_cast<std::size_t>(step_)];
      res.skipped = true;
      res.ended_tick = std::max(tick, res.started_tick);
      for (const SiteResult& r : sites_) {
        if (!SiteInStep(st, r.site)) continue;
        const bool open = st.complete == StepSpec::Complete::kRead
                              ? !r.reached_mm
                              : !(r.entry && r.entry->pd_mm);
        if (open) res.missed.push_back(r.site.ToString());
      }
      feedback_.push_back("step '" + res.id + "' left undone for the diagnosis");
      ++step_;
      step_results_[static_cast<std::size_t>(step_)].started_tick = tick;
      Advance(tick);
    }
  }
  Advance(tick);
}

LessonResult LessonRun::Finish() const {
  const RubricSpec& rb = spec_.rubric;
  LessonResult out;
  out.lesson_name = spec_.name;
  out.pass_mark = spec_.pass_mark;
  out.lesson_file = spec_.file.string();
  out.scene_file = scene_.spec.file.string();
  out.mode = ToString(spec_.mode);
  out.student = student_;
  out.case_seed = case_seed_;
  out.generated_case = spec_.case_spec.generated;
  out.rate_hz = rate_hz_;
  out.rubric = rb;
  out.sites = sites_;
  // An attempt that ends with the tip still in a sulcus: that visit's reading.
  {
    ProbeReadingTracker open = tracker_;
    ProbeReading reading;
    if (open.Complete(last_tick_, &reading)) ApplyReading(reading, &out.sites);
  }
  for (std::size_t i = 0; i < out.sites.size(); ++i) {
    SiteResult& s = out.sites[i];
    if (s.reached_mm) continue;
    if (visit_deepest_[i] > -1e8)
      s.no_reading =
          Format("entered but less than %.1f mm deep (deepest %.1f mm)",
                 ProbeReadingTracker::kMinDepthMm, std::max(0.0, visit_deepest_[i]));
    else if (near_other_[i])
      s.no_reading = "the tip was nearer another site's line";
    else
      s.no_reading = "never entered its sulcus";
  }
  out.steps = step_results_;
  out.first_tick = first_tick_;
  out.last_tick = last_tick_;
  out.duration_s =
      ticks_ > 0 ? static_cast<double>(last_tick_ - first_tick_ + 1) / rate_hz_ : 0;
  out.force_trace = force_trace_;
  out.feedback = feedback_;
  out.sites_total = static_cast<int>(sites_.size());
  out.complete = step_ >= static_cast<int>(spec_.steps.size()) && !timed_out_;
  if (!out.complete)
    out.ended = !ending_.empty() ? ending_
                : timed_out_     ? "the time limit was reached"
                                 : "it ended before the last step";
  out.interruptions = interruptions_;
  out.kind = ToString(spec_.kind);
  if (inspection_)
    ScoreInspection(out);
  else
    ScoreProbing(out);
  auto& L = out.lines;

  // Time and steps.
  L.push_back(Line("time", nullptr, 0, S::kInfo, 0,
                   Format("%.1f s in all", out.duration_s), last_tick_));
  if (!out.complete)
    L.push_back(
        Line("time", nullptr, 0, S::kInfo, 0, "incomplete: " + out.ended, last_tick_));
  for (const LessonResult::Interruption& i : out.interruptions) {
    const double lost_s =
        static_cast<double>(i.lost_tick - std::min(i.lost_tick, first_tick_)) / rate_hz_;
    L.push_back(Line(
        "time", nullptr, 0, S::kInfo, 0,
        i.back_tick
            ? Format("the device stopped answering at %.1f s and was back %.1f s later",
                     lost_s, static_cast<double>(i.back_tick - i.lost_tick) / rate_hz_)
            : Format("the device stopped answering at %.1f s and did not come back",
                     lost_s),
        i.lost_tick));
  }
  for (const StepResult& st : out.steps)
    L.push_back(
        Line("time", nullptr, 0, S::kInfo, 0,
             Format("step '%s': %s in %.1f s", st.id.c_str(),
                    st.completed   ? "done"
                    : st.timed_out ? "timed out"
                    : st.skipped   ? "left unfinished"
                                   : "not finished",
                    static_cast<double>((st.ended_tick ? st.ended_tick : last_tick_) -
                                        st.started_tick) /
                        rate_hz_),
             st.ended_tick ? st.ended_tick : last_tick_));

  // Scores.
  const std::map<std::string, double> weights = {
      {"technique", rb.technique},   {"reading", rb.reading},
      {"charting", rb.charting},     {"force", rb.force},
      {"angulation", rb.angulation}, {"coverage", rb.coverage},
      {"bleeding", rb.bleeding},     {"completeness", rb.completeness},
      {"diagnosis", rb.diagnosis},   {"damage", rb.DamageWeight()},
      {"findings", rb.findings},     {"sequence", rb.sequence}};
  std::map<std::string, std::pair<double, int>> sums;
  for (const RubricLine& l : L) {
    if (l.status == S::kInfo) continue;
    auto& [sum, n] = sums[l.category];
    sum += l.credit;
    ++n;
  }
  double wsum = 0, score = 0;
  for (const auto& [cat, w] : weights) {
    const auto it = sums.find(cat);
    if (it == sums.end() || w <= 0) continue;
    // The per-site technique lines count over every site of the path: a site
    // not probed is a share of the examination not done (one site of 24 done
    // well is not a fifth of the marks).
    const bool per_site =
        !inspection_ && (cat == "technique" || cat == "force" || cat == "angulation");
    const int over = per_site
                         ? std::max(it->second.second, static_cast<int>(sites_.size()))
                         : it->second.second;
    const double credit = it->second.first / over;
    out.category_credit[cat] = credit;
    out.category_weight[cat] = w;
    wsum += w;
    score += w * credit;
  }
  out.total = wsum > 0 ? 100 * score / wsum : 0;
  return out;
}

}  // namespace sulcus
