// Attempts that are never lost: an attempt cut short by a stopped program is
// rebuilt from its recording and entries; a keeping stopped at any instant, or a
// disk that fills while it is kept, leaves the attempt stored or waiting, and a
// sync stores it exactly once; a device that vanishes mid-lesson is named.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/haptics/recording.h"
#include "core/lesson/attempt.h"
#include "core/lesson/report.h"
#include "core/lesson/results.h"
#include "core/lesson/scripted_student.h"
#include "tests/common/kill_sweep.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Lesson() {
  return fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing.yaml";
}
fs::path Out(const std::string& name) { return test::OutputPath("recovery", name); }
fs::path Cache() { return fs::path(SULCUS_TEST_OUTPUT) / "probing-cache"; }

using Made = test::MadeAttempt;
Made MakeAttempt(const fs::path& base, const std::string& student) {
  return test::MakeSpotAttempt(base, student, Cache());
}

TEST(Recovery, AnAttemptCutShortByAStoppedProgramIsRebuiltAndKeptAsIncomplete) {
  const fs::path results = Out("recovery");
  fs::remove_all(results);
  const AttemptFolder folder = NewAttemptFolder(results, "ada");
  // A student who charts each site as it reads it, so entries are spread over
  // the attempt (the careful one charts everything at the end).
  AttemptOptions o;
  o.student = "charting";
  o.device = "student:charting";
  o.cache_dir = Cache();
  o.record = folder.recording();
  const AttemptOutcome whole = RunAttempt(Lesson(), o);
  ASSERT_TRUE(whole.result.complete);
  // The program stops at about the middle: the recording ends there (its last
  // frame cut in half) and the entries saved so far are those made before it.
  const std::uint64_t cut =
      whole.result.first_tick + (whole.result.last_tick - whole.result.first_tick) / 2;
  Answers so_far;
  for (const ChartEntry& e : whole.answers.entries)
    if (e.tick < cut) so_far.entries.push_back(e);
  ASSERT_GT(so_far.entries.size(), 3u);
  ASSERT_LT(so_far.entries.size(), whole.answers.entries.size());
  SaveAnswers(so_far, folder.answers());
  fs::resize_file(folder.recording(), fs::file_size(folder.recording()) / 2 + 101);
  WriteAttemptMarker(folder, {Lesson(), "ada", "practice", 0, folder.started});
  EXPECT_EQ(ReadAttemptMarker(folder.dir).student, "ada");

  // A folder whose marker is broken is reported once, left as it was, and not tried
  // again.
  const AttemptFolder broken = NewAttemptFolder(results, "bob");
  std::ofstream(broken.dir / "attempt.yaml") << "lesson: [unclosed\n";
  ASSERT_EQ(UnfinishedAttempts(results), (std::vector<fs::path>{folder.dir, broken.dir}));
  EXPECT_THROW(RecoverAttempt(broken.dir, ResultsPlace(results), Cache()), LoadError);
  EXPECT_TRUE(fs::exists(broken.dir / "recovery.txt"));
  EXPECT_TRUE(fs::exists(broken.dir / "attempt.yaml"));
  // A link among the attempts to a folder elsewhere is never recovered into.
  const fs::path elsewhere = Out("recovery-elsewhere");
  fs::remove_all(elsewhere);
  fs::create_directories(elsewhere);
  std::ofstream(elsewhere / "attempt.yaml") << "lesson: x\n";
  fs::create_directory_symlink(elsewhere, results / "attempts" / "linked");
  EXPECT_EQ(UnfinishedAttempts(results), std::vector<fs::path>{folder.dir});

  const RecoveredAttempt kept =
      RecoverAttempt(folder.dir, ResultsPlace(results), Cache());
  EXPECT_FALSE(kept.result.complete);
  EXPECT_NE(kept.result.ended.find("rebuilt from its recording"), std::string::npos)
      << kept.result.ended;
  EXPECT_LT(kept.result.sites_charted, whole.result.sites_charted);
  EXPECT_EQ(kept.result.sites_charted, static_cast<int>(so_far.entries.size()));
  EXPECT_LT(kept.result.last_tick, whole.result.last_tick);
  EXPECT_LT(kept.result.total, whole.result.total);
  EXPECT_TRUE(fs::exists(folder.dir / "report.html"));
  EXPECT_TRUE(UnfinishedAttempts(results).empty());
  ResultsDb db(results / "results.db");
  const auto rows = db.Attempts("ada");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].id, kept.id);
  EXPECT_FALSE(rows[0].complete);
  EXPECT_EQ(rows[0].started, folder.started);
}

