#include "core/lesson/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "core/base/files.h"
#include "core/base/text.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

// HTML text: the markup characters escaped, a newline as a space.
std::string H(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '"':
        o += "&quot;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '&':
        o += "&amp;";
        break;
      case '\n':
        o += " ";
        break;
      default:
        o += c;
    }
  }
  return o;
}
std::string J(const std::string& s) { return JsonQuote(s); }
std::string Num(double v, int digits = 3) {
  if (!std::isfinite(v)) return "null";
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}
std::string F(const char* fmt, auto... a) {
  char b[256];
  std::snprintf(b, sizeof b, fmt, a...);
  return b;
}

std::string DxJson(const Diagnosis& d) {
  std::string s =
      "{\"kind\": " + J(ToString(d.kind)) + ", \"stage\": " + J(ToString(d.stage)) +
      ", \"extent\": " + J(ToString(d.extent)) + ", \"grade\": " + J(ToString(d.grade)) +
      ", \"summary\": " + J(d.Summary()) + ", \"bop_pct\": " + Num(d.bop_pct, 1) +
      ", \"worst_interdental_cal_mm\": " + std::to_string(d.worst_interdental_cal_mm) +
      ", \"extent_pct\": " + Num(d.extent_pct, 1) + ", \"path\": [";
  for (std::size_t i = 0; i < d.path.size(); ++i) s += (i ? ", " : "") + J(d.path[i]);
  return s + "]}";
}

std::string Opt(const std::optional<double>& v, int digits) {
  return v ? Num(*v, digits) : "null";
}

std::string CalibrationJson(const Agreement& g) {
  auto bias = [](const Bias& b) {
    return "{\"sites\": " + std::to_string(b.sites) +
           ", \"mean_mm\": " + Opt(b.mean_mm(), 3) + "}";
  };
  return "{\"sites\": " + std::to_string(g.sites) +
         ", \"exact_pct\": " + Num(g.exact_pct, 1) +
         ", \"within_1mm_pct\": " + Num(g.within_1mm_pct, 1) +
         ", \"depth_kappa\": " + Opt(g.depth_kappa, 3) +
         ", \"bleeding_kappa\": " + Opt(g.bleeding_kappa, 3) +
         ", \"meets_target\": " + (g.MeetsTarget() ? "true" : "false") +
         ", \"bias\": {\"all\": " + bias(g.all) +
         ", \"interdental\": " + bias(g.interdental) + ", \"mid\": " + bias(g.mid) +
         ", \"posterior\": " + bias(g.posterior) + ", \"anterior\": " + bias(g.anterior) +
         ", \"deep\": " + bias(g.deep) + ", \"shallow\": " + bias(g.shallow) + "}}";
}

// The chart as an examiner's calibration reads it: agreement, kappa, bias by
// kind of site, and whether the clinical target is met.
std::string CalibrationHtml(const Agreement& g, const std::string& against = "the truth",
                            const char* minus = "true") {
  std::ostringstream o;
  o << "<h2>Calibration against " << H(against) << "</h2>\n";
  if (g.sites == 0) {
    o << "<p class=meta>No site charted: nothing to compare.</p>\n";
    return o.str();
  }
  auto kappa = [](const std::optional<double>& k) {
    return k ? Num(*k, 2) : std::string("- (every site the same)");
  };
  o << "<p>" << g.sites << " sites: exact " << Num(g.exact_pct, 0) << " %, within 1 mm "
    << Num(g.within_1mm_pct, 0) << " %; weighted kappa for depth " << kappa(g.depth_kappa)
    << ", kappa for bleeding " << kappa(g.bleeding_kappa) << ". Target (within 1 mm at "
    << "90 % of sites or more, weighted kappa above 0.6): <b>"
    << (g.MeetsTarget() ? "met" : "not met") << "</b>.</p>\n";
  o << "<table><tr><th>bias (charted minus " << minus << ")</th>";
  const std::pair<const char*, const Bias*> kinds[] = {
      {"interdental", &g.interdental},   {"mid-sites", &g.mid},
      {"posterior teeth", &g.posterior}, {"anterior teeth", &g.anterior},
      {"deep (5 mm or more)", &g.deep},  {"shallow", &g.shallow}};
  for (const auto& [name, b] : kinds) o << "<th>" << name << "</th>";
  o << "</tr><tr><th>mm (sites)</th>";
  for (const auto& [name, b] : kinds)
    o << "<td>" << (b->mean_mm() ? F("%+.2f", *b->mean_mm()) : std::string("-")) << " ("
      << b->sites << ")</td>";
  o << "</tr></table>\n";
  return o.str();
}

// Colour of a signed error in whole mm: green exact, amber 1 mm, red more.
const char* ErrorColour(int err) {
  return err == 0 ? "#3a9d4a" : std::abs(err) == 1 ? "#e0a020" : "#d03030";
}

