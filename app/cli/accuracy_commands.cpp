// `sulcus-cli accuracy-cost`: what accuracy costs in time. For one object it
// builds sphere-trees at several leaf budgets and measures what each buys (how
// far leaves stick out of the surface) and what it costs (build time, frame time,
// contact pairs), then sweeps the solver's penetration tolerance. Writes CSV
// files and, when gnuplot is installed, PNG plots.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>

#include "app/cli/commands.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/tooth.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/primitives.h"
#include "core/haptics/effects.h"
#include "core/haptics/engine.h"
#include "core/haptics/haptic_loop.h"
#include "core/haptics/scripted_device.h"
#include "core/scene/scene.h"
#include "core/session/session.h"
#include "core/spheretree/cache.h"
#include "core/spheretree/mesh_oracle.h"
#include "core/spheretree/metrics.h"

namespace sulcus::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct FrameStats {
  double p50_us = 0, p99_us = 0, mean_pairs = 0, mean_linearizations = 0,
         max_penetration_mm = 0;
  double contact_share = 0;  // frames with an active contact
  std::uint64_t faults = 0;
  EngineFaults kinds;
};

// "pair overflow 12, solver 3": the kinds of fault a run had.
std::string FaultKinds(const EngineFaults& f) {
  std::string out;
  auto add = [&](const char* name, std::uint64_t n) {
    if (n == 0) return;
    if (!out.empty()) out += ", ";
    out += name + std::string(" ") + std::to_string(n);
  };
  add("non-finite device", f.nonfinite_device);
  add("pair overflow", f.pair_overflow);
  add("solver", f.solver);
  add("penetration", f.penetration);
  add("sweep", f.sweep);
  add("held, brought to free space", f.held);
  add("inside, brought out", f.inside);
  add("placed apart, rejoined the device", f.rejoined);
  return out;
}

// Slides the probe over the object, kept perpendicular to it (its shaft along
// the direction from the object's centre) and pressed 0.3 mm toward the centre
// from the graphic tool, a device that follows the surface with a steady push:
// 300 frames to settle, then 3000 measured frames.
FrameStats RunSlide(const SphereTree& probe, const SphereTree& object, const Aabb& box,
                    EngineParams params) {
  const EngineModel model(probe, {{&object, RigidTransform::Identity()}}, params);
  EngineData d(model);
  const Vector3 c = 0.5 * (box.min + box.max);
  auto direction = [](double t) {
    const double a = 0.8 * std::sin(t), b = 0.6 + 0.5 * std::sin(0.7 * t);
    return Vector3(std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b));
  };
  auto pose = [&](double t, double dist) {
    const Vector3 u = direction(t);
    return RigidTransform(
        Quaternion::FromTwoVectors(Vector3::UnitZ(), u).toRotationMatrix(), c + dist * u);
  };
  ResetTool(pose(0, box.extent().norm()), &d);
  std::vector<double> us;
  double pairs = 0, lin = 0, pen = 0;
  int in_contact = 0;
  const int warmup = 300, frames = 3000;
  for (int i = 0; i < warmup + frames; ++i) {
    const double t = std::max(0, i - warmup) * 0.002;
    const RigidTransform X = pose(t, (d.X_WG.translation() - c).norm() - 0.3);
    const auto t0 = Clock::now();
    Step(model, X, &d);
    const double dt =
        std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
    if (i < warmup) continue;
    us.push_back(dt);
    pairs += d.num_pairs;
    lin += d.linearizations;
    in_contact += d.active_contacts > 0;
    pen = std::max(pen, d.max_penetration_mm);
  }
  std::sort(us.begin(), us.end());
  FrameStats s;
  s.p50_us = us[us.size() / 2];
  s.p99_us = us[us.size() * 99 / 100];
  s.mean_pairs = pairs / frames;
  s.mean_linearizations = lin / frames;
  s.max_penetration_mm = pen;
  s.contact_share = static_cast<double>(in_contact) / frames;
  s.faults = d.faults.total();
  s.kinds = d.faults;
  return s;
}

// Sliding at a constant device depth over a flat face (the top of a box, at
// z = top): the normal force should be constant and the rendered tool level; the
// sphere bumps make both ripple. 300 frames pressed 0.3 mm below the face, then
// 3,000 frames along x at 4 mm/s. A pop is a frame whose force changes by more
// than 0.05 N beyond what the device's own move explains (k_t times it).
struct RippleStats {
  double force_ripple_pct = 0;  // peak to peak of the normal force over its mean
  double height_ripple_mm = 0;  // peak to peak of the rendered tool's height
  int pops = 0;
  double worst_pop_n = 0;
  double gap_mean_mm = 0,
         gap_max_mm =
             0;  // the tool's true distance above the face (the air gap a hand feels)
  double p50_us = 0, p99_us = 0;
  std::uint64_t faults = 0;
};

