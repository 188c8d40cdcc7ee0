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
  ToothChart* Find(int fdi);
  const ToothChart* Find(int fdi) const;
};

/// Neighbours in the arch: the same quadrant one position apart, or the two
/// central incisors of one jaw.
bool AdjacentTeeth(int fdi_a, int fdi_b);

enum class Stage { kNone = 0, kI = 1, kII = 2, kIII = 3, kIV = 4 };
enum class Extent { kNone, kLocalized, kGeneralized };
const char* ToString(Stage s);   // "I", "II", ... ("none")
const char* ToString(Extent e);  // "localized", "generalized" ("none")
std::optional<Stage> StageFromString(const std::string& s);
std::optional<Extent> ExtentFromString(const std::string& s);

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
  bool stage_iv_assessable =
      false;  // needs teeth lost and why, mobility, bite: not in the chart
  std::vector<std::string> path;  // the decision tree's steps, one line each
  std::string Summary()
      const;  // "periodontitis stage III, localized" / "localized gingivitis" / ...
};
const char* ToString(Diagnosis::Kind k);

/// Stages I to III, the extent and the case definition from the chart alone.
/// Stage IV and the grade need facts a chart does not hold; Diagnosis says so.
Diagnosis Classify2017(const PerioChart& chart);

}  // namespace sulcus
