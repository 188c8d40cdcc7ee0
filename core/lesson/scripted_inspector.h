#pragma once
// Scripted inspectors with known behaviour, for inspection lessons (tests,
// demonstrations, the headless main program): the hand visits every region and
// tooth surface of the lesson's steps in order, the tip resting on each with a
// light press (until its hand feels 0.2 N), coming to it from above and off the
// surface so that the shank stays clear of the neighbours; what it records is
// what it examined, from the scene's truth.
//
//   thorough  every region and surface; records every finding it examined.
//   skipping  leaves out the left buccal mucosa and the lingual surfaces of the
//             lower molars.
//   mistaken  thorough, but records caries on a sound surface (the occlusal of
//             the first caries-free tooth of the lesson, written in at the end)
//             and leaves out the last carious surface of the truth.
//   rough     thorough, but presses the tongue's dorsum at about 1 N and forces
//             the tip into the first carious lesion at about 1.5 N.

#include <memory>
#include <string>
#include <vector>

#include "core/lesson/lesson.h"
#include "core/lesson/scripted_student.h"

namespace sulcus {

const std::vector<std::string>& ScriptedInspectorNames();

class ScriptedInspector final : public ScriptedHand {
 public:
  /// Throws std::invalid_argument for an unknown name or a lesson that is not an
  /// inspection.
  ScriptedInspector(const std::string& name, const LessonSpec& spec,
                    const CompiledScene& scene);
  const std::string& name() const { return name_; }
  std::unique_ptr<Device> MakeDevice() const override;
  /// The units (InspectionUnit::Name) this inspector leaves out on purpose.
  const std::vector<std::string>& skipped() const { return skipped_; }
  /// The findings it gets wrong on purpose: recorded where there is none, left out.
  const std::vector<Finding>& false_findings() const { return false_; }
  const std::vector<Finding>& missed_findings() const { return missed_; }

  /// Records findings into `lesson` as it examines, and submits at the end.
  void Attach(LessonRun* lesson) override { lesson_ = lesson; }
  void OnTick(const TickRecord& r) override;
  void OnEnd() override;

 private:
  std::string name_;
  std::vector<ScriptedStudent::Move> moves_;
  std::vector<std::string> skipped_;
  Odontogram truth_;
  std::vector<Finding> false_, missed_;
  LessonRun* lesson_ = nullptr;
  std::vector<bool> seen_;  // per unit: its findings recorded
  std::uint64_t last_tick_ = 0;
};

}  // namespace sulcus