RippleStats RunFlatSlide(const SphereTree& probe, double probe_bottom,
                         const SphereTree& plate, const LeafPlanes* planes, double top,
                         EngineParams params) {
  const EngineModel model(probe, {{&plate, RigidTransform::Identity(), planes}}, params);
  EngineData d(model);
  auto at = [&](double x) {
    return RigidTransform(Matrix3::Identity(), Vector3(x, 0, top - 0.3));
  };
  ResetTool(RigidTransform(Matrix3::Identity(), Vector3(-6, 0, top + 1)), &d);
  RippleStats r;
  std::vector<double> us, fz, gz;
  Vector3 last_f = Vector3::Zero(), last_h = at(-6).translation();
  const int warmup = 300, frames = 3000;
  for (int i = 0; i < warmup + frames; ++i) {
    const double x = -6 + 12.0 * std::max(0, i - warmup) / frames;
    const RigidTransform X = at(x);
    const auto t0 = Clock::now();
    Step(model, X, &d);
    const double dt =
        std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
    if (i >= warmup) {
      us.push_back(dt);
      fz.push_back(d.force_W.z());
      gz.push_back(d.X_WG.translation().z());
      // The exact gap: the tool mesh's lowest point (it stays upright) over the face.
      const double gap = d.X_WG.translation().z() + probe_bottom - top;
      r.gap_mean_mm += gap / frames;
      r.gap_max_mm = std::max(r.gap_max_mm, gap);
      const double unexplained =
          UnexplainedForceChange(last_f, d.force_W, last_h, X.translation(), params.k_t);
      if (unexplained > kPopN) ++r.pops;
      r.worst_pop_n = std::max(r.worst_pop_n, unexplained);
    }
    last_f = d.force_W;
    last_h = X.translation();
  }
  std::sort(us.begin(), us.end());
  const auto [fmin, fmax] = std::minmax_element(fz.begin(), fz.end());
  const auto [gmin, gmax] = std::minmax_element(gz.begin(), gz.end());
  double mean = 0;
  for (double f : fz) mean += f / fz.size();
  r.force_ripple_pct = mean > 0 ? 100 * (*fmax - *fmin) / mean : 0;
  r.height_ripple_mm = *gmax - *gmin;
  r.p50_us = us[us.size() / 2];
  r.p99_us = us[us.size() * 99 / 100];
  r.faults = d.faults.total();
  return r;
}

