#include "core/lesson/answers.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/anatomy/soft_tissue.h"
#include "core/anatomy/tooth.h"
#include "core/base/yaml_reader.h"
#include "core/lesson/read_diagnosis.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

std::optional<DeclaredDiagnosis> ReadDiagnosis(YamlReader& r, const YAML::Node& n) {
  if (!r.IsMap(n, "'diagnosis'")) return std::nullopt;
  r.CheckKeys(n, {"periodontitis", "stage", "extent", "grade", "tick"}, "'diagnosis'");
  DeclaredDiagnosis d;
  if (n["periodontitis"])
    d.periodontitis = r.Bool(n["periodontitis"], "periodontitis", true);
  if (d.periodontitis) {
    if (!n["stage"] || !n["extent"]) {
      r.Error(n,
              "a periodontitis diagnosis needs 'stage' (I, II, III, IV) and 'extent' "
              "(localized, generalized, molar-incisor)");
      return std::nullopt;
    }
    if (const auto stage = ReadStage(r, n["stage"])) d.stage = *stage;
    const std::string ex = r.Text(n["extent"], "extent");
    const auto extent = ExtentFromString(ex);
    if (!extent || *extent == Extent::kNone)
      r.Error(n["extent"],
              "unknown extent '" + ex + "'" +
                  Suggest(ex, {"localized", "generalized", "molar-incisor"}));
    if (extent) d.extent = *extent;
    if (n["grade"])
      if (const auto grade = ReadGrade(r, n["grade"])) d.grade = *grade;
  }
  if (n["tick"])
    d.tick = static_cast<std::uint64_t>(r.Number(n["tick"], "tick", 0, 1e15, 0));
  return d;
}

// One line of `findings:`; a caries list gives one finding per surface.
void ReadFinding(YamlReader& r, const YAML::Node& n, std::vector<Finding>* out) {
  if (!r.IsMap(n, "a finding")) return;
  r.CheckKeys(n,
              {"tooth", "caries", "calculus", "inflamed", "status", "region", "lesion",
               "present", "tick"},
              "a finding");
  Finding f;
  if (n["tick"])
    f.tick = static_cast<std::uint64_t>(r.Number(n["tick"], "tick", 0, 1e15, 0));
  if (n["present"]) f.present = r.Bool(n["present"], "present", true);
  int kinds = 0;
  for (const char* k : {"caries", "calculus", "inflamed", "status", "lesion"})
    kinds += n[k] ? 1 : 0;
  if (kinds != 1) {
    r.Error(n,
            "a finding is one of: {tooth: 36, caries: [O, B]}, {tooth: 16, calculus: "
            "true}, {tooth: 31, inflamed: "
            "true}, {tooth: 24, status: 3} or {region: tongue_dorsum, lesion: ulcer}");
    return;
  }
  if (n["lesion"]) {
    f.kind = Finding::Kind::kLesion;
    f.lesion = r.Text(n["lesion"], "lesion");
    const auto& kinds_known = LesionKinds();
    if (std::find(kinds_known.begin(), kinds_known.end(), f.lesion) == kinds_known.end())
      r.Error(n["lesion"],
              "unknown lesion '" + f.lesion + "'" + Suggest(f.lesion, kinds_known));
    if (!n["region"]) {
      r.Error(n, "a lesion needs its 'region', e.g. tongue_lateral_border_left");
      return;
    }
    f.region = r.Text(n["region"], "region");
    const auto& regions = InspectionRegionNames();
    if (std::find(regions.begin(), regions.end(), f.region) == regions.end())
      r.Error(n["region"],
              "unknown region '" + f.region + "'" + Suggest(f.region, regions));
    out->push_back(f);
    return;
  }
  if (n["region"])
    r.Error(n["region"], "'region' goes with 'lesion'; tooth findings name a 'tooth'");
  if (!n["tooth"]) {
    r.Error(n, "a tooth finding needs 'tooth', an FDI number");
    return;
  }
  f.fdi = r.Integer(n["tooth"], "tooth", 11, 48, 0);
  if (n["calculus"] || n["inflamed"]) {
    const char* key = n["calculus"] ? "calculus" : "inflamed";
    f.kind = n["calculus"] ? Finding::Kind::kCalculus : Finding::Kind::kInflamed;
    if (!r.Bool(n[key], key, true)) f.present = false;
    out->push_back(f);
  } else if (n["status"]) {
    f.kind = Finding::Kind::kStatus;
    f.status = r.Integer(n["status"], "status", 0, 9, 0);
    out->push_back(f);
  } else {
    f.kind = Finding::Kind::kCaries;
    const YAML::Node c = n["caries"];
    std::vector<YAML::Node> items;
    if (c.IsSequence())
      for (const YAML::Node& i : c) items.push_back(i);
    else
      items.push_back(c);
    for (const YAML::Node& i : items) {
      const auto surface = SurfaceFromCode(i.IsScalar() ? i.Scalar() : "");
      if (!surface) {
        r.Error(i, "unknown surface '" + (i.IsScalar() ? i.Scalar() : "") +
                       "' (M, D, B, L, O)");
        continue;
      }
      f.surface = *surface;
      out->push_back(f);
    }
  }
}

