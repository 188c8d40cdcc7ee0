#pragma once
// Scripted students with known behaviour, for tests, demonstrations and the
// headless main program: a trajectory for the device (built from the scene's
// sulci) and a way of charting (what they enter after each reading).
//
//   careful     walks the probe around every surface in short up-and-down
//               strokes, parallel to the long axis (4 degrees off, as the crown
//               allows) and tilted under the contacts into the col, going down
//               each stroke until it feels 0.20 N (its device reads the force
//               it renders, as a hand does); charts what the probe reached,
//               rounded to the marking; declares the diagnosis of its chart.
//   rough       the same strokes, pushing each until it feels 2 N.
//   misreading  careful technique, but enters the reading plus 2 mm at three
//               sites (the first interdental site of each of the first three
//               teeth of the path).
//   spot        three straight insertions per surface (one per site), no walking.
//   lazy        careful, but skips the second tooth of the path.
//
// Students with human hands (the careful path and charting unless said):
//   tremor      a physiological tremor of 0.06 mm (9.5 and 11.3 Hz) and 0.3
//               degrees, a slow drift of 0.2 mm, resting 1 s at each floor.
//   slow        strokes at 2 mm/s instead of 12, moves three times slower.
//   hesitant    stops halfway down every stroke for 0.3 s, then goes on.
//   overshoot   goes down until it feels 0.36 N, then backs off to 0.22 N and
//               rests there (1 s in all, keeping the force as a person does).
//   occlusal    one insertion per site from 2 mm above the margin, coming down
//               over the crown (no walking).
//   charting    rests 1 s at the floor of each site's own stroke and charts the
//               site while the tip is still in it.
//   human       the careful-but-human student, several of the above at once:
//               tremor of 0.06 mm and drift, strokes at 3 mm/s and moves 1.5
//               times slower, a rest of 1 s keeping 0.22 N at each floor, and
//               charting at rest.
//   keys        the window's keys (N, R, the walking keys, T) on the window's
//               own device: core/lesson/scripted_keys.h.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/haptics/device.h"
#include "core/lesson/lesson.h"
#include "core/session/session.h"

namespace sulcus {

const std::vector<std::string>& ScriptedStudentNames();

/// A scripted hand that takes a lesson: the device it plays and, attached to
/// the lesson, what it enters as it goes (a consumer of the tick stream).
class ScriptedHand : public TickConsumer {
 public:
  virtual std::unique_ptr<Device> MakeDevice() const = 0;
  virtual void Attach(LessonRun* lesson) = 0;
  /// The loop this hand may send commands to, as the window's keys do (the
  /// keys student's N resets the tool to the hand, as the window's N does).
  /// Only where the hand runs on the thread that alone sends the loop
  /// commands (an offline session: RunAttempt); unset, nothing is sent.
  void SetLoop(HapticLoop* loop) { loop_ = loop; }

