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

#include <memory>
#include <string>
#include <vector>

#include "core/haptics/device.h"
#include "core/lesson/lesson.h"

namespace sulcus {

const std::vector<std::string>& ScriptedStudentNames();

/// A scripted hand that takes a lesson: the device it plays and, attached to
/// the lesson, what it enters as it goes (a consumer of the tick stream).
class ScriptedHand : public TickConsumer {
 public:
  virtual std::unique_ptr<Device> MakeDevice() const = 0;
  virtual void Attach(LessonRun* lesson) = 0;
};

/// The scripted student (probing lessons) or inspector (inspection lessons)
/// called `name`. Throws std::invalid_argument for a name the kind does not have.
std::unique_ptr<ScriptedHand> MakeScriptedHand(const std::string& name,
                                               const LessonSpec& spec,
                                               const CompiledScene& scene);

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
  LessonRun* lesson_ = nullptr;
  struct Seen {
    SiteRef site;
    double deepest = 0;
    bool bled = false;
    std::uint64_t tick = 0;
  };
  std::vector<Seen> seen_;
  std::uint64_t last_tick_ = 0;
};

/// A device that plays a list of moves (ScriptedStudent::Move) by loop time,
/// feeling the force written back (a stroke stops when it feels its force).
std::unique_ptr<Device> MakeHandDevice(std::vector<ScriptedStudent::Move> moves,
                                       std::string name);

}  // namespace sulcus