// One line of `views:`.
void ReadView(YamlReader& r, const YAML::Node& n, std::vector<ViewSample>* out) {
  if (!r.IsMap(n, "a view")) return;
  r.CheckKeys(n, {"tick", "eye", "at", "up", "angle"}, "a view");
  for (const char* k : {"tick", "eye", "at"})
    if (!n[k]) {
      r.Error(n, std::string("a view needs '") + k + "'");
      return;
    }
  ViewSample v;
  v.tick = static_cast<std::uint64_t>(r.Number(n["tick"], "tick", 0, 1e15, 0));
  double xyz[3] = {0, 0, 0};
  if (r.Numbers(n["eye"], "eye", 3, -1e4, 1e4, xyz, "mm", "x, y, z"))
    v.eye = Vector3(xyz[0], xyz[1], xyz[2]);
  if (r.Numbers(n["at"], "at", 3, -1e4, 1e4, xyz, "mm", "x, y, z"))
    v.focal = Vector3(xyz[0], xyz[1], xyz[2]);
  if (n["up"] && r.Numbers(n["up"], "up", 3, -1, 1, xyz, "", "x, y, z"))
    v.up = Vector3(xyz[0], xyz[1], xyz[2]);
  if (n["angle"]) v.view_angle_deg = r.Number(n["angle"], "angle", 1, 170, 30, "degrees");
  out->push_back(v);
}

// An FDI number of a permanent tooth, or an error at `n` saying why not.
int ReadTooth(YamlReader& r, const YAML::Node& n, int fdi) {
  try {
    FdiTooth::Parse(fdi);
    return fdi;
  } catch (const std::invalid_argument& e) {
    r.Error(n, e.what());
    return 0;
  }
}

// More entries than any examination makes (32 teeth, 6 sites, each corrected
// many times over): a file this long is not a student's chart.
constexpr std::size_t kMaxEntries = 10000;

}  // namespace

