// The haptic thread and its hand-offs (run under ThreadSanitizer in CI: the
// `tsan` preset), recordings and bit-exact replay.
#include "core/haptics/haptic_thread.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <span>
#include <sstream>
#include <thread>

#include "core/haptics/recording.h"
#include "core/haptics/scripted_device.h"
#include "tests/common/output.h"
#include "tests/core/haptics/test_scenes.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Out(const std::string& name) { return test::OutputPath("haptic_thread", name); }

test::Scene Block() {
  test::Scene s;
  s.tool = std::make_unique<SphereTree>(test::MakeProbe());
  s.Add(test::MakeBlock(4, 4, -1.5, -0.5, 0.5, 0.5), RigidTransform::Identity());
  return s;
}

RecordingHeader MakeHeader(std::uint64_t hash, double rate, const std::string& device) {
  RecordingHeader h;
  h.scene_hash = hash;
  h.rate_hz = rate;
  h.device_name = device;
  return h;
}

ScriptTarget BlockTop() {
  ScriptTarget t;
  t.p_W = Vector3(0, 0, 0);
  t.n_W = Vector3::UnitZ();
  return t;
}

TEST(TripleBuffer, ReaderAlwaysSeesACompleteValue) {
  struct Pair {
    std::uint64_t a = 0, b = 0;
  };
  TripleBuffer<Pair> buffer;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= 200000; ++i) {
      buffer.back() = {i, ~i};
      buffer.Publish();
    }
    done = true;
  });
  std::uint64_t last = 0, reads = 0;
  for (;;) {
    // Read `done` before acquiring: if it was set and nothing is fresh, the
    // writer's last value has been seen.
    const bool finished = done.load();
    if (!buffer.Acquire()) {
      if (finished) break;
      continue;
    }
    const Pair& p = buffer.front();
    ASSERT_EQ(p.b, ~p.a);
    ASSERT_GT(p.a, last) << "values arrive in order, never twice";
    last = p.a;
    ++reads;
  }
  writer.join();
  EXPECT_EQ(last, 200000u);
  EXPECT_GT(reads, 0u);
}

TEST(SpscRing, DeliversEverythingInOrderAndCountsDrops) {
  SpscRing<std::uint64_t, 1024> ring;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < 100000; ++i)
      while (!ring.Push(i)) std::this_thread::yield();
  });
  std::uint64_t next = 0, v = 0;
  while (next < 100000)
    if (ring.Pop(&v)) {
      ASSERT_EQ(v, next++);
    }
  producer.join();
  EXPECT_FALSE(ring.Pop(&v));
  SpscRing<int, 4> small;
  for (int i = 0; i < 6; ++i) small.Push(i);
  EXPECT_EQ(small.dropped(), 2u);
}

TEST(TimeHistogram, Percentiles) {
  TimeHistogram h;
  for (int i = 0; i < 1000; ++i) h.Add(i < 990 ? 100.2 : 900.5);
  h.Add(50000);
  EXPECT_EQ(h.count(), 1001u);
  EXPECT_DOUBLE_EQ(h.Percentile(0.5), 101);
  EXPECT_DOUBLE_EQ(h.Percentile(0.995), 901);
  EXPECT_DOUBLE_EQ(h.Percentile(1.0), 50000);
  EXPECT_DOUBLE_EQ(h.max_us(), 50000);
  EXPECT_EQ(h.CountAtLeast(900), 11u);
}

