// The 2017 classification on the worked cases of the clinical notes, and the
// chart's conventions (CAL, adjacency).
#include "core/lesson/chart.h"

#include <gtest/gtest.h>

namespace sulcus {
namespace {

// A chart of `teeth`, every site PD 2 with the margin 2 mm above the CEJ (CAL 0).
PerioChart Healthy(const std::vector<int>& teeth) {
  PerioChart c;
  for (int fdi : teeth) {
    ToothChart t;
    t.fdi = fdi;
    for (SiteValues& s : t.sites) {
      s.pd_mm = 2;
      s.recession_mm = -2;
    }
    c.teeth.push_back(t);
  }
  return c;
}

// Sets a site's PD and CAL (recession = CAL - PD).
void Set(PerioChart* c, int fdi, int site, int pd, int cal) {
  SiteValues& s = c->Find(fdi)->sites[site];
  s.pd_mm = pd;
  s.recession_mm = cal - pd;
}

std::vector<int> TwentyFour() {
  std::vector<int> t;
  for (int q = 1; q <= 4; ++q)
    for (int p = 1; p <= 6; ++p) t.push_back(q * 10 + p);
  return t;
}

TEST(Chart, CalIsDepthPlusRecessionWithHalvesRoundedDown) {
  SiteValues s;
  EXPECT_FALSE(s.cal_mm());
  s.pd_mm = 5;
  s.recession_mm = 1;
  EXPECT_EQ(*s.cal_mm(), 6);
  s.recession_mm = -0.5;  // 4.5 -> 4
  EXPECT_EQ(*s.cal_mm(), 4);
  s.recession_mm = -1.5;  // 3.5 -> 3
  EXPECT_EQ(*s.cal_mm(), 3);
  s.pd_mm = 1;  // the floor 0.5 mm coronal to the CEJ: no attachment lost
  EXPECT_EQ(*s.cal_mm(), 0);
}

TEST(Chart, AdjacentTeethAcrossTheMidlineToo) {
  EXPECT_TRUE(AdjacentTeeth(46, 47));
  EXPECT_TRUE(AdjacentTeeth(11, 21));
  EXPECT_TRUE(AdjacentTeeth(31, 41));
  EXPECT_FALSE(AdjacentTeeth(11, 41));
  EXPECT_FALSE(AdjacentTeeth(45, 47));
  EXPECT_FALSE(AdjacentTeeth(16, 26));
}

TEST(Staging2017, Cal4WithPd6AtTwoNonAdjacentTeethIsStageIII) {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 15, 0, 6, 4);  // (premolars: no molar-incisor pattern)
  Set(&c, 25, 2, 6, 4);
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.kind, Diagnosis::Kind::kPeriodontitis);
  EXPECT_EQ(d.worst_interdental_cal_mm, 4);
  EXPECT_EQ(d.stage, Stage::kIII) << d.Summary();
  EXPECT_EQ(d.extent, Extent::kLocalized);  // 2 of 24 teeth in the 3-4 mm band
}

TEST(Staging2017, TheSameWithPd6AtTwoAdjacentTeethOnlyIsStageII) {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 16, 0, 6, 4);
  Set(&c, 15, 2, 6, 4);
  Set(&c, 36, 0, 4, 3);  // loss at a tooth apart from them: a periodontitis case
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.kind, Diagnosis::Kind::kPeriodontitis);
  EXPECT_EQ(d.stage, Stage::kII) << d.Summary();
}

TEST(Staging2017, Cal5AtThreeOf24TeethIsStageIIILocalized) {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 15, 0, 5, 5);  // (premolars: no molar-incisor pattern)
  Set(&c, 25, 3, 5, 5);
  Set(&c, 35, 5, 5, 5);
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.stage, Stage::kIII);
  EXPECT_EQ(d.extent, Extent::kLocalized);
  EXPECT_DOUBLE_EQ(d.extent_pct, 12.5);
  EXPECT_EQ(d.Summary(), "periodontitis stage III, localized");
}

TEST(Staging2017, Bop20WithoutAttachmentLossIsLocalizedGingivitis) {
  PerioChart c = Healthy(TwentyFour());  // 144 sites
  int n = 0;
  for (ToothChart& t : c.teeth)
    for (SiteValues& s : t.sites)
      if (n++ % 5 == 0) s.bleeding = true;  // 29 of 144 = 20.1 %
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.kind, Diagnosis::Kind::kGingivitisLocalized) << d.Summary();
  EXPECT_NEAR(d.bop_pct, 20.1, 0.1);
}