// Slides the flat end of the probe over a tooth's buccal surface at a constant
// device depth: the device is held 0.3 mm inside the true surface along the
// outward radial direction at 1.5 mm above the CEJ (where a probe works),
// swept from 60 to 120 degrees around the tooth (its buccal face, +-30 degrees),
// the probe's axis along that direction. On a curved surface the true force
// turns and changes slowly; the sphere bumps add a fast ripple, measured as the
// peak to peak of |F| less its moving mean over 0.5 mm of travel, over the mean.
// The air gap is the end face's true distance to the tooth's mesh (every tenth
// frame; the probe is the 0.4 mm cylinder, its end face at probe_bottom).
RippleStats RunBuccalSlide(const SphereTree& probe, double probe_bottom,
                           const TriangleMesh& tooth, const SphereTree& tree,
                           const LeafPlanes* planes, EngineParams params) {
  const EngineModel model(probe, {{&tree, RigidTransform::Identity(), planes}}, params);
  EngineData d(model);
  const MeshOracle oracle(tooth);  // signed distance: negative inside the tooth
  const auto SignedDistance = [&oracle](const TriangleMesh&, const Vector3& p) {
    return oracle.Inside(p) ? -oracle.Distance(p) : oracle.Distance(p);
  };
  constexpr double kZ = 1.5, kDepth = 0.3, kPi = 3.14159265358979323846, kEndRadius = 0.4;
  auto pose = [&](double th, double depth) {
    const Vector3 u(std::cos(th), std::sin(th), 0);
    const Vector3 surface = OuterRadius(tooth, th, kZ) * u + Vector3(0, 0, kZ);
    Matrix3 R;
    R.col(2) = u;
    R.col(0) = Vector3::UnitZ().cross(u).normalized();
    R.col(1) = R.col(2).cross(R.col(0));
    // The end face's centre (probe_bottom along the axis from the origin) at `depth`
    // inside.
    return RigidTransform(R, surface - depth * u - probe_bottom * u);
  };
  const double th0 = kPi / 3, th1 = 2 * kPi / 3;
  ResetTool(pose(th0, -1.0), &d);
  RippleStats r;
  std::vector<double> us, f, travel, gaps;
  Vector3 last_f = Vector3::Zero(), last_h = pose(th0, kDepth).translation();
  const int warmup = 300, frames = 3000;
  double path = 0;
  Vector3 last_end = Vector3::Zero();
  for (int i = 0; i < warmup + frames; ++i) {
    const double th = th0 + (th1 - th0) * std::max(0, i - warmup) / frames;
    const RigidTransform X = pose(th, kDepth);
    const auto t0 = Clock::now();
    Step(model, X, &d);
    const double dt =
        std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
    const Vector3 end = d.X_WG * Vector3(0, 0, probe_bottom);
    if (i >= warmup) {
      if (i > warmup) path += (end - last_end).norm();
      us.push_back(dt);
      f.push_back(d.force_W.norm());
      travel.push_back(path);
      if ((i - warmup) % 10 == 0) {
        // The end face's true distance: its centre and 24 points of its rim (the
        // face meets a surface that tilts under it at the rim first).
        double gap = SignedDistance(tooth, end);
        for (int k = 0; k < 24; ++k) {
          const double a = 2 * kPi * k / 24;
          gap = std::min(
              gap, SignedDistance(
                       tooth, d.X_WG * Vector3(kEndRadius * std::cos(a),
                                               kEndRadius * std::sin(a), probe_bottom)));
        }
        gaps.push_back(gap);
      }
      const double unexplained =
          UnexplainedForceChange(last_f, d.force_W, last_h, X.translation(), params.k_t);
      if (unexplained > kPopN) ++r.pops;
      r.worst_pop_n = std::max(r.worst_pop_n, unexplained);
    }
    last_end = end;
    last_f = d.force_W;
    last_h = X.translation();
  }
  // The fast part of |F|: less its mean over +-0.25 mm of travel.
  double lo = 1e300, hi = -1e300, mean = 0, hlo = 1e300, hhi = -1e300;
  std::size_t a = 0, b = 0;
  double window_sum = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    while (b < f.size() && travel[b] <= travel[i] + 0.25) window_sum += f[b++];
    while (travel[a] < travel[i] - 0.25) window_sum -= f[a++];
    const double fast = f[i] - window_sum / static_cast<double>(b - a);
    lo = std::min(lo, fast), hi = std::max(hi, fast);
    mean += f[i] / static_cast<double>(f.size());
  }
  for (double g : gaps) {
    hlo = std::min(hlo, g), hhi = std::max(hhi, g);
    r.gap_mean_mm += g / static_cast<double>(gaps.size());
  }
  r.force_ripple_pct = mean > 0 ? 100 * (hi - lo) / mean : 0;
  r.height_ripple_mm = hhi - hlo;  // here: the spread of the air gap along the sweep
  r.gap_max_mm = hhi;
  std::sort(us.begin(), us.end());
  r.p50_us = us[us.size() / 2];
  r.p99_us = us[us.size() * 99 / 100];
  r.faults = d.faults.total();
  return r;
}

