#include "core/lesson/scripted_keys.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <optional>

#include "core/haptics/key_device.h"
#include "core/haptics/probe_keys.h"

namespace sulcus {

namespace {

// The device the session reads: the keys' device, finished when the student is.
class KeysDevice final : public Device {
 public:
  KeysDevice(std::shared_ptr<MouseKeyboardDevice> keys,
             std::shared_ptr<std::atomic<bool>> done)
      : keys_(std::move(keys)), done_(std::move(done)) {
    caps_ = keys_->caps();
    caps_.name = "student:keys";
  }
  const DeviceCaps& caps() const override { return caps_; }
  bool Read(double t_s, DeviceSample* out) noexcept override {
    return keys_->Read(t_s, out);
  }
  void Write(const Vector3& f, const Vector3& t) noexcept override { keys_->Write(f, t); }
  bool finished() const noexcept override { return done_->load(); }

 private:
  std::shared_ptr<MouseKeyboardDevice> keys_;
  std::shared_ptr<std::atomic<bool>> done_;
  DeviceCaps caps_;
};

class ScriptedKeys final : public ScriptedHand {
 public:
  static constexpr double kPressN = 0.24, kPressStepN = 0.02, kKeyS = 0.05;
  static constexpr double kWalkEveryS = 0.6;  // steps kWalkStepMm (probe_keys.h)
  static constexpr double kStillS = 0.5, kGiveUpS = 8.0;

  ScriptedKeys(const LessonSpec& spec, const CompiledScene& scene)
      : spec_(spec),
        sites_(scene.effects.sites),
        done_(std::make_shared<std::atomic<bool>>()) {
    const ProbingSite* first = spec.path.empty() ? nullptr : Site(spec.path.front());
    keys_ = std::make_shared<MouseKeyboardDevice>(first ? PoseOverSite(*first, 6.0)
                                                        : RigidTransform::Identity());
  }
  std::unique_ptr<Device> MakeDevice() const override {
    return std::make_unique<KeysDevice>(keys_, done_);
  }
  void Attach(LessonRun* lesson) override { lesson_ = lesson; }

  void OnTick(const TickRecord& r) override {
    last_tick_ = r.tick;
    const double t = r.time_s;
    if (!lesson_) {
      done_->store(true);
      return;
    }
    const double f = TipLocator::ProbingForce(r.force_W, r.X_WG);
    const auto tip = lesson_->tip_site();
    const auto depth = lesson_->tip_depth_mm();
    switch (phase_) {
      case Phase::kChoose: {
        target_ = NextSite();
        if (!target_) {
          phase_ = Phase::kEnd;
          since_ = t;
          break;
        }
        const ProbingSite* p = Site(*target_);
        if (!p) {
          given_up_.push_back(*target_);
          break;
        }
        since_ = t;
        if (tip && depth && *depth >= 0.5 && tip->fdi == target_->fdi &&
            (tip->site < 3) == (target_->site < 3) && p->ring) {
          phase_ = Phase::kWalk;  // along the sulcus to it
          next_key_ = t;
        } else {
          N(*p);
          phase_ = Phase::kPress;
          next_key_ = t + kKeyS;
        }
        break;
      }
      case Phase::kPress:
        if (t >= next_key_) {  // R
          keys_->SetPress(std::min(kPressN, keys_->press() + kPressStepN));
          next_key_ = t + kKeyS;
          if (keys_->press() >= kPressN - 1e-9) {
            phase_ = Phase::kSettle;
            since_ = t;
            still_ = -1;
          }
        }
        break;
      case Phase::kSettle: {
        const bool in = tip && *tip == *target_ && depth && *depth >= 0.5 &&
                        std::abs(f - kPressN) < 0.04;
        if (!in) {
          still_ = -1;
        } else if (still_ < 0) {
          still_ = t;
        } else if (t - still_ >= kStillS) {
          // Read the markings with the probe at the floor, and chart.
          ChartEntry e;
          e.site = *target_;
          e.tick = r.tick + 1;
          e.pd_mm = static_cast<int>(std::lround(*depth));
          lesson_->Enter(e);
          const SiteResult* s = Result(*target_);
          if (s && s->interproximal_contact) {
            phase_ = Phase::kColIn;
            since_ = t;
            still_ = -1;
            if (const auto to = TiltIntoCol(*Site(*target_), keys_->tip_pose()))
              keys_->PlaceTip(*to);  // T
          } else if (IsInterdental(target_->site)) {
            // No neighbour: the walk goes on round into the interproximal area.
            phase_ = Phase::kWalkOut;
            since_ = t;
            next_key_ = t;
          } else {
            phase_ = Phase::kChoose;
          }
          break;
        }
        if (t - since_ > kGiveUpS) Skip();
        break;
      }
      case Phase::kColIn:
        // Held under the contact a moment, then T again stands it up.
        if (lesson_->tip_under_contact()) {
          if (still_ < 0) still_ = t;
        }
        if ((still_ >= 0 && t - still_ >= 0.3) || t - since_ > 3.0) {
          const ProbingSite* p = Site(*target_);
          const RigidTransform at = keys_->tip_pose();
          keys_->PlaceTip(RigidTransform(
              Quaternion::FromTwoVectors(Vector3::UnitZ(), p->ring->AxisW()),
              at.translation()));
          phase_ = Phase::kColBack;
          since_ = t;
        }
        break;
      case Phase::kColBack:
        if (t - since_ >= 0.4) phase_ = Phase::kChoose;
        break;
      case Phase::kWalk: {
        if (t < next_key_) break;
        const ProbingSite* p = Site(*target_);
        if (!tip || t - since_ > 4 * kGiveUpS) {
          // Out of the sulcus: N instead.
          N(*p);
          phase_ = Phase::kPress;
          next_key_ = t + kKeyS;
          break;
        }
        const SulcusRing& ring = *p->ring;
        const Vector3 here = ring.ToRing(keys_->tip_pose().translation());
        const Vector3 there = ring.ToRing(p->margin_W);
        const double d = std::remainder(
            std::atan2(there.y(), there.x()) - std::atan2(here.y(), here.x()),
            2 * std::numbers::pi);
        const double left_mm = std::abs(d) * std::hypot(there.x(), there.y());
        if (left_mm < 0.12 && *tip == *target_) {
          phase_ = Phase::kSettle;
          since_ = t;
          still_ = -1;
          break;
        }
        const double step = std::min(kWalkStepMm, std::max(0.05, left_mm));
        if (const auto to =
                WalkAlongSulcus(*p, keys_->tip_pose(), d > 0 ? step : -step)) {
          keys_->PlaceTip(*to);  // comma or period
          keys_->Lift(kWalkLiftMm);
        }
        next_key_ = t + kWalkEveryS;
        break;
      }
      case Phase::kWalkOut: {
        if (t < next_key_) break;
        const TipLocation& at = lesson_->tip_location();
        const ProbingSite* p = Site(*target_);
        if (!tip || *tip != *target_ || at.to_contact_mm < 0 || at.to_contact_mm <= 1.2 ||
            t - since_ > kGiveUpS) {
          phase_ = Phase::kChoose;
          break;
        }
        const SulcusRing& ring = *p->ring;
        const Vector3 here = ring.ToRing(keys_->tip_pose().translation());
        const double contact = IsMesial(target_->site) ? 0.0 : std::numbers::pi;
        const double d = std::remainder(contact - std::atan2(here.y(), here.x()),
                                        2 * std::numbers::pi);
        const double step = std::min(kWalkStepMm, at.to_contact_mm - 1.0);
        if (const auto to =
                WalkAlongSulcus(*p, keys_->tip_pose(), d > 0 ? step : -step)) {
          keys_->PlaceTip(*to);
          keys_->Lift(kWalkLiftMm);
        }
        next_key_ = t + kWalkEveryS;
        break;
      }
      case Phase::kEnd:
        keys_->SetPress(0);  // X
        if (t - since_ >= 2.0) Finish();
        break;
      case Phase::kDone:
        break;
    }
  }