TEST(Staging2017, HealthGeneralizedGingivitisAndNotAssessable) {
  PerioChart c = Healthy(TwentyFour());
  EXPECT_EQ(Classify2017(c).kind, Diagnosis::Kind::kHealth);
  for (ToothChart& t : c.teeth)
    for (int s = 0; s < 3; ++s) t.sites[s].bleeding = true;  // 50 %
  EXPECT_EQ(Classify2017(c).kind, Diagnosis::Kind::kGingivitisGeneralized);
  EXPECT_EQ(Classify2017(Healthy({46, 47})).kind, Diagnosis::Kind::kNotAssessable)
      << "two neighbours only";
  PerioChart generalized = Healthy(TwentyFour());
  for (ToothChart& t : generalized.teeth) Set(&generalized, t.fdi, 0, 4, 3);
  const Diagnosis g = Classify2017(generalized);
  EXPECT_EQ(g.stage, Stage::kII);
  EXPECT_EQ(g.extent, Extent::kGeneralized);
  EXPECT_FALSE(g.path.empty()) << "the decision path is reported";
}

TEST(Staging2017, ComplexityIgnoresThirdMolarsAndTheDistalOfSecondMolars) {
  PerioChart c = Healthy({17, 18, 26, 27, 36});
  Set(&c, 17, 2, 6, 4);  // 17 DB: distal of a second molar, not counted
  Set(&c, 18, 0, 6, 4);  // a third molar, not counted
  Set(&c, 36, 0, 3, 3);
  EXPECT_EQ(Classify2017(c).stage, Stage::kII);
  Set(&c, 27, 0, 6, 4);  // 27 MB counts; with 36 MB? 36 has PD 3: still one tooth
  EXPECT_EQ(Classify2017(c).stage, Stage::kII);
  Set(&c, 36, 0, 6, 4);  // two non-adjacent teeth with PD 6
  EXPECT_EQ(Classify2017(c).stage, Stage::kIII);
}

// Bleeding charted where no depth was entered is not bleeding on probing: the
// share is of the sites probed.
TEST(Staging2017, BleedingCountsOnlyWhereTheSiteWasProbed) {
  PerioChart c = Healthy(TwentyFour());  // 144 sites probed
  for (int s = 0; s < 6; ++s) {
    c.Find(11)->sites[s].pd_mm.reset();  // 11 not probed, yet marked as bleeding
    c.Find(11)->sites[s].bleeding = true;
    c.Find(12)->sites[s].pd_mm.reset();
    c.Find(12)->sites[s].bleeding = true;
  }
  for (int s = 0; s < 6; ++s) c.Find(21)->sites[s].bleeding = true;  // 6 of 132 probed
  const Diagnosis d = Classify2017(c);
  EXPECT_NEAR(d.bop_pct, 100.0 * 6 / 132, 1e-9);
  EXPECT_EQ(d.kind, Diagnosis::Kind::kHealth) << d.Summary();
}

// Health needs every PD <= 3 mm: a 4 mm pocket with 2 mm of attachment loss at
// one tooth and no bleeding is neither health nor a case; nor is a pseudo-pocket.
TEST(Staging2017, APocketWithoutBleedingAndNoCaseIsNotHealth) {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 46, 1, 4, 2);  // 46 B: PD 4, CAL 2 (buccal: no case below CAL 3)
  Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.kind, Diagnosis::Kind::kNotClassifiable) << d.Summary();
  EXPECT_STREQ(ToString(d.kind), "not classifiable from this chart");
  PerioChart pseudo = Healthy(TwentyFour());
  Set(&pseudo, 46, 1, 4, 0);  // PD 4 without attachment loss
  EXPECT_EQ(Classify2017(pseudo).kind, Diagnosis::Kind::kNotClassifiable);
  Set(&c, 46, 1, 3, 2);
  EXPECT_EQ(Classify2017(c).kind, Diagnosis::Kind::kHealth) << "PD 3 mm is health";
}

// Furcation class II or III makes stage III whatever the CAL (the consensus
// table's footnote), from stage I as from stage II; the extent keeps the band
// that set the stage.
TEST(Staging2017, AFurcationClassIIMakesStageIIIFromStageI) {
  PerioChart c = Healthy(TwentyFour());
  // Interdental CAL 2 at 14 and 24 (upper first premolars, which have a
  // furcation; no first molar: no molar-incisor pattern): stage I.
  Set(&c, 14, 0, 3, 2);
  Set(&c, 24, 0, 3, 2);
  ASSERT_EQ(Classify2017(c).stage, Stage::kI);
  c.Find(14)->furcation = 2;
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.stage, Stage::kIII) << d.Summary();
  EXPECT_EQ(d.extent, Extent::kLocalized) << "2 of 24 teeth in the 1-2 mm band";
  c.Find(14)->furcation = 1;
  EXPECT_EQ(Classify2017(c).stage, Stage::kI) << "class I does not raise it";
}