Answers LoadAnswers(const fs::path& file) {
  YamlReader r(file, "answers file");
  Answers a;
  a.file = file;
  // Each site's first entry: its line and whether it had a tick.
  std::map<std::pair<int, int>, std::pair<int, bool>> given;
  auto add = [&](const ChartEntry& e, const YAML::Node& at) {
    const auto key = std::pair(e.site.fdi, e.site.site);
    const int line = at.Mark().line + 1;
    const bool tick = e.tick != kAfterReading;
    if (const auto it = given.find(key); it != given.end()) {
      if (!tick || !it->second.second) {
        r.Error(at, "site " + e.site.ToString() + " is given twice (first at line " +
                        std::to_string(it->second.first) +
                        "); give it once, or give each entry its tick (a later "
                        "entry is then a correction)");
        return;
      }
    } else {
      given[key] = {line, tick};
    }
    a.entries.push_back(e);
    a.entry_at.emplace_back(line, at.Mark().column + 1);
  };
  const YAML::Node root = LoadYamlMap(
      r, "an answers file is a map with 'chart:' or 'entries:', and 'diagnosis:'");
  r.CheckKeys(root, {"chart", "entries", "diagnosis", "findings", "submitted", "views"},
              "the answers");
  if (const YAML::Node vs = root["views"]) {
    if (!vs.IsSequence())
      r.Error(vs,
              "'views' must be a list of {tick: N, eye: [x, y, z], at: [x, y, z], up: "
              "[x, y, z], angle: deg}");
    else
      for (const YAML::Node& n : vs) ReadView(r, n, &a.views);
  }
  if (const YAML::Node fs = root["findings"]) {
    if (!fs.IsSequence())
      r.Error(fs,
              "'findings' must be a list, e.g. [{tooth: 36, caries: [O]}, {region: "
              "tongue_dorsum, lesion: ulcer}]");
    else
      for (const YAML::Node& n : fs) ReadFinding(r, n, &a.findings);
  }
  if (const YAML::Node sub = root["submitted"]) {
    bool b = false;
    if (sub.IsScalar() && YAML::convert<bool>::decode(sub, b)) {
      if (b) a.submitted = kAfterReading;
    } else {
      a.submitted = static_cast<std::uint64_t>(r.Number(sub, "submitted", 0, 1e15, 0));
    }
  }
  if (const YAML::Node chart = root["chart"]; chart && r.IsMap(chart, "'chart'")) {
    r.CheckUnique(chart, "'chart' (a tooth)");
    std::set<int> charted;
    for (auto it = chart.begin(); it != chart.end(); ++it) {
      int fdi = r.Integer(it->first, "tooth", 11, 48, 0);
      if (fdi) fdi = ReadTooth(r, it->first, fdi);
      if (fdi && !charted.insert(fdi).second) continue;  // CheckUnique said so
      const YAML::Node t = it->second;
      if (!r.IsMap(t, "a tooth's chart")) continue;
      r.CheckKeys(t, {"pd", "bleeding"}, "a tooth's chart");
      double pd[6] = {0, 0, 0, 0, 0, 0};
      const bool have_pd = t["pd"] && r.Numbers(t["pd"], "pd", 6, 1, 15, pd, "mm",
                                                "depths at MB, B, DB, ML, L, DL");
      std::array<bool, 6> bled{};
      if (const YAML::Node b = t["bleeding"]) {
        if (!b.IsSequence())
          r.Error(b, "'bleeding' must be a list of sites, e.g. [MB, DL]");
        else
          for (const YAML::Node& s : b) {
            const int site = s.IsScalar() ? SiteFromCode(s.Scalar()) : -1;
            if (site < 0)
              r.Error(s, "unknown site '" + (s.IsScalar() ? s.Scalar() : "") +
                             "' (MB, B, DB, ML, L, DL)");
            else
              bled[static_cast<std::size_t>(site)] = true;
          }
      }
      for (int s = 0; s < 6; ++s) {
        ChartEntry e;
        e.site = {fdi, s};
        if (have_pd) {
          if (pd[s] != std::floor(pd[s]))
            r.Error(t["pd"][s], "depths are whole millimetres");
          e.pd_mm = static_cast<int>(pd[s]);
        }
        e.bleeding = bled[static_cast<std::size_t>(s)];
        if (have_pd || e.bleeding) add(e, have_pd ? t["pd"][s] : it->first);
      }
    }
  }
  if (const YAML::Node entries = root["entries"]) {
    if (!entries.IsSequence()) {
      r.Error(entries,
              "'entries' must be a list of {site: \"46 DB\", pd: 5, bleeding: true, "
              "tick: 1234}");
    } else if (entries.size() > kMaxEntries) {
      r.Error(entries, "'entries' holds " + std::to_string(entries.size()) +
                           " entries; an answers file holds at most " +
                           std::to_string(kMaxEntries));
    } else {
      for (const YAML::Node& n : entries) {
        if (!r.IsMap(n, "an entry")) continue;
        r.CheckKeys(n, {"site", "pd", "bleeding", "tick"}, "an entry");
        ChartEntry e;
        if (!n["site"]) {
          r.Error(n, "an entry needs 'site', e.g. \"46 DB\"");
          continue;
        }
        std::istringstream s(r.Text(n["site"], "site"));
        std::string code;
        if (!(s >> e.site.fdi >> code) || SiteFromCode(code) < 0) {
          r.Error(n["site"], "a site is a tooth and a site code, e.g. \"46 DB\"");
          continue;
        }
        if (!ReadTooth(r, n["site"], e.site.fdi)) continue;
        e.site.site = SiteFromCode(code);
        if (n["pd"]) {
          if (const int pd = r.Integer(n["pd"], "pd", 1, 15, 0)) e.pd_mm = pd;
        }
        if (n["bleeding"]) e.bleeding = r.Bool(n["bleeding"], "bleeding", false);
        if (n["tick"])
          e.tick = static_cast<std::uint64_t>(r.Number(n["tick"], "tick", 0, 1e15, 0));
        add(e, n["site"]);
      }
    }
  }
  if (root["diagnosis"]) a.diagnosis = ReadDiagnosis(r, root["diagnosis"]);
  r.ThrowIfErrors();
  return a;
}

