// Examiner calibration: kappa against values worked by hand, and examiners of
// known bias read as such.
#include "core/lesson/calibration.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sulcus {
namespace {

PerioChart Chart(const std::vector<int>& teeth, int pd) {
  PerioChart c;
  for (int fdi : teeth) {
    ToothChart t;
    t.fdi = fdi;
    for (SiteValues& s : t.sites) s.pd_mm = pd;
    c.teeth.push_back(t);
  }
  return c;
}

TEST(Calibration, KappaAsWorkedByHand) {
  // Two raters, 10 items, yes/no: 4 yes-yes, 1 yes-no, 1 no-yes, 4 no-no.
  // po = 0.8, pe = 0.5 * 0.5 + 0.5 * 0.5 = 0.5: kappa 0.6.
  const std::vector<bool> a = {1, 1, 1, 1, 1, 0, 0, 0, 0, 0},
                          b = {1, 1, 1, 1, 0, 1, 0, 0, 0, 0};
  ASSERT_TRUE(CohenKappa(a, b).has_value());
  EXPECT_NEAR(*CohenKappa(a, b), 0.6, 1e-12);
  // Depths 2, 3, 4 against 2, 3, 5: observed |d| = 1 over 3 items; chance:
  // sum |i - j| n_i n_j / n over the marginals {2, 3, 4} x {2, 3, 5} / 3 =
  // (0+1+3 + 1+0+2 + 2+1+1) / 3 = 11 / 3: kappa = 1 - 1 / (11 / 3) = 8 / 11.
  const auto k = WeightedKappa({2, 3, 4}, {2, 3, 5});
  ASSERT_TRUE(k.has_value());
  EXPECT_NEAR(*k, 8.0 / 11.0, 1e-12);
  EXPECT_NEAR(*WeightedKappa({1, 4, 7}, {1, 4, 7}), 1.0, 1e-12);
  EXPECT_FALSE(WeightedKappa({3, 3}, {3, 3})) << "every item alike: no kappa";
  EXPECT_FALSE(CohenKappa({}, {}));
}

TEST(Calibration, AnExaminerWhoReadsDeepSitesShortIsSeenAsSuch) {
  PerioChart truth = Chart({16, 11, 46}, 3);
  truth.Find(16)->sites[0].pd_mm = 6;  // deep interdental sites at the molars
  truth.Find(46)->sites[2].pd_mm = 7;
  truth.Find(46)->sites[2].bleeding = true;
  truth.Find(16)->sites[0].bleeding = true;
  EXPECT_NEAR(*Agree(truth, truth).depth_kappa, 1.0, 1e-12);
  EXPECT_TRUE(Agree(truth, truth).MeetsTarget());

  PerioChart short_reader = truth;
  short_reader.Find(16)->sites[0].pd_mm = 4;  // 2 mm short at both deep sites
  short_reader.Find(46)->sites[2].pd_mm = 5;
  short_reader.Find(11)->sites[1].bleeding = true;  // and a bleeding point too many
  const Agreement g = Agree(short_reader, truth);
  EXPECT_EQ(g.sites, 18);
  EXPECT_NEAR(g.within_1mm_pct, 100.0 * 16 / 18, 1e-9);
  ASSERT_TRUE(g.deep.mean_mm());
  EXPECT_DOUBLE_EQ(*g.deep.mean_mm(), -2.0);
  EXPECT_DOUBLE_EQ(*g.shallow.mean_mm(), 0.0);
  EXPECT_DOUBLE_EQ(*g.interdental.mean_mm(), -4.0 / 12);
  EXPECT_DOUBLE_EQ(*g.mid.mean_mm(), 0.0);
  EXPECT_DOUBLE_EQ(*g.posterior.mean_mm(), -4.0 / 12);
  EXPECT_DOUBLE_EQ(*g.anterior.mean_mm(), 0.0);
  ASSERT_TRUE(g.depth_kappa && g.bleeding_kappa);
  EXPECT_LT(*g.depth_kappa, 1.0);
  EXPECT_LT(*g.bleeding_kappa, 1.0);
  EXPECT_FALSE(g.MeetsTarget()) << "89 % within 1 mm is under the 90 % target";

  // A site the examiner left blank is not compared.
  short_reader.Find(11)->sites[4].pd_mm.reset();
  EXPECT_EQ(Agree(short_reader, truth).sites, 17);
}

// The cohort's view: each student's charted depths over their attempts.
TEST(Calibration, EachStudentOfACohortOverAllTheirAttempts) {
  std::vector<ChartedSite> sites;
  for (int attempt = 0; attempt < 2; ++attempt)
    for (int s = 0; s < kSitesPerTooth; ++s) {
      sites.push_back({"ada", 46, s, 3 + s % 3, 3 + s % 3});  // exact
      sites.push_back({"bob", 11, s, 3 + s % 3 + (s == 0 ? 2 : 0), 3 + s % 3});
    }
  const auto cal = CohortCalibration(sites);
  ASSERT_EQ(cal.size(), 2u);
  EXPECT_EQ(cal[0].student, "ada");
  EXPECT_EQ(cal[0].depths.sites, 12);
  EXPECT_TRUE(cal[0].depths.MeetsTarget());
  EXPECT_EQ(cal[1].student, "bob");
  EXPECT_NEAR(cal[1].depths.within_1mm_pct, 100.0 * 10 / 12, 1e-9);
  EXPECT_DOUBLE_EQ(*cal[1].depths.interdental.mean_mm(), 2.0 * 2 / 8);
  EXPECT_DOUBLE_EQ(*cal[1].depths.anterior.mean_mm(), 4.0 / 12);
  EXPECT_FALSE(cal[1].depths.posterior.mean_mm()) << "bob charted an incisor only";
  EXPECT_FALSE(cal[1].depths.MeetsTarget());
  EXPECT_FALSE(cal[1].depths.bleeding_kappa) << "bleeding is not stored per site";
}

}  // namespace
}  // namespace sulcus