// A headless attempt in a real child process, killed with SIGKILL (a consumer
// stops the child at a tick, or after the last tick before the attempt is kept,
// and tells the parent): what it kept as it went (its marker, its recording up
// to what the recorder had written, its entries so far) rebuilds it,
// incomplete, in the results. `at` 0: after the last tick.
struct Killed {
  AttemptFolder folder;
  fs::path results;
};
Killed KillAttemptAt(const std::string& name, std::uint64_t at) {
  Killed k;
  k.results = Out(name);
  fs::remove_all(k.results);
  k.folder = NewAttemptFolder(k.results, "kim");
  int fds[2];
  EXPECT_EQ(pipe(fds), 0);
  const pid_t child = fork();
  EXPECT_GE(child, 0);
  if (child == 0) {
    close(fds[0]);
    struct Stop final : TickConsumer {
      int fd;
      std::uint64_t at;
      Stop(int f, std::uint64_t a) : fd(f), at(a) {}
      void Here() {
        const char c = 'k';
        if (write(fd, &c, 1) != 1) _exit(3);
        for (;;) pause();  // killed here
      }
      void OnTick(const TickRecord& r) override {
        if (at != 0 && r.tick == at) Here();
      }
      void OnEnd() override { Here(); }
    } stop(fds[1], at);
    AttemptOptions o;
    o.student = "kim";
    o.device = "student:careful";
    o.cache_dir = Cache();
    o.record = k.folder.recording();
    o.keep_in = &k.folder;
    o.consumers = {&stop};
    try {
      RunAttempt(Lesson(), o);
    } catch (...) {
      _exit(4);
    }
    _exit(5);
  }
  close(fds[1]);
  char c = 0;
  const bool told = read(fds[0], &c, 1) == 1;
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  close(fds[0]);
  EXPECT_TRUE(told) << "the child ended with "
                    << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  EXPECT_EQ(UnfinishedAttempts(k.results), std::vector<fs::path>{k.folder.dir});
  EXPECT_EQ(ReadAttemptMarker(k.folder.dir).student, "kim");
  return k;
}

TEST(Recovery, AHeadlessAttemptKilledMidLessonIsRebuiltFromItsRecording) {
  constexpr std::uint64_t kAt = 40000;  // four sites into the careful student's lesson
  const Killed k = KillAttemptAt("killed-mid", kAt);
  // The careful student charts when the probing is over: nothing entered yet.
  EXPECT_FALSE(fs::exists(k.folder.answers()));
  const Recording rec = ReadRecording(k.folder.recording());
  ASSERT_FALSE(rec.frames.empty());
  EXPECT_LE(rec.frames.back().tick, kAt);
  // At most what the recorder had not yet written is lost: its ring (8,192
  // ticks, which an offline run can fill ahead of the writer) and a stdio buffer.
  EXPECT_GT(rec.frames.back().tick, kAt - 8192 - 100);

  const RecoveredAttempt kept =
      RecoverAttempt(k.folder.dir, ResultsPlace(k.results), Cache());
  EXPECT_FALSE(kept.result.complete);
  EXPECT_GE(kept.result.sites_read, 3) << "the readings made before the kill are scored";
  EXPECT_LT(kept.result.sites_read, 24);
  EXPECT_EQ(kept.result.sites_charted, 0);
  EXPECT_LE(kept.result.last_tick, kAt);
  EXPECT_TRUE(UnfinishedAttempts(k.results).empty());
  ResultsDb db(k.results / "results.db");
  const auto rows = db.Attempts("kim");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].id, kept.id);
  EXPECT_FALSE(rows[0].complete);
}

