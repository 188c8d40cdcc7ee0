#include "core/lesson/attempt.h"

#include <sodium.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <ctime>
#include <fstream>
#include <random>

#include "core/base/files.h"
#include "core/base/yaml_reader.h"
#include "core/lesson/report.h"
#include "core/lesson/results.h"
#include "core/lesson/scripted_student.h"
#include "core/lesson/sign_in.h"
#include "core/lesson/xapi.h"

namespace sulcus {

namespace fs = std::filesystem;

AttemptFolder NewAttemptFolder(const std::filesystem::path& results,
                               const std::string& student) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char stamp[32], iso[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S-", &tm);
  std::strftime(iso, sizeof iso, "%Y-%m-%dT%H:%M:%SZ", &tm);
  // The folder's name carries the student's name for a person browsing the
  // folders, cut so that it stays a valid file name (the database keeps the name
  // whole).
  constexpr std::size_t kNameChars = 60;
  std::string name = stamp;
  for (char c : student.substr(0, kNameChars))
    name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  AttemptFolder f{results / "attempts" / name, iso};
  std::error_code ec;
  for (int n = 2; std::filesystem::exists(f.dir, ec); ++n)
    f.dir = results / "attempts" / (name + "-" + std::to_string(n));
  if (!std::filesystem::create_directories(f.dir, ec) && ec) {
    const std::string why =
        ec == std::errc::read_only_file_system || ec == std::errc::permission_denied
            ? "the results folder cannot be written (read-only)"
        : ec == std::errc::no_space_on_device ? "the disk is full"
        : ec == std::errc::not_a_directory
            ? "a file stands where a folder is needed on the way"
            : ec.message();
    throw std::runtime_error("cannot make the attempt's folder " + f.dir.string() + ": " +
                             why + "; set SULCUS_RESULTS_DIR to a writable folder");
  }
  return f;
}

Answers AnswersOf(const LessonResult& r) {
  Answers a;
  for (const SiteResult& s : r.sites)
    if (s.entry) a.entries.push_back(*s.entry);
  a.diagnosis = r.declared;
  if (a.diagnosis && a.diagnosis->tick == kAfterReading) a.diagnosis->tick = r.last_tick;
  a.findings = r.inspection.findings;
  a.submitted = r.inspection.submitted_tick;
  a.views = r.inspection.views;
  return a;
}

std::string AttemptUuid(const fs::path& dir) {
  const fs::path file = dir / "uuid";
  {
    std::ifstream in(file);
    std::string kept;
    if (in >> kept && kept.size() == 36) return kept;
  }
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
  unsigned char b[16];
  randombytes_buf(b, sizeof b);
  b[6] = static_cast<unsigned char>((b[6] & 0x0f) | 0x40);  // version 4
  b[8] = static_cast<unsigned char>((b[8] & 0x3f) | 0x80);  // RFC 4122 variant
  char text[37];
  std::snprintf(text, sizeof text,
                "%02x%02x%02x%02x-%02x%02x-%02x%02x-%02x%02x-%02x%02x%02x%02x%02x%02x",
                b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], b[8], b[9], b[10], b[11],
                b[12], b[13], b[14], b[15]);
  const fs::path tmp = dir / "uuid.tmp";
  {
    std::ofstream out(tmp);
    out << text << "\n";
    if (!out.flush())
      throw std::runtime_error(file.string() + ": cannot write the attempt's UUID");
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec)
    throw std::runtime_error(file.string() +
                             ": cannot write the attempt's UUID: " + ec.message());
  return text;
}

std::string DemonstrationRefusal(const ResultsPlace& place,
                                 const std::string& device_kind) {
  if (place.url.empty() || (device_kind != "scripted" && device_kind != "replay"))
    return "";
  std::unique_ptr<ResultsStore> store;
  try {
    store = OpenResults(place);
  } catch (const ResultsError&) {
    return "";
  }
  if (store->Setting(kDemonstrationsSetting).value_or("") == "allowed") return "";
  return "a " + device_kind +
         " attempt is not a student's own work: the lab's shared store (" +
         place.Describe() +
         ") takes one under a student's name only when the instructor allows "
         "demonstrations (`sulcus-cli results demonstrations allow`)";
}