// The teeth of a jaw in the chart's left-to-right order (the patient's right first).
std::vector<int> ChartOrder(const LessonResult& r, bool upper) {
  std::vector<int> teeth;
  for (const ToothChart& t : r.true_chart.teeth)
    if ((t.fdi / 10 <= 2) == upper) teeth.push_back(t.fdi);
  auto rank = [](int fdi) {
    const int q = fdi / 10, p = fdi % 10;
    return (q == 1 || q == 4) ? 10 - p : 10 + p;
  };
  std::sort(teeth.begin(), teeth.end(), [&](int a, int b) { return rank(a) < rank(b); });
  return teeth;
}

// The three sites of a surface in the chart's cell order (distal, middle,
// mesial mirrored by quadrant: the cell nearest the midline is mesial).
std::array<int, 3> CellSites(int fdi, bool buccal) {
  const bool right = fdi / 10 == 1 || fdi / 10 == 4;
  if (buccal) return right ? std::array{2, 1, 0} : std::array{0, 1, 2};
  return right ? std::array{5, 4, 3} : std::array{3, 4, 5};
}

const SiteResult* FindSite(const LessonResult& r, int fdi, int site) {
  for (const SiteResult& s : r.sites)
    if (s.site.fdi == fdi && s.site.site == site) return &s;
  return nullptr;
}

std::string Seconds(const LessonResult& r, std::uint64_t tick) {
  return F("%.2f", static_cast<double>(tick) / r.rate_hz);
}

// One band of the chart: rows of truth, entry, reached, recession, CAL, bleeding.
std::string ChartBand(const LessonResult& r, bool upper, bool buccal) {
  const std::vector<int> teeth = ChartOrder(r, upper);
  if (teeth.empty()) return "";
  std::ostringstream o;
  o << "<table class=chart><caption>" << (upper ? "upper " : "lower ")
    << (buccal ? "buccal" : (upper ? "palatal" : "lingual")) << "</caption><tr><th></th>";
  for (int t : teeth) {
    const ToothChart* c = r.true_chart.Find(t);
    o << "<th colspan=3>" << t << (c && !c->present ? " missing" : "") << "</th>";
  }
  o << "</tr>";
  auto row = [&](const char* label, auto cell) {
    o << "<tr><th>" << label << "</th>";
    for (int t : teeth)
      for (int s : CellSites(t, buccal)) o << cell(t, s);
    o << "</tr>";
  };
  auto red = [](std::optional<int> v) {
    if (!v) return std::string("<td class=none>-</td>");
    return std::string(*v >= 4 ? "<td class=deep>" : "<td>") + std::to_string(*v) +
           "</td>";
  };
  row("site",
      [&](int, int s) { return std::string("<td class=code>") + SiteCode(s) + "</td>"; });
  row("truth PD", [&](int t, int s) {
    const ToothChart* c = r.true_chart.Find(t);
    return red(c ? c->sites[s].pd_mm : std::nullopt);
  });
  row("entered PD", [&](int t, int s) {
    const SiteResult* x = FindSite(r, t, s);
    if (!x || !x->entry || !x->entry->pd_mm) return std::string("<td class=none>-</td>");
    const int err = *x->entry->pd_mm - x->truth_mm;
    return F(
        "<td style=\"background:%s;color:white\" title=\"entered %d, truth %d (%+d "
        "mm)\">%d</td>",
        ErrorColour(err), *x->entry->pd_mm, x->truth_mm, err, *x->entry->pd_mm);
  });
  row("reached", [&](int t, int s) {
    const SiteResult* x = FindSite(r, t, s);
    if (!x) return std::string("<td class=none>-</td>");
    if (!x->reached_mm)
      return "<td class=none title=\"no reading: " + H(x->no_reading) + "\">-</td>";
    return F("<td><a href=\"#t%llu\" title=\"at %s s\">%.1f</a></td>",
             static_cast<unsigned long long>(x->reading_tick),
             Seconds(r, x->reading_tick).c_str(), *x->reached_mm);
  });
  row("recession", [&](int t, int s) {
    const ToothChart* c = r.true_chart.Find(t);
    return c ? F("<td>%.1f</td>", c->sites[s].recession_mm) : std::string("<td>-</td>");
  });
  row("CAL (yours)", [&](int t, int s) {
    const ToothChart* c = r.student_chart.Find(t);
    return red(c ? c->sites[s].cal_mm() : std::nullopt);
  });
  row("bleeding", [&](int t, int s) {
    const SiteResult* x = FindSite(r, t, s);
    if (!x) return std::string("<td></td>");
    const bool marked = x->entry && x->entry->bleeding;
    const char* mark = x->bled && marked ? "&#9679;"
                       : x->bled         ? "&#9675;"
                       : marked          ? "&#215;"
                                         : "";
    const char* title = x->bled && marked ? "bled, charted"
                        : x->bled         ? "bled, not charted"
                        : marked          ? "charted, did not bleed"
                                          : "";
    return F("<td class=bleed title=\"%s\">%s</td>", title, mark);
  });
  o << "</table>";
  return o.str();
}

