// The inspection lesson's score: coverage of every region and surface, the
// order, the findings against the truth, damage (LessonRun::ScoreInspection).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/tooth.h"
#include "core/base/text.h"
#include "core/lesson/lesson.h"
#include "core/lesson/scoring_parts.h"

namespace sulcus {

using namespace lesson_detail;  // the helpers the state machine and scorers share

void LessonRun::ScoreInspection(LessonResult& out) const {
  auto& L = out.lines;
  const RubricSpec& rb = spec_.rubric;
  InspectionResult& in = out.inspection;
  in.regions = spec_.regions;
  in.teeth = spec_.teeth;
  in.units = inspection_->units();
  in.truth = TrueOdontogram(scene_.spec, spec_.teeth, spec_.regions);
  in.recorded = odontogram_;
  in.findings = findings_;
  for (Finding& f : in.findings)
    if (f.tick == kAfterReading) f.tick = last_tick_;
  in.submitted_tick = submitted_;
  in.presses = inspection_->presses();
  in.views = views_;
  const bool viewed = !views_.empty();
  auto seconds = [&](std::uint64_t tick) {
    return static_cast<double>(tick - std::min(tick, first_tick_)) / rate_hz_;
  };

  // Coverage: the units the steps name (all of them when no step names any).
  std::vector<bool> scored(in.units.size(), false);
  bool any = false;
  for (const auto& us : step_units_)
    for (int u : us) scored[static_cast<std::size_t>(u)] = any = true;
  if (!any) scored.assign(in.units.size(), true);
  for (const InspectionUnit& u : in.units) {
    if (!u.region.empty() && scored[static_cast<std::size_t>(&u - in.units.data())])
      L.push_back(Line(
          "coverage", nullptr, 0, u.touched ? S::kPass : S::kFail, u.touched ? 1 : 0,
          (u.touched
               ? Format("%s: examined at %.1f s (%.1f s on it)",
                        RegionLabel(u.region).c_str(), seconds(u.first_tick), u.dwell_s)
               : RegionLabel(u.region) + ": not examined") +
              (!viewed  ? ""
               : u.seen ? Format("; in view at %.1f s", seconds(u.seen_tick))
                        : "; never in view"),
          u.touched ? u.first_tick : last_tick_));
  }
  for (int fdi : spec_.teeth) {
    int asked = 0, done = 0, unseen = 0;
    std::string missed;
    std::uint64_t last = 0;
    for (int s = 0; s < 5; ++s) {
      const int u = inspection_->UnitOf(fdi, static_cast<ToothSurface>(s));
      if (u < 0 || !scored[static_cast<std::size_t>(u)]) continue;
      ++asked;
      const InspectionUnit& unit = in.units[static_cast<std::size_t>(u)];
      unseen += !unit.seen;
      if (unit.touched) {
        ++done;
        last = std::max(last, unit.first_tick);
      } else {
        missed += (missed.empty() ? "" : ", ") +
                  std::string(SurfaceCode(static_cast<ToothSurface>(s)));
      }
    }
    if (asked == 0) continue;
    L.push_back(
        Line("coverage", nullptr, fdi,
             done == asked ? S::kPass
             : done > 0    ? S::kPartial
                           : S::kFail,
             static_cast<double>(done) / asked,
             (done == asked ? Format("%d: every surface examined (%d)", fdi, asked)
                            : Format("%d: %s not examined (%d of %d surfaces)", fdi,
                                     missed.c_str(), done, asked)) +
                 (!viewed       ? ""
                  : unseen == 0 ? "; every surface in view"
                                : Format("; %d surface%s never in view", unseen,
                                         unseen == 1 ? "" : "s")),
             done == asked ? last : last_tick_));
  }

  if (!viewed)
    L.push_back(Line(
        "coverage", nullptr, 0, S::kInfo, 0,
        "no view was recorded (a headless attempt): what the view showed is not scored",
        last_tick_));

  // Sequence: each step examined in its turn.
  for (std::size_t k = 0; k < out.steps.size(); ++k) {
    if (step_units_[k].empty()) continue;
    const StepResult& st = out.steps[k];
    const std::string missed = Join(st.missed);
    if (st.completed)
      L.push_back(Line("sequence", nullptr, 0, S::kPass, 1,
                       "'" + st.id + "': examined in its turn", st.ended_tick));
    else if (st.skipped)
      L.push_back(
          Line("sequence", nullptr, 0, S::kFail, 0,
               "'" + st.id + "': left for a later step with " + missed + " not examined",
               st.ended_tick));
    else
      L.push_back(Line("sequence", nullptr, 0, S::kFail, 0,
                       "'" + st.id + "': not finished", last_tick_));
  }

  // Findings against the truth: every finding and every miss named.
  std::map<std::string, std::uint64_t> when;  // a unit's last finding
  for (const Finding& f : in.findings) {
    const std::string key =
        f.kind == Finding::Kind::kLesion ? "lesion " + f.region
        : f.kind == Finding::Kind::kCaries
            ? "caries " + std::to_string(f.fdi) + " " + SurfaceCode(f.surface)
            : std::string(ToString(f.kind)) + " " + std::to_string(f.fdi);
    when[key] = f.tick;
  }
  const std::uint64_t end_tick = submitted_ ? *submitted_ : last_tick_;
  auto tick_of = [&](const std::string& key) {
    const auto it = when.find(key);
    return it != when.end() ? it->second : end_tick;
  };
  auto judge = [&](FindingScore& sc, bool truth, bool said, const std::string& key,
                   const std::string& what, const char* found, const char* missed,
                   const char* wrong) {
    if (truth && said) {
      ++sc.tp;
      L.push_back(
          Line("findings", nullptr, 0, S::kPass, 1, what + ": " + found, tick_of(key)));
    } else if (truth) {
      ++sc.fn;
      L.push_back(
          Line("findings", nullptr, 0, S::kFail, 0, what + ": " + missed, end_tick));
    } else if (said) {
      ++sc.fp;
      L.push_back(
          Line("findings", nullptr, 0, S::kFail, 0, what + ": " + wrong, tick_of(key)));
    } else {
      ++sc.tn;
    }
  };
  FindingScore caries{"caries"}, calculus{"calculus"}, inflamed{"inflamed gingiva"},
      lesion{"lesion"}, status{"status"};
  for (const ToothRecord& t : in.truth.teeth) {
    const ToothRecord* r = in.recorded.Find(t.fdi);
    ToothRecord none;
    none.fdi = t.fdi;
    if (!r) r = &none;
    for (int s = 0; s < 5; ++s) {
      const std::string name =
          std::to_string(t.fdi) + " " + SurfaceCode(static_cast<ToothSurface>(s));
      judge(caries, t.caries[static_cast<std::size_t>(s)],
            r->caries[static_cast<std::size_t>(s)], "caries " + name, name,
            "caries found", "caries missed", "caries recorded on a sound surface");
    }
    const std::string tooth = std::to_string(t.fdi);
    judge(calculus, t.calculus, r->calculus, "calculus " + tooth, tooth, "calculus found",
          "calculus missed", "calculus recorded where there is none");
    judge(inflamed, t.inflamed, r->inflamed, "inflamed gingiva " + tooth, tooth,
          "inflamed gingiva found", "inflamed gingiva missed",
          "gingiva recorded as inflamed where it is healthy");
    // Status: the WHO code recorded (or implied by the caries marks) against the truth's.
    const int want = t.Status(), got = r->Status();
    if (want != 0 && got == want)
      ++status.tp;
    else if (want != 0)
      ++status.fn;
    else if (got != 0)
      ++status.fp;
    else
      ++status.tn;
    if (r->status && got != want)
      L.push_back(Line("findings", nullptr, t.fdi, S::kFail, 0,
                       Format("%d: status %d (%s) recorded; it is %d (%s)", t.fdi, got,
                              WhoStatusName(got), want, WhoStatusName(want)),
                       tick_of("status " + tooth)));
  }
  for (const std::string& region : spec_.regions) {
    const auto t = in.truth.lesions.find(region), r = in.recorded.lesions.find(region);
    const bool truth = t != in.truth.lesions.end(), said = r != in.recorded.lesions.end();
    const std::string what = RegionLabel(region);
    if (truth && said && t->second != r->second) {
      ++lesion.tp;
      L.push_back(Line("findings", nullptr, 0, S::kPartial, 0.5,
                       what + ": a lesion found, recorded as " + r->second + "; it is " +
                           t->second + " (look again)",
                       tick_of("lesion " + region)));
      continue;
    }
    judge(lesion, truth, said, "lesion " + region, what,
          ("a " + (truth ? t->second : std::string()) + " found").c_str(),
          ("a " + (truth ? t->second : std::string()) + " missed").c_str(),
          "a lesion recorded on healthy mucosa");
  }
  for (FindingScore* sc : {&caries, &calculus, &inflamed, &lesion, &status}) {
    in.scores.push_back(*sc);
    if (sc->kind == "status") continue;
    L.push_back(Line(
        "findings", nullptr, 0, S::kInfo, 0,
        Format("%s: sensitivity %.0f %% (%d of %d found), specificity %.0f %% (%d false)",
               sc->kind.c_str(), 100 * sc->sensitivity(), sc->tp, sc->tp + sc->fn,
               100 * sc->specificity(), sc->fp),
        end_tick));
  }
  if (!submitted_)
    L.push_back(Line("findings", nullptr, 0, S::kInfo, 0,
                     "the findings were not submitted as complete", last_tick_));
  L.insert(L.end(), felt_.begin(), felt_.end());

  // Damage: force on tissue above its limit, force into a lesion above the gentle limit.
  bool damaged = false;
  for (const auto& [line, idx] : damage_) {
    L.push_back(line);
    damaged = true;
  }
  for (const LesionPress& p : in.presses) {
    damaged = true;
    const bool tooth =
        !p.where.empty() && std::isdigit(static_cast<unsigned char>(p.where[0]));
    L.push_back(Line(
        "damage", nullptr, 0, S::kFail, 0,
        Format("%s: %.2f N into the lesion, above the gentle %.2f N%s",
               tooth ? p.where.c_str() : RegionLabel(p.where).c_str(), p.force_n,
               rb.lesion_force_n,
               tooth ? " (a tip forced into demineralised enamel cavitates it)" : ""),
        p.tick));
  }
  if (!damaged)
    L.push_back(Line("damage", nullptr, 0, S::kPass, 1,
                     "no tissue damaged, no lesion pressed hard", last_tick_));
}

}  // namespace sulcus