// Stage IV's complexity applies to any stage III case, however it became III:
// here a furcation of class II made a stage I chart stage III.
TEST(Staging2017, StageIVComplexityOnAStageIIIMadeByAFurcation) {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 14, 0, 3, 2);
  Set(&c, 24, 0, 3, 2);
  c.Find(14)->furcation = 2;
  c.patient.given = true;
  c.patient.age_years = 45;
  ASSERT_EQ(Classify2017(c).stage, Stage::kIII);
  c.Find(24)->mobility = 2;
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.stage, Stage::kIV) << d.Summary();
}

// Stage III by CAL at 15 and 25 (5 mm; premolars: no molar-incisor
// pattern), stage IV by what the history adds.
PerioChart StageIII() {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 15, 0, 6, 5);
  Set(&c, 25, 2, 6, 5);
  c.patient.given = true;
  c.patient.age_years = 45;
  return c;
}

TEST(Staging2017, WithoutThePatientStageIVAndTheGradeAreNotAssessed) {
  PerioChart c = StageIII();
  c.patient = {};
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.stage, Stage::kIII);
  EXPECT_FALSE(d.stage_iv_assessable);
  EXPECT_EQ(d.grade, Grade::kNone);
  EXPECT_EQ(d.Summary(), "periodontitis stage III, localized");
}

TEST(Staging2017, StageIVByToothLossOrComplexityOnStageIII) {
  PerioChart c = StageIII();
  Diagnosis d = Classify2017(c);
  EXPECT_TRUE(d.stage_iv_assessable);
  EXPECT_EQ(d.stage, Stage::kIII) << "no tooth lost, no complexity";
  c.patient.teeth_lost_to_periodontitis = 4;
  EXPECT_EQ(Classify2017(c).stage, Stage::kIII) << "4 teeth lost: still III";
  c.patient.teeth_lost_to_periodontitis = 5;
  EXPECT_EQ(Classify2017(c).stage, Stage::kIV) << "5 teeth lost";
  c.patient.teeth_lost_to_periodontitis = 0;
  c.Find(25)->mobility = 2;
  d = Classify2017(c);
  EXPECT_EQ(d.stage, Stage::kIV) << "secondary occlusal trauma";
  bool named = false;
  for (const std::string& step : d.path)
    named |= step.find("mobility of degree 2 or more") != std::string::npos &&
             step.find("25") != std::string::npos;
  EXPECT_TRUE(named) << "the path names the complexity and the tooth";
  c.Find(25)->mobility = 1;
  EXPECT_EQ(Classify2017(c).stage, Stage::kIII) << "mobility 1 is not complexity";
  c.patient.opposing_pairs = 9;
  EXPECT_EQ(Classify2017(c).stage, Stage::kIV) << "fewer than 10 opposing pairs";
  c.patient.opposing_pairs = 10;
  c.patient.drifting_flaring = true;
  EXPECT_EQ(Classify2017(c).stage, Stage::kIV) << "drifting or flaring";
  c.patient.drifting_flaring = false;
  c.patient.bite_collapse = true;
  EXPECT_EQ(Classify2017(c).stage, Stage::kIV) << "bite collapse";
}

TEST(Staging2017, ToothLossRaisesStageIOrIIToIIIButComplexityNeedsStageIII) {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 16, 0, 3, 2);  // stage I
  Set(&c, 26, 0, 3, 2);
  c.patient.given = true;
  c.Find(16)->mobility = 2;
  EXPECT_EQ(Classify2017(c).stage, Stage::kI)
      << "complexity alone does not make stage I stage IV";
  c.patient.teeth_lost_to_periodontitis = 2;
  const Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.stage, Stage::kIV)
      << "2 teeth lost make it III, and its mobility then makes it IV: " << d.Summary();
  c.Find(16)->mobility = 0;
  EXPECT_EQ(Classify2017(c).stage, Stage::kIII);
}

