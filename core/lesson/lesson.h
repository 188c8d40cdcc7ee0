#pragma once
// The lesson as a deterministic state machine over the tick stream (a
// TickConsumer) and the student's own inputs (chart entries, the declared
// diagnosis), each stamped with its tick. No clock: time is the tick's, so the
// same code runs live, offline and over a recording, and feeding the same
// stream and inputs gives the same result, bit for bit.
//
// While it runs it follows the steps, says which site is next and where the
// tip is ("in the sulcus of 46 DB"), and in practice mode gives the truth after
// each site. Finish() scores the attempt: per site the depth the probe reached
// against the truth (technique), the entry against what was reached (reading),
// the entry against the truth (charting), force at the floor against the band,
// angulation (mid-sites) or the col reached (interproximal sites), bleeding
// recorded or missed; per surface the share of the sulcus swept by the walking
// stroke; per lesson completeness, agreement within 1 mm, signed bias, time,
// tissue damage and the diagnosis (2017 rules) of the true chart, the student's
// chart and the student's declaration. Every line names the tick that caused it.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/haptics/probe_reading.h"
#include "core/haptics/tip_locator.h"
#include "core/lesson/calibration.h"
#include "core/lesson/chart.h"
#include "core/lesson/inspection.h"
#include "core/lesson/lesson_spec.h"
#include "core/session/session.h"

