#include "core/haptics/effects.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sulcus {
namespace {

// Whether a pair's tool leaf is on the working end (every leaf when the model does not
// say).
bool WorkingEnd(const EffectsModel& m, std::uint64_t key) {
  const auto leaf = static_cast<std::size_t>(ContactPair::ToolLeafOfKey(key));
  return m.tool_working_end.empty() ||
         (leaf < m.tool_working_end.size() && m.tool_working_end[leaf]);
}

// Soft tissue as springs: the graphic tool's leaf spheres pressing into soft
// leaves push back along the pair's normal with the leaf's stiffness; the
// deepest pair sets the magnitude, the penetration-weighted normals the direction.
class GingivaCompliance final : public LoopEffect {
 public:
  explicit GingivaCompliance(const EffectsModel& m)
      : m_(m), pairs_(kCapacity), scratch_(std::make_unique<CollisionScratch>()) {}
  const char* name() const override { return "gingiva_compliance"; }
  void Apply(const EngineModel& model, const EngineData& data, Vector3* force_W,
             Vector3* torque_W, HapticLoop* loop) noexcept override {
    (void)model;
    (void)torque_W;
    const CollisionWorld& w = *m_.soft_world;
    const CollisionStats cs =
        FindContacts(w, data.X_WG, 0.0, scratch_.get(), pairs_.data(), kCapacity);
    Vector3 dir = Vector3::Zero();
    double force = 0;
    int object = -1;
    for (int i = 0; i < cs.pairs; ++i) {
      const ContactPair& c = pairs_[i];
      const double depth = -c.gap;
      if (depth <= 0) continue;
      Vector3 n;
      w.PairGap(data.X_WG, c, &n);
      if (n.squaredNorm() == 0) continue;  // coincident centres: no direction to push
      const double k = m_.soft_leaf_stiffness[c.object][c.object_leaf];
      dir += depth * k * n;
      if (k * depth > force) {
        force = k * depth;
        object = m_.soft_first + c.object;
      }
    }
    if (force > 0 && dir.squaredNorm() > 0) *force_W += force * dir.normalized();
    if ((object >= 0) != touching_) {
      touching_ = object >= 0;
      if (touching_) {
        HapticEvent e = HapticEvent::Of(EventKind::kSoftContact, object);
        e.payload.force.force_n = force;
        loop->Emit(e);
      }
    }
  }
  void Reset() noexcept override { touching_ = false; }

 private:
  static constexpr int kCapacity = 1024;
  const EffectsModel& m_;
  std::vector<ContactPair> pairs_;
  std::unique_ptr<CollisionScratch> scratch_;
  bool touching_ = false;
};

// Readings (core/haptics/probe_reading.h) where the tip locator puts the tip,
// and bleeding at a bleeding site probed to its floor, once a visit.
class ProbingDepth final : public LoopEffect {
 public:
  ProbingDepth(const EffectsModel& m, double rate_hz, bool readings, bool bleeding)
      : m_(m),
        locator_(m.sites),
        tracker_(rate_hz),
        readings_(readings),
        bleeding_(bleeding) {}
  const char* name() const override {
    return readings_ && bleeding_ ? "probing_depth, bleeding_on_probing"
           : readings_            ? "probing_depth"
                                  : "bleeding_on_probing";
  }
  void Apply(const EngineModel&, const EngineData& data, Vector3* force_W, Vector3*,
             HapticLoop* loop) noexcept override {
    const TipLocation at = locator_.Locate(data.X_WG, tracker_.held());
    const double f = TipLocator::ProbingForce(*force_W, data.X_WG);
    ProbeReading r;
    if (tracker_.Update(loop->tick(), at, f, &r) && readings_ && !r.update) {
      const ProbingSite& s = m_.sites[static_cast<std::size_t>(r.site)];
      HapticEvent e = HapticEvent::Of(EventKind::kProbeReading, s.tooth);
      e.payload.reading = {s.fdi,       s.site,         r.depth_mm,    r.peak_force_n,
                           r.angle_deg, r.deepest_tick, r.entered_tick};
      loop->Emit(e);
    }
    if (tracker_.site() != bleed_site_) {
      bleed_site_ = tracker_.site();
      bled_ = false;
    }
    if (bleed_site_ < 0 || !bleeding_ || bled_) return;
    const ProbingSite& s = m_.sites[static_cast<std::size_t>(bleed_site_)];
    if (s.bleeding && at.site == bleed_site_ && at.depth_mm >= s.pocket_mm - 0.5) {
      bled_ = true;
      HapticEvent e = HapticEvent::Of(EventKind::kBleeding, s.tooth);
      e.payload.bleeding = {s.fdi, s.site, at.depth_mm, f};
      loop->Emit(e);
    }
  }
  void Reset() noexcept override {
    tracker_.Reset();
    bleed_site_ = -1;
    bled_ = false;
  }