std::int64_t KeepAttempt(const LessonResult& r, const AttemptFolder& folder,
                         const std::filesystem::path& report_dir,
                         const ResultsPlace& results,
                         const std::function<void(const char*)>& step) {
  auto at = [&](const char* name) {
    if (step) step(name);
  };
  // Write-ahead: the folder says the attempt waits for the store, durably,
  // before anything else is written, and stops saying so only after its row is
  // committed. A stop at any instant (a kill, Ctrl-C while the server hangs, a
  // full disk) leaves the attempt stored, or waiting: `results sync`, `lesson
  // recover` and the start page store it then, once (by its UUID).
  const fs::path unstored = folder.dir / kUnstoredFile;
  auto mark_waiting = [&](const std::string& why) {
    AtomicFile w(unstored);
    w.stream() << "This attempt is kept here but is not in the results store ("
               << results.Describe() << "): " << why
               << "\n`sulcus-cli results sync` stores it once the store can take it.\n";
    w.Commit();
    SyncFolder(folder.dir);
  };
  // Refused before anything is written: never stored, never waiting.
  if (const std::string why = DemonstrationRefusal(results, r.device_kind); !why.empty())
    throw std::runtime_error(why);
  at("start");
  bool marked = true;
  try {
    mark_waiting("it was being stored when the station stopped");
  } catch (const std::exception&) {
    // A full disk: without a report the attempt waits for recovery just the
    // same (UnfinishedAttempts), as long as no report is left unmarked below.
    marked = false;
  }
  at("marked");
  const std::string uuid = AttemptUuid(folder.dir);
  StatementKey(folder.dir);  // with the UUID: ids for the LMS, kept before any is sent
  SaveAnswers(AnswersOf(r), folder.answers());
  at("answers");
  ReportInfo info;
  info.recording = folder.recording().string();
  info.started = folder.started;
  WriteReport(r, info, report_dir);
  at("report");
  try {
    const std::unique_ptr<ResultsStore> store = OpenResults(results);
    info.attempt_id =
        store->Store(r, folder.started, info.recording, folder.answers().string(),
                     report_dir.string(), uuid, KeptSignIn(folder.dir));
  } catch (const std::exception& e) {
    try {
      mark_waiting(e.what());
      marked = true;
    } catch (const std::exception&) {
    }
    // Unmarked, a report would say "kept": without it the attempt waits.
    if (!marked) {
      std::error_code ec;
      fs::remove(report_dir / "report.json", ec);
    }
    throw;
  }
  at("stored");
  // The record for the school's LMS: sent, or waiting whole in the folder. If
  // it can be neither (a full disk), the attempt stays marked: a sync stores it
  // again (once, by its UUID) and makes and sends its statements then.
  try {
    QueueStatements(folder.dir, r, uuid, folder.started, XapiSettingsFromEnv());
  } catch (const std::exception&) {
    if (!marked) try {
        mark_waiting("stored, but its xAPI statements could be neither sent nor kept");
      } catch (const std::exception&) {
      }
    return info.attempt_id;
  }
  at("xapi");
  std::error_code ec;
  fs::remove(unstored, ec);
  SyncFolder(folder.dir);
  at("unmarked");
  try {
    WriteReport(r, info, report_dir);  // again, now naming its attempt
  } catch (const std::exception&) {
    // A full disk: the report written before the commit stands.
  }
  at("kept");
  return info.attempt_id;
}

void WriteAttemptMarker(const AttemptFolder& folder, const AttemptMarker& m) {
  YAML::Emitter e;
  e << YAML::Comment(
           "A Sulcus attempt: what it takes to rebuild it if it was not finished")
    << YAML::BeginMap;
  e << YAML::Key << "lesson" << YAML::Value << m.lesson.string();
  e << YAML::Key << "student" << YAML::Value << m.student;
  e << YAML::Key << "mode" << YAML::Value << m.mode;
  e << YAML::Key << "seed" << YAML::Value << m.seed;
  e << YAML::Key << "started" << YAML::Value << m.started;
  e << YAML::EndMap;
  const fs::path file = folder.dir / "attempt.yaml",
                 tmp = folder.dir / "attempt.yaml.tmp";
  {
    std::ofstream out(tmp);
    out << e.c_str() << "\n";
    if (!out.flush())
      throw std::runtime_error(tmp.string() + ": cannot write the attempt's marker");
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec)
    throw std::runtime_error(file.string() +
                             ": cannot write the attempt's marker: " + ec.message());
}

AttemptMarker ReadAttemptMarker(const fs::path& dir) {
  YamlReader r(dir / "attempt.yaml", "attempt marker");
  const YAML::Node root =
      LoadYamlMap(r, "a map with lesson, student, mode, seed and started");
  r.CheckKeys(root, {"lesson", "student", "mode", "seed", "started"},
              "the attempt marker");
  AttemptMarker m;
  for (const char* k : {"lesson", "student", "mode", "started"})
    if (!root[k]) r.Error(root, std::string("the attempt marker needs '") + k + "'");
  if (root["lesson"]) m.lesson = r.Text(root["lesson"], "lesson");
  if (root["student"]) m.student = r.Text(root["student"], "student");
  if (root["mode"]) {
    m.mode = r.Text(root["mode"], "mode");
    if (m.mode != "practice" && m.mode != "assessment")
      r.Error(root["mode"], "'mode' must be practice or assessment");
  }
  if (root["seed"])
    m.seed = static_cast<std::uint64_t>(r.Number(root["seed"], "seed", 0, 9.0e15, 0));
  if (root["started"]) m.started = r.Text(root["started"], "started");
  r.ThrowIfErrors();
  return m;
}

