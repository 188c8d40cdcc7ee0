// Generated cases: the scene's pockets, recession and bleeding drawn so that
// the true chart has the diagnosis a lesson's `case:` asks for (and, on a lesson
// of more than a sextant, the teeth's history: gaps, teeth taken out,
// furcation), the lesson fitted to the teeth the case left, and a case saved as
// a scene of its own.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <set>

#include "core/anatomy/gingiva.h"
#include "core/anatomy/tooth.h"
#include "core/lesson/lesson_spec.h"
#include "core/scene/scene.h"

namespace sulcus {

namespace fs = std::filesystem;

void FitLessonToCase(LessonSpec* spec, const SceneSpec& scene) {
  if (scene.missing.empty()) return;
  auto gone = [&](int fdi) { return scene.missing.count(fdi) > 0; };
  std::erase_if(spec->teeth, gone);
  std::erase_if(spec->path, [&](const SiteRef& s) { return gone(s.fdi); });
  for (StepSpec& st : spec->steps) std::erase_if(st.teeth, gone);
}

namespace {

// Occluding pairs: a tooth and its antagonist of the other jaw (11-41, 26-36,
// ...), both in the scene.
int OpposingPairs(const SceneSpec& s) {
  std::set<int> teeth;
  for (const ObjectSpec& o : s.objects)
    if (o.kind == ObjectSpec::Kind::kTooth) teeth.insert(o.fdi);
  int pairs = 0;
  for (int q : {1, 2})
    for (int p = 1; p <= 8; ++p)
      pairs += teeth.count(q * 10 + p) && teeth.count((q == 1 ? 40 : 30) + p);
  return pairs;
}

// The scene's gaps lost to periodontitis.
int LostToPeriodontitis(const SceneSpec& s) {
  return static_cast<int>(
      std::count_if(s.missing.begin(), s.missing.end(),
                    [](const auto& m) { return m.second.reason == "periodontitis"; }));
}

// Takes tooth `fdi` out of the scene (the tooth, its gingiva, its deposits)
// and lists it as missing for `why`.
void TakeOut(SceneSpec* s, int fdi, const std::string& why) {
  std::erase_if(s->objects, [&](const ObjectSpec& o) {
    return o.fdi == fdi &&
           (o.kind == ObjectSpec::Kind::kTooth || o.kind == ObjectSpec::Kind::kGingiva ||
            o.kind == ObjectSpec::Kind::kCalculus);
  });
  s->missing[fdi] = {why, 0, 0};
}

// The patient of a case that asks for a grade or stage IV: stage IV by tooth
// loss or by one complexity (a mobile diseased tooth, drifting, a collapsed
// bite, few opposing pairs); the grade from the age (against the bone loss the
// pockets leave) and the two risk factors, drawn toward the grade asked.
// The whole mouth's teeth lost: why each of the scene's gaps was lost (to
// periodontitis only from stage III), and teeth taken out of `order` (never a
// first molar or incisor a molar-incisor case needs) for stage IV by tooth
// loss (5 to 8 in all) or one for stage III.
template <typename Uniform>
void DrawTeethLost(const CaseSpec& c, Uniform& uniform, std::vector<int>* order,
                   SceneSpec* s) {
  for (auto& [fdi, m] : s->missing)
    m.reason = c.stage >= Stage::kIII && uniform(0, 1) == 0 ? "periodontitis"
               : uniform(0, 1) == 0                         ? "caries"
                                                            : "unknown";
  int lost = LostToPeriodontitis(*s);
  const int want = c.stage == Stage::kIV && uniform(0, 3) == 0 ? uniform(5, 8)
                   : c.stage == Stage::kIII                    ? lost + uniform(0, 1)
                                                               : lost;
  const bool keep = c.extent == Extent::kMolarIncisor;
  for (auto it = order->begin(); lost < want && it != order->end();) {
    if (keep && (FirstMolar(*it) || Incisor(*it))) {
      ++it;
      continue;
    }
    TakeOut(s, *it, "periodontitis");
    ++lost;
    it = order->erase(it);
  }
}

template <typename Uniform>
void DrawPatient(const CaseSpec& c, int sick_tooth, bool whole, Uniform& uniform,
                 SceneSpec* s) {
  PatientFacts p;
  p.given = true;
  // Grade A (under 0.25 % of the root lost a year of age) is an older
  // patient's: in the whole mouth it is drawn from 60 to 90.
  p.age_years = whole && c.grade == Grade::kA ? uniform(60, 90) : uniform(25, 80);
  p.opposing_pairs = uniform(10, 14);
  if (whole) {
    // The whole mouth shows its own history: the teeth lost to periodontitis
    // are its gaps of that reason, the opposing pairs are counted on it, and
    // stage IV's complexity is a mobile diseased tooth, drifting or a collapsed
    // bite (tooth loss was drawn with the gaps).
    p.teeth_lost_to_periodontitis = LostToPeriodontitis(*s);
    p.opposing_pairs = OpposingPairs(*s);
    if (c.stage == Stage::kIV && p.teeth_lost_to_periodontitis < 5) {
      switch (uniform(0, 2)) {
        case 0:
          for (ObjectSpec& o : s->objects)
            if (o.kind == ObjectSpec::Kind::kTooth && o.fdi == sick_tooth)
              o.mobility = uniform(2, 3);
          break;
        case 1:
          p.drifting_flaring = true;
          break;
        default:
          p.bite_collapse = true;
      }
    }
  } else if (c.stage == Stage::kIV) {
    switch (uniform(0, 4)) {
      case 0:
        p.teeth_lost_to_periodontitis = uniform(5, 8);
        break;
      case 1:
        for (ObjectSpec& o : s->objects)
          if (o.kind == ObjectSpec::Kind::kTooth && o.fdi == sick_tooth)
            o.mobility = uniform(2, 3);
        break;
      case 2:
        p.drifting_flaring = true;
        break;
      case 3:
        p.bite_collapse = true;
        break;
      default:
        p.opposing_pairs = uniform(6, 9);
    }
  } else if (c.stage == Stage::kIII) {
    p.teeth_lost_to_periodontitis = uniform(0, 2);
  }
  const Grade g = c.grade == Grade::kNone ? static_cast<Grade>(uniform(1, 3)) : c.grade;
  if (g == Grade::kC && uniform(0, 1) == 0) {
    p.cigarettes_per_day = uniform(10, 25);
  } else if (g == Grade::kC) {
    p.hba1c_pct = 7.0 + 0.1 * uniform(0, 25);
  } else if (g == Grade::kB && uniform(0, 2) == 0) {
    p.cigarettes_per_day = uniform(1, 9);
  } else if (g == Grade::kB && uniform(0, 1) == 0) {
    p.hba1c_pct = 5.8 + 0.1 * uniform(0, 11);
  }
  s->patient = p;
}

}  // namespace

SceneSpec ApplyCase(const SceneSpec& scene, const std::vector<int>& teeth,
                    const CaseSpec& c, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&](int lo, int hi) {
    return std::uniform_int_distribution<int>(lo, hi)(rng);
  };
  // The deepest attachment loss the stage asks for (whole mm of CAL at the worst site).
  const int cal_lo = c.stage == Stage::kI ? 1 : c.stage == Stage::kII ? 3 : 5;
  const int cal_hi = c.stage == Stage::kI ? 2 : c.stage == Stage::kII ? 4 : 7;
  // A patient only where the case asks for what needs one (the draws of the
  // other cases stay as they were).
  const bool patient = c.grade != Grade::kNone || c.stage == Stage::kIV;
  // A lesson of more than a sextant draws the history of its teeth too: why
  // each of the scene's gaps was lost (to periodontitis only from stage III),
  // teeth taken out for stage IV by tooth loss (5 to 8 in all) or one for
  // stage III, furcation involvement of diseased molars. A sextant's draws stay
  // as they were.
  const bool whole = teeth.size() > 8;
  const bool molar_incisor = c.extent == Extent::kMolarIncisor;
  auto first_molar_or_incisor = [](int fdi) { return FirstMolar(fdi) || Incisor(fdi); };
  for (int attempt = 0; attempt < 5000; ++attempt) {
    SceneSpec s = scene;
    std::vector<int> order = teeth;
    std::shuffle(order.begin(), order.end(), rng);
    if (whole) DrawTeethLost(c, uniform, &order, &s);
    // Which teeth are diseased: one or two for localized, most for generalized,
    // the first molars and incisors for the molar-incisor pattern.
    const int n = static_cast<int>(order.size());
    if (molar_incisor)
      std::stable_partition(order.begin(), order.end(), first_molar_or_incisor);
    const int diseased =
        molar_incisor ? static_cast<int>(std::count_if(order.begin(), order.end(),
                                                       first_molar_or_incisor))
        : c.extent == Extent::kLocalized
            // The whole mouth's healthy teeth lose no attachment (below), so a
            // localized case has 2 or more diseased teeth, under 30 % of them.
            ? (whole ? uniform(2, std::max(2, (3 * n - 1) / 10)) : 1)
            : std::max(1, uniform((n + 1) / 2, n));
    for (ObjectSpec& o : s.objects) {
      if (o.kind != ObjectSpec::Kind::kTooth && o.kind != ObjectSpec::Kind::kGingiva)
        continue;
      if (std::find(order.begin(), order.end(), o.fdi) == order.end()) continue;
      if (o.kind == ObjectSpec::Kind::kGingiva)
        continue;  // refreshed from the tooth below
      const bool sick = std::find(order.begin(), order.begin() + diseased, o.fdi) !=
                        order.begin() + diseased;
      o.has_sites = true;
      const double max_loss = MaxAttachmentLoss(Dimensions(FdiTooth::Parse(o.fdi)));
      for (int site = 0; site < 6; ++site) {
        double pd, rec;
        if (sick) {
          // Grade A in the whole mouth: the least loss the stage allows, so that
          // an older patient's bone loss over age can stay under 0.25.
          const int cal =
              IsInterdental(site)
                  ? uniform(cal_lo, whole && c.grade == Grade::kA ? cal_lo : cal_hi)
                  : uniform(1, std::min(cal_lo, 3));
          rec = uniform(
              0, 2);  // the scene's recession: 0 keeps the margin 1.5 mm above the CEJ
          // Charted CAL = pd + rec - 1.5 with the half rounding down = pd + rec - 2.
          pd = std::max(1, cal - static_cast<int>(rec) + 2);
          // Below stage III the whole mouth keeps its pockets under 6 mm: PD 6
          // at two non-adjacent teeth is stage III's complexity.
          if (whole && c.stage < Stage::kIII) pd = std::min(pd, 5.0);
        } else {
          // In the whole mouth a healthy tooth's interdental sulci are 1 or 2 mm
          // (a 3 mm sulcus is charted as 1 mm of attachment lost, and a healthy
          // mouth of those would be stage I everywhere).
          pd = whole && IsInterdental(site) ? uniform(1, 2) : uniform(1, 3);
          rec = 0;
        }
        pd = std::min(pd, std::floor(max_loss - rec));
        o.pocket_mm[site] = pd;
        o.recession_mm[site] = rec;
        o.bleeding[site] = sick ? uniform(0, 2) > 0 : uniform(0, 9) == 0;
      }
      if (patient) o.mobility = sick ? uniform(0, 1) : 0;
      if (whole) {
        // A diseased molar's furcation: class I at most below stage III
        // (class II or III would make it stage III).
        o.furcation.clear();
        const std::vector<std::string> entrances = FurcationEntrances(o.fdi);
        if (sick && !entrances.empty()) {
          const int hamp = uniform(0, c.stage >= Stage::kIII ? 2 : 1);
          if (hamp > 0)
            o.furcation[entrances[static_cast<std::size_t>(
                uniform(0, static_cast<int>(entrances.size()) - 1))]] = hamp;
        }
      }
    }
    if (patient) DrawPatient(c, order.front(), whole, uniform, &s);
    for (ObjectSpec& g : s.objects) {
      if (g.kind != ObjectSpec::Kind::kGingiva) continue;
      for (const ObjectSpec& t : s.objects)
        if (t.kind == ObjectSpec::Kind::kTooth && t.fdi == g.fdi) {
          g.pocket_mm = t.pocket_mm;
          g.recession_mm = t.recession_mm;
          g.bleeding = t.bleeding;
          g.has_sites = true;
        }
      if (g.trees.target_error_mm == 0) {
        g.trees.leaves = std::min(g.trees.leaves, kCaseGingivaLeaves);
        g.trees.spend = SphereTreeParams::Spend::kWorst;
        g.trees.tighten_passes = kCaseGingivaTightenPasses;
      }
    }
    if (whole && !patient) s.patient.teeth_lost_to_periodontitis = LostToPeriodontitis(s);
    const Diagnosis d = Classify2017(TrueChart(s, teeth));
    if (d.kind == Diagnosis::Kind::kPeriodontitis && d.stage == c.stage &&
        d.extent == c.extent && (c.grade == Grade::kNone || d.grade == c.grade))
      return s;
  }
  throw std::runtime_error(
      std::string("no case of stage ") + ToString(c.stage) + ", " + ToString(c.extent) +
      (c.grade == Grade::kNone ? std::string()
                               : std::string(", grade ") + ToString(c.grade)) +
      " can be drawn on these teeth (try another extent or grade, or more teeth)");
}