 private:
  const EffectsModel& m_;
  TipLocator locator_;
  ProbeReadingTracker tracker_;
  bool readings_, bleeding_;
  int bleed_site_ = -1;
  bool bled_ = false;
};

// The force on each object in contact above its damage limit (once per episode).
class TissueDamage final : public LoopEffect {
 public:
  explicit TissueDamage(const EffectsModel& m)
      : m_(m), over_(m.damage_limit_n.size(), 0), below_(m.damage_limit_n.size(), 0) {}
  const char* name() const override { return "tissue_damage"; }
  void Apply(const EngineModel&, const EngineData& data, Vector3* force_W, Vector3*,
             HapticLoop* loop) noexcept override {
    // Each object bears its share of the contact force (its pairs' multipliers):
    // a tool pressed on a tooth while brushing the lip does not hurt the lip.
    std::array<std::size_t, kQpMaxActive> objects;
    std::array<double, kQpMaxActive> share;
    int n = 0;
    for (int i = 0; i < data.num_active_keys; ++i) {
      const auto object =
          static_cast<std::size_t>(ContactPair::ObjectOfKey(data.active_keys[i]));
      if (object >= over_.size()) continue;
      int k = 0;
      while (k < n && objects[k] != object) ++k;
      if (k == n) {
        objects[k] = object;
        share[k] = 0;
        ++n;
      }
      if (WorkingEnd(m_, data.active_keys[i])) share[k] += data.active_share[i];
    }
    // An episode starts when the force on an object passes its limit and ends
    // once the force has stayed below kEpisodeEnd of the limit (or off the
    // object) for kEpisodeGapS: a press that hovers about the limit, or whose
    // contact flickers, is one episode, not one per ripple.
    const double f = force_W->norm();
    const auto gap_ticks =
        static_cast<std::uint32_t>(std::max(1.0, kEpisodeGapS * loop->options().rate_hz));
    for (std::size_t object = 0; object < over_.size(); ++object) {
      if (!over_[object]) continue;
      int k = 0;
      while (k < n && objects[k] != object) ++k;
      const bool below = k == n || f * share[k] < kEpisodeEnd * m_.damage_limit_n[object];
      below_[object] = below ? below_[object] + 1 : 0;
      if (below_[object] >= gap_ticks) over_[object] = 0;
    }
    for (int k = 0; k < n; ++k) {
      const std::size_t object = objects[k];
      const double on = f * share[k];
      if (on > m_.damage_limit_n[object] && !over_[object]) {
        HapticEvent e =
            HapticEvent::Of(EventKind::kTissueDamage, static_cast<int>(object));
        e.payload.damage = {on, m_.damage_limit_n[object]};
        loop->Emit(e);
        over_[object] = 1;
        below_[object] = 0;
      }
    }
  }
  static constexpr double kEpisodeEnd = 0.8, kEpisodeGapS = 0.1;
  void Reset() noexcept override {
    std::fill(over_.begin(), over_.end(), 0);
    std::fill(below_.begin(), below_.end(), 0);
  }