// An attempt the database could not take (here a folder where the database
// file should be) is kept in its folder, marked, and stored by the next
// recovery: once.
TEST(Recovery, AnAttemptTheDatabaseCouldNotTakeIsStoredLaterAndOnce) {
  const fs::path results = Out("unstored");
  const Made made = MakeAttempt(results, "uma");
  const AttemptFolder& folder = made.folder;
  const AttemptOutcome& out = made.out;
  fs::create_directories(results / "results.db");
  EXPECT_ANY_THROW(KeepAttempt(out.result, folder, folder.dir, ResultsPlace(results)));
  EXPECT_TRUE(fs::exists(folder.dir / "report.json")) << "the report is kept";
  EXPECT_TRUE(fs::exists(folder.dir / kUnstoredFile)) << "and says it is not stored";
  fs::remove_all(results / "results.db");
  const auto waiting = UnfinishedAttempts(results);
  ASSERT_EQ(waiting.size(), 1u);
  EXPECT_EQ(waiting[0], folder.dir);
  const RecoveredAttempt kept =
      RecoverAttempt(folder.dir, ResultsPlace(results), Cache());
  EXPECT_GT(kept.id, 0);
  EXPECT_FALSE(fs::exists(folder.dir / kUnstoredFile));
  EXPECT_TRUE(UnfinishedAttempts(results).empty()) << "stored once";
  ResultsDb db(results / "results.db");
  EXPECT_EQ(db.Attempts("uma").size(), 1u);
}

// The kill sweep through KeepAttempt: a station stopped at each step of
// keeping an attempt (before the waiting mark, after it, after the entries,
// the report, the commit, the unmarking, the xAPI statements, at the end; by
// SIGKILL, SIGTERM and SIGINT in turn) and at timed instants within it (a
// child killed 0 to 30 ms after it started keeping): after a sync (the
// recovery of every attempt left waiting) every attempt is in the store
// exactly once, and none waits. Prints how each stop left the attempt.
TEST(Recovery, AKeepingStoppedAtAnyInstantIsStoredExactlyOnceAfterASync) {
  // One attempt, run once; each stop keeps a copy of its folder.
  const Made made = MakeAttempt(Out("sweep-template"), "sam");
  int waited = 0, n = 0;
  for (const test::SweepStop& st : test::SweepStops({0, 500, 2000, 5000, 10000, 30000})) {
    const fs::path results = Out("sweep-" + std::to_string(n++));
    fs::remove_all(results);
    waited += test::StopAndSync(made.folder, made.out.result, ResultsPlace(results), st,
                                Cache());
    ResultsDb db(results / "results.db");
    EXPECT_EQ(db.Attempts("sam").size(), 1u) << st.What() << ": exactly once";
  }
  // Stopped before the commit, the attempt must have waited.
  EXPECT_GE(waited, 5);
}

// A disk that fills while an attempt is kept (the station's results folder and
// its SQLite store on a small disk, filled but 0 bytes to 1 MB): the keeping
// fails at the mark, the entries, the report, the store or the xAPI record, or
// succeeds; each time the attempt is stored or waiting, and once the disk has
// room a sync stores it exactly once.
TEST(Recovery, ADiskThatFillsWhileAnAttemptIsKeptLosesNothing) {
  const Made made = MakeAttempt(Out("full-disk-template"), "fay");
  test::SmallDisk disk(Out("full-disk"), 4);
  int waited = 0, n = 0;
  for (const std::uintmax_t free :
       {0, 4096, 16384, 65536, 131072, 196608, 262144, 393216, 1048576}) {
    const fs::path results = disk.dir() / ("case-" + std::to_string(n++));
    const auto rows = [&] {
      return static_cast<int>(ResultsDb(results / "results.db").Attempts("fay").size());
    };
    waited += test::FullDiskAndSync(made.folder, made.out.result, disk,
                                    ResultsPlace(results), free, Cache(), rows);
    EXPECT_EQ(rows(), 1) << free << " bytes free: exactly once";
    fs::remove_all(results);  // room for the next case
  }
  EXPECT_GE(waited, 4) << "a disk with no room left most cases waiting";
}

TEST(Recovery, AHeadlessAttemptKilledBeforeItWasKeptLosesNoEntry) {
  const Killed k = KillAttemptAt("killed-end", 0);
  const Answers saved = LoadAnswers(k.folder.answers());
  EXPECT_EQ(saved.entries.size(), 24u) << "the chart, saved as it was entered";
  EXPECT_TRUE(saved.diagnosis.has_value());
  const RecoveredAttempt kept =
      RecoverAttempt(k.folder.dir, ResultsPlace(k.results), Cache());
  EXPECT_EQ(kept.result.sites_charted, 24);
  EXPECT_TRUE(kept.result.declared.has_value());
  EXPECT_TRUE(kept.result.complete) << "every step was done before the kill";
  ResultsDb db(k.results / "results.db");
  EXPECT_EQ(db.Attempts("kim").size(), 1u);
}

