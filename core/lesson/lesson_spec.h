#pragma once
// Lesson files (lessons/*.yaml, every key in lessons/README.md): what the
// student is asked to do on which scene, in which order, and how it is scored.
// Loaded like a scene: every error at once as `file:line:column: message`.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/lesson/chart.h"
#include "core/scene/scene.h"

namespace sulcus {

/// An entry's tick "after the last reading at that site" (a chart entry) or "at
/// the end" (a finding, a declaration): resolved by LessonRun::Finish().
inline constexpr std::uint64_t kAfterReading = ~std::uint64_t{0};

struct SiteRef {
  int fdi = 0;
  int site = 0;  // 0..5: MB, B, DB, ML, L, DL
  bool operator==(const SiteRef&) const = default;
  std::string ToString() const;  // "46 DB"
};

/// The rubric: weights (points out of their sum) and the clinical tolerances,
/// defaults from the probing literature (lessons/README.md has the sources).
struct RubricSpec {
  // Weights of the categories.
  double technique = 20, reading = 15, charting = 15, force = 15, angulation = 10,
         coverage = 10, bleeding = 5, completeness = 10, diagnosis = 10;
  // Tolerances.
  double technique_full_mm = 0.5, technique_partial_mm = 1.0;  // |reached - truth|
  double force_low_n = 0.15, force_high_n = 0.30, force_damage_n = 0.50;
  double angle_full_deg = 5, angle_pass_deg = 10;  // facial and oral mid-sites
  // Interproximal: the tip within this of the col's midline (where the sulcus
  // meets the neighbour's under the contact), along the sulcus.
  double col_reach_mm = 1.0;
  double coverage_min = 0.80;  // share of a surface's sulcus arc swept
  // Inspection lessons.
  double findings = 40, sequence = 10;
  double damage = -1;  // < 0: as much as force
  double lesion_force_n =
      0.5;  // pressing a lesion harder than this is damage (it cavitates)
  double touch_dwell_s =
      0.1;  // the tip resting on a region or surface this long counts as examining it
  double DamageWeight() const { return damage >= 0 ? damage : force; }
};

struct StepSpec {
  // Probing: read, charted, diagnosis. Inspection: touched (every region and
  // surface of the step examined by the tip), recorded (the findings submitted).
  enum class Complete { kRead, kCharted, kDiagnosis, kTouched, kRecorded };
  std::string id;
  std::string instruction;
  Complete complete = Complete::kRead;
  std::vector<int> teeth;  // empty: all the lesson's teeth
  enum class Surface { kAll, kBuccal, kLingual } surface = Surface::kAll;
  double time_limit_s = 0;  // 0: none
  // Inspection: the regions (InspectionRegionNames) and the teeth's surfaces
  // (bits 1 << ToothSurface) the step examines.
  std::vector<std::string> regions;
  unsigned surfaces = 0x1f;
  int line = 0;
};
const char* ToString(StepSpec::Complete c);

/// A generated case: the scene's pockets, recession and bleeding drawn so that
/// the true chart has this diagnosis under the 2017 rules.
struct CaseSpec {
  bool generated = false;
  Stage stage = Stage::kIII;
  Extent extent = Extent::kLocalized;
  // A grade asked for (and stage IV) gives the case a patient: age, smoking,
  // diabetes, teeth lost, the bite, drawn with the pockets.
  Grade grade = Grade::kNone;
  bool random_seed =
      false;  // `seed: random`: drawn at the start of each attempt, then stored with it
  std::uint64_t seed = 1;
};

struct LessonSpec {
  /// A probing lesson (sites read and charted, a diagnosis) or an inspection
  /// (regions and tooth surfaces examined, findings recorded on an odontogram).
  enum class Kind { kProbing, kInspection } kind = Kind::kProbing;
  std::filesystem::path file;
  std::string name, description;
  std::filesystem::path scene;  // resolved against the lesson's folder
  enum class Mode { kPractice, kAssessment } mode = Mode::kPractice;
  std::string probe;          // the probe the lesson expects (the scene's, checked)
  std::vector<int> teeth;     // in the scene; default: every tooth with sites
  std::vector<SiteRef> path;  // default: the standard charting path over `teeth`
  std::vector<StepSpec> steps;
  RubricSpec rubric;
  double time_limit_s = 0;  // 0: none
  double pass_mark = 70;    // the score (of 100) an attempt passes with
  CaseSpec case_spec;
  // `calibration: {reference: FILE}`: a reference examiner's chart of the same
  // case (an answers file: an instructor's attempt's answers.yaml, or a chart
  // written by hand). The report sets the student's chart against it, as a
  // calibration exercise does, besides against the truth.
  std::filesystem::path reference_file;
  PerioChart reference;  // its depths and bleeding (empty without one)
  bool has_reference() const { return !reference_file.empty(); }
  std::vector<std::string>
      regions;  // inspection: the regions examined (default: every one the scene has)
  bool inspection() const { return kind == Kind::kInspection; }
  bool practice() const { return mode == Mode::kPractice; }
};
const char* ToString(LessonSpec::Mode m);
const char* ToString(LessonSpec::Kind k);

/// Reads and checks a lesson file and the scene it names (the teeth must be in
/// it with sites, the probe must be the scene's). Throws LoadError with every
/// error found, each `file:line:column: message`.
LessonSpec LoadLessonSpec(const std::filesystem::path& file);

/// The lesson files (.yaml) of each folder, each folder's sorted by name; a
/// folder that is missing or unreadable gives none.
std::vector<std::filesystem::path> LessonFiles(
    const std::vector<std::filesystem::path>& dirs);

/// The usual charting path (Open Dental's): upper buccal 18 -> 28, upper palatal
/// 28 -> 18, lower buccal 48 -> 38, lower lingual 38 -> 48, over the given teeth.
std::vector<SiteRef> StandardPath(std::vector<int> teeth);

/// The most leaves a generated case's gingiva is built with (5 levels). Each
/// case rebuilds the gingiva's sphere-trees (its pockets reshape it; its teeth
/// and the rest come from the cache); at 1,024 leaves a share builds in about
/// 5 s instead of 20 to 40 s at 3,072, and the scripted students read and score
/// the same (docs/accuracy-cost: within 1 mm 100 % at both; at 512 it is not).
inline constexpr int kCaseGingivaLeaves = 1024;

/// A generated case's gingiva spends those leaves on the min-max cover only
/// (SphereTreeParams::Spend::kWorst), tightened this many times, as the
/// fixed scenes' do not (their trees, and the recorded attempts replayed on
/// them, stay as they were measured). On the four shares of a case the worst
/// leaf was the same or lower (0.58 against 0.66 mm on the deepest pockets'
/// share), the mean 0.01 to 0.05 mm higher, and the four built in 6.9 s
/// instead of 9.6 s: with a furcation jaw's, what brings a new case within
/// 10 s on two cores (docs/engine.md, "A new case in under 10 s").
inline constexpr int kCaseGingivaTightenPasses = 1;

/// The lesson on the scene its case drew: a tooth the case took out (stage IV
/// by tooth loss, in a lesson of more than a sextant) leaves the lesson's
/// teeth, path and steps.
void FitLessonToCase(LessonSpec* spec, const SceneSpec& scene);

/// The scene with a generated case applied: pockets, recession and bleeding of
/// the lesson's teeth drawn from `seed` until the true chart classifies as asked
/// (at most a few thousand draws; throws std::runtime_error when none fits).
/// Its gingiva's trees have at most kCaseGingivaLeaves leaves, spent as
/// kCaseGingivaTightenPasses says.
SceneSpec ApplyCase(const SceneSpec& scene, const std::vector<int>& teeth,
                    const CaseSpec& c, std::uint64_t seed);

/// Writes the scene the lesson runs on with its case drawn for `stage`,
/// `extent` and `seed` as a scene file of its own at `out` (the lesson's scene
/// with its teeth's pockets, recession and bleeding replaced; every other key as
/// it was; the case named in the file's first lines). The file is read back and
/// its true chart checked against the drawn one. An instructor's fixed case for
/// lessons without `case:`. Throws std::runtime_error naming the file (a scene
/// that names mesh files can only be saved in its own folder), LoadError.
SceneSpec SaveCaseScene(const LessonSpec& lesson, const CaseSpec& c, std::uint64_t seed,
                        const std::filesystem::path& out);

/// The scene's true chart over `teeth` (clinical recession: the scene's
/// recession minus the healthy margin's 1.5 mm above the CEJ).
PerioChart TrueChart(const SceneSpec& scene, const std::vector<int>& teeth);

}  // namespace sulcus
