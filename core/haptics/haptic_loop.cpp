#include "core/haptics/haptic_loop.h"

#include <algorithm>
#include <cmath>

namespace sulcus {
namespace {

void ClampNorm(Vector3* v, double limit) {
  const double n = v->norm();
  if (n > limit) *v *= limit / n;
}

}  // namespace

const char* ToString(EventKind kind) {
  switch (kind) {
    case EventKind::kContactBegan:
      return "contact_began";
    case EventKind::kContactEnded:
      return "contact_ended";
    case EventKind::kForceAbove:
      return "force_above";
    case EventKind::kForceBelow:
      return "force_below";
    case EventKind::kDeviceLost:
      return "device_lost";
    case EventKind::kDeviceBack:
      return "device_back";
    case EventKind::kOverrun:
      return "overrun";
    case EventKind::kCommand:
      return "command";
    case EventKind::kProbeReading:
      return "probe_reading";
    case EventKind::kBleeding:
      return "bleeding";
    case EventKind::kTissueDamage:
      return "tissue_damage";
    case EventKind::kSoftContact:
      return "soft_contact";
    case EventKind::kCariesCatch:
      return "caries_catch";
    case EventKind::kCalculusTouched:
      return "calculus";
    case EventKind::kCount:
      break;
  }
  return "?";
}

const char* ToString(HapticCommand::Kind kind) {
  switch (kind) {
    case HapticCommand::Kind::kPause:
      return "pause";
    case HapticCommand::Kind::kResume:
      return "resume";
    case HapticCommand::Kind::kResetTool:
      return "reset_tool";
    case HapticCommand::Kind::kSetForceScale:
      return "set_force_scale";
    case HapticCommand::Kind::kSetForceLimit:
      return "set_force_limit";
    case HapticCommand::Kind::kSetTorqueLimit:
      return "set_torque_limit";
  }
  return "?";
}

HapticLoop::HapticLoop(const EngineModel& model, Device* device,
                       const LoopOptions& options, std::span<LoopEffect* const> effects)
    : model_(model),
      device_(device),
      options_(options),
      effects_(effects),
      data_(model),
      force_limit_n_(std::min(model.params.max_force_n, device->caps().max_force_n)),
      torque_limit_nmm_(
          std::min(model.params.max_torque_nmm, device->caps().max_torque_nmm)) {
  options_.force_scale = std::clamp(options_.force_scale, 0.0, 1.0);
}

void HapticLoop::Reset(const RigidTransform& X_WG) {
  ResetTool(X_WG, &data_);
  ramp_start_tick_ = tick_;
  contact_force_valid_ = false;
  for (LoopEffect* e : effects_) e->Reset();
}

void HapticLoop::Emit(const HapticEvent& e) noexcept {
  HapticEvent stamped = e;
  stamped.tick = tick_;
  if (record_.num_events < TickRecord::kMaxEvents) {
    record_.events[record_.num_events++] = stamped;
  } else {
    ++record_.events_dropped;
    ++faults_.events_dropped;
  }
}

void HapticLoop::Apply(const HapticCommand& c) noexcept {
  using K = HapticCommand::Kind;
  const double v = std::isfinite(c.value) ? c.value : 0.0;
  switch (c.kind) {
    case K::kPause:
      paused_ = true;
      break;
    case K::kResume:
      if (paused_) ramp_start_tick_ = tick_;
      paused_ = false;
      break;
    case K::kResetTool:
      reset_pending_ = true;  // to the hand's pose read this tick (below)
      break;
    case K::kSetForceScale:
      options_.force_scale = std::clamp(v, 0.0, 1.0);
      break;
    case K::kSetForceLimit:
      force_limit_n_ = std::clamp(
          v, 0.0, std::min(model_.params.max_force_n, device_->caps().max_force_n));
      break;
    case K::kSetTorqueLimit:
      torque_limit_nmm_ = std::clamp(
          v, 0.0, std::min(model_.params.max_torque_nmm, device_->caps().max_torque_nmm));
      break;
  }
  HapticEvent e = HapticEvent::Of(EventKind::kCommand);
  e.payload.command = {static_cast<std::uint8_t>(c.kind), v};
  Emit(e);
}

void HapticLoop::Tick(bool overrun) noexcept {
  const double rate = options_.rate_hz > 0 ? options_.rate_hz : 1000.0;
  const double t = static_cast<double>(tick_) / rate;
  record_.num_events = 0;
  record_.events_dropped = 0;
  record_.tick = tick_;
  record_.time_s = t;
  record_.overrun = overrun;

  HapticCommand command;
  while (commands_.Pop(&command)) Apply(command);

  // Device: hold the last reading when none is fresh; after the timeout, zero force.
  DeviceSample s;
  const bool fresh = device_->Read(t, &s);
  record_.fresh = fresh;
  if (fresh) {
    // On the recording grid, so that a recording holds exactly the pose used.
    if (!s.coded && !s.as_given && EncodePose(s.X_WH, &s.code)) {
      s.X_WH = DecodePose(s.code);
      s.coded = true;
    }
    sample_ = s;
    last_fresh_tick_ = tick_;
    if (!device_ok_) {
      device_ok_ = true;
      ramp_start_tick_ = tick_;
      Emit(HapticEvent::Of(EventKind::kDeviceBack));
    }
  } else if (device_ok_ &&
             (device_->lost() || static_cast<double>(tick_ - last_fresh_tick_) >=
                                     options_.safety.device_timeout_s * rate)) {
    device_ok_ = false;
    ++faults_.device_stalls;
    Emit(HapticEvent::Of(EventKind::kDeviceLost));
  }
  record_.sample = sample_;
  // A reset takes the tool to the hand as read this tick: a hand put
  // somewhere new (N, Reset tool) and the reset sent after it arrive together.
  if (reset_pending_) {
    reset_pending_ = false;
    Reset(sample_.X_WH);
  }

  const std::uint64_t engine_faults_before = data_.faults.total();
  if (!paused_) Step(model_, sample_.X_WH, &data_);
  Vector3 F = data_.force_W, T = data_.torque_W;
  // Rise limit (SafetyParams::slip_n_per_s): a rise of the force not explained
  // by the device's move is spread over ticks. A fall is sent at once: the
  // engine already eases a slip (EngineParams::slip_step_mm), and force the
  // contact no longer gives is never held.
  if (options_.safety.slip_n_per_s > 0 && F.allFinite()) {
    const Vector3 at = sample_.X_WH.translation();
    if (contact_force_valid_ && at.allFinite()) {
      const double allowed = options_.safety.slip_n_per_s / rate +
                             model_.params.k_t * (at - contact_device_W_).norm();
      const double before = contact_force_W_.norm(), now = F.norm();
      if (now > before + allowed) F *= (before + allowed) / now;
    }
    contact_force_W_ = F;
    contact_device_W_ = at;
    contact_force_valid_ = at.allFinite();
  }
  for (LoopEffect* e : effects_) e->Apply(model_, data_, &F, &T, this);
  faults_.engine = data_.faults.total();
  if (faults_.engine != engine_faults_before) ramp_start_tick_ = tick_;

  // Safety: NaN guard, watchdog, pause, ramp, scale, clamps.
  if (!F.allFinite() || !T.allFinite()) {
    ++faults_.nonfinite_output;
    ramp_start_tick_ = tick_;
    F.setZero();
    T.setZero();
  }
  if (overrun) {
    ++faults_.overruns;
    ramp_start_tick_ = tick_;
    Emit(HapticEvent::Of(EventKind::kOverrun));
  }
  const double ramp_ticks = options_.safety.ramp_s * rate;
  const double since = static_cast<double>(tick_ - ramp_start_tick_);
  const double ramp = ramp_ticks > 0 ? std::min(1.0, since / ramp_ticks) : 1.0;
  output_scale_ = (overrun || paused_ || !device_ok_) ? 0.0 : ramp * options_.force_scale;
  F *= output_scale_;
  T *= output_scale_;
  ClampNorm(&F, force_limit_n_);
  ClampNorm(&T, torque_limit_nmm_);
  force_W_ = F;
  torque_W_ = T;
  device_->Write(F, T);

  const double f = F.norm();
  if (!force_above_ && f > options_.force_event_n) {
    force_above_ = true;
    HapticEvent e = HapticEvent::Of(EventKind::kForceAbove);
    e.payload.force.force_n = f;
    Emit(e);
  } else if (force_above_ && f < 0.9 * options_.force_event_n) {
    force_above_ = false;
    HapticEvent e = HapticEvent::Of(EventKind::kForceBelow);
    e.payload.force.force_n = f;
    Emit(e);
  }
  UpdateContacts();
  max_force_n_ = std::max(max_force_n_, f);
  if (data_.num_active_keys > 0) {
    ++contact_ticks_;
    contact_force_sum_n_ += f;
  }
  if (data_.force_saturated) ++saturated_ticks_;

  record_.X_WG = data_.X_WG;
  record_.force_W = F;
  record_.torque_W = T;
  FillSnapshot();
  snapshots_.Publish();
  ++tick_;
}

void HapticLoop::UpdateContacts() noexcept {
  std::array<std::uint64_t, HapticSnapshot::kMaxObjects / 64> now{};
  for (int i = 0; i < data_.num_active_keys; ++i) {
    const int object = ContactPair::ObjectOfKey(data_.active_keys[i]);
    if (object < HapticSnapshot::kMaxObjects)
      now[object / 64] |= std::uint64_t{1} << (object % 64);
  }
  for (std::size_t w = 0; w < now.size(); ++w) {
    const std::uint64_t changed = now[w] ^ in_contact_[w];
    for (int b = 0; b < 64; ++b) {
      if (!((changed >> b) & 1)) continue;
      Emit(HapticEvent::Of(
          ((now[w] >> b) & 1) ? EventKind::kContactBegan : EventKind::kContactEnded,
          static_cast<int>(w * 64 + b)));
    }
  }
  in_contact_ = now;
}

void HapticLoop::FillSnapshot() noexcept {
  HapticSnapshot& s = snapshots_.back();
  s.tick = tick_;
  s.time_s = record_.time_s;
  s.X_WH = sample_.X_WH;
  s.X_WG = data_.X_WG;
  s.force_W = force_W_;
  s.torque_W = torque_W_;
  s.engine_force_W = data_.force_W;
  s.output_scale = output_scale_;
  s.saturated = data_.force_saturated;
  s.paused = paused_;
  s.device_ok = device_ok_;
  s.buttons = sample_.buttons;
  s.num_pairs = data_.num_pairs;
  s.active_contacts = data_.active_contacts;
  s.max_penetration_mm = data_.max_penetration_mm;
  s.qp_iterations = data_.qp_iterations;
  s.linearizations = data_.linearizations;
  s.timings = data_.timings;
  s.in_contact = in_contact_;
  int shown = 0;
  for (int i = 0; i < data_.num_pairs && shown < HapticSnapshot::kMaxShownPairs; ++i)
    if (data_.pairs[i].gap < 0.05) {
      const ContactPair& c = data_.pairs[i];
      s.shown_centers_W[shown] = model_.world.ObjectCenter(c.object, c.object_leaf);
      s.shown_radii[shown] = model_.world.ObjectRadius(c.object, c.object_leaf);
      s.shown_pairs[shown++] = c;
    }
  s.num_shown_pairs = shown;
  s.faults = faults_;
  s.max_force_n = max_force_n_;
  s.contact_ticks = contact_ticks_;
  s.contact_force_sum_n = contact_force_sum_n_;
  s.saturated_ticks = saturated_ticks_;
}

}  // namespace sulcus
