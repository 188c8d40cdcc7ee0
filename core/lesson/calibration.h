#pragma once
// Examiner calibration: how an examiner's chart agrees with a reference chart
// (the truth, or a reference examiner's chart of the same case), with the
// figures clinical probing studies report: exact agreement, agreement within
// 1 mm, weighted kappa for the depths, kappa for bleeding, and the bias by
// kind of site.

#include <optional>
#include <string>
#include <vector>

#include "core/lesson/chart.h"

namespace sulcus {

/// A signed mean over some sites; empty when there were none.
struct Bias {
  int sites = 0;
  double sum_mm = 0;
  std::optional<double> mean_mm() const {
    return sites > 0 ? std::optional<double>(sum_mm / sites) : std::nullopt;
  }
};

struct Agreement {
  int sites = 0;  // sites with a depth in both charts
  double exact_pct = 0, within_1mm_pct = 0;
  // Linearly weighted kappa over the depths in mm, and Cohen's kappa for
  // bleeding; empty where chance agreement is already complete (every site
  // the same value in both charts), which no kappa can measure.
  std::optional<double> depth_kappa, bleeding_kappa;
  // Examiner minus reference, by kind of site: interdental (MB, DB, ML, DL) and
  // mid-sites (B, L); posterior (premolars and molars) and anterior teeth;
  // deep (the reference 5 mm or more) and shallow.
  Bias all, interdental, mid, posterior, anterior, deep, shallow;
  /// The clinical target examiners are calibrated to: within 1 mm at 90 % of
  /// sites or more and a weighted kappa above 0.6 (lessons/README.md).
  bool MeetsTarget() const {
    return sites > 0 && within_1mm_pct >= 90 && depth_kappa && *depth_kappa > 0.6;
  }
};

/// Linearly weighted kappa of two ratings of the same items (whole numbers);
/// empty when the ratings are empty or chance agreement is complete.
std::optional<double> WeightedKappa(const std::vector<int>& a, const std::vector<int>& b);

/// Cohen's kappa of two yes/no ratings of the same items; empty as above.
std::optional<double> CohenKappa(const std::vector<bool>& a, const std::vector<bool>& b);

/// The examiner's chart against the reference, over the sites both measured.
Agreement Agree(const PerioChart& examiner, const PerioChart& reference);

/// One charted site of a stored attempt: what the student entered, the truth.
struct ChartedSite {
  std::string student;
  int fdi = 0, site = 0, entered_mm = 0, truth_mm = 0;
};

/// A student's depths over all their attempts against the truth, as the
/// instructor's view compares a cohort with the target (bleeding is not
/// stored per site, so only the depths).
struct ExaminerCalibration {
  std::string student;
  Agreement depths;  // bleeding_kappa empty
};

/// Per student, in name order.
std::vector<ExaminerCalibration> CohortCalibration(const std::vector<ChartedSite>& sites);

}  // namespace sulcus
