#include "core/lesson/answers.h"

#include <fstream>
#include <sstream>

#include "core/scene/yaml_reader.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

std::optional<DeclaredDiagnosis> ReadDiagnosis(YamlReader& r, const YAML::Node& n) {
  if (!r.IsMap(n, "'diagnosis'")) return std::nullopt;
  r.CheckKeys(n, {"periodontitis", "stage", "extent", "tick"}, "'diagnosis'");
  DeclaredDiagnosis d;
  if (n["periodontitis"]) {
    bool v = true;
    if (!n["periodontitis"].IsScalar() || !YAML::convert<bool>::decode(n["periodontitis"], v))
      r.Error(n["periodontitis"], "'periodontitis' must be true or false");
    d.periodontitis = v;
  }
  if (d.periodontitis) {
    if (!n["stage"] || !n["extent"]) {
      r.Error(n, "a periodontitis diagnosis needs 'stage' (I, II, III, IV) and 'extent' (localized, generalized)");
      return std::nullopt;
    }
    const std::string st = r.Text(n["stage"], "stage"), ex = r.Text(n["extent"], "extent");
    const auto stage = StageFromString(st);
    const auto extent = ExtentFromString(ex);
    if (!stage || *stage == Stage::kNone) r.Error(n["stage"], "'stage' must be I, II, III or IV, not '" + st + "'");
    if (!extent || *extent == Extent::kNone)
      r.Error(n["extent"], "'extent' must be localized or generalized" + Suggest(ex, {"localized", "generalized"}));
    if (stage) d.stage = *stage;
    if (extent) d.extent = *extent;
  }
  if (n["tick"]) d.tick = static_cast<std::uint64_t>(r.Number(n["tick"], "tick", 0, 1e15, 0));
  return d;
}

}  // namespace

Answers LoadAnswers(const fs::path& file) {
  YamlReader r(file);
  Answers a;
  const YAML::Node root = LoadYamlMap(r, "answers file", "an answers file is a map with 'chart:' or 'entries:', and 'diagnosis:'");
  r.CheckKeys(root, {"chart", "entries", "diagnosis"}, "the answers");
  if (const YAML::Node chart = root["chart"]; chart && r.IsMap(chart, "'chart'")) {
    for (auto it = chart.begin(); it != chart.end(); ++it) {
      const int fdi = r.Integer(it->first, "tooth", 11, 48, 0);
      const YAML::Node t = it->second;
      if (!r.IsMap(t, "a tooth's chart")) continue;
      r.CheckKeys(t, {"pd", "bleeding"}, "a tooth's chart");
      double pd[6] = {0, 0, 0, 0, 0, 0};
      const bool have_pd = t["pd"] && r.Numbers(t["pd"], "pd", 6, 0, 15, pd, "mm", "depths at MB, B, DB, ML, L, DL");
      std::array<bool, 6> bled{};
      if (const YAML::Node b = t["bleeding"]) {
        if (!b.IsSequence()) r.Error(b, "'bleeding' must be a list of sites, e.g. [MB, DL]");
        else
          for (const YAML::Node& s : b) {
            const int site = s.IsScalar() ? SiteFromCode(s.Scalar()) : -1;
            if (site < 0) r.Error(s, "unknown site '" + (s.IsScalar() ? s.Scalar() : "") + "' (MB, B, DB, ML, L, DL)");
            else bled[static_cast<std::size_t>(site)] = true;
          }
      }
      for (int s = 0; s < 6; ++s) {
        ChartEntry e;
        e.site = {fdi, s};
        if (have_pd) {
          if (pd[s] != std::floor(pd[s])) r.Error(t["pd"][s], "depths are whole millimetres");
          e.pd_mm = static_cast<int>(pd[s]);
        }
        e.bleeding = bled[static_cast<std::size_t>(s)];
        if (have_pd || e.bleeding) a.entries.push_back(e);
      }
    }
  }
  if (const YAML::Node entries = root["entries"]) {
    if (!entries.IsSequence()) {
      r.Error(entries, "'entries' must be a list of {site: \"46 DB\", pd: 5, bleeding: true, tick: 1234}");
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
        e.site.site = SiteFromCode(code);
        if (n["pd"]) e.pd_mm = r.Integer(n["pd"], "pd", 0, 15, 0);
        if (n["bleeding"]) {
          bool v = false;
          if (!n["bleeding"].IsScalar() || !YAML::convert<bool>::decode(n["bleeding"], v))
            r.Error(n["bleeding"], "'bleeding' must be true or false");
          e.bleeding = v;
        }
        if (n["tick"]) e.tick = static_cast<std::uint64_t>(r.Number(n["tick"], "tick", 0, 1e15, 0));
        a.entries.push_back(e);
      }
    }
  }
  if (root["diagnosis"]) a.diagnosis = ReadDiagnosis(r, root["diagnosis"]);
  if (!r.errors().empty()) throw SceneLoadError(r.errors());
  return a;
}

void SaveAnswers(const Answers& a, const fs::path& file) {
  std::ostringstream o;
  o << "# What the student entered, with the tick of each entry (sulcus-cli lesson report reads it).\n";
  o << "entries:\n";
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
    if (d.periodontitis) o << ", stage: " << ToString(d.stage) << ", extent: " << ToString(d.extent);
    if (d.tick != kAfterReading) o << ", tick: " << d.tick;
    o << "}\n";
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