// The per-site signed error map: each site a cell coloured by entry - truth,
// with the technique error (reached - truth) beneath. Against a reference
// examiner's chart: entry - reference (over- and under-reading against the
// examiner), with the reference's own error (reference - truth) beneath.
std::string ErrorMap(const LessonResult& r, const PerioChart* reference = nullptr) {
  std::ostringstream o;
  const std::vector<int> lower = ChartOrder(r, false), upper = ChartOrder(r, true);
  const int cell = 32, gap = 8;
  int width = 0;
  for (const auto* teeth : {&upper, &lower})
    width = std::max<int>(width, static_cast<int>(teeth->size()) * (3 * cell + gap));
  const int rows = (upper.empty() ? 0 : 2) + (lower.empty() ? 0 : 2);
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width + 80
    << "\" height=\"" << rows * (2 * cell + 8) + 20
    << "\" font-family=\"sans-serif\" font-size=\"11\">";
  int y = 10;
  auto band = [&](const std::vector<int>& teeth, bool buccal, const char* label) {
    o << "<text x=\"0\" y=\"" << y + cell / 2 + 4 << "\">" << label << "</text>";
    for (std::size_t i = 0; i < teeth.size(); ++i) {
      const int x0 = 70 + static_cast<int>(i) * (3 * cell + gap);
      const std::array<int, 3> sites = CellSites(teeth[i], buccal);
      for (int c = 0; c < 3; ++c) {
        const SiteResult* s = FindSite(r, teeth[i], sites[c]);
        const int x = x0 + c * cell;
        if (!s) continue;
        std::string fill = "#cccccc", text = "?";
        std::optional<int> ref;
        if (reference)
          if (const ToothChart* t = reference->Find(teeth[i]))
            ref = t->sites[sites[c]].pd_mm;
        const std::optional<int> against = reference ? ref : std::optional(s->truth_mm);
        if (s->entry && s->entry->pd_mm && against) {
          const int err = *s->entry->pd_mm - *against;
          fill = ErrorColour(err);
          text = F("%+d", err);
        }
        o << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"" << cell - 2
          << "\" height=\"" << cell - 2 << "\" fill=\"" << fill << "\"><title>"
          << s->site.ToString()
          << (reference ? ": charted minus the reference examiner"
                        : ": charted minus truth")
          << "</title></rect>";
        o << "<text x=\"" << x + cell / 2 - 1 << "\" y=\"" << y + cell / 2 + 3
          << "\" fill=\"white\" text-anchor=\"middle\">" << text << "</text>";
        const std::string tech = reference ? (ref ? F("%+d", *ref - s->truth_mm) : "-")
                                 : s->reached_mm
                                     ? F("%+.1f", *s->reached_mm - s->truth_mm)
                                     : "-";
        o << "<text x=\"" << x + cell / 2 - 1 << "\" y=\"" << y + cell + 10
          << "\" text-anchor=\"middle\" fill=\"#555\">" << tech << "<title>"
          << s->site.ToString()
          << (reference ? ": the reference examiner minus truth"
                        : ": reached minus truth (technique)")
          << "</title></text>";
      }
      o << "<text x=\"" << x0 + cell * 3 / 2 << "\" y=\"" << y - 1
        << "\" text-anchor=\"middle\" font-weight=\"bold\">" << teeth[i] << "</text>";
    }
    y += 2 * cell + 8;
  };
  if (!upper.empty()) {
    band(upper, true, "upper B");
    band(upper, false, "upper P");
  }
  if (!lower.empty()) {
    band(lower, false, "lower L");
    band(lower, true, "lower B");
  }
  o << "</svg>";
  return o.str();
}

// A site's force while the tip was in it, against the band.
std::string ForceTrace(const LessonResult& r, const SiteResult& s,
                       const RubricSpec& band) {
  const std::uint64_t from = s.entered_tick,
                      to = std::max(s.left_tick, s.entered_tick + 1);
  std::vector<std::pair<std::uint64_t, float>> pts;
  for (const auto& p : r.force_trace)
    if (p.first >= from && p.first <= to) pts.push_back(p);
  const int w = 180, h = 60;
  double fmax = 0.6;
  for (const auto& p : pts) fmax = std::max(fmax, static_cast<double>(p.second));
  auto X = [&](std::uint64_t t) {
    return 2 + (w - 4) * static_cast<double>(t - from) / static_cast<double>(to - from);
  };
  auto Y = [&](double f) { return h - 2 - (h - 4) * f / fmax; };
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h
    << "\">";
  o << "<rect x=\"0\" y=\"0\" width=\"" << w << "\" height=\"" << h
    << "\" fill=\"#f6f6f6\"/>";
  o << "<rect x=\"0\" y=\"" << Num(Y(band.force_high_n), 1) << "\" width=\"" << w
    << "\" height=\"" << Num(Y(band.force_low_n) - Y(band.force_high_n), 1)
    << "\" fill=\"#cfe8cf\"><title>the band " << Num(band.force_low_n, 2) << "-"
    << Num(band.force_high_n, 2) << " N</title></rect>";
  o << "<line x1=\"0\" x2=\"" << w << "\" y1=\"" << Num(Y(band.force_damage_n), 1)
    << "\" y2=\"" << Num(Y(band.force_damage_n), 1)
    << "\" stroke=\"#d03030\" stroke-dasharray=\"3,2\"/>";
  if (!pts.empty()) {
    o << "<polyline fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"1.3\" points=\"";
    for (const auto& [t, f] : pts) o << Num(X(t), 1) << "," << Num(Y(f), 1) << " ";
    o << "\"/>";
  }
  o << "<line x1=\"" << Num(X(s.reading_tick), 1) << "\" x2=\""
    << Num(X(s.reading_tick), 1) << "\" y1=\"0\" y2=\"" << h
    << "\" stroke=\"#333\" stroke-width=\"0.8\"><title>deepest</title></line>";
  o << "</svg>";
  return o.str();
}

