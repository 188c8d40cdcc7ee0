// The probing lesson's score: each site read, charted and held against the
// truth, the walking strokes, completeness, the diagnosis (LessonRun::ScoreProbing).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/tooth.h"
#include "core/lesson/lesson.h"
#include "core/lesson/scoring_parts.h"

namespace sulcus {

using namespace lesson_detail;  // the helpers the state machine and scorers share

void LessonRun::ScoreProbing(LessonResult& out) const {
  const RubricSpec& rb = spec_.rubric;
  auto& L = out.lines;

  // Entries entered "after the reading" take the tick after the site's last reading.
  for (SiteResult& s : out.sites)
    if (s.entry && s.entry->tick == kAfterReading)
      s.entry->tick = s.reached_mm ? s.left_tick + 1 : last_tick_;

  int charted = 0, within1 = 0, exact = 0, proximal = 0, in_band = 0, read = 0;
  double bias = 0, bias_prox = 0;
  for (const SiteResult& s : out.sites) {
    const SiteRef& site = s.site;
    const std::string name = site.ToString();
    if (!s.reached_mm) {
      L.push_back(Line(
          "technique", &site, 0, S::kFail, 0,
          name + ": not probed" + (s.no_reading.empty() ? "" : " (" + s.no_reading + ")"),
          last_tick_));
    } else {
      ++read;
      const double reached = *s.reached_mm, err = reached - s.truth_mm;
      const double a = std::abs(err);
      const S st = a <= rb.technique_full_mm      ? S::kPass
                   : a <= rb.technique_partial_mm ? S::kPartial
                                                  : S::kFail;
      L.push_back(
          Line("technique", &site, 0, st, Credit(st),
               Format("%s: the tip reached %.1f mm, the true depth is %d mm (%+.1f mm)%s",
                      name.c_str(), reached, s.truth_mm, err,
                      err < -rb.technique_full_mm  ? ": stopped short of the floor"
                      : err > rb.technique_full_mm ? ": pushed through the floor"
                                                   : ""),
               s.reading_tick));
      // Force at the floor: what the hand held there (a tremor's highest tick
      // is not the probing force); the highest tick judges damage below.
      const double f = s.held_force_n;
      if (f >= rb.force_low_n && f <= rb.force_high_n) {
        ++in_band;
        L.push_back(Line("force", &site, 0, S::kPass, 1,
                         Format("%s: %.2f N at the floor, in the band %.2f-%.2f N",
                                name.c_str(), f, rb.force_low_n, rb.force_high_n),
                         s.reading_tick));
      } else if (f < rb.force_low_n) {
        L.push_back(Line("force", &site, 0, S::kPartial, 0.5,
                         Format("%s: %.2f N at the floor, lighter than %.2f N: the floor "
                                "may not have been felt",
                                name.c_str(), f, rb.force_low_n),
                         s.reading_tick));
      } else if (f <= rb.force_damage_n) {
        L.push_back(Line("force", &site, 0, S::kPartial, 0.5,
                         Format("%s: %.2f N at the floor, heavier than %.2f N: healthy "
                                "gingiva may bleed falsely",
                                name.c_str(), f, rb.force_high_n),
                         s.reading_tick));
      } else {
        L.push_back(Line("force", &site, 0, S::kFail, 0,
                         Format("%s: %.2f N at the floor, above %.2f N", name.c_str(), f,
                                rb.force_damage_n),
                         s.reading_tick));
      }
      const bool damaged = s.peak_force_n > rb.force_damage_n;
      L.push_back(Line(
          "damage", &site, 0, damaged ? S::kFail : S::kPass, damaged ? 0 : 1,
          damaged ? Format("%s: %.2f N drove the tip into the attachment: tissue damage",
                           name.c_str(), s.peak_force_n)
                  : name + ": no tissue damage",
          s.reading_tick));
      // Angulation, or the col under the contact.
      if (s.interproximal_contact) {
        L.push_back(Line(
            "angulation", &site, 0, s.col_reached ? S::kPass : S::kFail,
            s.col_reached ? 1 : 0,
            s.col_reached
                ? name + ": the tip reached the col under the contact"
                : name +
                      ": the tip did not reach the col under the contact (tilt it under "
                      "the contact point)",
            s.reading_tick));
      } else {
        const double ang = s.angle_deg;
        const S st2 = AngleStatus(ang, rb);
        L.push_back(Line("angulation", &site, 0, st2, Credit(st2),
                         Format("%s: the probe %.1f degrees off the long axis (full "
                                "credit within %.0f, pass within "
                                "%.0f)",
                                name.c_str(), ang, rb.angle_full_deg, rb.angle_pass_deg),
                         s.reading_tick));
      }
      // Bleeding.
      const bool marked = s.entry && s.entry->bleeding;
      if (s.bled && marked) {
        L.push_back(Line("bleeding", &site, 0, S::kPass, 1,
                         name + ": bleeding seen and charted", s.bleed_tick));
      } else if (s.bled) {
        L.push_back(Line("bleeding", &site, 0, S::kFail, 0,
                         name + ": bled on probing, not charted", s.bleed_tick));
      } else if (marked) {
        L.push_back(Line("bleeding", &site, 0, S::kFail, 0,
                         name + ": bleeding charted where none was seen", s.entry->tick));
      } else {
        L.push_back(Line("bleeding", &site, 0, S::kPass, 1,
                         name + ": no bleeding, none charted", s.reading_tick));
      }
      if (s.bled && std::max(s.bleed_force_n, s.held_force_n) > rb.force_high_n)
        L.push_back(Line(
            "bleeding", &site, 0, S::kInfo, 0,
            Format("%s: bleeding possibly caused by probing force (%.2f N, above %.2f N)",
                   name.c_str(), std::max(s.bleed_force_n, s.held_force_n),
                   rb.force_high_n),
            s.bleed_tick));
    }
    // The entry: against what was reached (reading) and against the truth (charting).
    if (s.entry && s.entry->pd_mm) {
      ++charted;
      const int entered = *s.entry->pd_mm;
      if (s.reached_mm) {
        const double err = entered - *s.reached_mm, a = std::abs(err);
        const S st = a <= 0.5 ? S::kPass : a <= 1.5 ? S::kPartial : S::kFail;
        L.push_back(
            Line("reading", &site, 0, st, Credit(st),
                 Format("%s: entered %d mm where the probe reached %.1f mm (%+.1f mm)",
                        name.c_str(), entered, *s.reached_mm, err),
                 s.entry->tick));
      } else {
        L.push_back(Line(
            "reading", &site, 0, S::kFail, 0,
            Format("%s: entered %d mm without probing the site", name.c_str(), entered),
            s.entry->tick));
      }
      const int diff = entered - s.truth_mm;
      const S st = diff == 0 ? S::kPass : std::abs(diff) == 1 ? S::kPartial : S::kFail;
      L.push_back(Line("charting", &site, 0, st, Credit(st),
                       Format("%s: charted %d mm, the true depth is %d mm (%+d mm)",
                              name.c_str(), entered, s.truth_mm, diff),
                       s.entry->tick));
      within1 += std::abs(diff) <= 1;
      exact += diff == 0;
      bias += diff;
      if (IsInterdental(site.site)) {
        ++proximal;
        bias_prox += diff;
      }
    } else {
      // A site left blank scores as a wrong depth and a wrong reading, never
      // better than a depth 1 mm off: leaving an uncertain site blank must not pay.
      L.push_back(
          Line("reading", &site, 0, S::kFail, 0,
               name + ": no reading entered" +
                   (s.reached_mm ? Format(" (the probe reached %.1f mm)", *s.reached_mm)
                                 : std::string(" (not probed)")),
               last_tick_));
      L.push_back(Line("charting", &site, 0, S::kFail, 0,
                       name + ": not charted (scored as a wrong depth)", last_tick_));
    }
  }
  for (const auto& [line, idx] : damage_) L.push_back(line);

  // Walking-stroke coverage per surface that the path asks for.
  for (std::size_t i = 0; i < geometry_.teeth.size(); ++i) {
    const LessonGeometry::Tooth& t = geometry_.teeth[i];
    for (int side = 0; side < 2; ++side) {
      const bool buccal = side == 0;
      const bool asked =
          std::any_of(sites_.begin(), sites_.end(), [&](const SiteResult& s) {
            return s.site.fdi == t.fdi && (s.site.site < 3) == buccal;
          });
      if (!asked) continue;
      const SurfaceTrack& st = surfaces_[i][static_cast<std::size_t>(side)];
      SurfaceCoverage c;
      c.fdi = t.fdi;
      c.buccal = buccal;
      const int n = static_cast<int>(st.bins.size());
      int total = 0, swept = 0;
      for (int k = 0; k < n; ++k) {
        const double deg = SegmentDeg(k, n), d = buccal ? deg : 360.0 - deg;
        const auto [from, to] = arcs_[i][static_cast<std::size_t>(side)];
        if (d < from || d > to) continue;
        ++total;
        swept += st.bins[static_cast<std::size_t>(k)];
        c.bins.push_back(st.bins[static_cast<std::size_t>(k)]);
      }
      c.swept = total > 0 ? static_cast<double>(swept) / total : 0;
      c.touch_share =
          st.in_ticks > 0 ? static_cast<double>(st.touch_ticks) / st.in_ticks : 0;
      c.strokes = st.strokes;
      c.stroke_mm = st.strokes > 0 ? st.swing_sum / st.strokes : 0;
      c.first_tick = st.first;
      c.last_tick = st.last;
      const char* surface = buccal ? "buccal" : "lingual";
      const bool ok = c.swept >= rb.coverage_min;
      // A surface short of the minimum keeps at most half its credit, in proportion.
      L.push_back(
          Line("coverage", nullptr, t.fdi, ok ? S::kPass : S::kFail,
               ok ? 1 : 0.5 * c.swept / rb.coverage_min,
               Format("%d %s: %.0f %% of the sulcus swept (at least %.0f %%), %d strokes "
                      "of %.1f mm, the tip "
                      "on the tooth %.0f %% of the time%s",
                      t.fdi, surface, 100 * c.swept, 100 * rb.coverage_min, c.strokes,
                      c.stroke_mm, 100 * c.touch_share,
                      ok ? "" : ": spot-probing misses pockets; walk the probe around"),
               st.any ? st.last : last_tick_));
      out.coverage.push_back(std::move(c));
    }
  }

  // Completeness.
  std::string unread, uncharted;
  for (const SiteResult& s : out.sites) {
    if (!s.reached_mm) unread += (unread.empty() ? "" : ", ") + s.site.ToString();
    if (!(s.entry && s.entry->pd_mm))
      uncharted += (uncharted.empty() ? "" : ", ") + s.site.ToString();
  }
  const double total = std::max(1, out.sites_total);
  L.push_back(Line("completeness", nullptr, 0,
                   read == out.sites_total ? S::kPass : S::kFail, read / total,
                   Format("%d of %d sites probed%s%s", read, out.sites_total,
                          unread.empty() ? "" : "; not probed: ", unread.c_str()),
                   last_tick_));
  L.push_back(Line("completeness", nullptr, 0,
                   charted == out.sites_total ? S::kPass : S::kFail, charted / total,
                   Format("%d of %d sites charted%s%s", charted, out.sites_total,
                          uncharted.empty() ? "" : "; not charted: ", uncharted.c_str()),
                   last_tick_));

  // The charts and the diagnosis.
  out.true_chart = TrueChart(scene_.spec, spec_.teeth);
  out.student_chart = GivenChart();
  for (const SiteResult& s : out.sites) {
    ToothChart* t = out.student_chart.Find(s.site.fdi);
    if (!t || !s.entry) continue;
    t->sites[s.site.site].pd_mm = s.entry->pd_mm;
    t->sites[s.site.site].bleeding = s.entry->bleeding;
  }
  out.agreement = Agree(out.student_chart, out.true_chart);
  if (spec_.has_reference()) {
    out.reference_chart = spec_.reference;
    out.reference_name = spec_.reference_file.filename().string();
    out.reference_agreement = Agree(out.student_chart, out.reference_chart);
    const Agreement& g = *out.reference_agreement;
    L.push_back(Line(
        "calibration", nullptr, 0, S::kInfo, 0,
        Format("against the reference examiner (%s): %d sites, exact %.0f %%, within 1 "
               "mm %.0f %%, weighted kappa %s, bias %+.2f mm: the target (within 1 mm "
               "at 90 %% of sites, kappa above 0.6) is %s",
               out.reference_name.c_str(), g.sites, g.exact_pct, g.within_1mm_pct,
               g.depth_kappa ? Format("%.2f", *g.depth_kappa).c_str() : "-",
               g.all.mean_mm().value_or(0), g.MeetsTarget() ? "met" : "not met"),
        last_tick_));
  }
  out.true_dx = Classify2017(out.true_chart);
  out.chart_dx = Classify2017(out.student_chart);
  out.declared = declared_;
  const bool chart_agrees = out.chart_dx.Summary() == out.true_dx.Summary();
  L.push_back(
      Line("diagnosis", nullptr, 0, S::kInfo, 0,
           "your chart gives " + out.chart_dx.Summary() + "; the true chart " +
               out.true_dx.Summary() +
               (chart_agrees ? "" : " (the difference comes from the measurements)"),
           last_tick_));
  if (declared_) {
    const std::uint64_t tick =
        declared_->tick == kAfterReading ? last_tick_ : declared_->tick;
    double credit = 0;
    const bool truth_perio = out.true_dx.kind == Diagnosis::Kind::kPeriodontitis;
    if (truth_perio && declared_->periodontitis) {
      // Stage and extent, and the grade where the patient's facts give one.
      const bool graded = out.true_dx.grade != Grade::kNone;
      const double part = graded ? 1.0 / 3 : 0.5;
      credit = part * (declared_->stage == out.true_dx.stage) +
               part * (declared_->extent == out.true_dx.extent) +
               (graded ? part * (declared_->grade == out.true_dx.grade) : 0.0);
    } else {
      credit = truth_perio == declared_->periodontitis ? 1 : 0;
    }
    const bool matches_chart = out.chart_dx.kind == Diagnosis::Kind::kPeriodontitis &&
                               declared_->periodontitis &&
                               declared_->stage == out.chart_dx.stage &&
                               declared_->extent == out.chart_dx.extent &&
                               declared_->grade == out.chart_dx.grade;
    L.push_back(
        Line("diagnosis", nullptr, 0,
             credit >= 1  ? S::kPass
             : credit > 0 ? S::kPartial
                          : S::kFail,
             credit,
             "declared " + declared_->Summary() + "; the true chart gives " +
                 out.true_dx.Summary() +
                 (credit < 1 && matches_chart
                      ? " (your declaration follows your chart: check the readings)"
                  : credit < 1 ? " (your chart gives " + out.chart_dx.Summary() +
                                     ": check the staging rules)"
                               : ""),
             tick));
  } else {
    L.push_back(
        Line("diagnosis", nullptr, 0, S::kFail, 0, "no diagnosis declared", last_tick_));
  }

  out.sites_read = read;
  out.sites_charted = charted;
  out.within_1mm_pct = charted ? 100.0 * within1 / charted : 0;
  out.exact_pct = charted ? 100.0 * exact / charted : 0;
  out.bias_mm = charted ? bias / charted : 0;
  out.bias_proximal_mm = proximal ? bias_prox / proximal : 0;
  out.force_in_band_pct = read ? 100.0 * in_band / read : 0;
}

}  // namespace sulcus