namespace sulcus {

/// What the student entered for one site, as a clinician calls it out.
struct ChartEntry {
  std::uint64_t tick = kAfterReading;
  SiteRef site;
  std::optional<int> pd_mm;  // empty: bleeding only
  bool bleeding = false;
};

struct DeclaredDiagnosis {
  std::uint64_t tick = kAfterReading;  // kAfterReading: at the end
  bool periodontitis = true;
  Stage stage = Stage::kNone;
  Extent extent = Extent::kNone;
  Grade grade = Grade::kNone;  // none: not declared (a scene without a patient)
  std::string Summary() const;
};

struct RubricLine {
  enum class Status { kPass, kPartial, kFail, kInfo };
  std::string category;  // technique, reading, charting, force, angulation, coverage,
                         // bleeding, completeness, damage, diagnosis, time
  std::optional<SiteRef> site;
  int fdi = 0;  // the tooth of a site or surface line (0: the lesson)
  Status status = Status::kInfo;
  double credit = 0;  // 0..1 (info lines do not count)
  std::string message;
  std::uint64_t tick = 0;  // the moment that caused the line
};
const char* ToString(RubricLine::Status s);

/// The angulation of a site without a contact, as the score judges it (the
/// window's panel colours the live angle with the same answer).
RubricLine::Status AngleStatus(double angle_deg, const RubricSpec& rubric);

struct SiteResult {
  SiteRef site;
  int truth_mm = 0;
  double recession_mm = 0;           // clinical (margin to CEJ, + apical)
  bool truth_bleeding = false;       // the scene's
  int insertions = 0;                // visits that gave a reading (probe_reading.h)
  std::optional<double> reached_mm;  // the deepest reading
  double held_force_n =
      0;  // the force held at the floor in that reading's dwell (scored)
  double peak_force_n = 0;  // the highest tick of that dwell (the damage line's)
  double angle_deg = 0;
  /// Why a site has no reading ("" when it has one): "never entered its sulcus",
  /// "entered but less than 0.5 mm deep (deepest X mm)", or "the tip was nearer
  /// another site's line".
  std::string no_reading;
  bool col_reached = false, interproximal_contact = false;
  std::uint64_t reading_tick = 0, entered_tick = 0, left_tick = 0;
  std::optional<ChartEntry> entry;
  bool bled = false;
  double bleed_force_n = 0;
  std::uint64_t bleed_tick = 0;
};

struct SurfaceCoverage {
  int fdi = 0;
  bool buccal = true;
  double swept = 0;        // share of the surface's sulcus arc the tip swept (0..1)
  double touch_share = 0;  // share of the in-sulcus ticks the tooth was touched
  double stroke_mm = 0;    // mean up-and-down excursion of the walking stroke
  int strokes = 0;
  std::uint64_t first_tick = 0, last_tick = 0;
  std::vector<bool> bins;  // the arc in 5-degree bins, swept or not (the report draws it)
};

struct StepResult {
  std::string id, instruction;
  bool completed = false, timed_out = false;
  bool skipped = false;  // inspection: left for a later step before it was done
  std::vector<std::string>
      missed{};  // inspection: what it had not examined when it ended
  std::uint64_t started_tick = 0, ended_tick = 0;
};

/// Sensitivity and specificity of one kind of finding against the truth.
struct FindingScore {
  std::string kind;  // caries (per tooth surface), calculus, inflamed gingiva (per
                     // tooth), lesion (per region), status (per tooth)
  int tp = 0, fn = 0, fp = 0, tn = 0;
  double sensitivity() const {
    return tp + fn > 0 ? static_cast<double>(tp) / (tp + fn) : 1.0;
  }
  double specificity() const {
    return fp + tn > 0 ? static_cast<double>(tn) / (fp + tn) : 1.0;
  }
};

/// What an inspection lesson adds to the result.
struct InspectionResult {
  std::vector<std::string> regions;
  std::vector<int> teeth;
  std::vector<InspectionUnit> units;  // regions, then five surfaces per tooth
  Odontogram truth, recorded;
  std::vector<Finding> findings;  // as entered, ticks resolved
  std::optional<std::uint64_t> submitted_tick;
  std::vector<FindingScore> scores;  // caries, calculus, inflamed gingiva, lesion, status
  std::vector<LesionPress> presses;  // lesions pressed harder than the rubric's limit
  std::vector<ViewSample> views;     // the window's camera as it moved (empty: headless)
};

struct LessonResult {
  std::string kind = "probing";  // or inspection
  std::string lesson_name, lesson_file, scene_file, mode, student;
  /// What the attempt was taken with (DeviceKindOf): haptic, keys, scripted or
  /// replay; a scripted or replayed attempt is not a student's own work.
  std::string device_kind;
  std::uint64_t case_seed = 0;
  bool generated_case = false;
  double rate_hz = 1000;
  RubricSpec rubric;              // what it was scored against
  std::vector<SiteResult> sites;  // in path order
  std::vector<SurfaceCoverage> coverage;
  std::vector<StepResult> steps;
  std::vector<RubricLine> lines;
  std::map<std::string, double> category_credit;  // 0..1, categories that have lines
  std::map<std::string, double> category_weight;
  double total = 0;       // 0..100
  double pass_mark = 70;  // the lesson's: total >= pass_mark passes
  int sites_total = 0, sites_read = 0, sites_charted = 0;
  double within_1mm_pct = 0, exact_pct = 0, bias_mm = 0, bias_proximal_mm = 0;
  double force_in_band_pct = 0;
  std::uint64_t first_tick = 0, last_tick = 0;
  double duration_s = 0;
  PerioChart true_chart, student_chart;
  Agreement agreement;  // the student's chart against the true one (calibration)
  // With a reference examiner (the lesson's `calibration:`): the student's
  // chart against the reference examiner's, and that chart.
  std::optional<Agreement> reference_agreement;
  PerioChart reference_chart;
  std::string reference_name;  // the reference chart's file name
  Diagnosis true_dx, chart_dx;
  std::optional<DeclaredDiagnosis> declared;
  std::vector<std::pair<std::uint64_t, float>>
      force_trace;  // (tick, force along the probe, N) every kTraceEvery ticks
  std::vector<std::string> feedback;  // what the student was told (practice)
  /// Every step done. An attempt that ended before (the window closed, the
  /// program stopped, the device was lost) is kept and scored as far as it went.
  bool complete = false;
  std::string ended;  // how an incomplete attempt ended ("" when complete)
  /// The device stopped answering at lost_tick and came back at back_tick (0: it did
  /// not).
  struct Interruption {
    std::uint64_t lost_tick = 0, back_tick = 0;
  };
  std::vector<Interruption> interruptions;
  InspectionResult inspection;  // inspection lessons
  static constexpr int kTraceEvery = 5;
};

/// Blood at the margin of a site that bled on probing, as the student sees it:
/// a point kBloodFirstS after the tip reached the floor, growing along the
/// margin into a line by kBloodFullS; kept until every site of the lesson in
/// that quadrant is charted (and at least until it has fully grown).
struct BloodMark {
  SiteRef site;
  double grown = 0;  // 0: a point; 1: the line across the site
  static constexpr double kBloodFirstS = 1.0, kBloodFullS = 10.0;
};

/// What a lesson needs of the compiled scene, computed once: each tooth's
/// frame and sulcus ring, and its engine index (for contacts).
struct LessonGeometry {
  struct Tooth {
    int fdi = 0, object = -1;
    RigidTransform X_WT;
    bool mirrored = false;
    std::vector<double> margin_z, floor_z, sulcus_r;  // per segment
    std::array<double, 6> site_angle{};
    bool mesial_contact = false, distal_contact = false;  // a neighbour in the scene
  };
  std::vector<Tooth> teeth;
  const Tooth* Find(int fdi) const;
};
LessonGeometry MakeLessonGeometry(const CompiledScene& scene,
                                  const std::vector<int>& teeth);

class LessonRun final : public TickConsumer {
 public:
  /// `scene` is the compiled scene the lesson runs on (with its case applied).
  LessonRun(const LessonSpec& spec, const CompiledScene& scene, std::string student = "",
            std::uint64_t case_seed = 0);