TEST(Grading2017, BoneLossOverAgeThenSmokingAndDiabetesRaiseIt) {
  PerioChart c = StageIII();
  Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.grade, Grade::kB) << "no bone loss known: B assumed";
  c.patient.bone_loss_pct = 9;  // 0.20 a year at 45
  d = Classify2017(c);
  EXPECT_EQ(d.grade, Grade::kA);
  EXPECT_NEAR(d.bone_loss_per_age, 0.2, 1e-12);
  EXPECT_EQ(d.Summary(), "periodontitis stage III, localized, grade A");
  c.patient.bone_loss_pct = 45;  // 1.0: B
  EXPECT_EQ(Classify2017(c).grade, Grade::kB);
  c.patient.bone_loss_pct = 50;  // 1.11: C
  EXPECT_EQ(Classify2017(c).grade, Grade::kC);
  c.patient.bone_loss_pct = 9;
  c.patient.cigarettes_per_day = 5;
  EXPECT_EQ(Classify2017(c).grade, Grade::kB) << "a smoker under 10 a day: at least B";
  c.patient.cigarettes_per_day = 10;
  EXPECT_EQ(Classify2017(c).grade, Grade::kC) << "10 a day: C";
  c.patient.cigarettes_per_day = 0;
  c.patient.hba1c_pct = 6.5;
  EXPECT_EQ(Classify2017(c).grade, Grade::kB) << "diabetes under 7.0 %: at least B";
  c.patient.hba1c_pct = 7.0;
  EXPECT_EQ(Classify2017(c).grade, Grade::kC);
  c.patient.bone_loss_pct = 50;
  c.patient.hba1c_pct = 6.5;
  EXPECT_EQ(Classify2017(c).grade, Grade::kC) << "a modifier never lowers the grade";
}

// The molar-incisor pattern by the rule of the presentation it replaced: at
// least two teeth in the band, at least one a first molar, at most two that
// are neither first molars nor incisors.
TEST(Staging2017, TheMolarIncisorPatternIsTwoTeethOneAFirstMolarAtMostTwoOthers) {
  PerioChart c = Healthy(TwentyFour());
  Set(&c, 16, 0, 6, 5);
  Set(&c, 31, 2, 6, 5);
  Set(&c, 46, 3, 6, 5);
  Diagnosis d = Classify2017(c);
  EXPECT_EQ(d.extent, Extent::kMolarIncisor) << d.Summary();
  EXPECT_EQ(d.Summary(), "periodontitis stage III, molar-incisor");
  bool said = false;
  for (const std::string& step : d.path)
    said |= step.find("at least one a first molar") != std::string::npos;
  EXPECT_TRUE(said) << "the path says the rule";
  Set(&c, 14, 0, 6, 5);  // a premolar: one other
  Set(&c, 15, 0, 6, 5);  // two others
  EXPECT_EQ(Classify2017(c).extent, Extent::kMolarIncisor) << "two others at most";
  Set(&c, 24, 0, 6, 5);  // three
  EXPECT_EQ(Classify2017(c).extent, Extent::kLocalized)
      << "three others: not the pattern";
  c = Healthy(TwentyFour());
  Set(&c, 16, 0, 6, 5);
  Set(&c, 46, 0, 6, 5);
  EXPECT_EQ(Classify2017(c).extent, Extent::kMolarIncisor)
      << "16 and 46 alone are the pattern: incisors are not required";
  c = Healthy(TwentyFour());
  Set(&c, 12, 0, 6, 5);
  Set(&c, 31, 0, 6, 5);
  EXPECT_EQ(Classify2017(c).extent, Extent::kLocalized) << "no first molar";
  c = Healthy(TwentyFour());
  Set(&c, 16, 0, 6, 5);
  Set(&c, 44, 0, 3, 2);  // (a second tooth with loss: a case)
  EXPECT_EQ(Classify2017(c).extent, Extent::kLocalized) << "one tooth in the band";
  // A sextant: 46 and 47 are two teeth, one a first molar.
  PerioChart s = Healthy({47, 46, 45, 44});
  Set(&s, 46, 0, 6, 5);
  Set(&s, 44, 0, 3, 2);
  EXPECT_NE(Classify2017(s).extent, Extent::kMolarIncisor) << "46 alone";
  Set(&s, 47, 0, 6, 5);
  EXPECT_EQ(Classify2017(s).extent, Extent::kMolarIncisor);
  EXPECT_EQ(ExtentFromString("molar-incisor"), Extent::kMolarIncisor);
  EXPECT_EQ(GradeFromString("C"), Grade::kC);
  EXPECT_FALSE(GradeFromString("D"));
}

}  // namespace
}  // namespace sulcus