void Plot(const fs::path& dir) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::printf(
        "gnuplot not found: CSV written, no plots (scripts/install-deps.sh installs "
        "gnuplot-nox)\n");
    return;
  }
  const fs::path gp = dir / "plots.gp";
  std::ofstream out(gp);
  out << "set datafile separator ','\nset terminal pngcairo size 900,560 font "
         "'Sans,11'\nset grid\n"
      << "set key left top\n"
      << "set output '" << (dir / "resolution.png").string() << "'\n"
      << "set title 'Sphere-tree resolution: what it buys (protrusion) and what it costs "
         "(time)'\n"
      << "set logscale x 2\nset xlabel 'leaf spheres'\nset ylabel 'protrusion, % of "
         "largest extent'\n"
      << "set y2label 'time (us per frame; build: ms)'\nset y2tics\nset logscale y\nset "
         "logscale y2\n"
      << "plot '" << (dir / "resolution.csv").string()
      << "' skip 1 using 1:3 with linespoints lw 2 title 'worst protrusion',"
      << " '' skip 1 using 1:4 with linespoints lw 2 title 'mean protrusion',"
      << " '' skip 1 using 1:6 axes x1y2 with linespoints dt 2 lw 2 title 'frame p50 "
         "(us)',"
      << " '' skip 1 using 1:7 axes x1y2 with linespoints dt 2 lw 2 title 'frame p99 "
         "(us)',"
      << " '' skip 1 using 1:($5*1000) axes x1y2 with linespoints dt 3 lw 2 title 'build "
         "(ms)'\n"
      << "unset logscale\nset logscale x 10\nset format x '10^{%L}'\nunset y2tics\nunset "
         "y2label\n"
      << "set output '" << (dir / "tolerance.png").string() << "'\n"
      << "set title 'Solver tolerance: penetration allowed vs frame time'\n"
      << "set xlabel 'penetration tolerance (mm)'\nset ylabel 'us per frame / "
         "linearisations x 10'\nset logscale y\n"
      << "plot '" << (dir / "tolerance.csv").string()
      << "' skip 1 using 1:2 with linespoints lw 2 title 'frame p50 (us)',"
      << " '' skip 1 using 1:3 with linespoints lw 2 title 'frame p99 (us)',"
      << " '' skip 1 using 1:($4*10) with linespoints lw 2 title 'mean linearisations x "
         "10'\n"
      << "unset logscale\nset logscale x 2\nset format x '%g'\nset y2tics\n"
      << "set output '" << (dir / "ripple.png").string() << "'\n"
      << "set title 'Sliding on a flat plate: what the hand feels of the sphere "
         "bumps'\nset key right center\n"
      << "set xlabel 'leaf spheres of the plate'\nset ylabel 'normal force ripple, % "
         "(peak to peak / mean)'\n"
      << "set y2label 'rendered tool height ripple (mm)'\nset logscale y\nset logscale "
         "y2\n"
      << "plot '" << (dir / "ripple.csv").string()
      << "' skip 1 using 1:2 with linespoints lw 2 title 'force ripple %, spheres',"
      << " '' skip 1 using 1:($11 > 0.01 ? $11 : 0.01) with linespoints lw 2 title "
         "'force ripple %, clipped leaves (0.01 = none)',"
      << " 7 with lines dt 2 lw 1 title 'Weber fraction for force (7 %)',"
      << " '' skip 1 using 1:3 axes x1y2 with linespoints dt 3 lw 2 title 'height ripple "
         "(mm), spheres',"
      << " '' skip 1 using 1:($12 > 1e-5 ? $12 : 1e-5) axes x1y2 with linespoints dt 3 "
         "lw 2 title 'height ripple (mm), clipped leaves'\n"
      << "unset logscale\nset logscale x 2\n"
      << "set output '" << (dir / "buccal_ripple.png").string() << "'\n"
      << "set title 'Sliding along a molar''s buccal surface: force ripple and the air "
         "gap felt'\nset key right top\n"
      << "set xlabel 'leaf spheres of the tooth'\nset ylabel 'fast force ripple, % (peak "
         "to peak / mean)'\n"
      << "set y2label 'air gap felt, mean (mm)'\nset yrange [0:*]\nset y2range [0:*]\n"
      << "plot '" << (dir / "buccal_ripple.csv").string()
      << "' skip 1 every 2::0 using 1:3 with linespoints lw 2 lc rgb '#1f77b4' title "
         "'force ripple %, spheres',"
      << " '' skip 1 every 2::1 using 1:3 with linespoints lw 2 lc rgb '#d62728' title "
         "'force ripple %, clipped leaves',"
      << " 7 with lines dt 2 lw 1 lc rgb '#555555' title 'Weber fraction for force (7 "
         "%)',"
      << " '' skip 1 every 2::0 using 1:5 axes x1y2 with linespoints dt 3 lw 2 lc rgb "
         "'#1f77b4' title 'air gap (mm), spheres',"
      << " '' skip 1 every 2::1 using 1:5 axes x1y2 with linespoints dt 3 lw 2 lc rgb "
         "'#d62728' title 'air gap (mm), clipped leaves'\n";
  out.close();
  if (std::system(("gnuplot '" + gp.string() + "'").c_str()) == 0) {
    std::printf("plots: %s, %s, %s, %s\n", (dir / "resolution.png").c_str(),
                (dir / "tolerance.png").c_str(), (dir / "ripple.png").c_str(),
                (dir / "buccal_ripple.png").c_str());
  } else {
    std::printf("gnuplot failed on %s\n", gp.c_str());
  }
}