// A device that vanishes mid-lesson (as if unplugged) and comes back: wraps the
// careful student's hand, says it is gone between two times.
class VanishingDevice final : public Device {
 public:
  VanishingDevice(std::unique_ptr<Device> hand, double from_s, double to_s)
      : hand_(std::move(hand)), from_s_(from_s), to_s_(to_s) {}
  const DeviceCaps& caps() const override { return hand_->caps(); }
  void Start() override { hand_->Start(); }
  void Stop() noexcept override { hand_->Stop(); }
  // The hand waits while the device is gone: its script resumes where it was.
  bool Read(double t_s, DeviceSample* out) noexcept override {
    gone_ = t_s >= from_s_ && t_s < to_s_;
    if (gone_) return false;
    return hand_->Read(t_s >= to_s_ ? t_s - (to_s_ - from_s_) : t_s, out);
  }
  void Write(const Vector3& f, const Vector3& t) noexcept override { hand_->Write(f, t); }
  bool finished() const noexcept override { return hand_->finished(); }
  bool lost() const noexcept override { return gone_; }

 private:
  std::unique_ptr<Device> hand_;
  double from_s_, to_s_;
  bool gone_ = false;
};

TEST(DeviceLoss,
     ADeviceUnpluggedMidLessonGetsZeroForceAtOnceTheAttemptGoesOnAndTheReportNamesIt) {
  const LessonSpec spec = LoadLessonSpec(Lesson());
  const auto scene = CompileScene(LessonScene(spec, 0), Cache());
  ScriptedStudent student("careful", spec, *scene);
  LessonRun lesson(spec, *scene, "una");
  student.Attach(&lesson);
  constexpr double kFrom = 40.0, kTo = 41.0;  // seconds, while the student probes
  DeviceSpec device;
  device.device = std::make_unique<VanishingDevice>(student.MakeDevice(), kFrom, kTo);
  device.name = "student:careful, unplugged for a second";
  SessionOptions so;
  so.max_ticks =
      static_cast<std::uint64_t>((spec.time_limit_s + 1) * scene->spec.rate_hz);
  Session session(*scene, std::move(device), so);
  struct Forces final : TickConsumer {
    std::vector<double> n;
    void OnTick(const TickRecord& r) override {
      if (n.size() <= r.tick) n.resize(r.tick + 1);
      n[r.tick] = r.force_W.norm();
    }
  } forces;
  session.AddConsumer(&lesson);
  session.AddConsumer(&student);
  session.AddConsumer(&forces);
  session.RunOffline();
  const double rate = scene->spec.rate_hz;
  const auto from = static_cast<std::size_t>(kFrom * rate),
             to = static_cast<std::size_t>(kTo * rate);
  ASSERT_GT(forces.n.size(), to + 1000);
  double before = 0;
  for (std::size_t t = from - 1000; t < from; ++t) before = std::max(before, forces.n[t]);
  EXPECT_GT(before, 0.1) << "the student was probing when the device went";
  for (std::size_t t = from; t < to; ++t) ASSERT_EQ(forces.n[t], 0.0) << "tick " << t;
  // Back: the force rises from zero over the ramp (0.5 s), it does not jump.
  EXPECT_EQ(forces.n[to], 0.0);
  for (std::size_t t = to + 1; t < to + 50; ++t)
    EXPECT_LT(forces.n[t], 0.05) << "tick " << t;

  const LessonResult r = lesson.Finish();
  ASSERT_EQ(r.interruptions.size(), 1u);
  EXPECT_EQ(r.interruptions[0].lost_tick, from);
  EXPECT_EQ(r.interruptions[0].back_tick, to);
  EXPECT_TRUE(r.complete) << r.ended;
  EXPECT_EQ(r.sites_charted, 24);
  ReportInfo info;
  const std::string html = ReportHtml(r, info);
  EXPECT_NE(html.find("the device stopped answering at 40.0 s and was back 1.0 s later"),
            std::string::npos);
}

}  // namespace
}  // namespace sulcus