std::vector<fs::path> UnfinishedAttempts(const fs::path& results) {
  std::vector<fs::path> out;
  std::error_code ec;
  const fs::path attempts = results / "attempts";
  if (!fs::is_directory(attempts, ec)) return out;
  for (const fs::directory_entry& d : fs::directory_iterator(attempts, ec)) {
    // Only folders inside the results: a link out of them is never followed
    // (a sync writes into what it recovers).
    if (d.is_symlink(ec) || !d.is_directory(ec)) continue;
    const fs::path dir = d.path();
    if (!fs::exists(dir / "attempt.yaml", ec) || fs::exists(dir / "recovery.txt", ec))
      continue;
    // Never kept, or kept in its folder but not in the database.
    if (!fs::exists(dir / "report.json", ec) || fs::exists(dir / kUnstoredFile, ec))
      out.push_back(dir);
  }
  std::sort(out.begin(), out.end());  // folder names start with their UTC time
  return out;
}

RecoveredAttempt RecoverAttempt(const fs::path& dir, const ResultsPlace& results,
                                const fs::path& cache_dir,
                                const BuildProgress& progress) {
  try {
    const AttemptMarker m = ReadAttemptMarker(dir);
    AttemptFolder folder{dir, m.started};
    AttemptOptions o;
    o.student = m.student;
    o.device = "replay:" + folder.recording().string();
    o.kind_of_recording = true;
    if (fs::exists(folder.answers())) o.answers = folder.answers();
    o.seed = m.seed;
    o.cache_dir = cache_dir;
    o.progress = progress;
    o.mode = m.mode == "assessment" ? LessonSpec::Mode::kAssessment
                                    : LessonSpec::Mode::kPractice;
    o.ending =
        "Sulcus stopped before the attempt was kept; it was rebuilt from its recording "
        "and entries";
    AttemptOutcome out = RunAttempt(m.lesson, o);
    LessonResult& r = out.result;
    const std::int64_t id = KeepAttempt(r, folder, dir, results);
    return {id, std::move(r)};
  } catch (const ResultsError&) {
    // The attempt was rebuilt; the store could not take it (a server down, a
    // full disk): it waits in its folder and is tried again, not marked as failed.
    throw;
  } catch (const std::exception& e) {
    std::ofstream why(dir / "recovery.txt");
    why << "This attempt could not be rebuilt: " << e.what() << "\n"
        << "Its files are left as they were; remove this file to try again.\n";
    throw;
  }
}

namespace {

// Rewrites the attempt's entries after each new one (atomically, SaveAnswers), so
// that a program stopped mid-attempt loses nothing entered. A file that cannot be
// written is said once and the attempt goes on (its entries are kept in memory).
class EntrySaver final : public TickConsumer {
 public:
  EntrySaver(const LessonRun& lesson, fs::path file, std::vector<std::string>* notes)
      : lesson_(lesson), file_(std::move(file)), notes_(notes) {}
  void OnTick(const TickRecord&) override { SaveIfNew(); }
  void OnEnd() override {
    SaveIfNew();
  }  // a scripted student charts when the probing ends

 private:
  void SaveIfNew() {
    if (lesson_.entries().size() == saved_ &&
        lesson_.declared().has_value() == declared_ &&
        lesson_.findings().size() == findings_ &&
        lesson_.submitted().has_value() == submitted_ && lesson_.views().size() == views_)
      return;
    saved_ = lesson_.entries().size();
    declared_ = lesson_.declared().has_value();
    findings_ = lesson_.findings().size();
    views_ = lesson_.views().size();
    submitted_ = lesson_.submitted().has_value();
    Answers a;
    a.entries = lesson_.entries();
    a.diagnosis = lesson_.declared();
    a.findings = lesson_.findings();
    a.submitted = lesson_.submitted();
    a.views = lesson_.views();
    try {
      SaveAnswers(a, file_);
    } catch (const std::exception& e) {
      if (!failed_)
        notes_->push_back(std::string("the entries cannot be saved as they go: ") +
                          e.what());
      failed_ = true;
    }
  }