 private:
  const EffectsModel& m_;
  std::vector<std::uint8_t> over_;
  std::vector<std::uint32_t> below_;  // ticks in a row below the episode's end
};

class CariesCatch final : public LoopEffect {
 public:
  explicit CariesCatch(const EffectsModel& m) : m_(m) {}
  const char* name() const override { return "caries_catch"; }
  void Apply(const EngineModel&, const EngineData& data, Vector3* force_W, Vector3*,
             HapticLoop* loop) noexcept override {
    const Vector3 tip = data.X_WG.translation();
    // The lesion under the tip, if its tooth is being touched.
    int on = -1;
    double weight = 0;
    for (std::size_t l = 0; l < m_.lesions.size(); ++l) {
      const CariesLesion& c = m_.lesions[l];
      const double d = (tip - c.centre_W).norm();
      if (d > c.radius_mm + kTipReachMm || !Touching(data, c.tooth)) continue;
      on = static_cast<int>(l);
      weight = std::clamp(1 - d / (c.radius_mm + kTipReachMm), 0.0, 1.0);
      break;
    }
    if (on < 0) {
      caught_ = -1;
      return;
    }
    const CariesLesion& c = m_.lesions[static_cast<std::size_t>(on)];
    const CariesFeel& f = m_.caries;
    const double normal =
        force_W->dot(c.normal_W);  // > 0: the tip pressed into the surface
    if (normal <= 0) {
      caught_ = -1;
      return;
    }
    // Softer than enamel: less of the normal force at the lesion.
    *force_W -= (1 - f.softness) * weight * normal * c.normal_W;
    const Vector3 device = data.X_WH.translation();
    if (caught_ != on) {
      if (normal < f.catch_force_n) return;
      caught_ = on;
      anchor_ = device;
      HapticEvent e = HapticEvent::Of(EventKind::kCariesCatch, c.tooth);
      e.payload.damage = {normal, f.catch_force_n};
      loop->Emit(e);
    }
    if (normal < 0.3 * f.catch_force_n) {  // lifted off: free again
      caught_ = -1;
      return;
    }
    // Caught: a tangential spring back to where it caught, holding up to a share
    // of the normal force; beyond that it slips (the anchor follows).
    Vector3 slip = device - anchor_;
    slip -= slip.dot(c.normal_W) * c.normal_W;
    const double cap = f.catch_ratio * normal;
    const double stretch = slip.norm();
    if (f.catch_k_n_per_mm * stretch > cap && stretch > 0) {
      anchor_ += slip * (1 - cap / (f.catch_k_n_per_mm * stretch));
      slip *= cap / (f.catch_k_n_per_mm * stretch);
    }
    *force_W -= f.catch_k_n_per_mm * slip;
  }
  void Reset() noexcept override { caught_ = -1; }

 private:
  static constexpr double kTipReachMm =
      0.3;  // the tip's radius and a little: touching the lesion's rim counts
  static bool Touching(const EngineData& data, int object) {
    for (int i = 0; i < data.num_active_keys; ++i)
      if (ContactPair::ObjectOfKey(data.active_keys[i]) == object) return true;
    return false;
  }
  const EffectsModel& m_;
  int caught_ = -1;
  Vector3 anchor_ = Vector3::Zero();
};

// A deposit met by the working end: an event once per contact episode.
class CalculusTouch final : public LoopEffect {
 public:
  explicit CalculusTouch(const EffectsModel& m)
      : m_(m), touching_(m.deposits.size(), 0), now_(m.deposits.size(), 0) {}
  const char* name() const override { return "calculus"; }
  void Apply(const EngineModel&, const EngineData& data, Vector3* force_W, Vector3*,
             HapticLoop* loop) noexcept override {
    std::fill(now_.begin(), now_.end(), 0);
    const double f = force_W->norm();
    for (int i = 0; i < data.num_active_keys; ++i) {
      const auto o =
          static_cast<std::size_t>(ContactPair::ObjectOfKey(data.active_keys[i]));
      if (o >= m_.deposits.size() || m_.deposits[o].fdi == 0 ||
          !WorkingEnd(m_, data.active_keys[i]))
        continue;
      now_[o] = 1;
      if (touching_[o]) continue;
      touching_[o] = 1;
      HapticEvent e = HapticEvent::Of(EventKind::kCalculusTouched, static_cast<int>(o));
      e.payload.calculus = {m_.deposits[o].fdi, m_.deposits[o].site,
                            f * data.active_share[i]};
      loop->Emit(e);
    }
    for (std::size_t o = 0; o < now_.size(); ++o) touching_[o] = touching_[o] && now_[o];
  }
  void Reset() noexcept override { std::fill(touching_.begin(), touching_.end(), 0); }