  // The stream.
  void OnTick(const TickRecord& r) override;
  /// The stream ended: entries scheduled past its last tick apply now.
  void OnEnd() override;
  // The student's inputs (kAfterReading ticks are resolved in Finish()).
  /// Charting a site while the tip is in its sulcus completes its reading at once.
  void Enter(const ChartEntry& e);
  /// An entry applied when the stream reaches its tick, as it was entered live
  /// (a replay with the attempt's answers; kAfterReading: at once).
  void Schedule(const ChartEntry& e);
  void Declare(const DeclaredDiagnosis& d);
  // Inspection lessons: a finding recorded on the odontogram, and the
  // odontogram submitted as complete (kAfterReading: at the end).
  void Record(const Finding& f);
  void Submit(std::uint64_t tick);
  /// The window's camera (inspection lessons: what the view showed).
  void View(const ViewSample& v);
  const std::vector<ViewSample>& views() const { return views_; }

  // Live state.
  int current_step() const { return step_; }  // == steps().size() when all are done
  const std::vector<StepResult>& steps() const { return step_results_; }
  bool done() const {
    return step_ >= static_cast<int>(spec_.steps.size()) || timed_out_;
  }
  /// The site to probe next: from the site read last, round the path, the first
  /// that the current step asks for and that has no reading at the floor (or,
  /// in a charting step, no depth charted). Moving on past a site (reading a
  /// later one) moves Next on too; the skipped site comes round again.
  std::optional<SiteRef> next_site() const;
  /// A reading at the floor: the probe held against the pocket's floor (at
  /// least kFloorForceN along it), not a touch in the sulcus.
  static constexpr double kFloorForceN = 0.1;
  static bool ReadAtFloor(const SiteResult& s);
  /// Where the tip is now: the site whose sulcus holds it, if any.
  std::optional<SiteRef> tip_site() const;
  /// The probe's angle to the long axis of the tooth whose sulcus holds the tip.
  std::optional<double> tip_angle_deg() const {
    return tip_at_.site >= 0 ? std::optional(tip_at_.angle_deg) : std::nullopt;
  }
  /// The tip's depth below the margin of the site whose sulcus holds it.
  std::optional<double> tip_depth_mm() const {
    return tip_at_.site >= 0 ? std::optional(tip_at_.depth_mm) : std::nullopt;
  }
  /// Where the tip is now, as the tip locator put it (site -1: in no sulcus).
  const TipLocation& tip_location() const { return tip_at_; }
  /// The tip under the contact of an interdental site that has one: what the
  /// score credits as the col reached (the panel shows this answer).
  bool tip_under_contact() const {
    return TipLocator::UnderContact(tip_at_, spec_.rubric.col_reach_mm);
  }
  /// The blood showing now (the window draws it; the scripted students chart
  /// bleeding from it).
  std::vector<BloodMark> blood_shown() const;
  /// Whether blood has shown at site s so far (a site never probed never bleeds).
  bool blood_seen(const SiteRef& s) const;
  /// The compiled scene's clinical recession per site (for the chart).
  double recession_mm(const SiteRef& s) const;
  /// The chart of the lesson's teeth as an examiner starts it: what is given,
  /// not measured (the patient's history and radiograph, each tooth's mobility
  /// and furcation, the recession), no depths, no bleeding.
  PerioChart GivenChart() const;
  const std::vector<std::string>& feedback() const { return feedback_; }
  std::uint64_t last_tick() const { return last_tick_; }
  const LessonSpec& spec() const { return spec_; }
  const std::vector<ChartEntry>& entries() const { return entries_; }
  /// The sites in path order as far as the attempt has gone (readings so far).
  const std::vector<SiteResult>& sites() const { return sites_; }
  const std::optional<DeclaredDiagnosis>& declared() const { return declared_; }
  const std::vector<Finding>& findings() const { return findings_; }
  std::optional<std::uint64_t> submitted() const { return submitted_; }
  /// The odontogram as recorded so far (inspection lessons).
  const Odontogram& odontogram() const { return odontogram_; }
  /// Inspection lessons: the tracker (null for probing lessons).
  const InspectionTracker* inspection() const {
    return inspection_ ? &*inspection_ : nullptr;
  }
  /// Inspection lessons: the current step's regions and surfaces not yet examined.
  std::vector<std::string> pending() const;