  const LessonRun& lesson_;
  fs::path file_;
  std::vector<std::string>* notes_;
  std::size_t saved_ = 0, findings_ = 0, views_ = 0;
  bool declared_ = false, submitted_ = false, failed_ = false;
};

}  // namespace

SceneSpec LessonScene(const LessonSpec& spec, std::uint64_t seed) {
  SceneSpec scene = LoadSceneSpec(spec.scene);
  if (spec.case_spec.generated)
    scene = ApplyCase(scene, spec.teeth, spec.case_spec, seed);
  return scene;
}

AttemptOutcome RunAttempt(const std::filesystem::path& lesson_file,
                          const AttemptOptions& o) {
  using Clock = std::chrono::steady_clock;
  AttemptOutcome out;
  out.spec = LoadLessonSpec(lesson_file);
  const LessonSpec& spec = out.spec;
  if (o.seed) {
    out.seed = *o.seed;
  } else if (spec.case_spec.generated && spec.case_spec.random_seed) {
    out.seed = std::random_device{}() & 0xffffffffu;  // recorded with the attempt
  } else {
    out.seed = spec.case_spec.seed;
  }
  const auto t0 = Clock::now();
  out.scene = CompileScene(LessonScene(spec, out.seed), o.cache_dir, o.progress);
  FitLessonToCase(&out.spec, out.scene->spec);
  out.compile_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const CompiledScene& scene = *out.scene;

  if (o.mode) out.spec.mode = *o.mode;
  if (o.keep_in)
    WriteAttemptMarker(*o.keep_in, {lesson_file, o.student, ToString(spec.mode), out.seed,
                                    o.keep_in->started});
  LessonRun lesson(spec, scene, o.student, spec.case_spec.generated ? out.seed : 0);
  LessonDevice made = MakeLessonDevice(o.device, spec, scene, 60.0);
  if (!made.device.device)
    throw std::invalid_argument(
        "the mouse takes a lesson in the window (sulcus); here "
        "give student:NAME, scripted:NAME or replay:FILE");
  std::unique_ptr<ScriptedHand> student = std::move(made.student);
  DeviceSpec device = std::move(made.device);
  const std::string device_kind = o.kind_of_recording && device.replayed
                                      ? DeviceKindOf(device.replayed->header.device_name)
                                      : DeviceKindOf(o.device);
  out.notes = device.notes;
  SessionOptions so;
  so.record = o.record;
  so.device_name = device.name;
  so.max_ticks =
      spec.time_limit_s > 0
          ? static_cast<std::uint64_t>((spec.time_limit_s + 1) * scene.spec.rate_hz)
          : 0;
  Session session(scene, std::move(device), so);
  session.AddConsumer(&lesson);
  if (student && o.answers.empty()) {
    student->Attach(&lesson);
    student->SetLoop(&session.loop());  // offline: the hand's thread alone sends
    session.AddConsumer(student.get());
  }
  std::unique_ptr<EntrySaver> saver;
  if (o.keep_in) {
    saver = std::make_unique<EntrySaver>(lesson, o.keep_in->answers(), &out.notes);
    session.AddConsumer(saver.get());
  }
  for (TickConsumer* c : o.consumers) session.AddConsumer(c);
  // The answers are read before the run (a bad file fails at once), and each
  // entry applies when the stream reaches its tick, as it did live: charting a
  // site with the tip in it completes its reading there.
  std::optional<Answers> answers;
  if (!o.answers.empty()) {
    answers = LoadAnswers(o.answers);
    CheckAnswersFor(*answers, spec.teeth);
    for (const ChartEntry& e : answers->entries) lesson.Schedule(e);
  }
  const auto t1 = Clock::now();
  session.RunOffline();
  out.run_s = std::chrono::duration<double>(Clock::now() - t1).count();
  out.ticks = session.ticks_delivered();
  if (answers) {
    const Answers& a = *answers;
    if (a.diagnosis) lesson.Declare(*a.diagnosis);
    for (const Finding& f : a.findings) lesson.Record(f);
    if (a.submitted) lesson.Submit(*a.submitted);
    for (const ViewSample& v : a.views) lesson.View(v);
  }
  lesson.SetEnding(o.ending);
  out.result = lesson.Finish();
  out.result.device_kind = device_kind;
  // What was entered, with every tick resolved, so the attempt can be rebuilt.
  out.answers = AnswersOf(out.result);
  for (const ChartEntry& e : lesson.entries()) {
    const bool known = std::any_of(out.result.sites.begin(), out.result.sites.end(),
                                   [&](const SiteResult& s) { return s.site == e.site; });
    if (!known)
      out.answers.entries.push_back(
          e);  // entries for sites outside the path are kept too
  }
  return out;
}

}  // namespace sulcus