// Effects: the scene's scripted insert (two insertions, 8,000 ticks, offline)
// with no effect, each effect alone and all together: what each costs per tick
// and what it buys (readings, soft contacts, bleeding and damage events).
void RunEffectsStudy(const fs::path& scene_file, const fs::path& dir) {
  const SceneSpec base = LoadSceneSpec(scene_file);
  struct Config {
    std::string label;
    std::vector<Effect> effects;
  };
  std::vector<Config> configs = {{"contact only", {Effect::kContact}}};
  for (Effect e : base.effects)
    if (e != Effect::kContact) configs.push_back({ToString(e), {Effect::kContact, e}});
  configs.push_back({"all of the scene's", base.effects});
  // Friction is measured whether or not the scene names it (on its objects'
  // coefficients).
  if (!base.HasEffect(Effect::kFriction)) {
    configs.push_back(
        {"friction (not in the scene)", {Effect::kContact, Effect::kFriction}});
    std::vector<Effect> all = base.effects;
    all.push_back(Effect::kFriction);
    configs.push_back({"all of the scene's + friction", all});
  }
  std::ofstream csv(dir / "effects.csv");
  csv << "config,tick_mean_us,tick_p50_us,tick_p99_us,readings,reading_mm,max_force_n,"
         "soft_contacts,bleeding,damage,"
         "caries_catches,calculus_touches,stuck_ticks,sliding_ticks\n";
  std::printf(
      "effects on %s: the scripted insert, 8000 ticks offline (each tick timed 3 times, "
      "averaged)\n",
      scene_file.c_str());
  std::printf("  %-36s %8s %8s %8s  %8s %8s %9s %5s %5s %5s %5s %5s %6s %6s\n", "effects",
              "mean us", "p50 us", "p99 us", "readings", "reading", "max F (N)", "soft",
              "bleed", "harm", "catch", "calc", "stuck", "slide");
  for (const Config& c : configs) {
    SceneSpec spec = base;
    spec.effects = c.effects;
    const auto scene = CompileScene(spec, DefaultCacheDir());
    const ScriptTarget target = FindScriptTarget(*scene, "insert");
    std::vector<double> tick_us;
    int readings = 0, soft = 0, bleeding = 0, damage = 0, catches = 0, calculus = 0,
        stuck = 0, sliding = 0;
    double reading = 0, max_force = 0;
    for (int run = 0; run < 3; ++run) {
      // Counts the effects' events of the first run.
      struct Counter final : TickConsumer {
        void OnTick(const TickRecord& r) override {
          max_force = std::max(max_force, r.force_W.norm());
          for (int i = 0; i < r.num_events; ++i) {
            const HapticEvent& e = r.events[i];
            switch (e.kind) {
              case EventKind::kProbeReading:
                ++readings;
                reading = e.payload.reading.depth_mm;
                break;
              case EventKind::kSoftContact:
                ++soft;
                break;
              case EventKind::kBleeding:
                ++bleeding;
                break;
              case EventKind::kTissueDamage:
                ++damage;
                break;
              case EventKind::kCariesCatch:
                ++catches;
                break;
              case EventKind::kCalculusTouched:
                ++calculus;
                break;
              default:
                break;
            }
          }
        }
        int readings = 0, soft = 0, bleeding = 0, damage = 0, catches = 0, calculus = 0;
        double reading = 0, max_force = 0;
      } counter;
      DeviceSpec d;
      d.device = std::make_unique<ScriptedDevice>(MakeScript("insert", target, 8.0));
      d.name = "scripted:insert";
      SessionOptions so;
      so.max_ticks = 8000;
      Session session(*scene, std::move(d), so);
      session.AddConsumer(&counter);
      std::vector<double> us;
      us.reserve(8000);
      int run_stuck = 0, run_sliding = 0;
      session.RunOffline([&](const HapticLoop& loop) {
        us.push_back(session.last_step_us());
        run_stuck += loop.data().friction == EngineData::Friction::kStick;
        run_sliding += loop.data().friction == EngineData::Friction::kSlip;
      });
      if (run == 0) {
        readings = counter.readings, soft = counter.soft, bleeding = counter.bleeding,
        damage = counter.damage;
        catches = counter.catches;
        calculus = counter.calculus;
        reading = counter.reading, max_force = counter.max_force;
        stuck = run_stuck, sliding = run_sliding;
      }
      if (tick_us.empty()) tick_us.assign(us.size(), 0);
      for (std::size_t i = 0; i < us.size(); ++i)
        tick_us[i] += us[i] / 3;  // mean over runs, tick by tick
    }
    std::vector<double> sorted = tick_us;
    std::sort(sorted.begin(), sorted.end());
    double mean = 0;
    for (double v : sorted) mean += v / sorted.size();
    const double p50 = sorted[sorted.size() / 2], p99 = sorted[sorted.size() * 99 / 100];
    std::printf(
        "  %-36s %8.2f %8.2f %8.2f  %8d %8.2f %9.3f %5d %5d %5d %5d %5d %6d %6d\n",
        c.label.c_str(), mean, p50, p99, readings, reading, max_force, soft, bleeding,
        damage, catches, calculus, stuck, sliding);
    csv << '"' << c.label << '"' << ',' << mean << ',' << p50 << ',' << p99 << ','
        << readings << ',' << reading << ',' << max_force << ',' << soft << ','
        << bleeding << ',' << damage << ',' << catches << ',' << calculus << ',' << stuck
        << ',' << sliding << '\n';
  }
  csv.close();
  const fs::path gp = dir / "effects.gp";
  std::ofstream out(gp);
  out << "set datafile separator ','\nset terminal pngcairo size 900,480 font "
         "'Sans,11'\nset grid ytics\n"
      << "set output '" << (dir / "effects.png").string() << "'\n"
      << "set title 'Effects: what each costs per haptic tick (probing scene, scripted "
         "insert)'\n"
      << "set style data histograms\nset style histogram clustered gap 1\nset style fill "
         "solid 0.8 border -1\n"
      << "set ylabel 'microseconds per tick'\nset xtics rotate by -20\nset key left top\n"
      << "set termoption noenhanced\nset yrange [0:*]\n"
      << "plot '" << (dir / "effects.csv").string()
      << "' skip 1 using 2:xtic(1) title 'mean',"
      << " '' skip 1 using 3 title 'p50', '' skip 1 using 4 title 'p99'\n";
  out.close();
  std::printf("CSV: %s\n", (dir / "effects.csv").c_str());
  if (std::system(("gnuplot '" + gp.string() + "'").c_str()) == 0)
    std::printf("plot: %s\n", (dir / "effects.png").c_str());
}

}  // namespace