 private:
  const EffectsModel& m_;
  std::vector<std::uint8_t> touching_, now_;
};

class SurfaceTexture final : public LoopEffect {
 public:
  explicit SurfaceTexture(const EffectsModel& m) : m_(m) {}
  const char* name() const override { return "surface_texture"; }
  void Apply(const EngineModel&, const EngineData& data, Vector3* force_W, Vector3*,
             HapticLoop*) noexcept override {
    const Vector3 tip = data.X_WG.translation();
    const double f = force_W->norm();
    // The surface touched: the first textured object among the active pairs.
    int object = -1;
    for (int i = 0; i < data.num_active_keys && object < 0; ++i) {
      const auto o =
          static_cast<std::size_t>(ContactPair::ObjectOfKey(data.active_keys[i]));
      if (o < m_.texture_kind.size() && m_.texture_kind[o] != TextureKind::kNone)
        object = static_cast<int>(o);
    }
    if (object < 0 || f < 1e-3) {
      has_last_ = false;
      return;
    }
    const Vector3 normal = *force_W / f;
    if (has_last_) {
      Vector3 step = tip - last_;
      step -= step.dot(normal) * normal;
      slid_mm_ += step.norm();
    }
    last_ = tip;
    has_last_ = true;
    const auto o = static_cast<std::size_t>(object);
    const Texture* t = &m_.texture.calculus;
    if (m_.texture_kind[o] == TextureKind::kTooth) {
      // Above the CEJ (the tooth frame's z = 0, scalloped within a millimetre): enamel.
      t = (m_.X_OW[o] * tip).z() >= 0 ? &m_.texture.enamel : &m_.texture.root;
    }
    const double press = std::min(1.0, f / 0.5);
    *force_W += press * t->amplitude_n *
                std::sin(2 * std::numbers::pi * slid_mm_ / t->period_mm) * normal;
  }
  void Reset() noexcept override {
    has_last_ = false;
    slid_mm_ = 0;
  }

 private:
  const EffectsModel& m_;
  Vector3 last_ = Vector3::Zero();
  bool has_last_ = false;
  double slid_mm_ = 0;
};

}  // namespace

std::vector<std::unique_ptr<LoopEffect>> MakeEffects(const EffectsModel& m,
                                                     double rate_hz) {
  std::vector<std::unique_ptr<LoopEffect>> out;
  if (m.on.gingiva_compliance && m.soft_world)
    out.push_back(std::make_unique<GingivaCompliance>(m));
  const bool depth = m.on.probing_depth, bleeding = m.on.bleeding_on_probing;
  if ((depth || bleeding) && !m.sites.empty())
    out.push_back(std::make_unique<ProbingDepth>(m, rate_hz, depth, bleeding));
  if (m.on.caries_catch && !m.lesions.empty())
    out.push_back(std::make_unique<CariesCatch>(m));
  if (m.on.surface_texture) out.push_back(std::make_unique<SurfaceTexture>(m));
  const bool deposits = std::any_of(m.deposits.begin(), m.deposits.end(),
                                    [](const auto& d) { return d.fdi != 0; });
  if (m.on.calculus && deposits) out.push_back(std::make_unique<CalculusTouch>(m));
  if (m.on.tissue_damage) out.push_back(std::make_unique<TissueDamage>(m));
  return out;
}

std::vector<LoopEffect*> EffectPointers(
    const std::vector<std::unique_ptr<LoopEffect>>& effects) {
  std::vector<LoopEffect*> p;
  for (const auto& e : effects) p.push_back(e.get());
  return p;
}

}  // namespace sulcus