// A surface's sulcus arc, swept bins dark.
std::string CoverageArc(const SurfaceCoverage& c) {
  const int w = 120, h = 66;
  const double cx = w / 2.0, cy = c.buccal ? 60 : 6, r = 50;
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h
    << "\">";
  const int n = static_cast<int>(c.bins.size());
  for (int i = 0; i < n; ++i) {
    const double a0 = std::numbers::pi * (i + 0.1) / n,
                 a1 = std::numbers::pi * (i + 0.9) / n;
    const double s = c.buccal ? -1 : 1;
    o << "<line x1=\"" << Num(cx + r * std::cos(a0), 1) << "\" y1=\""
      << Num(cy + s * r * std::sin(a0), 1) << "\" x2=\"" << Num(cx + r * std::cos(a1), 1)
      << "\" y2=\"" << Num(cy + s * r * std::sin(a1), 1) << "\" stroke=\""
      << (c.bins[static_cast<std::size_t>(i)] ? "#1f5fa8" : "#e04040")
      << "\" stroke-width=\"7\"/>";
  }
  o << "</svg>";
  return o.str();
}

}  // namespace

std::string ReportJson(const LessonResult& r, const ReportInfo& info) {
  std::ostringstream o;
  o << "{\n  \"format\": \"sulcus-lesson-report 1\",\n";
  o << "  \"kind\": " << J(r.kind) << ",\n";
  o << "  \"lesson\": " << J(r.lesson_name)
    << ",\n  \"lesson_file\": " << J(r.lesson_file) << ",\n";
  if (r.kind == "inspection") {
    const InspectionResult& in = r.inspection;
    o << "  \"inspection\": {\"examined\": [";
    bool first = true;
    for (const InspectionUnit& u : in.units) {
      if (!u.touched) continue;
      o << (first ? "" : ", ") << "{\"unit\": " << J(u.Name())
        << ", \"tick\": " << u.first_tick << "}";
      first = false;
    }
    o << "],\n    \"not_examined\": [";
    first = true;
    for (const InspectionUnit& u : in.units) {
      if (u.touched) continue;
      o << (first ? "" : ", ") << J(u.Name());
      first = false;
    }
    o << "],\n    \"scores\": [";
    for (std::size_t i = 0; i < in.scores.size(); ++i) {
      const FindingScore& f = in.scores[i];
      o << (i ? ", " : "") << "{\"kind\": " << J(f.kind) << ", \"tp\": " << f.tp
        << ", \"fn\": " << f.fn << ", \"fp\": " << f.fp << ", \"tn\": " << f.tn
        << ", \"sensitivity\": " << Num(f.sensitivity(), 4)
        << ", \"specificity\": " << Num(f.specificity(), 4) << "}";
    }
    o << "],\n    \"findings\": [";
    for (std::size_t i = 0; i < in.findings.size(); ++i)
      o << (i ? ", " : "") << "{\"finding\": " << J(in.findings[i].ToString())
        << ", \"tick\": " << in.findings[i].tick << "}";
    o << "],\n    \"lesion_presses\": [";
    for (std::size_t i = 0; i < in.presses.size(); ++i)
      o << (i ? ", " : "") << "{\"where\": " << J(in.presses[i].where)
        << ", \"force_n\": " << Num(in.presses[i].force_n, 3)
        << ", \"tick\": " << in.presses[i].tick << "}";
    o << "]},\n";
  }
  o << "  \"scene_file\": " << J(r.scene_file) << ",\n  \"mode\": " << J(r.mode) << ",\n";
  o << "  \"student\": " << J(r.student) << ",\n  \"started\": " << J(info.started)
    << ",\n";
  o << "  \"attempt_id\": " << info.attempt_id
    << ",\n  \"recording\": " << J(info.recording) << ",\n";
  o << "  \"generated_case\": " << (r.generated_case ? "true" : "false")
    << ",\n  \"case_seed\": " << r.case_seed << ",\n";
  o << "  \"rate_hz\": " << Num(r.rate_hz, 1) << ",\n  \"first_tick\": " << r.first_tick
    << ",\n  \"last_tick\": " << r.last_tick
    << ",\n  \"duration_s\": " << Num(r.duration_s, 3) << ",\n";
  o << "  \"complete\": " << (r.complete ? "true" : "false")
    << ",\n  \"ended\": " << J(r.ended) << ",\n  \"interruptions\": [";
  for (std::size_t i = 0; i < r.interruptions.size(); ++i)
    o << (i ? ", " : "") << "{\"lost_tick\": " << r.interruptions[i].lost_tick
      << ", \"back_tick\": " << r.interruptions[i].back_tick << "}";
  o << "],\n";
  o << "  \"total\": " << Num(r.total, 2) << ",\n  \"pass_mark\": " << Num(r.pass_mark, 1)
    << ",\n  \"passed\": " << (r.total >= r.pass_mark ? "true" : "false")
    << ",\n  \"categories\": {";
  bool first = true;
  for (const auto& [cat, credit] : r.category_credit) {
    o << (first ? "" : ", ") << J(cat) << ": {\"credit\": " << Num(credit, 4)
      << ", \"weight\": " << Num(r.category_weight.at(cat), 2) << "}";
    first = false;
  }
  o << "},\n  \"summary\": {\"sites_total\": " << r.sites_total
    << ", \"sites_read\": " << r.sites_read << ", \"sites_charted\": " << r.sites_charted
    << ", \"within_1mm_pct\": " << Num(r.within_1mm_pct, 1)
    << ", \"exact_pct\": " << Num(r.exact_pct, 1)
    << ", \"bias_mm\": " << Num(r.bias_mm, 3)
    << ", \"bias_interdental_mm\": " << Num(r.bias_proximal_mm, 3)
    << ", \"force_in_band_pct\": " << Num(r.force_in_band_pct, 1) << "},\n";
  o << "  \"calibration\": " << CalibrationJson(r.agreement) << ",\n";
  if (r.reference_agreement)
    o << "  \"reference_calibration\": {\"reference\": " << JsonQuote(r.reference_name)
      << ", \"agreement\": " << CalibrationJson(*r.reference_agreement) << "},\n";
  o << "  \"diagnosis\": {\"truth\": " << DxJson(r.true_dx)
    << ",\n    \"chart\": " << DxJson(r.chart_dx) << ",\n    \"declared\": ";
  if (r.declared)
    o << "{\"summary\": " << J(r.declared->Summary())
      << ", \"periodontitis\": " << (r.declared->periodontitis ? "true" : "false")
      << ", \"stage\": " << J(ToString(r.declared->stage))
      << ", \"extent\": " << J(ToString(r.declared->extent))
      << ", \"grade\": " << J(ToString(r.declared->grade)) << "}";
  else
    o << "null";
  o << "},\n  \"sites\": [\n";
  for (std::size_t i = 0; i < r.sites.size(); ++i) {
    const SiteResult& s = r.sites[i];
    o << "    {\"site\": " << J(s.site.ToString()) << ", \"fdi\": " << s.site.fdi
      << ", \"code\": " << J(SiteCode(s.site.site)) << ", \"truth_mm\": " << s.truth_mm
      << ", \"recession_mm\": " << Num(s.recession_mm, 2)
      << ", \"reached_mm\": " << (s.reached_mm ? Num(*s.reached_mm, 3) : "null")
      << ", \"entered_mm\": "
      << (s.entry && s.entry->pd_mm ? std::to_string(*s.entry->pd_mm) : "null")
      << ", \"held_force_n\": " << Num(s.held_force_n, 3)
      << ", \"peak_force_n\": " << Num(s.peak_force_n, 3)
      << ", \"angle_deg\": " << Num(s.angle_deg, 2)
      << ", \"col_reached\": " << (s.col_reached ? "true" : "false")
      << ", \"interproximal_contact\": " << (s.interproximal_contact ? "true" : "false")
      << ", \"insertions\": " << s.insertions
      << ", \"no_reading\": " << (s.reached_mm ? std::string("null") : J(s.no_reading))
      << ", \"bled\": " << (s.bled ? "true" : "false")
      << ", \"bleeding_charted\": " << (s.entry && s.entry->bleeding ? "true" : "false")
      << ", \"reading_tick\": " << s.reading_tick
      << ", \"entry_tick\": " << (s.entry ? s.entry->tick : 0) << "}"
      << (i + 1 < r.sites.size() ? "," : "") << "\n";
  }
  o << "  ],\n  \"coverage\": [\n";
  for (std::size_t i = 0; i < r.coverage.size(); ++i) {
    const SurfaceCoverage& c = r.coverage[i];
    o << "    {\"fdi\": " << c.fdi
      << ", \"surface\": " << J(c.buccal ? "buccal" : "lingual")
      << ", \"swept\": " << Num(c.swept, 3)
      << ", \"touch_share\": " << Num(c.touch_share, 3) << ", \"strokes\": " << c.strokes
      << ", \"stroke_mm\": " << Num(c.stroke_mm, 2) << "}"
      << (i + 1 < r.coverage.size() ? "," : "") << "\n";
  }
  o << "  ],\n  \"steps\": [\n";
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    const StepResult& s = r.steps[i];
    o << "    {\"id\": " << J(s.id)
      << ", \"completed\": " << (s.completed ? "true" : "false")
      << ", \"timed_out\": " << (s.timed_out ? "true" : "false")
      << ", \"started_tick\": " << s.started_tick << ", \"ended_tick\": " << s.ended_tick
      << "}" << (i + 1 < r.steps.size() ? "," : "") << "\n";
  }
  o << "  ],\n  \"lines\": [\n";
  for (std::size_t i = 0; i < r.lines.size(); ++i) {
    const RubricLine& l = r.lines[i];
    o << "    {\"category\": " << J(l.category)
      << ", \"status\": " << J(ToString(l.status)) << ", \"credit\": " << Num(l.credit, 3)
      << ", \"site\": " << (l.site ? J(l.site->ToString()) : "null")
      << ", \"fdi\": " << l.fdi << ", \"tick\": " << l.tick
      << ", \"message\": " << J(l.message) << "}" << (i + 1 < r.lines.size() ? "," : "")
      << "\n";
  }
  o << "  ]\n}\n";
  return o.str();
}