  /// The device is not answering now (a kDeviceLost without its kDeviceBack).
  bool device_lost() const {
    return !interruptions_.empty() && interruptions_.back().back_tick == 0;
  }
  /// How the attempt ended when it ends before its last step (kept in the result).
  void SetEnding(std::string why) { ending_ = std::move(why); }

  /// Scores the attempt (any time; usually after OnEnd).
  LessonResult Finish() const;

 private:
  void ScoreProbing(LessonResult& out) const;
  void ScoreInspection(LessonResult& out) const;
  void FollowInspection(const TickRecord& r);
  void LeaveStepsUntil(int later, std::uint64_t tick);
  struct ToothTrack;
  void Track(const TickRecord& r);
  void Advance(std::uint64_t tick);
  bool StepComplete(const StepSpec& s) const;
  bool SiteInStep(const StepSpec& s, const SiteRef& site) const;
  int SiteIndex(const SiteRef& s) const;
  void Locate(const TickRecord& r);
  // A reading into `sites`: the site's result when it became its reading.
  SiteResult* ApplyReading(const ProbeReading& reading,
                           std::vector<SiteResult>* sites) const;
  void Read(const ProbeReading& reading);  // into sites_, with its feedback

  LessonSpec spec_;
  const CompiledScene& scene_;
  LessonGeometry geometry_;
  std::string student_;
  std::uint64_t case_seed_;
  double rate_hz_;
  std::vector<SiteResult> sites_;  // path order
  std::vector<ChartEntry> entries_;
  std::optional<DeclaredDiagnosis> declared_;
  std::vector<StepResult> step_results_;
  int step_ = 0;
  bool timed_out_ = false, ended_ = false;
  std::string ending_;
  std::vector<LessonResult::Interruption> interruptions_;
  std::uint64_t first_tick_ = 0, last_tick_ = 0, ticks_ = 0;
  TipLocation tip_at_;
  // Readings: the one tip locator, the dwell tracker, per scene site its path
  // index (-1: not in the lesson), per path site what the tip did there.
  TipLocator locator_;
  ProbeReadingTracker tracker_;
  std::vector<int> path_index_;
  int last_read_ = -1;                 // path index of the site of the latest reading
  std::vector<double> visit_deepest_;  // per path site: deepest while located there
  std::vector<std::uint8_t>
      near_other_;                     // per path site: near its line, placed elsewhere
  std::vector<ChartEntry> scheduled_;  // Schedule()d, in tick order
  std::vector<std::string> feedback_;
  std::vector<std::pair<std::uint64_t, float>> force_trace_;
  std::vector<std::uint8_t> in_contact_;  // per engine object
  struct SurfaceTrack {
    std::vector<bool> bins;
    std::uint64_t in_ticks = 0, touch_ticks = 0, first = 0, last = 0;
    double ext_depth = 0, turn_depth = 0, swing_sum = 0;
    int strokes = 0, direction = 0;
    bool any = false;
  };
  std::vector<std::array<SurfaceTrack, 2>>
      surfaces_;  // per geometry tooth: buccal, lingual
  // Per geometry tooth and surface, the arc the walking stroke is to sweep
  // (degrees from the contact's line, the lingual arc mirrored: 360 less
  // the angle): from col to col less kColMarginMm, within kArcFromDeg..kArcToDeg.
  std::vector<std::array<std::pair<double, double>, 2>> arcs_;
  std::vector<std::pair<RubricLine, int>>
      damage_;                    // tissue_damage events (line, site index or -1)
  std::vector<RubricLine> felt_;  // calculus deposits met (info), the first time each
  // Inspection lessons.
  std::optional<InspectionTracker> inspection_;
  std::vector<std::vector<int>> step_units_;  // per step, its units
  std::vector<Finding> findings_;
  std::optional<std::uint64_t> submitted_;
  Odontogram odontogram_, truth_;
  std::vector<ViewSample> views_;
};

}  // namespace sulcus
