#pragma once
// The periodontal chart (after Open Dental's perio chart and the Bern chart) and
// the 2017 AAP/EFP classification of periodontitis applied to it (Tonetti,
// Greenwell, Kornman 2018, with the operational rules epidemiologists use).
//
// Conventions, fixed here once: probing depth (PD) in whole millimetres;
// `recession_mm` positive when the margin lies apical to the CEJ (root exposed),
// negative when it lies coronal (health: the margin about 1.5 mm above the CEJ);
// CAL = PD + recession, derived, never stored; CAL is charted in whole mm, a
// half millimetre rounding down (toward less attachment loss), and never below 0.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/scene/patient.h"

namespace sulcus {

/// Site codes in charting order: MB, B, DB, ML, L, DL.
inline constexpr int kSitesPerTooth = 6;
const char* SiteCode(int site);
/// -1 for a code that is not a site (case-sensitive: "MB", "DL", ...).
int SiteFromCode(const std::string& code);
/// MB, DB, ML, DL are interdental; B and L are the facial and oral mid-sites.
inline bool IsInterdental(int site) { return site != 1 && site != 4; }
/// Mesial sites (MB, ML).
inline bool IsMesial(int site) { return site == 0 || site == 3; }

struct SiteValues {
  std::optional<int> pd_mm;  // unmeasured: empty
  double recession_mm = 0;
  bool bleeding = false;
  bool measured() const { return pd_mm.has_value(); }
  /// Whole-mm CAL (PD + recession, half rounding down); empty when unmeasured.
  std::optional<int> cal_mm() const;
};

struct ToothChart {
  int fdi = 0;
  bool present = true;
  int mobility = 0;   // Miller 0-3
  int furcation = 0;  // worst entrance, Hamp 0-3
  std::array<SiteValues, kSitesPerTooth> sites{};
};

struct PerioChart {
  std::vector<ToothChart> teeth;
  PatientFacts patient;  // the history and radiograph beside the chart
  ToothChart* Find(int fdi);
  const ToothChart* Find(int fdi) const;
};

/// The teeth of the molar-incisor pattern: first molars, incisors.
inline bool FirstMolar(int fdi) { return fdi % 10 == 6; }
inline bool Incisor(int fdi) { return fdi % 10 == 1 || fdi % 10 == 2; }

/// Neighbours in the arch: the same quadrant one position apart, or the two
/// central incisors of one jaw.
bool AdjacentTeeth(int fdi_a, int fdi_b);

enum class Stage { kNone = 0, kI = 1, kII = 2, kIII = 3, kIV = 4 };
/// Localized (under 30 % of the teeth), generalized, or the molar-incisor
/// pattern (the teeth in the stage's band are first molars and incisors only,
/// at least one of each).
enum class Extent { kNone, kLocalized, kGeneralized, kMolarIncisor };
/// Grade A (slow), B (moderate), C (rapid progression); none: not assessed.
enum class Grade { kNone, kA, kB, kC };
const char* ToString(Stage s);   // "I", "II", ... ("none")
const char* ToString(Extent e);  // "localized", "generalized", "molar-incisor" ("none")
const char* ToString(Grade g);   // "A", "B", "C" ("none")
std::optional<Stage> StageFromString(const std::string& s);
std::optional<Extent> ExtentFromString(const std::string& s);
std::optional<Grade> GradeFromString(const std::string& s);

struct Diagnosis {
  enum class Kind {
    kNotAssessable,
    kHealth,
    kGingivitisLocalized,
    kGingivitisGeneralized,
    kPeriodontitis,
    // Not a case, yet not health: a pocket (PD >= 4 mm) with bleeding under 10 %,
    // as a pseudo-pocket or with attachment loss short of a case.
    kNotClassifiable
  };
  Kind kind = Kind::kNotAssessable;
  Stage stage = Stage::kNone;
  Extent extent = Extent::kNone;
  double bop_pct = 0;  // bleeding sites / sites measured (a site with a depth)
  int worst_interdental_cal_mm = 0;
  double extent_pct = 0;  // share of teeth in the band that set the stage
  // Stage IV and the grade need the patient's facts (PerioChart::patient).
  bool stage_iv_assessable = false;
  Grade grade = Grade::kNone;     // none: no patient facts
  double bone_loss_per_age = -1;  // % bone loss / age in years (-1: not known)
  std::vector<std::string> path;  // the decision tree's steps, one line each
  /// "periodontitis stage III, localized" (", grade B" with the patient's
  /// facts) / "localized gingivitis" / ...
  std::string Summary() const;
};
const char* ToString(Diagnosis::Kind k);

/// The case definition, stage, extent and grade. Stages I to III and the
/// extent come from the chart; stage IV (teeth lost to periodontitis, mobility
/// of degree 2 or more, drifting or flaring, a collapsed bite, fewer than 10
/// opposing pairs) and the grade (bone loss over age, smoking, HbA1c) need the
/// patient's facts in `chart.patient`; without them Diagnosis says they were
/// not assessed. Where the consensus leaves a choice, lessons/README.md says
/// what Sulcus does.
Diagnosis Classify2017(const PerioChart& chart);

}  // namespace sulcus