namespace {

std::string Categories(const LessonResult& r) {
  std::ostringstream o;
  o << "<table class=cats><tr>";
  for (const auto& [cat, credit] : r.category_credit) o << "<th>" << H(cat) << "</th>";
  o << "</tr><tr>";
  for (const auto& [cat, credit] : r.category_credit)
    o << "<td>" << Num(100 * credit, 0)
      << " %<br><span class=bar style=\"width:" << Num(60 * credit, 0)
      << "px\"></span><br><small>weight " << Num(r.category_weight.at(cat), 0)
      << "</small></td>";
  o << "</tr></table>\n";
  return o.str();
}

// An inspection: the odontogram, truth beside what was recorded, surface by
// surface; what was examined; sensitivity and specificity per kind of finding.
std::string InspectionHtml(const LessonResult& r) {
  const InspectionResult& in = r.inspection;
  std::ostringstream o;
  o << "<h2>Findings</h2>\n<table><tr><th>kind</th><th>found</th><th>missed</"
       "th><th>false</th><th>sensitivity</th>"
       "<th>specificity</th></tr>";
  for (const FindingScore& s : in.scores)
    o << "<tr><th>" << H(s.kind) << "</th><td>" << s.tp << "</td><td>" << s.fn
      << "</td><td>" << s.fp << "</td><td>" << Num(100 * s.sensitivity(), 0)
      << " %</td><td>" << Num(100 * s.specificity(), 0) << " %</td></tr>";
  // Swatches with a text inside, so that they show in the window's report view too.
  auto swatch = [&](const char* colour, const char* what) {
    o << "<span style=\"background:" << colour << "\">&nbsp;&nbsp;&nbsp;</span>&nbsp;"
      << what << " &nbsp; ";
  };
  o << "</table>\n<h2>Odontogram</h2>\n<p>Each tooth's surfaces M D B L O: ";
  swatch("#9c2a1a", "caries recorded and true");
  swatch("#e0a020", "caries missed");
  swatch("#7a4fb0", "recorded, not there");
  swatch("#cfe3f5", "examined");
  o << "white: not examined. Ca calculus and G inflamed gingiva (recorded / true), then "
       "the WHO status (recorded / "
       "true).</p>\n<table>";
  auto examined = [&](const std::string& name) {
    for (const InspectionUnit& u : in.units)
      if (u.Name() == name) return u.touched;
    return false;
  };
  auto row = [&](bool upper) {
    o << "<tr>";
    for (const ToothRecord& t : in.truth.teeth) {
      if ((t.fdi / 10 <= 2) != upper) continue;
      const ToothRecord* rec = in.recorded.Find(t.fdi);
      o << "<td><b>" << t.fdi << "</b><br>";
      for (int s = 0; s < 5; ++s) {
        const std::string code = SurfaceCode(static_cast<ToothSurface>(s));
        const bool truth = t.caries[static_cast<std::size_t>(s)],
                   said = rec && rec->caries[static_cast<std::size_t>(s)];
        const char* bg = truth && said                                  ? "#9c2a1a"
                         : truth                                        ? "#e0a020"
                         : said                                         ? "#7a4fb0"
                         : examined(std::to_string(t.fdi) + " " + code) ? "#cfe3f5"
                                                                        : "#fff";
        o << "<span title=\"" << t.fdi << " " << code
          << "\" style=\"display:inline-block;width:13px;font-size:10px;"
          << "background:" << bg << ";color:" << (truth || said ? "#fff" : "#444")
          << "\">" << code << "</span>";
      }
      auto flag = [&](const char* name, bool truth, bool said) {
        if (!truth && !said) return;
        o << "<br><small style=\"color:" << (truth == said ? "#2a7a3a" : "#c02020")
          << "\">" << name << " " << (said ? "&#10003;" : "-") << "/"
          << (truth ? "&#10003;" : "-") << "</small>";
      };
      flag("Ca", t.calculus, rec && rec->calculus);
      flag("G", t.inflamed, rec && rec->inflamed);
      o << "<br><small>" << (rec ? rec->Status() : 0) << "/" << t.Status()
        << "</small></td>";
    }
    o << "</tr>";
  };
  row(true);
  row(false);
  auto seen = [&](const std::string& name) {
    for (const InspectionUnit& u : in.units)
      if (u.Name() == name) return u.seen;
    return false;
  };
  o << "</table>\n<h2>Soft "
       "tissues</h2>\n<table><tr><th>region</th><th>examined</th><th>in "
       "view</th><th>recorded</th>"
       "<th>truth</th></tr>";
  for (const std::string& g : in.regions) {
    const auto t = in.truth.lesions.find(g), s = in.recorded.lesions.find(g);
    o << "<tr><td style=\"text-align:left\">" << H(RegionLabel(g)) << "</td><td>"
      << (examined(g) ? "&#10003;" : "-") << "</td><td>"
      << (in.views.empty() ? "not recorded"
          : seen(g)        ? "&#10003;"
                           : "-")
      << "</td><td>" << H(s != in.recorded.lesions.end() ? s->second : "-") << "</td><td>"
      << H(t != in.truth.lesions.end() ? t->second : "-") << "</td></tr>";
  }
  o << "</table>\n";
  if (!in.presses.empty()) {
    o << "<h2>Lesions pressed too hard</h2>\n<ul>";
    for (const LesionPress& p : in.presses)
      o << "<li><a href=\"#t" << p.tick << "\">" << Seconds(r, p.tick)
        << " s</a>: " << H(p.where) << ", " << Num(p.force_n, 2) << " N</li>";
    o << "</ul>\n";
  }
  return o.str();
}

}  // namespace