void CheckAnswersFor(const Answers& answers, const std::vector<int>& lesson_teeth) {
  std::vector<ErrorAt> errors;
  const std::string teeth = Join(lesson_teeth);
  for (std::size_t i = 0; i < answers.entries.size(); ++i) {
    const int fdi = answers.entries[i].site.fdi;
    if (std::find(lesson_teeth.begin(), lesson_teeth.end(), fdi) != lesson_teeth.end())
      continue;
    const auto [line, column] =
        i < answers.entry_at.size() ? answers.entry_at[i] : std::pair(0, 0);
    errors.push_back({answers.file.string(), line, column,
                      "tooth " + std::to_string(fdi) +
                          " is not in the lesson (its teeth: " + teeth + ")"});
  }
  if (!errors.empty()) throw LoadError("answers file", std::move(errors));
}

void SaveAnswers(const Answers& a, const fs::path& file) {
  std::ostringstream o;
  o << "# What the student entered, with the tick of each entry (sulcus-cli lesson "
       "report reads it).\n";
  o << (a.entries.empty() ? "entries: []\n" : "entries:\n");
  for (const ChartEntry& e : a.entries) {
    o << "  - {site: \"" << e.site.ToString() << "\"";
    if (e.pd_mm) o << ", pd: " << *e.pd_mm;
    o << ", bleeding: " << (e.bleeding ? "true" : "false");
    if (e.tick != kAfterReading) o << ", tick: " << e.tick;
    o << "}\n";
  }
  if (a.diagnosis) {
    const DeclaredDiagnosis& d = *a.diagnosis;
    o << "diagnosis: {periodontitis: " << (d.periodontitis ? "true" : "false");
    if (d.periodontitis)
      o << ", stage: " << ToString(d.stage) << ", extent: " << ToString(d.extent);
    if (d.periodontitis && d.grade != Grade::kNone) o << ", grade: " << ToString(d.grade);
    if (d.tick != kAfterReading) o << ", tick: " << d.tick;
    o << "}\n";
  }
  if (!a.findings.empty()) o << "findings:\n";
  for (const Finding& f : a.findings) {
    o << "  - {";
    switch (f.kind) {
      case Finding::Kind::kLesion:
        o << "region: " << f.region << ", lesion: " << f.lesion;
        break;
      case Finding::Kind::kCaries:
        o << "tooth: " << f.fdi << ", caries: " << SurfaceCode(f.surface);
        break;
      case Finding::Kind::kCalculus:
        o << "tooth: " << f.fdi << ", calculus: true";
        break;
      case Finding::Kind::kInflamed:
        o << "tooth: " << f.fdi << ", inflamed: true";
        break;
      case Finding::Kind::kStatus:
        o << "tooth: " << f.fdi << ", status: " << f.status;
        break;
    }
    if (!f.present) o << ", present: false";
    if (f.tick != kAfterReading) o << ", tick: " << f.tick;
    o << "}\n";
  }
  if (a.submitted) {
    if (*a.submitted == kAfterReading)
      o << "submitted: true\n";
    else
      o << "submitted: " << *a.submitted << "\n";
  }
  if (!a.views.empty()) o << "views:\n";
  char line[256];
  for (const ViewSample& v : a.views) {
    std::snprintf(line, sizeof line,
                  "  - {tick: %llu, eye: [%.3f, %.3f, %.3f], at: [%.3f, %.3f, %.3f], up: "
                  "[%.4f, %.4f, %.4f], angle: %.2f}\n",
                  static_cast<unsigned long long>(v.tick), v.eye.x(), v.eye.y(),
                  v.eye.z(), v.focal.x(), v.focal.y(), v.focal.z(), v.up.x(), v.up.y(),
                  v.up.z(), v.view_angle_deg);
    o << line;
  }
  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << o.str();
    if (!out) throw std::runtime_error(file.string() + ": cannot write the answers");
  }
  fs::rename(tmp, file);
}

}  // namespace sulcus