  void OnEnd() override {
    if (phase_ != Phase::kDone) Finish();
  }

 private:
  enum class Phase {
    kChoose,
    kPress,
    kSettle,
    kColIn,
    kColBack,
    kWalk,
    kWalkOut,
    kEnd,
    kDone
  };

  const ProbingSite* Site(const SiteRef& s) const {
    for (const ProbingSite& p : sites_)
      if (p.fdi == s.fdi && p.site == s.site) return &p;
    return nullptr;
  }
  const SiteResult* Result(const SiteRef& s) const {
    for (const SiteResult& x : lesson_->sites())
      if (x.site == s) return &x;
    return nullptr;
  }
  // The first site of the path not charted and not given up on.
  std::optional<SiteRef> NextSite() const {
    for (const SiteRef& s : spec_.path) {
      const SiteResult* x = Result(s);
      if (x && x->entry && x->entry->pd_mm) continue;
      if (std::find(given_up_.begin(), given_up_.end(), s) != given_up_.end()) continue;
      return s;
    }
    return std::nullopt;
  }
  // N: the hand over the site, and the tool reset to it (as the window's N
  // sends Reset tool), so that the tip does not drag through the tissue from
  // the site before.
  void N(const ProbingSite& p) {
    keys_->Set(PoseOverSite(p, 1.0));
    if (loop_) loop_->Send({HapticCommand::Kind::kResetTool});
  }
  void Skip() {
    given_up_.push_back(*target_);
    phase_ = Phase::kChoose;
  }
  void Finish() {
    phase_ = Phase::kDone;
    // Bleeding where it showed; then the diagnosis of the chart.
    PerioChart chart = lesson_->GivenChart();
    for (const SiteRef& s : spec_.path) {
      const SiteResult* x = Result(s);
      const bool bled = lesson_->blood_seen(s);
      if (bled) {
        ChartEntry b;
        b.site = s;
        b.tick = last_tick_ + 1;
        b.bleeding = true;
        lesson_->Enter(b);
      }
      if (ToothChart* tc = chart.Find(s.fdi); tc && x && x->entry && x->entry->pd_mm)
        tc->sites[s.site] = {*x->entry->pd_mm, lesson_->recession_mm(s), bled};
    }
    lesson_->Declare(DiagnosisOfChart(chart, last_tick_));
    done_->store(true);
  }

  const LessonSpec& spec_;
  const std::vector<ProbingSite>& sites_;
  std::shared_ptr<MouseKeyboardDevice> keys_;
  std::shared_ptr<std::atomic<bool>> done_;
  LessonRun* lesson_ = nullptr;
  Phase phase_ = Phase::kChoose;
  std::optional<SiteRef> target_;
  std::vector<SiteRef> given_up_;
  double since_ = 0, next_key_ = 0, still_ = -1;
  std::uint64_t last_tick_ = 0;
};

}  // namespace

std::unique_ptr<ScriptedHand> MakeScriptedKeys(const LessonSpec& spec,
                                               const CompiledScene& scene) {
  return std::make_unique<ScriptedKeys>(spec, scene);
}

}  // namespace sulcus