 protected:
  HapticLoop* loop_ = nullptr;
};

/// The scripted student (probing lessons) or inspector (inspection lessons)
/// called `name`. Throws std::invalid_argument for a name the kind does not have.
std::unique_ptr<ScriptedHand> MakeScriptedHand(const std::string& name,
                                               const LessonSpec& spec,
                                               const CompiledScene& scene);

/// The device a lesson is taken with, made from its name (ParseDeviceName): a
/// scripted student (with the hand that enters its chart) or what MakeDevice
/// makes. For "mouse", `device.device` is empty: the window makes its own.
/// Throws std::invalid_argument for a bad name, as MakeDevice does for a file.
struct LessonDevice {
  DeviceSpec device;
  std::unique_ptr<ScriptedHand> student;  // set for student:NAME
};
LessonDevice MakeLessonDevice(const std::string& spelling, const LessonSpec& spec,
                              const CompiledScene& scene, double seconds);

class ScriptedStudent final : public ScriptedHand {
 public:
  /// Throws std::invalid_argument for an unknown name.
  ScriptedStudent(const std::string& name, const LessonSpec& spec,
                  const CompiledScene& scene);
  const std::string& name() const { return name_; }
  /// A fresh device that plays this student's hand (it reacts to the force
  /// written to it, so it is deterministic for a given scene and build).
  std::unique_ptr<Device> MakeDevice() const override;
  /// One move of the hand: to a pose in a time, or a probing stroke along the
  /// tool's axis until a force is felt (or a depth is reached), then back.
  struct Move {
    bool stroke = false;
    RigidTransform X_WH;           // the end pose (a stroke: its top)
    double duration_s = 0;         // a move's
    double max_depth_mm = 0;       // a stroke's: from its top along the axis
    double target_force_n = 0.22;  // a stroke stops going down at this force
    Vector3 direction_W =
        Vector3::Zero();  // a stroke's way in (zero: down the tool's axis)
    double speed_mm_s = 12,
           hold_s = 0.1;  // a stroke's speed in and how long it rests at the bottom
    /// A move's: the hand stops it where it feels this much force (0: never),
    /// as a hand coming down to a surface stops when it meets it.
    double stop_force_n = 0;
    /// A stroke's, when not zero: it starts wherever the hand is (a move
    /// stopped short) rather than at X_WH, and goes toward this point,
    /// max_depth_mm past it.
    Vector3 aim_W = Vector3::Zero();
    /// A stroke's, when not zero: while it rests at the bottom the hand keeps
    /// this force as a person does, correcting slowly on what it feels (the
    /// felt force low-passed at 3 Hz, 4 mm/s per newton of error): an
    /// overshoot is backed off, a tremor's swing is not chased.
    double hold_force_n = 0;
    /// A stroke's, when not zero: it stops this deep for pause_s on the way down.
    double pause_at_mm = 0, pause_s = 0;
    /// A stroke's: the student charts the site while resting at its floor.
    bool chart_at_rest = false;
  };
  /// How a hand departs from the moves it means: tremor (two sines of 9.5 and
  /// 11.3 Hz in fixed directions), angular tremor, a slow drift (0.07 Hz), and
  /// keyboard steps (the position snapped to step_mm, at most one step per
  /// step_s on each axis).
  struct HandStyle {
    double tremor_mm = 0, tremor_deg = 0, drift_mm = 0;
    double step_mm = 0, step_s = 0.01;
  };
  /// The sites whose entry this student gets wrong on purpose (misreading).
  const std::vector<SiteRef>& misread_sites() const { return misread_; }
  const std::vector<int>& skipped_teeth() const { return skipped_; }

  /// Chart entries follow the stream: after each site's reading the student
  /// enters it into `lesson` (attach before the lesson's own OnTick is not needed:
  /// entries carry their tick). At the end it declares its chart's diagnosis.
  void Attach(LessonRun* lesson) override { lesson_ = lesson; }
  void OnTick(const TickRecord& r) override;
  void OnEnd() override;

 private:
  std::string name_;
  const LessonSpec& spec_;
  std::vector<Move> moves_;
  std::vector<SiteRef> misread_;
  std::vector<int> skipped_;
  HandStyle hand_;
  bool chart_at_rest_ = false;
  LessonRun* lesson_ = nullptr;
  // Charting at rest: the site the tip rests in, since when, how deep.
  std::optional<SiteRef> rest_site_;
  double rest_since_s_ = 0, rest_depth_ = 0;
  std::vector<SiteRef> charted_;
  struct Seen {
    SiteRef site;
    double deepest = 0;
    bool bled = false;
    std::uint64_t tick = 0;
  };
  std::vector<Seen> seen_;
  std::uint64_t last_tick_ = 0;
};

/// What a scripted student declares: the diagnosis of its own chart by the
/// 2017 rules, stamped `tick`.
DeclaredDiagnosis DiagnosisOfChart(const PerioChart& chart, std::uint64_t tick);

/// A device that plays a list of moves (ScriptedStudent::Move) by loop time,
/// feeling the force written back (a stroke stops when it feels its force).
std::unique_ptr<Device> MakeHandDevice(std::vector<ScriptedStudent::Move> moves,
                                       std::string name,
                                       ScriptedStudent::HandStyle hand = {});

}  // namespace sulcus
