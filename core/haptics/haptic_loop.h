#pragma once
// The body of the haptic thread, one tick at a time and without any clock, so
// that the thread, a replay "as fast as possible" and the tests run exactly the
// same code: apply the window's commands, read the device, step the engine, run
// the scene's effects, apply the safety rules, write the device, emit events and
// publish the snapshot. Never allocates, never throws after construction.

#include <array>
#include <cstdint>
#include <span>
#include <type_traits>

#include "core/haptics/device.h"
#include "core/haptics/engine.h"
#include "core/haptics/realtime.h"

namespace sulcus {

struct SafetyParams {
  double ramp_s = 0.5;  // output rises linearly over this after a start or a fault
  double device_timeout_s = 0.010;  // no fresh reading for this long: zero force
  // The contact force rises within a tick by at most what the device's own
  // move explains (k_t times how far it moved) plus this rate times the tick
  // (a rendered tool pushed out of an overlap would otherwise be felt as a
  // knock). A fall is never held back: the engine eases a slip off an edge
  // (EngineParams::slip_step_mm), so the force sent is what the contact gives.
  // 0: no limit. Faults, pauses and a lost device still cut the force at once.
  double slip_n_per_s = 40.0;
};

/// How much a force's change over a tick exceeds what the device's own move
/// explains (k_t times how far it moved), N. Above kPopN it is a pop: a click
/// the hand feels. The engine's slip easing (EngineParams::slip_step_mm) keeps a
/// fall at most k_t times slip_step_mm a tick, the loop's rise limit
/// (SafetyParams::slip_n_per_s) a rise at most slip_n_per_s over the rate.
inline double UnexplainedForceChange(const Vector3& force_before,
                                     const Vector3& force_after,
                                     const Vector3& device_before,
                                     const Vector3& device_after, double k_t) {
  return (force_after - force_before).norm() -
         k_t * (device_after - device_before).norm();
}
inline constexpr double kPopN = 0.05;

enum class EventKind : std::uint8_t {
  kContactBegan,  // object: which object (engine index)
  kContactEnded,
  kForceAbove,  // the force sent rose above LoopOptions::force_event_n; force
  kForceBelow,  // and fell back below 90 % of it
  kDeviceLost,  // no fresh reading for device_timeout_s
  kDeviceBack,
  kOverrun,       // the thread was late (watchdog): zero force this tick
  kCommand,       // a command was applied; command
  kProbeReading,  // probing_depth: one insertion at a site ended; reading
  kBleeding,  // bleeding_on_probing: a bleeding site was probed to its floor; bleeding
  kTissueDamage,  // tissue_damage: the force on an object rose above its limit; damage
  kSoftContact,   // gingiva_compliance: the probe began pressing soft tissue; force
  kCariesCatch,   // caries_catch: the tip caught in a carious lesion; object (the tooth),
                  // damage (force, 0)
  kCalculusTouched,  // calculus: the working end met a calculus deposit; object (the
                     // deposit), calculus
  kCount,            // not a kind: how many there are (a new kind goes above)
};
inline constexpr int kNumEventKinds = static_cast<int>(EventKind::kCount);
const char* ToString(EventKind kind);

/// A probing reading: the deepest point of one insertion into a site's sulcus.
struct ReadingPayload {
  std::int32_t fdi = 0;     // the tooth
  std::int32_t site = 0;    // 0..5: MB, B, DB, ML, L, DL
  double depth_mm = 0;      // deepest tip depth below the margin
  double peak_force_n = 0;  // the largest force along the probe's axis while the tip
                            // dwelt at its deepest (within 0.2 mm)
  double axis_angle_deg =
      0;  // the tool axis against the tooth's long axis at the deepest moment
  std::uint64_t deepest_tick = 0;  // when the tip was deepest
  std::uint64_t entered_tick = 0;  // when the tip entered the site
};
struct BleedingPayload {
  std::int32_t fdi = 0, site = 0;
  double depth_mm = 0, force_n = 0;  // at the moment the site bled
};
struct CalculusPayload {
  std::int32_t fdi = 0, site = 0;  // the deposit's tooth and probing site
  double force_n = 0;              // the deposit's share of the contact force when met
};
struct DamagePayload {
  double force_n = 0, limit_n = 0;
};
struct ForcePayload {
  double force_n = 0;
};
struct CommandPayload {
  std::uint8_t command = 0;  // HapticCommand::Kind
  double value = 0;
};

/// One event of a tick. `object` is the engine's index of the object it is about
/// (teeth and soft tissue alike: CompiledScene::spec.objects), -1 when none; the
/// payload that goes with the kind is the only one set.
struct HapticEvent {
  EventKind kind = EventKind::kContactBegan;
  std::int32_t object = -1;
  std::uint64_t tick = 0;
  union Payload {
    ReadingPayload reading;
    BleedingPayload bleeding;
    DamagePayload damage;
    ForcePayload force;
    CommandPayload command;
    CalculusPayload calculus;
    Payload() : reading() {}
  } payload;
  static HapticEvent Of(EventKind kind, int object = -1) {
    HapticEvent e;
    e.kind = kind;
    e.object = object;
    return e;
  }
};
static_assert(std::is_trivially_copyable_v<HapticEvent>);

struct HapticCommand {
  enum class Kind : std::uint8_t {
    kPause,
    kResume,
    kResetTool,
    kSetForceScale,
    kSetForceLimit,
    kSetTorqueLimit
  };
  Kind kind = Kind::kPause;
  double value = 0;  // scale 0..1, limit in N or N*mm
};
const char* ToString(HapticCommand::Kind kind);

/// Faults of the loop (beyond the engine's own), counted, never thrown.
struct LoopFaults {
  std::uint64_t overruns = 0;  // ticks the watchdog zeroed because the thread was late
  std::uint64_t device_stalls = 0;  // episodes without fresh device readings
  std::uint64_t nonfinite_output = 0;
  std::uint64_t engine = 0;  // EngineFaults::total()
  std::uint64_t events_dropped =
      0;  // a tick had more events than TickRecord holds (counted, never silent)
  std::uint64_t total() const {
    return overruns + device_stalls + nonfinite_output + engine;
  }
};

/// What the window and the lesson read: the latest tick, copied whole.
struct HapticSnapshot {
  static constexpr int kMaxShownPairs = 64;
  static constexpr int kMaxObjects = 256;
  std::uint64_t tick = 0;
  double time_s = 0;
  RigidTransform X_WH, X_WG;
  Vector3 force_W = Vector3::Zero();  // as sent to the device (ramped, clamped)
  Vector3 torque_W = Vector3::Zero();
  Vector3 engine_force_W = Vector3::Zero();  // the spring before the safety rules
  double output_scale = 0;                   // ramp times the force scale, 0..1
  bool saturated = false, paused = false, device_ok = true;
  std::uint32_t buttons = 0;
  int num_pairs = 0, active_contacts = 0;
  double max_penetration_mm = 0;
  int qp_iterations = 0, linearizations = 0;
  StepTimings timings;
  std::array<std::uint64_t, kMaxObjects / 64> in_contact{};  // bit per object
  int num_shown_pairs = 0;
  std::array<ContactPair, kMaxShownPairs> shown_pairs{};
  // The object spheres of those pairs, in the world (the window draws them
  // without reading the engine's model).
  std::array<Vector3, kMaxShownPairs> shown_centers_W{};
  std::array<double, kMaxShownPairs> shown_radii{};
  LoopFaults faults;
  // Totals since the start.
  double max_force_n = 0;           // the largest force sent
  std::uint64_t contact_ticks = 0;  // ticks with at least one active contact
  double contact_force_sum_n = 0;   // sum of the force sent over those ticks
  std::uint64_t saturated_ticks = 0;
  bool InContact(int object) const {
    return object >= 0 && object < kMaxObjects &&
           ((in_contact[object / 64] >> (object % 64)) & 1);
  }
};

class HapticLoop;

/// An effect a scene asked for (effects.h). Runs after the engine step, may
/// change the output force and emit events. Only the effects a scene names are
/// in the loop's list, so an effect not named costs nothing.
class LoopEffect {
 public:
  virtual ~LoopEffect() = default;
  virtual const char* name() const = 0;
  /// Never allocates, never throws.
  virtual void Apply(const EngineModel& model, const EngineData& data, Vector3* force_W,
                     Vector3* torque_W, HapticLoop* loop) noexcept = 0;
  virtual void Reset() noexcept {}
};

struct LoopOptions {
  double rate_hz = 1000;
  SafetyParams safety;
  double force_event_n = 1.0;  // kForceAbove / kForceBelow threshold
  double force_scale = 1.0;    // 0..1, the window can change it
};

/// One recorded tick: the loop's inputs (device reading, freshness, lateness,
/// commands as events) and outputs (graphic pose, wrench, events).
struct TickRecord {
  static constexpr int kMaxEvents = 16;  // more in one tick are counted in events_dropped
  std::uint64_t tick = 0;
  double time_s = 0;
  DeviceSample sample;
  bool fresh = true, overrun = false;
  RigidTransform X_WG;
  Vector3 force_W = Vector3::Zero(), torque_W = Vector3::Zero();
  int num_events = 0;
  std::uint32_t events_dropped = 0;  // this tick's events beyond kMaxEvents
  std::array<HapticEvent, kMaxEvents> events{};
};

/// Where the haptic thread hands each tick's record: a fixed ring another thread
/// drains (RecordingWriter, Session). Push never blocks, allocates or throws.
class TickSink {
 public:
  virtual ~TickSink() = default;
  virtual void Push(const TickRecord& r) noexcept = 0;
};

class HapticLoop {
 public:
  static constexpr std::size_t kCommandCapacity = 64;

