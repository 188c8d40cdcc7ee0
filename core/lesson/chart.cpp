#include "core/lesson/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/base/text.h"

namespace sulcus {
namespace {

constexpr const char* kCodes[kSitesPerTooth] = {"MB", "B", "DB", "ML", "L", "DL"};

// Among `teeth`, are there two that are not neighbours?
bool TwoNonAdjacent(const std::vector<int>& teeth) {
  for (std::size_t i = 0; i < teeth.size(); ++i)
    for (std::size_t j = i + 1; j < teeth.size(); ++j)
      if (!AdjacentTeeth(teeth[i], teeth[j])) return true;
  return false;
}

std::string List(const std::vector<int>& teeth) {
  return teeth.empty() ? "none" : Join(teeth);
}

// Stage IV, or III, from the teeth lost to periodontitis; stage IV from the
// complexity the history and the chart show, on a stage III case.
void StageFromHistory(const PerioChart& chart, Diagnosis* d) {
  const PatientFacts& p = chart.patient;
  char line[256];
  if (p.teeth_lost_to_periodontitis >= 5) {
    std::snprintf(line, sizeof line,
                  "tooth loss: %d teeth lost to periodontitis (5 or more): stage IV",
                  p.teeth_lost_to_periodontitis);
    d->path.push_back(line);
    d->stage = Stage::kIV;
    return;
  }
  if (p.teeth_lost_to_periodontitis >= 1 && d->stage < Stage::kIII) {
    std::snprintf(line, sizeof line,
                  "tooth loss: %d teeth lost to periodontitis (1 to 4): stage III",
                  p.teeth_lost_to_periodontitis);
    d->path.push_back(line);
    d->stage = Stage::kIII;
  }
  if (d->stage != Stage::kIII) return;
  std::vector<std::string> why;
  std::vector<int> mobile;
  for (const ToothChart& t : chart.teeth)
    if (t.present && t.mobility >= 2) mobile.push_back(t.fdi);
  if (!mobile.empty())
    why.push_back("mobility of degree 2 or more (secondary occlusal trauma) at " +
                  List(mobile));
  if (p.drifting_flaring) why.push_back("drifting or flaring");
  if (p.bite_collapse) why.push_back("bite collapse (masticatory dysfunction)");
  if (p.opposing_pairs && *p.opposing_pairs < 10)
    why.push_back("fewer than 10 opposing pairs (" + std::to_string(*p.opposing_pairs) +
                  ")");
  if (why.empty()) {
    d->path.push_back(
        "stage IV complexity: no mobility of degree 2 or more, no drifting or flaring, "
        "no bite collapse, 10 or more opposing pairs: stays stage III");
    return;
  }
  d->path.push_back("stage IV complexity: " + Join(why) + ": stage IV");
  d->stage = Stage::kIV;
}

// The molar-incisor pattern. The consensus gives it no operational rule; this
// is the one of the presentation it replaced (localized aggressive
// periodontitis, 1999): the teeth in the band that set the stage are at least
// two, at least one of them a first molar, and at most two of them are neither
// first molars nor incisors (16 and 46 alone are the pattern; incisors are not
// required). The path says the rule and the teeth.
void MolarIncisorPattern(const PerioChart& chart, int band_lo, int band_hi,
                         Diagnosis* d) {
  std::vector<int> band, molars, others;
  for (const ToothChart& t : chart.teeth) {
    if (!t.present) continue;
    int worst = -100;
    for (int s = 0; s < kSitesPerTooth; ++s)
      if (IsInterdental(s) && t.sites[s].measured())
        worst = std::max(worst, *t.sites[s].cal_mm());
    if (worst < band_lo || worst > band_hi) continue;
    band.push_back(t.fdi);
    if (FirstMolar(t.fdi)) molars.push_back(t.fdi);
    if (!FirstMolar(t.fdi) && !Incisor(t.fdi)) others.push_back(t.fdi);
  }
  if (band.empty()) return;
  const bool pattern = band.size() >= 2 && !molars.empty() && others.size() <= 2;
  std::string why = "the teeth in the band (" + List(band) + "): ";
  if (band.size() < 2)
    why += "fewer than 2";
  else if (molars.empty())
    why += "no first molar among them";
  else if (others.size() > 2)
    why += std::to_string(others.size()) + " of them (" + List(others) +
           ") neither first molars nor incisors, more than 2";
  else
    why += "2 or more, first molar " + List(molars) + ", " +
           std::to_string(others.size()) +
           " neither first molars nor incisors (2 at most)";
  why += pattern ? ": molar-incisor pattern" : ": no molar-incisor pattern";
  d->path.push_back(why +
                    " (the rule: at least 2 teeth, at least one a first molar, at "
                    "most 2 neither first molars nor incisors)");
  if (pattern) d->extent = Extent::kMolarIncisor;
}

// Grade B unless the bone lost for the patient's age says A or C; smoking and
// diabetes only raise it.
void GradeFromHistory(const PatientFacts& p, Diagnosis* d) {
  char line[256];
  if (!p.given) {
    d->path.push_back(
        "grade not assessed: it needs the patient's age, radiograph, smoking and "
        "diabetes");
    return;
  }
  Grade g = Grade::kB;
  if (p.age_years && p.bone_loss_pct) {
    d->bone_loss_per_age = *p.bone_loss_pct / *p.age_years;
    g = d->bone_loss_per_age < 0.25  ? Grade::kA
        : d->bone_loss_per_age > 1.0 ? Grade::kC
                                     : Grade::kB;
    std::snprintf(line, sizeof line,
                  "bone loss %.0f %% at the worst site at age %d: %.2f %% a year of age "
                  "(< 0.25 A, 0.25-1.0 B, > 1.0 C): grade %s",
                  *p.bone_loss_pct, *p.age_years, d->bone_loss_per_age, ToString(g));
  } else {
    std::snprintf(line, sizeof line, "no bone loss for the age known: grade B assumed");
  }
  d->path.push_back(line);
  const auto raise = [&](Grade to, const std::string& why) {
    if (to <= g) {
      d->path.push_back(why + ": grade " + ToString(to) + " or less, stays " +
                        ToString(g));
      return;
    }
    g = to;
    d->path.push_back(why + ": grade " + ToString(g));
  };
  if (p.cigarettes_per_day > 0)
    raise(p.cigarettes_per_day >= 10 ? Grade::kC : Grade::kB,
          "smoking " + std::to_string(p.cigarettes_per_day) +
              " cigarettes a day (< 10 B, 10 or more C)");
  if (p.hba1c_pct) {
    std::snprintf(line, sizeof line, "diabetes, HbA1c %.1f %% (< 7.0 B, 7.0 or more C)",
                  *p.hba1c_pct);
    raise(*p.hba1c_pct >= 7.0 ? Grade::kC : Grade::kB, line);
  }
  d->grade = g;
}

}  // namespace

const char* SiteCode(int site) {
  return site >= 0 && site < kSitesPerTooth ? kCodes[site] : "?";
}

int SiteFromCode(const std::string& code) {
  for (int i = 0; i < kSitesPerTooth; ++i)
    if (code == kCodes[i]) return i;
  return -1;
}

std::optional<int> SiteValues::cal_mm() const {
  if (!pd_mm) return std::nullopt;
  // Whole mm, a half rounding down: 4.5 -> 4. A pocket floor coronal to the CEJ
  // (PD 1 with the margin 1.5 mm above it) is no attachment lost: 0, never negative.
  return std::max(0, static_cast<int>(std::ceil(*pd_mm + recession_mm - 0.5 - 1e-9)));
}

ToothChart* PerioChart::Find(int fdi) {
  for (ToothChart& t : teeth)
    if (t.fdi == fdi) return &t;
  return nullptr;
}
const ToothChart* PerioChart::Find(int fdi) const {
  return const_cast<PerioChart*>(this)->Find(fdi);
}

bool AdjacentTeeth(int a, int b) {
  const int qa = a / 10, qb = b / 10, pa = a % 10, pb = b % 10;
  if (qa == qb) return std::abs(pa - pb) == 1;
  // The central incisors of one jaw touch across the midline (11-21, 31-41).
  const bool same_jaw = (qa <= 2) == (qb <= 2);
  return same_jaw && pa == 1 && pb == 1;
}

const char* ToString(Stage s) {
  switch (s) {
    case Stage::kI:
      return "I";
    case Stage::kII:
      return "II";
    case Stage::kIII:
      return "III";
    case Stage::kIV:
      return "IV";
    default:
      return "none";
  }
}
const char* ToString(Extent e) {
  switch (e) {
    case Extent::kLocalized:
      return "localized";
    case Extent::kGeneralized:
      return "generalized";
    case Extent::kMolarIncisor:
      return "molar-incisor";
    default:
      return "none";
  }
}
const char* ToString(Grade g) {
  switch (g) {
    case Grade::kA:
      return "A";
    case Grade::kB:
      return "B";
    case Grade::kC:
      return "C";
    default:
      return "none";
  }
}
std::optional<Stage> StageFromString(const std::string& s) {
  for (Stage v : {Stage::kNone, Stage::kI, Stage::kII, Stage::kIII, Stage::kIV})
    if (s == ToString(v)) return v;
  return std::nullopt;
}
std::optional<Extent> ExtentFromString(const std::string& s) {
  for (Extent v :
       {Extent::kNone, Extent::kLocalized, Extent::kGeneralized, Extent::kMolarIncisor})
    if (s == ToString(v)) return v;
  return std::nullopt;
}
std::optional<Grade> GradeFromString(const std::string& s) {
  for (Grade v : {Grade::kNone, Grade::kA, Grade::kB, Grade::kC})
    if (s == ToString(v)) return v;
  return std::nullopt;
}

const char* ToString(Diagnosis::Kind k) {
  switch (k) {
    case Diagnosis::Kind::kNotAssessable:
      return "not assessable";
    case Diagnosis::Kind::kHealth:
      return "periodontal health";
    case Diagnosis::Kind::kGingivitisLocalized:
      return "localized gingivitis";
    case Diagnosis::Kind::kGingivitisGeneralized:
      return "generalized gingivitis";
    case Diagnosis::Kind::kPeriodontitis:
      return "periodontitis";
    case Diagnosis::Kind::kNotClassifiable:
      return "not classifiable from this chart";
  }
  return "?";
}

std::string Diagnosis::Summary() const {
  if (kind != Kind::kPeriodontitis) return ToString(kind);
  std::string s =
      std::string("periodontitis stage ") + ToString(stage) + ", " + ToString(extent);
  if (grade != Grade::kNone) s += std::string(", grade ") + ToString(grade);
  return s;
}

Diagnosis Classify2017(const PerioChart& chart) {
  Diagnosis d;
  char line[256];
  std::vector<int> measured, interdental_loss, oral_loss, deep_pd;
  int present = 0, bleeding = 0, sites_measured = 0;
  bool pseudo_pocket = false, pocket = false;
  int worst_interdental = 0, worst_any = 0;
  for (const ToothChart& t : chart.teeth) {
    if (!t.present) continue;
    ++present;
    bool any = false, inter = false, oral = false, deep = false;
    for (int s = 0; s < kSitesPerTooth; ++s) {
      const SiteValues& v = t.sites[s];
      // Bleeding on probing counts where the site was probed (has a depth).
      if (!v.measured()) continue;
      ++sites_measured;
      if (v.bleeding) ++bleeding;
      any = true;
      const int cal = *v.cal_mm(), pd = *v.pd_mm;
      pocket |= pd >= 4;
      worst_any = std::max(worst_any, cal);
      if (IsInterdental(s)) {
        worst_interdental = std::max(worst_interdental, cal);
        inter |= cal >= 1;
      } else {
        oral |= cal >= 3 && pd > 3;
      }
      if (pd >= 4 && cal < 1) pseudo_pocket = true;
      // Complexity: PD >= 6 mm, third molars and the distal of second molars not counted.
      const bool excluded = t.fdi % 10 == 8 || (t.fdi % 10 == 7 && (s == 2 || s == 5));
      deep |= pd >= 6 && !excluded;
    }
    if (any) measured.push_back(t.fdi);
    if (inter) interdental_loss.push_back(t.fdi);
    if (oral) oral_loss.push_back(t.fdi);
    if (deep) deep_pd.push_back(t.fdi);
  }
  d.bop_pct = sites_measured > 0 ? 100.0 * bleeding / sites_measured : 0;
  d.worst_interdental_cal_mm = worst_interdental;
  if (!TwoNonAdjacent(measured)) {
    d.path.push_back("fewer than 2 non-adjacent teeth measured (" + List(measured) +
                     "): not assessable");
    return d;
  }
  const bool by_interdental = TwoNonAdjacent(interdental_loss);
  const bool by_oral = oral_loss.size() >= 2;
  std::snprintf(
      line, sizeof line, "interdental CAL >= 1 mm at teeth %s: %s",
      List(interdental_loss).c_str(),
      by_interdental ? "at 2 or more non-adjacent teeth" : "not at 2 non-adjacent teeth");
  d.path.push_back(line);
  if (!by_interdental) {
    std::snprintf(line, sizeof line,
                  "buccal/oral CAL >= 3 mm with PD > 3 mm at teeth %s: %s",
                  List(oral_loss).c_str(), by_oral ? "2 or more" : "fewer than 2");
    d.path.push_back(line);
  }
  if (!by_interdental && !by_oral) {
    if (pseudo_pocket)
      d.path.push_back(
          "PD >= 4 mm without attachment loss: pseudo-pocket, not periodontitis");
    std::snprintf(line, sizeof line,
                  "not a periodontitis case; bleeding on probing %.1f %% of sites",
                  d.bop_pct);
    d.path.push_back(line);
    d.kind = d.bop_pct >= 10 ? (d.bop_pct <= 30 ? Diagnosis::Kind::kGingivitisLocalized
                                                : Diagnosis::Kind::kGingivitisGeneralized)
             : pocket        ? Diagnosis::Kind::kNotClassifiable
                             : Diagnosis::Kind::kHealth;
    d.path.push_back(
        std::string("BOP < 10 % with every PD <= 3 mm: health; 10-30 %: localized "
                    "gingivitis; > 30 %: generalized; BOP < 10 % with a PD >= 4 mm: "
                    "neither: ") +
        ToString(d.kind));
    return d;
  }
  d.kind = Diagnosis::Kind::kPeriodontitis;
  const int worst = worst_interdental >= 1 ? worst_interdental : worst_any;
  d.stage = worst >= 5 ? Stage::kIII : worst >= 3 ? Stage::kII : Stage::kI;
  std::snprintf(
      line, sizeof line,
      "worst interdental CAL %d mm: stage %s (1-2 mm I, 3-4 mm II, >= 5 mm III)", worst,
      ToString(d.stage));
  d.path.push_back(line);
  // The extent's band is the one that set the stage, before complexity raised it.
  int band_lo = d.stage == Stage::kIII ? 5 : d.stage == Stage::kII ? 3 : 1;
  int band_hi = d.stage == Stage::kIII ? 1000 : d.stage == Stage::kII ? 4 : 2;
  int furcation = 0;
  for (const ToothChart& t : chart.teeth)
    furcation = std::max(furcation, t.present ? t.furcation : 0);
  if (d.stage != Stage::kIII && furcation >= 2) {
    // The consensus table's footnote: furcation class II or III shifts the stage
    // to at least III irrespective of CAL.
    std::snprintf(line, sizeof line,
                  "complexity: furcation class %s: stage III whatever the CAL",
                  furcation >= 3 ? "III" : "II");
    d.path.push_back(line);
    d.stage = Stage::kIII;
  } else if (d.stage == Stage::kII) {
    if (TwoNonAdjacent(deep_pd)) {
      d.stage = Stage::kIII;
      d.path.push_back("complexity: PD >= 6 mm at 2 or more non-adjacent teeth (" +
                       List(deep_pd) + "): stage III");
    } else {
      d.path.push_back("complexity: PD >= 6 mm at " + List(deep_pd) +
                       " (not at 2 non-adjacent teeth), no furcation "
                       "class II or III: stays stage II");
    }
  }
  const PatientFacts& patient = chart.patient;
  d.stage_iv_assessable = patient.given;
  if (!patient.given) {
    if (d.stage == Stage::kIII)
      d.path.push_back(
          "stage IV not assessed: it needs the teeth lost to periodontitis, mobility and "
          "the bite, which the chart does not hold");
  } else {
    StageFromHistory(chart, &d);
  }
  int in_band = 0;
  for (const ToothChart& t : chart.teeth) {
    if (!t.present) continue;
    int tooth_worst = -100;
    for (int s = 0; s < kSitesPerTooth; ++s)
      if (IsInterdental(s) && t.sites[s].measured())
        tooth_worst = std::max(tooth_worst, *t.sites[s].cal_mm());
    if (tooth_worst >= band_lo && tooth_worst <= band_hi) ++in_band;
  }
  d.extent_pct = present > 0 ? 100.0 * in_band / present : 0;
  d.extent = d.extent_pct < 30 ? Extent::kLocalized : Extent::kGeneralized;
  std::snprintf(
      line, sizeof line,
      "extent: %d of %d teeth (%.1f %%) have their worst interdental CAL in the %d%s mm "
      "band: %s (< 30 %% localized)",
      in_band, present, d.extent_pct, band_lo,
      band_hi >= 1000 ? "+" : ("-" + std::to_string(band_hi)).c_str(),
      ToString(d.extent));
  d.path.push_back(line);
  MolarIncisorPattern(chart, band_lo, band_hi, &d);
  GradeFromHistory(patient, &d);
  return d;
}

}  // namespace sulcus