SceneSpec SaveCaseScene(const LessonSpec& lesson, const CaseSpec& c, std::uint64_t seed,
                        const fs::path& out) {
  const SceneSpec base = LoadSceneSpec(lesson.scene);
  const SceneSpec cased = ApplyCase(base, lesson.teeth, c, seed);
  YAML::Node root;
  try {
    root = YAML::LoadFile(lesson.scene.string());
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(lesson.scene.string() + ": " + e.what());
  }
  std::error_code ec;
  const fs::path from = fs::weakly_canonical(lesson.scene.parent_path(), ec);
  const fs::path to = fs::weakly_canonical(fs::absolute(out).parent_path(), ec);
  bool meshes = false;
  for (const YAML::Node& o : root["objects"])
    meshes |= o.IsMap() && o["mesh"].IsDefined();
  if (meshes && from != to)
    throw std::runtime_error(
        out.string() + ": " + lesson.scene.string() +
        " names mesh files relative to its folder; save the case in " + from.string());
  const std::string what =
      std::string("stage ") + ToString(c.stage) + ", " + ToString(c.extent) +
      (c.grade == Grade::kNone ? std::string()
                               : std::string(", grade ") + ToString(c.grade)) +
      ", seed " + std::to_string(seed);
  const std::string name =
      (base.name.empty() ? lesson.scene.stem().string() : base.name) + " (case: " + what +
      ")";
  root["name"] = name;
  root["description"] = "Periodontitis " + what + ", drawn by Sulcus on " +
                        lesson.scene.filename().string() + " for the lesson " +
                        lesson.file.filename().string() + ".";
  if (cased.patient.given) {
    const PatientFacts& p = cased.patient;
    YAML::Node n(YAML::NodeType::Map);
    n.SetStyle(YAML::EmitterStyle::Flow);
    if (p.age_years) n["age"] = *p.age_years;
    n["cigarettes_per_day"] = p.cigarettes_per_day;
    if (p.hba1c_pct) n["hba1c_pct"] = std::round(*p.hba1c_pct * 10) / 10;
    n["teeth_lost_to_periodontitis"] = p.teeth_lost_to_periodontitis;
    n["drifting_flaring"] = p.drifting_flaring;
    n["bite_collapse"] = p.bite_collapse;
    if (p.opposing_pairs) n["opposing_pairs"] = *p.opposing_pairs;
    root["patient"] = n;
  }
  // The gingiva's trees as the case is built (kCaseGingivaLeaves, on the
  // min-max cover tightened kCaseGingivaTightenPasses times), so that the
  // saved scene opens from the trees its lesson built.
  for (const ObjectSpec& g : cased.objects) {
    if (g.kind != ObjectSpec::Kind::kGingiva || g.trees.target_error_mm > 0) continue;
    YAML::Node trees = root["spheretree"];
    if (!trees || !trees.IsMap()) trees = YAML::Node(YAML::NodeType::Map);
    YAML::Node gt(YAML::NodeType::Map);
    gt.SetStyle(YAML::EmitterStyle::Flow);
    gt["levels"] = g.trees.levels;
    gt["branch"] = g.trees.branching;
    gt["leaves"] = g.trees.leaves;
    gt["spend"] = SpendName(g.trees.spend);
    gt["tighten_passes"] = g.trees.tighten_passes;
    trees["gingiva"] = gt;
    root["spheretree"] = trees;
    break;
  }
  // The teeth the case took out leave the objects, and every gap is listed
  // with the reason the case drew for it.
  if (!cased.missing.empty()) {
    YAML::Node objects(YAML::NodeType::Sequence);
    for (const YAML::Node& o : root["objects"])
      if (!(o.IsMap() && o["tooth"] && cased.missing.count(o["tooth"].as<int>(0))))
        objects.push_back(o);
    root["objects"] = objects;
    YAML::Node missing(YAML::NodeType::Map);
    missing.SetStyle(YAML::EmitterStyle::Flow);
    for (const auto& [fdi, m] : cased.missing) missing[fdi] = m.reason;
    root["missing"] = missing;
  }
  for (YAML::Node o : root["objects"]) {
    if (!o.IsMap() || !o["tooth"]) continue;
    const int fdi = o["tooth"].as<int>(0);
    if (std::find(lesson.teeth.begin(), lesson.teeth.end(), fdi) == lesson.teeth.end())
      continue;
    for (const ObjectSpec& t : cased.objects) {
      if (t.kind != ObjectSpec::Kind::kTooth || t.fdi != fdi) continue;
      YAML::Node pockets(YAML::NodeType::Sequence), recession(YAML::NodeType::Sequence),
          bleeding(YAML::NodeType::Sequence);
      for (int s = 0; s < 6; ++s) {
        pockets.push_back(t.pocket_mm[s]);
        recession.push_back(t.recession_mm[s]);
        if (t.bleeding[s]) bleeding.push_back(kSiteCodes[s]);
      }
      for (YAML::Node* n : {&pockets, &recession, &bleeding})
        n->SetStyle(YAML::EmitterStyle::Flow);
      o["pockets_mm"] = pockets;
      o["recession_mm"] = recession;
      if (bleeding.size() > 0)
        o["bleeding"] = bleeding;
      else
        o.remove("bleeding");
      if (t.mobility > 0)
        o["mobility"] = t.mobility;
      else
        o.remove("mobility");
      if (!t.furcation.empty()) {
        YAML::Node f(YAML::NodeType::Map);
        f.SetStyle(YAML::EmitterStyle::Flow);
        for (const auto& [entrance, hamp] : t.furcation) f[entrance] = hamp;
        o["furcation"] = f;
      } else {
        o.remove("furcation");
      }
    }
  }
  YAML::Emitter e;
  e << root;
  const fs::path tmp = fs::path(out).concat(".tmp");
  {
    std::ofstream f(tmp);
    f << "# " << name << "\n"
      << "# A generated periodontitis case (" << what << ") written by Sulcus from\n"
      << "# " << lesson.scene.filename().string() << "; the lesson "
      << lesson.file.filename().string() << " draws the same case from the same seed.\n"
      << e.c_str() << "\n";
    if (!f.flush()) throw std::runtime_error(tmp.string() + ": cannot write the scene");
  }
  fs::rename(tmp, out, ec);
  if (ec)
    throw std::runtime_error(out.string() + ": cannot write the scene: " + ec.message());
  // Read back: the file must give the chart that was drawn.
  SceneSpec back = LoadSceneSpec(out);
  const PerioChart want = TrueChart(cased, lesson.teeth),
                   got = TrueChart(back, lesson.teeth);
  for (std::size_t t = 0; t < want.teeth.size(); ++t)
    for (int s = 0; s < kSitesPerTooth; ++s) {
      const auto& a = want.teeth[t].sites[s];
      const auto& b = t < got.teeth.size() ? got.teeth[t].sites[s] : a;
      if (t >= got.teeth.size() || a.pd_mm != b.pd_mm ||
          a.recession_mm != b.recession_mm || a.bleeding != b.bleeding ||
          want.teeth[t].mobility != got.teeth[t].mobility ||
          want.teeth[t].furcation != got.teeth[t].furcation ||
          want.teeth[t].present != got.teeth[t].present ||
          want.teeth[t].fdi != got.teeth[t].fdi)
        throw std::runtime_error(
            out.string() +
            ": the saved scene does not read back as the drawn case (tooth " +
            std::to_string(want.teeth[t].fdi) + ")");
    }
  return back;
}

}  // namespace sulcus