  /// The model and device must outlive the loop. Effects run in the given order.
  HapticLoop(const EngineModel& model, Device* device, const LoopOptions& options,
             std::span<LoopEffect* const> effects = {});

  /// Puts both tools at X_WG and restarts the ramp.
  void Reset(const RigidTransform& X_WG);

  /// One tick at loop time tick/rate. `overrun` says the thread was too late for
  /// this tick (the watchdog zeroes the output).
  void Tick(bool overrun) noexcept;

  // Other threads.
  bool Send(const HapticCommand& c) noexcept { return commands_.Push(c); }
  TripleBuffer<HapticSnapshot>& snapshots() { return snapshots_; }

  // The haptic thread (or the test that drives the loop).
  void Emit(const HapticEvent& e) noexcept;
  const TickRecord& last_record() const { return record_; }
  const EngineData& data() const { return data_; }
  std::uint64_t tick() const { return tick_; }
  const LoopOptions& options() const { return options_; }
  const LoopFaults& faults() const { return faults_; }
  const EngineModel& model() const { return model_; }
  bool device_finished() const noexcept { return device_->finished(); }
  /// Applies a command now (the thread does it at the top of a tick; a replay
  /// re-applies recorded ones).
  void Apply(const HapticCommand& c) noexcept;

 private:
  void UpdateContacts() noexcept;
  void FillSnapshot() noexcept;

