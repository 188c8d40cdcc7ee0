// `sulcus-cli run`, `sulcus-cli devices`, `sulcus-cli recording ...`: the real
// haptic thread without a window, the USB devices, and recordings.

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "app/cli/commands.h"
#include "core/base/files.h"
#include "core/haptics/devices/usb_discovery.h"
#include "core/haptics/effects.h"
#include "core/haptics/haptic_thread.h"
#include "core/haptics/recording.h"
#include "core/haptics/scripted_device.h"
#include "core/scene/scene.h"
#include "core/session/session.h"
#include "core/spheretree/cache.h"

namespace sulcus::cli {
namespace {

struct RunArgs {
  std::string scene, device = "scripted:random", record;
  double rate_hz = 0;  // 0: the scene's
  double seconds = 5;
  int object = -1;
  std::uint64_t seed = 1;
  bool no_realtime = false;
  double spin_us = -1;  // the thread's default
  bool offline = false;
  std::vector<double>
      trace;  // offline: print the engine's state each tick from trace[0] to trace[1] s
};

// One tick of the engine, for --trace: the device and rendered tool, the force,
// the contact query and the solve, and the fault counters.
void TraceTick(const HapticLoop& l, const SceneSpec& spec, double rate_hz) {
  const EngineData& d = l.data();
  const TickRecord& r = l.last_record();
  const Vector3 h = d.X_WH.translation(), g = d.X_WG.translation();
  std::printf(
      "trace %" PRIu64
      " %.4f s: device (%.3f %.3f %.3f) tool (%.3f %.3f %.3f) |g-h| %.3f mm force %.3f N "
      "(engine %.3f) step %.1f us (collide %.1f rows %.1f qp %.1f) pairs %d active %d "
      "pen %.4f mm margin %.3f sweeps %d tests %d%s qp %d it %d lin %d%s%s "
      "faults overflow %" PRIu64 " solver %" PRIu64 " pen %" PRIu64 " sweep %" PRIu64
      " held %" PRIu64 " inside %" PRIu64 " rejoined %" PRIu64 "\n",
      r.tick, static_cast<double>(r.tick) / rate_hz, h.x(), h.y(), h.z(), g.x(), g.y(),
      g.z(), (g - h).norm(), r.force_W.norm(), d.force_W.norm(), d.timings.total_us,
      d.timings.collide_us, d.timings.constraints_us, d.timings.solve_us, d.num_pairs,
      d.active_contacts, d.max_penetration_mm, d.margin_mm, d.sweeps, d.node_tests,
      d.node_budget_hit ? " (budget hit)" : "", static_cast<int>(d.qp_status),
      d.qp_iterations, d.linearizations, d.pair_overflow ? " overflow" : "",
      d.inside ? " INSIDE" : "", d.faults.pair_overflow, d.faults.solver,
      d.faults.penetration, d.faults.sweep, d.faults.held, d.faults.inside,
      d.faults.rejoined);
  // Which objects the pairs are with, and how many distinct tool leaves they use.
  std::map<int, std::pair<int, std::set<int>>> by_object;
  for (int i = 0; i < d.num_pairs; ++i) {
    auto& e = by_object[d.pairs[static_cast<std::size_t>(i)].object];
    ++e.first;
    e.second.insert(d.pairs[static_cast<std::size_t>(i)].tool_leaf);
  }
  if (!by_object.empty()) {
    std::printf("  pairs by object:");
    for (const auto& [object, e] : by_object)
      std::printf(" %s %d (tool leaves %zu)", ObjectName(spec, object).c_str(), e.first,
                  e.second.size());
    std::printf("\n");
  }
}

// The share of a signal's energy above `above_hz`, in percent: Welch's method
// (segments of 256 ticks, half overlapping, Hann window, each segment's mean
// removed); segments where the signal is zero throughout (no contact) add
// nothing. -1 when no segment holds any energy.
double HighFrequencyShare(const std::vector<float>& x, double rate_hz, double above_hz) {
  constexpr int kN = 256;
  if (x.size() < kN) return -1;
  std::vector<double> window(kN), cos_table(kN), sin_table(kN), y(kN);
  for (int i = 0; i < kN; ++i) {
    window[static_cast<std::size_t>(i)] =
        0.5 - 0.5 * std::cos(2 * std::numbers::pi * i / (kN - 1));
    cos_table[static_cast<std::size_t>(i)] = std::cos(2 * std::numbers::pi * i / kN);
    sin_table[static_cast<std::size_t>(i)] = std::sin(2 * std::numbers::pi * i / kN);
  }
  double total = 0, high = 0;
  for (std::size_t start = 0; start + kN <= x.size(); start += kN / 2) {
    double mean = 0;
    for (int i = 0; i < kN; ++i) mean += x[start + static_cast<std::size_t>(i)];
    mean /= kN;
    for (int i = 0; i < kN; ++i)
      y[static_cast<std::size_t>(i)] = (x[start + static_cast<std::size_t>(i)] - mean) *
                                       window[static_cast<std::size_t>(i)];
    for (int k = 1; k <= kN / 2; ++k) {
      double re = 0, im = 0;
      for (int i = 0; i < kN; ++i) {
        const auto j = static_cast<std::size_t>((k * i) % kN);
        re += y[static_cast<std::size_t>(i)] * cos_table[j];
        im -= y[static_cast<std::size_t>(i)] * sin_table[j];
      }
      const double e = re * re + im * im;
      total += e;
      if (k * rate_hz / kN > above_hz) high += e;
    }
  }
  return total > 0 ? 100.0 * high / total : -1;
}

// Counts what the run did, from the tick stream.
class RunSummary final : public TickConsumer {
 public:
  RunSummary(const SceneSpec& spec, double rate_hz) : spec_(spec), rate_hz_(rate_hz) {}
  void OnTick(const TickRecord& r) override {
    // Pops of the force sent (UnexplainedForceChange).
    const Vector3 at = r.sample.X_WH.translation();
    if (ticks_++ > 0) {
      const double unexplained =
          UnexplainedForceChange(last_force_, r.force_W, last_at_, at, spec_.haptics.k_t);
      if (unexplained > kPopN) {
        ++pops;
        if (unexplained > worst_pop_n) {
          worst_pop_n = unexplained;
          worst_pop_tick = r.tick;
        }
      }
    }
    // Force where nothing supports it: more than kUnsupportedN sent while the
    // coupling spring (tool to device) holds under kSpringHeldN, and how far
    // the rendered tool moves in one tick.
    const Vector3 tool = r.X_WG.translation();
    if (ticks_ > 1) {
      const double jump = (tool - last_tool_).norm();
      if (jump > max_jump_mm) {
        max_jump_mm = jump;
        max_jump_tick = r.tick;
      }
      // Beyond the device's own move in the tick: the tool's own jump.
      const double own = jump - (at - last_at_).norm();
      if (own > max_own_jump_mm) {
        max_own_jump_mm = own;
        max_own_jump_tick = r.tick;
      }
    }
    const double spring = spec_.haptics.k_t * (tool - at).norm();
    if (r.force_W.norm() > kUnsupportedN && spring < kSpringHeldN) {
      ++unsupported;
      longest_unsupported = std::max(longest_unsupported, ++run_);
    } else {
      run_ = 0;
    }
    last_tool_ = tool;
    last_force_ = r.force_W;
    last_at_ = at;
    if (force_n.size() < kMaxForceSamples)
      force_n.push_back(static_cast<float>(r.force_W.norm()));
    events += static_cast<std::uint64_t>(r.num_events);
    for (int i = 0; i < r.num_events; ++i) {
      const HapticEvent& e = r.events[i];
      if (e.kind == EventKind::kContactBegan) ++began[e.object];
      const bool effect =
          e.kind == EventKind::kProbeReading || e.kind == EventKind::kBleeding ||
          e.kind == EventKind::kTissueDamage || e.kind == EventKind::kSoftContact;
      if (!effect || lines.size() >= 40) continue;
      char t[32];
      std::snprintf(t, sizeof t, "%.3f s: ", static_cast<double>(e.tick) / rate_hz_);
      lines.push_back(t + DescribeEvent(spec_, e));
    }
  }
  std::map<int, int> began;
  std::uint64_t events = 0;
  std::vector<std::string> lines;
  std::uint64_t pops = 0, worst_pop_tick = 0;
  double worst_pop_n = 0;
  std::uint64_t unsupported = 0, longest_unsupported = 0, max_jump_tick = 0;
  double max_jump_mm = 0;
  std::uint64_t max_own_jump_tick = 0;
  double max_own_jump_mm = 0;
  static constexpr double kUnsupportedN = 0.3, kSpringHeldN = 0.05;
  // The force sent, a tick at a time (the first hour at 1 kHz), for its spectrum.
  static constexpr std::size_t kMaxForceSamples = 3600000;
  std::vector<float> force_n;