// How the thread waits for its next tick: the polled end of the wait, and the
// tenth of each period it always sleeps (the clock is not read: a plan only).
TEST(HapticThread, PollsMostOfAShortPeriodAndAlwaysSleepsATenth) {
  constexpr std::int64_t k10kHz = 100'000, k1kHz = 1'000'000;  // ns
  EXPECT_EQ(SpinNs(k10kHz, -1), 90'000);
  EXPECT_EQ(SpinNs(k1kHz, -1), 100'000);
  EXPECT_EQ(SpinNs(k10kHz, 0), 0);
  EXPECT_EQ(SpinNs(k10kHz, 30), 30'000);
  EXPECT_EQ(SpinNs(k10kHz, 500), 90'000) << "never more than 90 % of the period";
  // A tick due at 100 us whose predecessor ended at 2 us: poll from 10 us.
  EXPECT_EQ(PollFrom(2'000, 100'000, k10kHz, 90'000), 12'000)
      << "a tenth of the period slept after the work";
  EXPECT_EQ(PollFrom(2'000, 100'000, k10kHz, 40'000), 60'000);
  EXPECT_EQ(PollFrom(2'000, 100'000, k10kHz, 0), 100'000)
      << "spin 0 sleeps the whole wait";
  // Long work leaves less than a tenth: sleep until the deadline, never past it.
  EXPECT_EQ(PollFrom(95'000, 100'000, k10kHz, 90'000), 100'000);
  // At 1 kHz, work of 5 us: sleep until 900 us, poll the last 100.
  EXPECT_EQ(PollFrom(5'000, 1'000'000, k1kHz, SpinNs(k1kHz, -1)), 900'000);
}

// The real thread at 1 kHz, with a reader taking snapshots and events and sending
// commands meanwhile, as the window does.
TEST(HapticThread, RunsAtItsRateWhileAnotherThreadReadsAndCommands) {
  const test::Scene scene = Block();
  const auto model = scene.Model();
  ScriptedDevice device(MakeScript("poke", BlockTop(), 10.0));
  HapticLoop loop(*model, &device, {});
  // Counts the events of every tick, on the haptic thread, as a sink may.
  struct CountingSink final : TickSink {
    void Push(const TickRecord& r) noexcept override {
      events.fetch_add(static_cast<std::uint64_t>(r.num_events));
    }
    std::atomic<std::uint64_t> events{0};
  } sink;
  ThreadOptions options;
  options.max_ticks = 400;
  options.sink = &sink;
  HapticThread thread(&loop, options);
  thread.Start();
  std::uint64_t last_tick = 0, snapshots = 0;
  bool commanded = false;
  while (thread.running()) {
    if (loop.snapshots().Acquire()) {
      const HapticSnapshot& s = loop.snapshots().front();
      ASSERT_GE(s.tick, last_tick);
      ASSERT_TRUE(s.force_W.allFinite());
      last_tick = s.tick;
      ++snapshots;
      (void)thread.stats().period_us.Percentile(0.99);  // readable at any time
    }
    if (!commanded && last_tick > 100)
      commanded = loop.Send({HapticCommand::Kind::kSetForceScale, 0.5});
    std::this_thread::sleep_for(std::chrono::microseconds(300));
  }
  thread.Join();
  EXPECT_EQ(thread.stats().ticks.load(), 400u);
  EXPECT_EQ(thread.stats().step_us.count(), 400u);
  EXPECT_EQ(thread.stats().period_us.count(), 399u);
  EXPECT_GT(snapshots, 10u);
  EXPECT_TRUE(commanded);
  EXPECT_GE(sink.events.load(), 1u) << "at least the command's event";
  // The period is measured, whatever the machine's load; it cannot be below 0.
  EXPECT_GT(thread.stats().period_us.Percentile(0.5), 0.0);
}

// Hands each tick to a recorder and keeps what the loop computed, exactly, in
// room reserved before the thread starts.
class KeepingSink final : public TickSink {
 public:
  struct Kept {
    std::uint64_t tick;
    RigidTransform X_WG;
    Vector3 force_W, torque_W;
  };
  KeepingSink(TickSink* next, std::size_t room) : next_(next), kept_(room) {}
  void Push(const TickRecord& r) noexcept override {
    next_->Push(r);
    const std::size_t i = n_.load(std::memory_order_relaxed);
    if (i < kept_.size()) {
      kept_[i] = {r.tick, r.X_WG, r.force_W, r.torque_W};
      n_.store(i + 1, std::memory_order_release);
    }
  }
  std::span<const Kept> kept() const {
    return {kept_.data(), n_.load(std::memory_order_acquire)};
  }

 private:
  TickSink* next_;
  std::vector<Kept> kept_;
  std::atomic<std::size_t> n_{0};
};

// A recording holds the device's readings exactly (they are on the grid the loop
// snaps them to), so replaying it reproduces every pose and wrench the loop
// computed bit for bit; the rendered pose and the wrench are stored on their own
// grids, within half a step of what was computed.
TEST(Recording, ReplayReproducesPosesAndWrenchesBitForBit) {
  const test::Scene scene = Block();
  const auto model = scene.Model();
  const fs::path file = Out("random.rec");
  LoopOptions lo;
  lo.rate_hz = 2000;
  std::vector<KeepingSink::Kept> computed;
  {
    ScriptedDevice device(MakeScript("random", BlockTop(), 0.6, 7));
    HapticLoop loop(*model, &device, lo);
    RecordingWriter writer(file, MakeHeader(42, lo.rate_hz, "scripted:random"));
    KeepingSink keeping(&writer, 100000);
    ThreadOptions options;
    options.sink = &keeping;
    HapticThread thread(&loop, options);
    thread.Start();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    loop.Send({HapticCommand::Kind::kSetForceScale, 0.7});  // commands are replayed too
    thread.Join();
    writer.Finish();
    EXPECT_EQ(writer.dropped(), 0u);
    EXPECT_EQ(writer.written(), thread.stats().ticks.load());
    computed.assign(keeping.kept().begin(), keeping.kept().end());
  }
  const Recording rec = ReadRecording(file);
  EXPECT_EQ(rec.header.device_name, "scripted:random");
  EXPECT_EQ(rec.header.scene_hash, 42u);
  EXPECT_TRUE(rec.warning.empty()) << rec.warning;
  ASSERT_GE(rec.frames.size(), 1200u);
  ASSERT_EQ(rec.frames.size(), computed.size());
  // Compact: the residuals of a smooth hand are a byte or two, compressed further.
  EXPECT_LT(static_cast<double>(rec.file_bytes) / rec.frames.size(), 30.0);

  double worst_p = 0, worst_f = 0, worst_t = 0, worst_R = 0;
  for (std::size_t i = 0; i < rec.frames.size(); ++i) {
    const TickRecord& f = rec.frames[i];
    ASSERT_EQ(f.tick, computed[i].tick);
    worst_p = std::max(
        worst_p,
        (f.X_WG.translation() - computed[i].X_WG.translation()).cwiseAbs().maxCoeff());
    worst_R = std::max(
        worst_R, (f.X_WG.rotation() - computed[i].X_WG.rotation()).cwiseAbs().maxCoeff());
    worst_f = std::max(worst_f, (f.force_W - computed[i].force_W).cwiseAbs().maxCoeff());
    worst_t =
        std::max(worst_t, (f.torque_W - computed[i].torque_W).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst_p, kPositionStepMm / 2);
  EXPECT_LE(worst_f, 0.5 / 65536);
  EXPECT_LE(worst_t, 0.5 / 4096);
  EXPECT_LT(worst_R, 4 * kQuaternionStep);

  ReplayDevice replay(rec);
  HapticLoop loop(*model, &replay, lo);
  std::size_t differing = 0, in_contact = 0;
  ReplayOffline(rec, &loop, [&](std::size_t i, const HapticLoop& l) {
    const KeepingSink::Kept& want = computed[i];
    const TickRecord& got = l.last_record();
    const bool same = got.X_WG.ToMatrix4() == want.X_WG.ToMatrix4() &&
                      got.force_W == want.force_W && got.torque_W == want.torque_W;
    if (!same) ++differing;
    if (want.force_W.norm() > 0) ++in_contact;
  });
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(in_contact, rec.frames.size() / 4) << "the run must exercise contact";
  EXPECT_TRUE(replay.finished());
}

// The grid is its own fixed point: a decoded pose encodes to the same code, so a
// reading is snapped once and a replayed one is never moved again.
TEST(PoseGrid, ADecodedPoseHasTheSameCode) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int mismatches = 0;
  double worst_p = 0, worst_angle = 0;
  for (int i = 0; i < 20000; ++i) {
    const Quaternion q = Quaternion(u(rng), u(rng), u(rng), u(rng)).normalized();
    const RigidTransform X(q.toRotationMatrix(), Vector3(u(rng), u(rng), u(rng)) * 80);
    PoseCode code;
    ASSERT_TRUE(EncodePose(X, &code));
    const RigidTransform Y = DecodePose(code);
    worst_p =
        std::max(worst_p, (Y.translation() - X.translation()).cwiseAbs().maxCoeff());
    worst_angle = std::max(worst_angle, Quaternion(Y.rotation()).angularDistance(q));
    PoseCode again;
    ASSERT_TRUE(EncodePose(Y, &again));
    if (!(again == code)) ++mismatches;
  }
  EXPECT_LE(worst_p, kPositionStepMm / 2);
  EXPECT_LT(worst_angle, 1e-5);  // radians
  // Re-encoding may move a component by one step (normalising changes the norm
  // in the last bits); the loop never re-encodes a coded reading, so what matters
  // is that this is rare and tiny.
  EXPECT_LT(mismatches, 20000);
  PoseCode code;
  const RigidTransform bad(Matrix3::Identity(),
                           Vector3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
  EXPECT_FALSE(EncodePose(bad, &code));
}

TEST(Recording, BadFilesGiveClearErrorsAndTruncationKeepsFrames) {
  const fs::path file = Out("short.rec");
  {
    const test::Scene scene = Block();
    const auto model = scene.Model();
    ScriptedDevice device(MakeScript("poke", BlockTop(), 0.05));
    HapticLoop loop(*model, &device, {});
    RecordingWriter writer(file, MakeHeader(0, 1000, "scripted:poke"));
    // Two drains: the writer flushes the compressed stream at each.
    for (int i = 0; i < 50; ++i) {
      loop.Tick(false);
      writer.Push(loop.last_record());
      if (i == 24)
        while (writer.written() < 25)
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    writer.Finish();
  }
  const Recording whole = ReadRecording(file);
  ASSERT_EQ(whole.frames.size(), 50u);
  EXPECT_TRUE(whole.warning.empty()) << whole.warning;

  // Cut inside the last drain's bytes, as a crash would: the first drain's 25
  // frames are kept, with a warning.
  const fs::path cut = Out("cut.rec");
  fs::copy_file(file, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(file) - 20);
  const Recording partial = ReadRecording(cut);
  EXPECT_EQ(partial.frames.size(), 25u);
  EXPECT_NE(partial.warning.find("truncated after frame 25"), std::string::npos)
      << partial.warning;

  // Corrupt compressed bytes are refused or cut short, never read as ticks.
  const fs::path garbled = Out("garbled.rec");
  fs::copy_file(file, garbled, fs::copy_options::overwrite_existing);
  {
    std::fstream f(garbled, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(file)) - 30);
    const char junk[8] = {'\x13', '\x37', '\x42', '\x42', '\x13', '\x37', '\x42', '\x42'};
    f.write(junk, 8);
  }
  try {
    const Recording bad = ReadRecording(garbled);
    EXPECT_LT(bad.frames.size(), 50u);
    EXPECT_NE(bad.warning.find("truncated after frame"), std::string::npos)
        << bad.warning;
  } catch (const RecordingError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt"), std::string::npos) << e.what();
  }

  const fs::path text = Out("not.rec");
  std::ofstream(text) << "hello, this is not a recording";
  try {
    ReadRecording(text);
    FAIL();
  } catch (const RecordingError& e) {
    EXPECT_EQ(std::string(e.what()),
              text.string() + ": not a Sulcus recording (expected 'SULCUSR' at byte 0)");
  }
  // Another version.
  const fs::path v2 = Out("v2.rec");
  fs::copy_file(file, v2, fs::copy_options::overwrite_existing);
  {
    std::fstream f(v2, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(8);
    const std::uint32_t version = 4;
    f.write(reinterpret_cast<const char*>(&version), 4);
  }
  try {
    ReadRecording(v2);
    FAIL();
  } catch (const RecordingError& e) {
    EXPECT_EQ(std::string(e.what()),
              v2.string() +
                  ": byte 12: recording format version 4, this build reads versions 2 "
                  "and 3");
  }
  EXPECT_THROW(ReadRecording(Out("missing.rec")), RecordingError);

  std::ostringstream csv;
  ExportCsv(whole, csv);
  std::istringstream lines(csv.str());
  std::string line;
  int n = 0;
  std::getline(lines, line);
  EXPECT_EQ(line.rfind("tick,t_s,device_t_s,fresh,overrun,buttons,h_x_mm", 0), 0u);
  while (std::getline(lines, line)) ++n;
  EXPECT_EQ(n, 50);
}

TEST(Trajectory, CsvErrorsNameFileAndLine) {
  const fs::path file = Out("bad.csv");
  std::ofstream(file)
      << "t_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg\n0,0,0,0,0,0,0\n0.1,1,0,zero,0,0,0\n";
  try {
    LoadTrajectoryCsv(file);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ":3: column 4 is 'zero', expected a finite number");
  }
  std::ofstream(file)
      << "t_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg\n0,0,0,0,0,0,0\n0,1,0,0,0,0\n";
  try {
    LoadTrajectoryCsv(file);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() +
                  ":3: expected 7 or 8 columns "
                  "(t_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg[,buttons]), got 6");
  }
  std::ofstream(file) << "t_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg,buttons\n0,0,0,0,0,0,0,"
                         "0\n1,10,0,0,0,0,90,1\n";
  const Trajectory t = LoadTrajectoryCsv(file);
  EXPECT_DOUBLE_EQ(t.Sample(0.5).X_WH.translation().x(), 5);
  EXPECT_EQ(t.Sample(1).buttons, 1u);
  // A spreadsheet's file: a UTF-8 byte order mark before the header.
  std::ofstream(file)
      << "\xEF\xBB\xBFt_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg\n0,0,0,0,0,0,"
         "0\n1,10,0,0,0,0,0\n";
  EXPECT_DOUBLE_EQ(LoadTrajectoryCsv(file).Sample(1).X_WH.translation().x(), 10);
  // A megabyte cell is named, not echoed.
  std::ofstream(file) << "t_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg\n0,0,0,"
                      << std::string(1 << 20, 'z') << ",0,0,0\n";
  try {
    LoadTrajectoryCsv(file);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_LT(std::string(e.what()).size(), 400u);
    EXPECT_NE(std::string(e.what()).find("... (1048576 characters)"), std::string::npos);
  }
}

}  // namespace
}  // namespace sulcus