  const EngineModel& model_;
  Device* device_;
  LoopOptions options_;
  std::span<LoopEffect* const> effects_;
  EngineData data_;
  std::uint64_t tick_ = 0;
  std::uint64_t ramp_start_tick_ = 0;
  std::uint64_t last_fresh_tick_ = 0;
  bool reset_pending_ = false;
  bool paused_ = false, device_ok_ = true, force_above_ = false;
  double output_scale_ = 0;
  double force_limit_n_, torque_limit_nmm_;
  DeviceSample sample_;
  Vector3 force_W_ = Vector3::Zero(), torque_W_ = Vector3::Zero();
  // The engine's contact force after the slip limit, and the device position it followed.
  Vector3 contact_force_W_ = Vector3::Zero(), contact_device_W_ = Vector3::Zero();
  bool contact_force_valid_ = false;
  std::array<std::uint64_t, HapticSnapshot::kMaxObjects / 64> in_contact_{};
  LoopFaults faults_;
  double max_force_n_ = 0, contact_force_sum_n_ = 0;
  std::uint64_t contact_ticks_ = 0, saturated_ticks_ = 0;
  TickRecord record_;
  SpscRing<HapticCommand, kCommandCapacity> commands_;
  TripleBuffer<HapticSnapshot> snapshots_;
};

}  // namespace sulcus