 private:
  const SceneSpec& spec_;
  double rate_hz_;
  std::uint64_t ticks_ = 0;
  std::uint64_t run_ = 0;
  Vector3 last_force_ = Vector3::Zero(), last_at_ = Vector3::Zero(),
          last_tool_ = Vector3::Zero();
};

int Run(const RunArgs& a) {
  SceneSpec spec = LoadSceneSpec(a.scene);
  // A rate of its own: the slip eased at the scene's speed (mm/s), not per frame.
  if (a.rate_hz > 0) spec.haptics.slip_step_mm *= spec.rate_hz / a.rate_hz;
  std::fprintf(stderr, "compiling %s ...\n", a.scene.c_str());
  const auto t0 = std::chrono::steady_clock::now();
  const auto scene = CompileScene(spec, DefaultCacheDir());
  std::fprintf(
      stderr, "compiled in %.2f s\n",
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());

  DeviceSpec device = MakeDevice(a.device, *scene, a.seconds, a.seed, a.object);
  for (const std::string& n : device.notes) std::fprintf(stderr, "%s\n", n.c_str());
  const double recorded_rate = device.replayed ? device.replayed->header.rate_hz : 0;
  SessionOptions so;
  so.rate_hz = a.rate_hz > 0       ? a.rate_hz
               : recorded_rate > 0 ? recorded_rate
                                   : spec.rate_hz;
  so.max_ticks = static_cast<std::uint64_t>(a.seconds * so.rate_hz);
  so.realtime = !a.no_realtime;
  so.spin_us = a.spin_us;
  so.record = a.record;
  Session session(*scene, std::move(device), so);
  RunSummary summary(scene->spec, so.rate_hz);
  session.AddConsumer(&summary);
  std::fprintf(stderr, "running %s at %.0f Hz for %.1f s ...\n",
               session.device_name().c_str(), so.rate_hz, a.seconds);
  std::vector<int>
      node_tests;  // offline: the collision work of each tick, in sphere tests
  if (a.offline) {
    node_tests.reserve(so.max_ticks);
    // As fast as possible, on this thread: the same ticks, no clock.
    session.RunOffline([&](const HapticLoop& l) {
      node_tests.push_back(l.data().node_tests);
      const double t = static_cast<double>(l.last_record().tick) / so.rate_hz;
      if (a.trace.size() == 2 && t >= a.trace[0] && t <= a.trace[1])
        TraceTick(l, scene->spec, so.rate_hz);
    });
  } else {
    session.Start();
    while (session.running()) {
      session.Pump();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    session.Stop();
  }
  HapticLoop& loop = session.loop();
  loop.snapshots().Acquire();
  const HapticSnapshot& s = loop.snapshots().front();
  static const TimingStats kNoThread;
  const TimingStats& st = session.thread() ? session.thread()->stats() : kNoThread;
  const TimeHistogram& step_hist = a.offline ? session.offline_step_us() : st.step_us;

  if (session.thread())
    if (const std::string notes = session.thread()->notes(); !notes.empty())
      std::printf("note: %s\n", notes.c_str());
  std::string on;
  for (const auto& e : session.effects())
    on += std::string(on.empty() ? "" : ", ") + e->name();
  std::printf("effects: %s\n", on.empty() ? "contact only" : on.c_str());
  for (const std::string& l : summary.lines) std::printf("  %s\n", l.c_str());
  const std::uint64_t ticks = a.offline ? loop.tick() : st.ticks.load();
  const double miss_pct = ticks ? 100.0 * st.misses.load() / ticks : 0;
  std::printf(
      "timing: %" PRIu64
      " ticks at %.0f Hz; period p50 %.0f us, p99 %.0f us, p99.9 %.0f us, worst %.0f us "
      "(tick %" PRIu64 "); %" PRIu64 " deadline misses (%.3f %%; %" PRIu64
      " began more than a tenth of a period late, the others' work was too long)\n",
      ticks, so.rate_hz, st.period_us.Percentile(0.5), st.period_us.Percentile(0.99),
      st.period_us.Percentile(0.999), st.worst_period_us.load(), st.worst_tick.load(),
      st.misses.load(), miss_pct, st.late_start_misses.load());
  std::printf("step: p50 %.0f us, p99 %.0f us, p99.9 %.0f us, max %.0f us%s\n",
              step_hist.Percentile(0.5), step_hist.Percentile(0.99),
              step_hist.Percentile(0.999), step_hist.max_us(),
              a.offline ? " (offline)" : "");
  if (!node_tests.empty()) {
    std::sort(node_tests.begin(), node_tests.end());
    std::printf("collision: sphere tests a tick p50 %d, p99 %d, p99.9 %d, max %d\n",
                node_tests[node_tests.size() / 2],
                node_tests[node_tests.size() * 99 / 100],
                node_tests[node_tests.size() * 999 / 1000], node_tests.back());
  }
  // Read after the thread has stopped (joined): the engine's own counters.
  if (const int budget = loop.model().params.solve_pairs; budget > 0)
    std::printf("crowded: %" PRIu64
                " ticks met more than %d pairs (haptics: solve_pairs) and %" PRIu64
                " had the step toward the device limited by the margin cap (never below "
                "0.1 mm a tick)\n",
                loop.data().shortened_frames, budget, loop.data().capped_frames);
  std::printf("contact: %" PRIu64 " ticks in contact (%.1f %%)", s.contact_ticks,
              ticks ? 100.0 * s.contact_ticks / ticks : 0.0);
  for (const auto& [object, n] : summary.began)
    std::printf("; %s touched %d times", ObjectName(scene->spec, object).c_str(), n);
  std::printf(
      "\nforce: max %.3f N, mean in contact %.3f N, saturated %" PRIu64 " ticks\n",
      s.max_force_n, s.contact_ticks ? s.contact_force_sum_n / s.contact_ticks : 0.0,
      s.saturated_ticks);
  std::printf(
      "pops: %" PRIu64
      " ticks whose force changed by more than %.2f N beyond the device's own move",
      summary.pops, kPopN);
  if (summary.pops > 0)
    std::printf(" (worst %.3f N at %.3f s)", summary.worst_pop_n,
                static_cast<double>(summary.worst_pop_tick) / so.rate_hz);
  std::printf("\n");
  // Soft gingiva pushes with its own springs (up to about 0.5 N in a sulcus,
  // the coupling spring near zero): not counted there. Texture and a caries
  // catch add force beside the spring too, smaller, and are counted with it.
  const SceneSpec& sc = scene->spec;
  if (sc.HasEffect(Effect::kGingivaCompliance)) {
    std::printf(
        "unsupported force: not counted (soft gingiva pushes beyond the coupling "
        "spring)");
  } else {
    std::printf("unsupported force: %" PRIu64
                " ticks sent more than %.2f N while the "
                "spring held under %.2f N (longest run %" PRIu64 " ticks)",
                summary.unsupported, RunSummary::kUnsupportedN, RunSummary::kSpringHeldN,
                summary.longest_unsupported);
  }
  std::printf(
      "; the rendered tool's largest jump in a tick %.3f mm at %.3f s, "
      "beyond the device's own move %.3f mm at %.3f s (%" PRIu64 " slips eased)\n",
      summary.max_jump_mm, static_cast<double>(summary.max_jump_tick) / so.rate_hz,
      summary.max_own_jump_mm,
      static_cast<double>(summary.max_own_jump_tick) / so.rate_hz,
      loop.data().eased_frames);
  if (const double share = HighFrequencyShare(summary.force_n, so.rate_hz, 100.0);
      share >= 0)
    std::printf(
        "spectrum: %.2f %% of the force's energy above 100 Hz (256-tick Hann segments, "
        "each one's mean removed)\n",
        share);
  std::printf("faults: %" PRIu64 " (engine %" PRIu64 ", overruns %" PRIu64
              ", device stalls %" PRIu64 ", non-finite output %" PRIu64
              "); events %" PRIu64 ", dropped %" PRIu64 "; ticks not delivered %" PRIu64
              "\n",
              s.faults.total(), s.faults.engine, s.faults.overruns,
              s.faults.device_stalls, s.faults.nonfinite_output, summary.events,
              s.faults.events_dropped, session.dropped_ticks());
  if (const RecordingWriter* w = session.recorder())
    std::printf("recorded %" PRIu64 " ticks to %s (%" PRIu64 " dropped)\n", w->written(),
                a.record.c_str(), w->dropped());
  std::printf("run rate_hz=%.0f ticks=%" PRIu64 " misses=%" PRIu64
              " late_start_misses=%" PRIu64
              " period_p50_us=%.1f period_p99_us=%.1f period_p999_us=%.1f worst_us=%.1f "
              "step_p50_us=%.1f "
              "step_p99_us=%.1f step_p999_us=%.1f max_force_n=%.3f faults=%" PRIu64
              " pops=%" PRIu64 "\n",
              so.rate_hz, ticks, st.misses.load(), st.late_start_misses.load(),
              st.period_us.Percentile(0.5), st.period_us.Percentile(0.99),
              st.period_us.Percentile(0.999), st.worst_period_us.load(),
              step_hist.Percentile(0.5), step_hist.Percentile(0.99),
              step_hist.Percentile(0.999), s.max_force_n, s.faults.total(), summary.pops);
  return 0;
}

}  // namespace

void AddRunCommands(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* run = app.add_subcommand(
      "run",
      "Run the real haptic thread headless on a scene, then print timing, "
      "contact and force statistics");
  run->add_option("--scene", a->scene, "Scene file (.yaml)")->required();
  run->add_option("--device", a->device,
                  "scripted:NAME (line, poke, slide, arc, insert, random), "
                  "scripted:FILE.csv or replay:FILE")
      ->capture_default_str();
  run->add_option("--rate", a->rate_hz,
                  "Haptic rate in Hz (default: the scene's; a replay's own)")
      ->check(Finite() & CLI::Range(100.0, 20000.0));
  run->add_option("--seconds", a->seconds, "How long to run")
      ->capture_default_str()
      ->check(Finite() & CLI::Range(0.01, 3600.0));
  run->add_option("--record", a->record, "Record the session to this file");
  run->add_option(
         "--object", a->object,
         "Index of the object a scripted trajectory works on (default: first tooth)")
      ->check(WholeNumber());
  run->add_option("--seed", a->seed, "Seed of the random trajectory")
      ->capture_default_str()
      ->check(WholeNumber());
  run->add_flag("--no-realtime", a->no_realtime,
                "Do not ask for real-time priority and a pinned core");
  run->add_option("--spin-us", a->spin_us,
                  "Microseconds at the end of each wait spent polling the clock instead "
                  "of sleeping "
                  "(default: 90 % of the period, at most 100; at most 90 %, and a tenth "
                  "of the period is always slept; "
                  "0: sleep the whole wait)")
      ->check(CLI::Range(0.0, 1000.0));
  run->add_flag(
      "--offline", a->offline,
      "No thread and no clock: tick as fast as possible (timing figures are then empty)");
  run->add_option("--trace", a->trace,
                  "With --offline: print the engine's state at every tick from FROM to "
                  "TO seconds (FROM TO)")
      ->expected(2);
  run->callback([a] {
    if (!a->trace.empty() && (!a->offline || a->trace[0] > a->trace[1]))
      throw CLI::ValidationError(
          "--trace", "takes FROM TO in seconds (FROM <= TO) and needs --offline");
    if (!a->record.empty()) {
      std::vector<KeptFile> inputs = {{a->scene, "the scene being run"}};
      if (const std::filesystem::path in = ParseDeviceName(a->device).file(); !in.empty())
        inputs.push_back({in, "the device's input file"});
      RefuseOverwrite(a->record, inputs);
    }
    Finish(Run(*a));
  });

  auto watch = std::make_shared<double>(0);
  CLI::App* devices =
      app.add_subcommand("devices", "List the haptic and 6-DoF devices plugged in (USB)");
  devices->add_option("--watch", *watch,
                      "Then watch for devices arriving or leaving for this many seconds");
  devices->callback([watch] {
    std::printf("%s", DescribeScan(ScanUsb()).c_str());
    if (*watch > 0) {
      UsbWatcher watcher([](bool arrived, const UsbDeviceInfo& d) {
        std::printf("%s: %s (%s)\n", arrived ? "plugged in" : "unplugged", d.name.c_str(),
                    d.backend.c_str());
        std::fflush(stdout);
      });
      if (!watcher.supported()) {
        std::printf("cannot watch for devices: %s\n", watcher.error().c_str());
        return;
      }
      std::printf("watching for %.0f s ...\n", *watch);
      std::fflush(stdout);
      std::this_thread::sleep_for(std::chrono::duration<double>(*watch));
    }
  });

  CLI::App* recording = app.add_subcommand("recording", "Inspect and export recordings");
  recording->require_subcommand(1);
  auto file = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto csv = std::make_shared<bool>(false);
  CLI::App* exp =
      recording->add_subcommand("export", "Write a recording as CSV (one line per tick)");
  exp->add_option("FILE", *file, "Recording file")->required()->check(CLI::ExistingFile);
  exp->add_flag("--csv", *csv, "CSV (the only format so far)");
  exp->add_option("-o,--output", *out, "Output file (default: standard output)");
  // The callback holds every flag's storage: CLI11 writes through the pointers
  // while parsing, after this function has returned.
  exp->callback([file, out, csv] {
    (void)*csv;  // CSV is the only format; the flag is accepted for scripts that name it
    const Recording rec = ReadRecording(*file);
    if (!rec.warning.empty()) std::fprintf(stderr, "warning: %s\n", rec.warning.c_str());
    if (out->empty()) {
      ExportCsv(rec, std::cout);
    } else {
      RefuseOverwrite(*out, {{*file, "the recording being exported"}});
      AtomicFile f(*out);
      ExportCsv(rec, f.stream());
      f.Commit();
      std::fprintf(stderr, "wrote %zu ticks to %s\n", rec.frames.size(), out->c_str());
    }
  });
  auto info_file = std::make_shared<std::string>();
  CLI::App* info =
      recording->add_subcommand("info", "Print a recording's header and length");
  info->add_option("FILE", *info_file, "Recording file")
      ->required()
      ->check(CLI::ExistingFile);
  info->callback([info_file] {
    const Recording rec = ReadRecording(*info_file);
    std::printf("%s: format %u, device '%s', scene '%s' (hash %016" PRIx64
                "), %.0f Hz, %zu ticks (%.2f s), %" PRIu64 " bytes (%.1f bytes a tick)\n",
                info_file->c_str(), rec.header.version, rec.header.device_name.c_str(),
                rec.header.scene_file.c_str(), rec.header.scene_hash, rec.header.rate_hz,
                rec.frames.size(), rec.frames.size() / rec.header.rate_hz, rec.file_bytes,
                rec.frames.empty()
                    ? 0.0
                    : static_cast<double>(rec.file_bytes) / rec.frames.size());
    if (!rec.warning.empty()) std::printf("warning: %s\n", rec.warning.c_str());
  });
}

}  // namespace sulcus::cli