std::string ReportHtml(const LessonResult& r, const ReportInfo& info) {
  const RubricSpec& band = r.rubric;  // the band the lesson scored against
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>"
    << H(r.lesson_name) << ": " << H(r.student)
    << "</title>\n<style>\n"
       "body{font-family:system-ui,sans-serif;margin:24px;color:#222;max-width:1100px}"
       "h1{font-size:22px;margin-bottom:4px}h2{font-size:17px;margin-top:28px;border-"
       "bottom:1px solid #ccc}"
       ".score{font-size:40px;font-weight:bold;color:#1f5fa8}.meta{color:#666}"
       "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid "
       "#ccc;padding:2px 5px;text-align:center;font-size:13px}"
       "table.chart caption{text-align:left;font-weight:bold;padding:4px "
       "0}td.deep{color:#d03030;font-weight:bold}"
       "td.none{color:#aaa}td.code{color:#777;font-size:11px}td.bleed{color:#d03030}"
       "table.lines td{text-align:left}tr.fail td.st{background:#f7d4d4}tr.partial "
       "td.st{background:#fbeacc}"
       "tr.pass td.st{background:#d8efd8}tr.info td.st{background:#e8e8f4}"
       ".cats td{min-width:70px}.bar{display:inline-block;height:10px;background:#1f5fa8}"
       ".sites{display:flex;flex-wrap:wrap;gap:10px}.site{border:1px solid "
       "#ddd;padding:4px;font-size:12px}"
       ".legend span{display:inline-block;width:12px;height:12px;margin:0 4px 0 "
       "12px;vertical-align:middle}"
       "</style></head><body>\n";
  o << "<h1>" << H(r.lesson_name) << "</h1>\n<div class=meta>" << H(r.student)
    << " &middot; " << H(r.mode) << " &middot; " << H(info.started) << " &middot; "
    << Num(r.duration_s, 1) << " s &middot; scene " << H(r.scene_file)
    << (r.generated_case ? " &middot; generated case, seed " + std::to_string(r.case_seed)
                         : "")
    << (info.attempt_id ? " &middot; attempt " + std::to_string(info.attempt_id) : "")
    << "</div>\n";
  if (!r.complete)
    o << "<p style=\"background:#fbeacc;padding:6px 10px;border-left:4px solid "
         "#d08a00\"><b>Incomplete attempt</b>: "
      << H(r.ended) << ". It is kept and scored as far as it went.</p>\n";
  o << "<p>" << (r.total >= r.pass_mark ? "Passed" : "Not passed")
    << ": the lesson passes at " << Num(r.pass_mark, 0) << " / 100.</p>\n";
  if (r.kind == "inspection") {
    o << "<p><span class=score>" << Num(r.total, 1) << "</span> / 100</p>\n"
      << Categories(r) << InspectionHtml(r);
  } else {
    o << "<p><span class=score>" << Num(r.total, 1) << "</span> / 100 &nbsp; "
      << r.sites_read << " of " << r.sites_total << " sites probed, " << r.sites_charted
      << " charted; within 1 mm of the truth " << Num(r.within_1mm_pct, 0) << " %, exact "
      << Num(r.exact_pct, 0) << " %; signed bias " << F("%+.2f", r.bias_mm)
      << " mm (interdental " << F("%+.2f", r.bias_proximal_mm)
      << " mm); force in the band at " << Num(r.force_in_band_pct, 0)
      << " % of sites.</p>\n";
    o << Categories(r);

    o << "<h2>Diagnosis (2017 "
         "classification)</h2>\n<table><tr><th></th><th>diagnosis</th><th>how</th></tr>";
    auto dx_row = [&](const char* who, const std::string& summary,
                      const std::vector<std::string>& path) {
      o << "<tr><th>" << who << "</th><td>" << H(summary)
        << "</td><td style=\"text-align:left\">";
      for (const std::string& p : path) o << H(p) << "<br>";
      o << "</td></tr>";
    };
    dx_row("the true chart", r.true_dx.Summary(), r.true_dx.path);
    dx_row("your chart", r.chart_dx.Summary(), r.chart_dx.path);
    dx_row("you declared", r.declared ? r.declared->Summary() : "nothing", {});
    o << "</table>\n";

    o << CalibrationHtml(r.agreement);
    if (r.reference_agreement) {
      o << CalibrationHtml(*r.reference_agreement,
                           "the reference examiner (" + r.reference_name + ")",
                           "the reference");
      o << "<p class=legend>Over- and under-reading against the reference examiner: "
           "charted minus the examiner's depth per site, with the examiner's own "
           "difference from the truth beneath:<span style=\"background:#3a9d4a\"></span>"
           "the same<span style=\"background:#e0a020\"></span>1 mm<span "
           "style=\"background:#d03030\"></span>2 mm or more</p>\n"
        << ErrorMap(r, &r.reference_chart) << "\n";
    }

    o << "<h2>Periodontal chart</h2>\n<p class=meta>Depths in mm; red at 4 mm and over. "
         "\"entered\" is coloured by its "
         "difference from the truth; \"reached\" is how deep the probe tip actually went "
         "(click for the moment); "
         "&#9679; bled and charted, &#9675; bled but not charted, &#215; charted but did "
         "not bleed.</p>\n";
    o << ChartBand(r, true, true) << ChartBand(r, true, false)
      << ChartBand(r, false, false) << ChartBand(r, false, true);

    o << "<h2>Error map</h2>\n<p class=legend>Charted minus true depth per site, with "
         "the technique error (reached minus "
         "true) beneath:<span style=\"background:#3a9d4a\"></span>exact<span "
         "style=\"background:#e0a020\"></span>1 mm"
         "<span style=\"background:#d03030\"></span>2 mm or more</p>\n"
      << ErrorMap(r) << "\n";

    o << "<h2>Force at each site</h2>\n<p class=meta>The force along the probe while the "
         "tip was in the site's sulcus "
         "(blue), the band of full credit (green), the tissue-damage limit (red dashes); "
         "the line marks the deepest moment.</p>\n<div "
         "class=sites>";
    for (const SiteResult& s : r.sites) {
      if (!s.reached_mm) continue;
      o << "<div class=site id=\"site-" << s.site.fdi << SiteCode(s.site.site) << "\"><b>"
        << H(s.site.ToString()) << "</b> " << Num(s.held_force_n, 2) << " N held (peak "
        << Num(s.peak_force_n, 2) << "), " << Num(*s.reached_mm, 1) << " mm<br>"
        << ForceTrace(r, s, band) << "</div>";
    }
    o << "</div>\n";

    o << "<h2>Walking stroke</h2>\n<p class=meta>Each surface's sulcus from one contact "
         "to the other: swept (blue) or "
         "missed (red).</p>\n<div class=sites>";
    for (const SurfaceCoverage& c : r.coverage)
      o << "<div class=site><b>" << c.fdi << " " << (c.buccal ? "buccal" : "lingual")
        << "</b> " << Num(100 * c.swept, 0) << " %<br>" << CoverageArc(c) << "<br>"
        << c.strokes << " strokes of " << Num(c.stroke_mm, 1) << " mm</div>";
    o << "</div>\n";
  }

  o << "<h2>Every line of the score</h2>\n<table "
       "class=lines><tr><th>status</th><th>category</th><th>moment (s)</th>"
       "<th>tick</th><th>what</th></tr>\n";
  // A moment's anchor is on its first line: lines of the same tick share it, and
  // an id is given once.
  std::set<std::uint64_t> anchored;
  for (const RubricLine& l : r.lines)
    o << "<tr class=" << ToString(l.status)
      << (anchored.insert(l.tick).second ? " id=\"t" + std::to_string(l.tick) + "\""
                                         : std::string())
      << "><td class=st>" << ToString(l.status) << "</td><td>" << H(l.category)
      << "</td><td><a href=\"#t" << l.tick << "\">" << Seconds(r, l.tick)
      << "</a></td><td>" << l.tick << "</td><td>" << H(l.message) << "</td></tr>\n";
  o << "</table>\n";
  if (!r.feedback.empty()) {
    o << "<h2>What you were told during the lesson</h2>\n<ul>";
    for (const std::string& f : r.feedback) o << "<li>" << H(f) << "</li>";
    o << "</ul>\n";
  }
  o << "<p class=meta>Recording: " << H(info.recording.empty() ? "none" : info.recording)
    << ". Every moment is the recording's tick; <code>sulcus-cli lesson report</code> "
       "rebuilds this page from it.</p>\n";
  o << "</body></html>\n";
  return o.str();
}

void WriteReport(const LessonResult& r, const ReportInfo& info, const fs::path& dir) {
  fs::create_directories(dir);
  for (const auto& [name, text] : {std::pair{"report.json", ReportJson(r, info)},
                                   std::pair{"report.html", ReportHtml(r, info)}}) {
    // Whole or not at all (flushed to the disk, then renamed): a full disk is
    // an error naming the file, never a report cut short.
    AtomicFile out(dir / name, true);
    out.stream() << text;
    out.Commit();
  }
}

}  // namespace sulcus
