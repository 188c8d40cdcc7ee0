#include "core/lesson/calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

namespace sulcus {

std::optional<double> WeightedKappa(const std::vector<int>& a,
                                    const std::vector<int>& b) {
  if (a.empty() || a.size() != b.size()) return std::nullopt;
  const double n = static_cast<double>(a.size());
  // Observed disagreement, and the disagreement chance would give from each
  // rater's own marginals, both weighted by the distance between categories.
  double observed = 0;
  for (std::size_t i = 0; i < a.size(); ++i) observed += std::abs(a[i] - b[i]);
  std::map<int, double> ra, rb;
  for (const int v : a) ra[v] += 1;
  for (const int v : b) rb[v] += 1;
  double expected = 0;
  for (const auto& [i, ni] : ra)
    for (const auto& [j, nj] : rb) expected += std::abs(i - j) * ni * nj / n;
  if (expected <= 0) return std::nullopt;
  return 1.0 - observed / expected;
}

std::optional<double> CohenKappa(const std::vector<bool>& a, const std::vector<bool>& b) {
  if (a.empty() || a.size() != b.size()) return std::nullopt;
  const double n = static_cast<double>(a.size());
  double agree = 0, ya = 0, yb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    agree += a[i] == b[i];
    ya += a[i];
    yb += b[i];
  }
  const double po = agree / n;
  const double pe = (ya / n) * (yb / n) + (1 - ya / n) * (1 - yb / n);
  if (pe >= 1) return std::nullopt;
  return (po - pe) / (1 - pe);
}

namespace {

// One site charted by both: the examiner's value and the reference's.
struct SitePair {
  int fdi = 0, site = 0, examiner_mm = 0, reference_mm = 0;
  bool examiner_bled = false, reference_bled = false;
};

Agreement AgreeSites(const std::vector<SitePair>& pairs) {
  Agreement g;
  std::vector<int> depth_e, depth_r;
  std::vector<bool> bleed_e, bleed_r;
  int exact = 0, within = 0;
  for (const SitePair& p : pairs) {
    const int d = p.examiner_mm - p.reference_mm;
    ++g.sites;
    exact += d == 0;
    within += std::abs(d) <= 1;
    depth_e.push_back(p.examiner_mm);
    depth_r.push_back(p.reference_mm);
    bleed_e.push_back(p.examiner_bled);
    bleed_r.push_back(p.reference_bled);
    const bool posterior = p.fdi % 10 >= 4;
    for (Bias* b : {&g.all, IsInterdental(p.site) ? &g.interdental : &g.mid,
                    posterior ? &g.posterior : &g.anterior,
                    p.reference_mm >= 5 ? &g.deep : &g.shallow}) {
      ++b->sites;
      b->sum_mm += d;
    }
  }
  if (g.sites == 0) return g;
  g.exact_pct = 100.0 * exact / g.sites;
  g.within_1mm_pct = 100.0 * within / g.sites;
  g.depth_kappa = WeightedKappa(depth_e, depth_r);
  g.bleeding_kappa = CohenKappa(bleed_e, bleed_r);
  return g;
}

}  // namespace

Agreement Agree(const PerioChart& examiner, const PerioChart& reference) {
  std::vector<SitePair> pairs;
  for (const ToothChart& r : reference.teeth) {
    const ToothChart* e = examiner.Find(r.fdi);
    if (!e || !r.present || !e->present) continue;
    for (int s = 0; s < kSitesPerTooth; ++s) {
      const SiteValues &ve = e->sites[s], &vr = r.sites[s];
      if (!ve.measured() || !vr.measured()) continue;
      pairs.push_back({r.fdi, s, *ve.pd_mm, *vr.pd_mm, ve.bleeding, vr.bleeding});
    }
  }
  return AgreeSites(pairs);
}

std::vector<ExaminerCalibration> CohortCalibration(
    const std::vector<ChartedSite>& sites) {
  std::map<std::string, std::vector<SitePair>> by_student;
  for (const ChartedSite& c : sites)
    if (c.site >= 0 && c.site < kSitesPerTooth)
      by_student[c.student].push_back({c.fdi, c.site, c.entered_mm, c.truth_mm});
  std::vector<ExaminerCalibration> out;
  for (const auto& [student, pairs] : by_student) {
    ExaminerCalibration e;
    e.student = student;
    e.depths = AgreeSites(pairs);
    e.depths.bleeding_kappa.reset();  // (not stored per site)
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace sulcus