void AddAccuracyCommands(CLI::App& app) {
  auto mesh_file = std::make_shared<std::string>();
  auto out_dir = std::make_shared<std::string>("accuracy-cost");
  CLI::App* cmd = app.add_subcommand(
      "accuracy-cost",
      "Measure what accuracy costs: sphere-tree resolution (protrusion vs build and "
      "frame time) and solver "
      "tolerance (penetration vs frame time), as a table, CSV and plots");
  cmd->add_option("--mesh", *mesh_file,
                  "Object to probe (default: a tooth-sized ellipsoid, 8 x 7 x 20 mm)");
  cmd->add_option("-o,--output", *out_dir, "Folder for CSV files and plots")
      ->capture_default_str();
  auto effects_scene = std::make_shared<std::string>();
  cmd->add_option(
      "--effects", *effects_scene,
      "Instead: measure each effect of this scene (cost per tick, what it buys)");
  cmd->callback([=] {
    if (!effects_scene->empty()) {
      fs::create_directories(*out_dir);
      RunEffectsStudy(*effects_scene, *out_dir);
      return;
    }
    TriangleMesh object;
    if (mesh_file->empty()) {
      object = MakeIcosphere(1.0, 4);
      object.Transform(Vector3(4, 3.5, 10).asDiagonal(), Vector3::Zero());
    } else {
      object = LoadMesh(*mesh_file);
    }
    const fs::path dir(*out_dir);
    fs::create_directories(dir);
    const fs::path cache = DefaultCacheDir();
    std::printf(
        "object: %s, %zu faces; probe: cylinder r 0.4 mm, 512 leaves; trees cached in "
        "%s\n",
        mesh_file->empty() ? "tooth-sized ellipsoid" : mesh_file->c_str(),
        object.num_faces(), cache.c_str());
    const TriangleMesh probe_mesh = MakeCylinder(0.4, 16, 24, 24);
    const double probe_bottom = probe_mesh.Bounds().min.z();
    const SphereTree probe = LoadOrBuildSphereTree(probe_mesh, ToolTreeParams(), cache);
    const Aabb box = object.Bounds();
    EvalParams fit_eval;  // the excess volume is not reported here: fewer volume samples
    fit_eval.volume_samples_per_sphere = 64;

    std::ofstream res(dir / "resolution.csv");
    res << "leaves_budget,leaves,protrusion_max_pct,protrusion_mean_pct,build_s,frame_"
           "p50_us,frame_p99_us,pairs,faults\n";
    std::printf("\nresolution (levels 4 up to 512 leaves, 5 above)\n");
    std::printf(
        "  budget leaves  worst %%   mean %%   build s  frame p50 us  p99 us  pairs  "
        "contact  faults\n");
    for (int budget : {8, 32, 64, 128, 256, 512, 1024, 2048}) {
      SphereTreeParams p;
      p.leaves = budget;
      p.levels = budget > 512 ? 5 : 4;
      CacheOutcome outcome;
      const auto t0 = Clock::now();
      const SphereTree tree = LoadOrBuildSphereTree(object, p, cache, {}, &outcome);
      double build_s = std::chrono::duration<double>(Clock::now() - t0).count();
      if (outcome.kind == CacheOutcome::Kind::kHit) {
        // Cached: rebuild once, untimed by the cache, to report the build cost.
        const auto t1 = Clock::now();
        BuildSphereTree(object, p);
        build_s = std::chrono::duration<double>(Clock::now() - t1).count();
      }
      const TreeMetrics m = EvaluateSphereTree(object, tree, fit_eval);
      const FrameStats f = RunSlide(probe, tree, box, EngineParams{});
      const double wp = 100 * m.leaves().protrusion_max_mm / m.largest_extent_mm;
      const double mp = 100 * m.leaves().protrusion_mean_mm / m.largest_extent_mm;
      std::printf(
          "  %6d %6zu  %7.3f  %7.3f  %8.2f  %12.2f  %6.2f  %5.0f  %6.0f%%  %6llu\n",
          budget, tree.NumLeaves(), wp, mp, build_s, f.p50_us, f.p99_us, f.mean_pairs,
          100 * f.contact_share, static_cast<unsigned long long>(f.faults));
      if (f.faults > 0)
        std::printf("          faults at %d leaves: %s\n", budget,
                    FaultKinds(f.kinds).c_str());
      res << budget << ',' << tree.NumLeaves() << ',' << wp << ',' << mp << ',' << build_s
          << ',' << f.p50_us << ',' << f.p99_us << ',' << f.mean_pairs << ',' << f.faults
          << '\n';
      std::fflush(stdout);
    }
    res.close();

    // Sliding on a flat plate (a 16 x 16 x 4 mm box) at constant depth, per leaf count.
    {
      const TriangleMesh box_mesh = MakeBox(Vector3(16, 16, 4), 8);
      const double top = box_mesh.Bounds().max.z();
      std::ofstream rip(dir / "ripple.csv");
      rip << "leaves,force_ripple_pct,height_ripple_mm,pops,worst_pop_n,frame_p50_us,"
             "frame_p99_us,faults,gap_mean_mm,"
             "gap_max_mm,planes_force_ripple_pct,planes_height_ripple_mm,planes_pops,"
             "planes_worst_pop_n,"
             "planes_frame_p50_us,planes_frame_p99_us,planes_faults,planes_gap_mean_mm,"
             "planes_gap_max_mm,"
             "clipped_leaves\n";
      std::printf(
          "\nsliding on a flat plate at constant depth (0.3 mm): normal force ripple (7 "
          "%% is about what a "
          "hand tells apart), rendered tool height ripple, pops (> 0.05 N in a frame "
          "beyond the device's move)\n");
      std::printf(
          "  budget leaves  surface  force ripple %%  height ripple mm  pops  worst pop "
          "N  frame p50 us  p99 us"
          "  faults  gap mean mm  gap max mm\n");
      for (int budget : {32, 128, 512, 2048}) {
        SphereTreeParams p;
        p.leaves = budget;
        p.levels = budget > 512 ? 5 : 4;
        const SphereTree plate = LoadOrBuildSphereTree(box_mesh, p, cache);
        // The same tree felt as spheres, then as leaves clipped by their fitted planes.
        const LeafPlanes planes = FitLeafPlanes(box_mesh, plate);
        rip << plate.NumLeaves();
        for (const LeafPlanes* lp : {static_cast<const LeafPlanes*>(nullptr), &planes}) {
          const RippleStats r =
              RunFlatSlide(probe, probe_bottom, plate, lp, top, EngineParams{});
          std::printf(
              "  %6d %6zu  %7s  %14.2f  %16.4f  %4d  %11.3f  %12.2f  %6.2f  %6llu  "
              "%11.4f  %10.4f\n",
              budget, plate.NumLeaves(), lp ? "planes" : "spheres", r.force_ripple_pct,
              r.height_ripple_mm, r.pops, r.worst_pop_n, r.p50_us, r.p99_us,
              static_cast<unsigned long long>(r.faults), r.gap_mean_mm, r.gap_max_mm);
          rip << ',' << r.force_ripple_pct << ',' << r.height_ripple_mm << ',' << r.pops
              << ',' << r.worst_pop_n << ',' << r.p50_us << ',' << r.p99_us << ','
              << r.faults << ',' << r.gap_mean_mm << ',' << r.gap_max_mm;
          std::fflush(stdout);
        }
        rip << ',' << planes.count() << '\n';
        std::printf("          %d of %zu leaves clipped by a plane\n", planes.count(),
                    plate.NumLeaves());
      }
    }

    // Sliding along a tooth's buccal surface (46) at constant depth, per leaf count.
    {
      const ToothModel tooth = GenerateTooth(46);
      std::ofstream bc(dir / "buccal_ripple.csv");
      bc << "leaves,surface,force_ripple_pct,gap_spread_mm,gap_mean_mm,gap_max_mm,pops,"
            "worst_pop_n,frame_p50_us,"
            "frame_p99_us,faults\n";
      std::printf(
          "\nsliding along tooth 46's buccal surface at constant depth (0.3 mm, 1.5 mm "
          "above the CEJ, 60 degrees "
          "of arc): fast force ripple (|F| less its mean over 0.5 mm of travel, peak to "
          "peak over the mean), "
          "the air gap felt (the probe's end face to the tooth's mesh) and its spread, "
          "pops\n");
      std::printf(
          "  budget leaves  surface  force ripple %%  gap mean mm  gap spread mm  gap "
          "max mm  pops  worst pop N"
          "  frame p50 us  p99 us  faults\n");
      for (int budget : {128, 512, 2048}) {
        SphereTreeParams p;
        p.leaves = budget;
        p.levels = budget > 512 ? 5 : 4;
        const SphereTree tree = LoadOrBuildSphereTree(tooth.mesh, p, cache);
        const LeafPlanes planes = FitLeafPlanes(tooth.mesh, tree);
        for (const LeafPlanes* lp : {static_cast<const LeafPlanes*>(nullptr), &planes}) {
          const RippleStats r =
              RunBuccalSlide(probe, probe_bottom, tooth.mesh, tree, lp, EngineParams{});
          std::printf(
              "  %6d %6zu  %7s  %14.2f  %11.4f  %13.4f  %10.4f  %4d  %11.3f  %12.2f  "
              "%6.2f  %6llu\n",
              budget, tree.NumLeaves(), lp ? "planes" : "spheres", r.force_ripple_pct,
              r.gap_mean_mm, r.height_ripple_mm, r.gap_max_mm, r.pops, r.worst_pop_n,
              r.p50_us, r.p99_us, static_cast<unsigned long long>(r.faults));
          bc << tree.NumLeaves() << ',' << (lp ? "planes" : "spheres") << ','
             << r.force_ripple_pct << ',' << r.height_ripple_mm << ',' << r.gap_mean_mm
             << ',' << r.gap_max_mm << ',' << r.pops << ',' << r.worst_pop_n << ','
             << r.p50_us << ',' << r.p99_us << ',' << r.faults << '\n';
          std::fflush(stdout);
        }
      }
    }

    // What the budget is spent on, at 512 leaves: the mean (default) or the worst.
    std::printf(
        "\nspend (512 leaves): what the leaves are traded for after the min-max cover\n");
    std::printf(
        "  spend  worst %%   mean %%   overlap  build s  frame p50 us  p99 us  pairs  "
        "faults\n");
    for (const auto spend :
         {SphereTreeParams::Spend::kWorst, SphereTreeParams::Spend::kMean}) {
      SphereTreeParams p;
      p.spend = spend;
      const auto t0 = Clock::now();
      const SphereTree tree = BuildSphereTree(object, p);
      const double build_s = std::chrono::duration<double>(Clock::now() - t0).count();
      const TreeMetrics m = EvaluateSphereTree(object, tree, fit_eval);
      const FrameStats f = RunSlide(probe, tree, box, EngineParams{});
      std::printf("  %5s  %7.3f  %7.3f  %7.2f  %7.2f  %12.2f  %6.2f  %5.0f  %6llu\n",
                  SpendName(spend),
                  100 * m.leaves().protrusion_max_mm / m.largest_extent_mm,
                  100 * m.leaves().protrusion_mean_mm / m.largest_extent_mm,
                  m.leaves().overlap, build_s, f.p50_us, f.p99_us, f.mean_pairs,
                  static_cast<unsigned long long>(f.faults));
      std::fflush(stdout);
    }

    const SphereTree tree512 = LoadOrBuildSphereTree(object, SphereTreeParams{}, cache);
    std::ofstream tol(dir / "tolerance.csv");
    tol << "tolerance_mm,frame_p50_us,frame_p99_us,linearizations,max_penetration_mm,"
           "faults\n";
    std::printf(
        "\nsolver tolerance (512 leaves): re-linearise until penetration and slack are "
        "below it\n");
    std::printf(
        "  tolerance mm  frame p50 us  p99 us  linearisations  max penetration mm  "
        "contact  faults\n");
    for (double t : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
      EngineParams p;
      p.penetration_tolerance_mm = t;
      p.max_linearizations = 8;
      const FrameStats f = RunSlide(probe, tree512, box, p);
      std::printf("  %12.0e  %12.2f  %6.2f  %14.2f  %18.2e  %6.0f%%  %6llu\n", t,
                  f.p50_us, f.p99_us, f.mean_linearizations, f.max_penetration_mm,
                  100 * f.contact_share, static_cast<unsigned long long>(f.faults));
      tol << t << ',' << f.p50_us << ',' << f.p99_us << ',' << f.mean_linearizations
          << ',' << f.max_penetration_mm << ',' << f.faults << '\n';
    }
    tol.close();
    std::printf("\nCSV: %s, %s, %s, %s\n", (dir / "resolution.csv").c_str(),
                (dir / "tolerance.csv").c_str(), (dir / "ripple.csv").c_str(),
                (dir / "buccal_ripple.csv").c_str());
    Plot(dir);
  });
}

}  // namespace sulcus::cli
