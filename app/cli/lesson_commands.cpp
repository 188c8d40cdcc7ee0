// `sulcus-cli lesson validate|run|report`, `sulcus-cli results list|show|export`:
// lessons headless, their reports and the results database.

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>
#include <string>

#include "app/cli/commands.h"
#include "core/base/files.h"
#include "core/base/names.h"
#include "core/base/text.h"
#include "core/lesson/attempt.h"
#include "core/lesson/instructor.h"
#include "core/lesson/report.h"
#include "core/lesson/results.h"
#include "core/lesson/scripted_student.h"
#include "core/lesson/sign_in.h"
#include "core/lesson/xapi.h"
#include "core/spheretree/cache.h"

namespace sulcus::cli {
namespace {

namespace fs = std::filesystem;

void PrintResult(const LessonResult& r) {
  std::printf("lesson: %s (%s), student %s\n", r.lesson_name.c_str(), r.mode.c_str(),
              r.student.c_str());
  // What needs attention and what was said; the lines that passed are counted
  // (every line is in the report).
  int passed = 0;
  for (const RubricLine& l : r.lines) {
    if (l.status == RubricLine::Status::kPass) {
      ++passed;
      continue;
    }
    std::printf("  %-8s %-12s %9.3f s  %s\n", ToString(l.status), l.category.c_str(),
                static_cast<double>(l.tick) / r.rate_hz, l.message.c_str());
  }
  std::printf("  (%d more lines passed; the report lists every line)\n", passed);
  std::printf("categories:");
  for (const auto& [cat, credit] : r.category_credit)
    std::printf(" %s %.0f%%", cat.c_str(), 100 * credit);
  if (r.kind == "inspection") {
    std::size_t examined = 0;
    for (const InspectionUnit& u : r.inspection.units) examined += u.touched;
    std::printf(
        "\nscore %.1f / 100; %zu of %zu regions and tooth surfaces examined; %.1f "
        "s\nfindings:",
        r.total, examined, r.inspection.units.size(), r.duration_s);
    for (const FindingScore& f : r.inspection.scores)
      if (f.kind != "status")
        std::printf(" %s %d of %d found, %d false;", f.kind.c_str(), f.tp, f.tp + f.fn,
                    f.fp);
    std::printf("\n");
    return;
  }
  std::printf(
      "\nscore %.1f / 100; %d of %d sites probed, %d charted; within 1 mm %.0f %%, exact "
      "%.0f %%, bias %+.2f mm "
      "(interdental %+.2f mm); force in band %.0f %%; %.1f s\n",
      r.total, r.sites_read, r.sites_total, r.sites_charted, r.within_1mm_pct,
      r.exact_pct, r.bias_mm, r.bias_proximal_mm, r.force_in_band_pct, r.duration_s);
  std::printf("diagnosis: truth %s; the student's chart %s; declared %s\n",
              r.true_dx.Summary().c_str(), r.chart_dx.Summary().c_str(),
              r.declared ? r.declared->Summary().c_str() : "nothing");
}

struct RunArgs {
  std::string lesson, device = "student:careful", student = "student", answers, out_dir,
                      results, passphrase_file;
  std::int64_t seed = -1;
  bool quiet = false, no_store = false;
};

// Progress of a cold scene build (the first run builds the sphere-trees, which
// takes a while): a line every 2 s once it has taken more than 1 s.
BuildProgress Progress() {
  struct State {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(),
                                          last = start;
  };
  auto st = std::make_shared<State>();
  return [st](std::string_view stage, double f) {
    const auto now = std::chrono::steady_clock::now();
    if (now - st->start > std::chrono::seconds(1) &&
        now - st->last > std::chrono::seconds(2)) {
      std::fprintf(
          stderr,
          "  building the scene's sphere-trees (first run only): %3.0f %% (%.*s)\n",
          100 * f, static_cast<int>(stage.size()), stage.data());
      st->last = now;
    }
    return true;
  };
}

// A report folder given with -o: checked before the attempt runs, so nothing
// is lost to a folder that cannot take it.
void CheckReportFolder(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw FileError("-o " + dir.string() +
                    ": is a file, not a folder; give a folder for the report");
  if (fs::exists(dir / "report.json", ec))
    throw FileError("-o " + dir.string() +
                    ": already holds the report of another attempt, which would be "
                    "replaced; give a new folder");
}

// The results place a subcommand works on: a folder or a PostgreSQL URL.
void AddResultsOption(CLI::App* c, std::string* where) {
  c->add_option("--results", *where,
                "Results folder, or a PostgreSQL URL (default: $SULCUS_RESULTS_URL, "
                "else the folder's results.db)");
}

int RunLesson(const RunArgs& typed) {
  // The name checked at the door, before the lesson: never refused after it;
  // trimmed and composed (NFC) as the window does, one spelling per student.
  RunArgs a = typed;
  a.student = NormalName(typed.student);
  if (const std::string why = NameProblem(a.student); !why.empty())
    throw std::invalid_argument("--student '" + TerminalSafe(Shorten(typed.student, 60)) +
                                "': " + why);
  const ResultsPlace results = ResultsOf(a.results);
  if (!a.no_store)
    if (const std::string why = DemonstrationRefusal(results, DeviceKindOf(a.device));
        !why.empty())
      throw std::invalid_argument("--device " + a.device + ": " + why);
  if (!a.out_dir.empty()) CheckReportFolder(a.out_dir);
  // The student signs in before the lesson (a store that asks for it refuses
  // the attempt otherwise); a scripted or replayed attempt is nobody's.
  std::string sign_in;
  const std::string kind = DeviceKindOf(a.device);
  if (!a.no_store && kind != "scripted" && kind != "replay") {
    const std::string pass = StudentPassphrase(a.passphrase_file);
    std::unique_ptr<ResultsStore> store;
    try {
      store = OpenResults(results);
    } catch (const ResultsError& e) {
      // The lesson is taken all the same and its attempt waits in its folder
      // (a sync stores it): never lost because the server is down.
      std::fprintf(stderr, "cannot sign in now (%s); the attempt will wait\n", e.what());
    }
    if (store && !pass.empty()) {
      sign_in = SignIn(*store, a.student, pass).token;
    } else if (store && store->Setting(kSignInSetting) == "required") {
      throw std::invalid_argument(
          "--student " + a.student + ": " + results.Describe() +
          " takes a student's attempt only from that student, signed in: give the "
          "passphrase in $SULCUS_STUDENT_PASSPHRASE or --passphrase-file");
    }
  }
  const AttemptFolder folder = NewAttemptFolder(results.dir, a.student);
  if (!sign_in.empty()) KeepSignIn(folder.dir, sign_in);
  AttemptOptions o;
  o.student = a.student;
  o.device = a.device;
  o.answers = a.answers;
  if (a.seed >= 0) o.seed = static_cast<std::uint64_t>(a.seed);
  o.cache_dir = DefaultCacheDir();
  o.record = folder.recording();
  o.progress = Progress();
  // Kept as it goes (a marker and the entries so far): if this program is
  // stopped mid-attempt, the next start rebuilds it (lesson recover, the window).
  if (!a.no_store) o.keep_in = &folder;
  std::fprintf(stderr, "lesson %s, student '%s', device %s\n", a.lesson.c_str(),
               a.student.c_str(), a.device.c_str());
  // The lesson by its full path, so that the attempt can be rebuilt from anywhere.
  const AttemptOutcome out = RunAttempt(fs::absolute(a.lesson).lexically_normal(), o);
  for (const std::string& n : out.notes) std::fprintf(stderr, "%s\n", n.c_str());
  std::fprintf(stderr,
               "scene ready in %.2f s; %" PRIu64
               " ticks (%.1f s of lesson) ran in %.2f s\n",
               out.compile_s, out.ticks, out.result.duration_s, out.run_s);
  const fs::path report_dir = a.out_dir.empty() ? folder.dir : fs::path(a.out_dir);
  int status = 0;
  if (a.no_store) {
    SaveAnswers(out.answers, folder.answers());
    ReportInfo info;
    info.recording = folder.recording().string();
    info.started = folder.started;
    WriteReport(out.result, info, report_dir);
  } else {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      const std::int64_t id = KeepAttempt(out.result, folder, report_dir, results);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
              .count();
      std::fprintf(
          stderr,
          "kept as attempt %lld in %s (entries, report and database row in %.1f ms)\n",
          static_cast<long long>(id), results.Describe().c_str(), ms);
      if (fs::exists(folder.dir / "xapi-waiting.txt"))
        std::fprintf(
            stderr,
            "note: its xAPI statements could not be sent to the LRS; `sulcus-cli "
            "results sync` sends them (%s)\n",
            (folder.dir / "xapi-waiting.txt").c_str());
      // Kept: with its report elsewhere, the folder's marker would read as unfinished.
      std::error_code ec;
      if (report_dir != folder.dir) fs::remove(folder.dir / "attempt.yaml", ec);
    } catch (const ResultsError& e) {
      std::fprintf(stderr,
                   "error: the attempt was not stored in the results store: %s\n"
                   "(its recording, entries and report are kept in %s; `sulcus-cli "
                   "results sync` stores it later)\n",
                   e.what(), folder.dir.c_str());
      status = 1;
    }
  }
  if (!a.quiet)
    PrintResult(out.result);
  else
    std::printf("score %.1f / 100 (%s)\n", out.result.total, out.result.student.c_str());
  std::printf("report: %s\n", (report_dir / "report.html").c_str());
  return status;
}

struct ReportArgs {
  std::string what, out_dir, lesson, answers, results;
  std::int64_t seed = -1;
};

int Report(const ReportArgs& a) {
  AttemptOptions o;
  o.cache_dir = DefaultCacheDir();
  fs::path lesson = a.lesson, answers = a.answers, recording, out_dir = a.out_dir;
  ReportInfo info;
  std::optional<AttemptRow> row;
  const bool id = !a.what.empty() && std::all_of(a.what.begin(), a.what.end(),
                                                 [](char c) { return std::isdigit(c); });
  if (id) {
    const auto db = OpenResults(ResultsOf(a.results));
    row = db->Attempt(std::stoll(a.what));
    if (!row) throw std::invalid_argument("no attempt " + a.what + " in " + db->where());
    lesson = row->lesson_file;
    recording = row->recording;
    if (answers.empty()) answers = row->answers;
    o.student = row->student;
    if (row->generated_case) o.seed = row->case_seed;
    info.attempt_id = row->id;
    info.started = row->started;
    if (out_dir.empty()) {
      // A folder read from the store is not trusted: the report is written
      // there only when it lies inside this results folder (a row can say
      // anything); otherwise -o names where.
      const ResultsPlace place = ResultsOf(a.results);
      if (!IsInsideFolder(row->report_dir, place.dir / "attempts"))
        throw std::invalid_argument("attempt " + a.what + "'s stored report folder '" +
                                    TerminalSafe(Shorten(row->report_dir, 120)) +
                                    "' is not inside " +
                                    (place.dir / "attempts").string() +
                                    "; give the folder to write the report in with -o");
      out_dir = row->report_dir;
    }
  } else {
    recording = a.what;
    if (lesson.empty())
      throw std::invalid_argument(
          "a recording needs --lesson FILE (the lesson it was taken in)");
    if (answers.empty() && fs::exists(recording.parent_path() / "answers.yaml"))
      answers = recording.parent_path() / "answers.yaml";
    if (out_dir.empty())
      out_dir = recording.parent_path().empty() ? "." : recording.parent_path();
  }
  if (a.seed >= 0) o.seed = static_cast<std::uint64_t>(a.seed);
  if (!fs::exists(recording))
    throw std::invalid_argument("the recording " + recording.string() + " is missing");
  o.device = "replay:" + recording.string();
  o.answers = answers;
  o.progress = Progress();
  const AttemptOutcome out = RunAttempt(lesson, o);
  for (const std::string& n : out.notes) std::fprintf(stderr, "%s\n", n.c_str());
  info.recording = recording.string();
  WriteReport(out.result, info, out_dir);
  std::printf("score %.1f / 100", out.result.total);
  if (row)
    std::printf(
        " (stored: %.1f%s)", row->total,
        std::abs(row->total - out.result.total) < 1e-9 ? ", the same" : ", DIFFERENT");
  std::printf("\nreport: %s\n", (out_dir / "report.html").c_str());
  return row && std::abs(row->total - out.result.total) >= 1e-9 ? 1 : 0;
}

// `lesson case`: the lesson's case drawn from a seed and saved as a scene file;
// an existing file is never replaced.
int WriteCase(const std::string& lesson_file, std::int64_t seed, const std::string& out) {
  const LessonSpec spec = LoadLessonSpec(lesson_file);
  if (!spec.case_spec.generated) {
    std::fprintf(stderr,
                 "error: %s draws no case (it has no `case:`); a case is drawn for a "
                 "lesson such as lessons/periodontal_probing_case.yaml\n",
                 lesson_file.c_str());
    return 1;
  }
  std::error_code ec;
  if (fs::exists(out, ec)) {
    std::fprintf(stderr, "error: %s exists and is not replaced; give a new file\n",
                 out.c_str());
    return 1;
  }
  const std::uint64_t s = seed >= 0 ? static_cast<std::uint64_t>(seed)
                                    : (std::random_device{}() & 0xffffffffu);
  const SceneSpec scene = SaveCaseScene(spec, spec.case_spec, s, out);
  std::printf("%s: the case of %s, stage %s, %s, seed %llu (%zu objects)\n", out.c_str(),
              lesson_file.c_str(), ToString(spec.case_spec.stage),
              ToString(spec.case_spec.extent), static_cast<unsigned long long>(s),
              scene.objects.size());
  return 0;
}

}  // namespace

// --results: a folder, or a PostgreSQL URL (the attempts' folders then stay in
// the default folder). Without it: the default folder and $SULCUS_RESULTS_URL.
ResultsPlace ResultsOf(const std::string& option) {
  if (IsResultsUrl(option)) {
    // Every user of the machine sees a command line (ps): a password there is
    // refused, with where to put it instead.
    if (!UrlPassword(option).empty())
      throw std::invalid_argument(
          "--results " + RedactUrl(option) +
          ": a password on the command line is shown to every user of this machine; "
          "give it in SULCUS_RESULTS_URL or a pgpass file (~/.pgpass) instead");
    return ResultsPlace(DefaultResultsDir(), option);
  }
  return ResultsPlaceFor(option.empty() ? DefaultResultsDir() : fs::path(option));
}

void RequireInstructor(const std::string& results_option) {
  const ResultsPlace place = ResultsOf(results_option);
  const InstructorLock lock(place);
  if (!lock.is_set())
    throw std::invalid_argument("no instructor's passphrase is set for " +
                                place.Describe() +
                                ": set it in the window's instructor view first");
  std::string pass;
  if (const char* env = std::getenv("SULCUS_INSTRUCTOR_PASSPHRASE")) {
    pass = env;
  } else {
    std::fprintf(stderr, "The instructor's passphrase: ");
    std::getline(std::cin, pass);
  }
  if (!lock.Check(pass))
    throw std::invalid_argument(
        "the instructor's passphrase is not right; nothing was changed");
}

std::string StudentPassphrase(const std::string& passphrase_file) {
  if (const char* env = std::getenv("SULCUS_STUDENT_PASSPHRASE"); env && *env) return env;
  if (passphrase_file.empty()) return "";
  std::ifstream in(passphrase_file);
  std::string line;
  if (!in || !std::getline(in, line))
    throw std::invalid_argument("--passphrase-file " + passphrase_file +
                                ": cannot be read (the passphrase is its first line)");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

void AddLessonCommands(CLI::App& app) {
  CLI::App* lesson = app.add_subcommand(
      "lesson", "Lessons: check a lesson file, run it headless, report an attempt");
  lesson->require_subcommand(1);

  auto file = std::make_shared<std::string>();
  CLI::App* validate = lesson->add_subcommand(
      "validate", "Check a lesson file and its scene; every error as file:line:column");
  validate->add_option("FILE", *file, "Lesson file (.yaml)")->required();
  validate->callback([file] {
    try {
      const LessonSpec s = LoadLessonSpec(*file);
      if (s.inspection())
        std::printf(
            "%s: valid: '%s', inspection, %s, scene %s, %zu teeth, %zu regions, %zu "
            "steps\n",
            file->c_str(), s.name.c_str(), ToString(s.mode), s.scene.string().c_str(),
            s.teeth.size(), s.regions.size(), s.steps.size());
      else
        std::printf("%s: valid: '%s', %s, scene %s, %zu teeth, %zu sites, %zu steps\n",
                    file->c_str(), s.name.c_str(), ToString(s.mode),
                    s.scene.string().c_str(), s.teeth.size(), s.path.size(),
                    s.steps.size());
    } catch (const LoadError& e) {
      std::fprintf(stderr, "%s\n%s\n", e.what(), e.Summary().c_str());
      Finish(1);
    }
  });

  auto a = std::make_shared<RunArgs>();
  CLI::App* run = lesson->add_subcommand(
      "run",
      "Take a lesson headless with a scripted or replayed device, score it, "
      "write its report and store the attempt");
  run->add_option("FILE", a->lesson, "Lesson file (.yaml)")->required();
  std::string students;
  for (const std::string& n : ScriptedStudentNames())
    students += (students.empty() ? "" : ", ") + n;
  run->add_option("--device", a->device,
                  "student:NAME (a scripted student: " + students +
                      "), scripted:NAME|FILE.csv, or replay:FILE")
      ->capture_default_str();
  run->add_option("--student", a->student, "Who takes the lesson")->capture_default_str();
  run->add_option("--passphrase-file", a->passphrase_file,
                  "The student's passphrase, the file's first line (or "
                  "$SULCUS_STUDENT_PASSPHRASE): signs the student in; set at first use");
  run->add_option("--answers", a->answers,
                  "An answers file: what the student charted and declared")
      ->check(CLI::ExistingFile);
  run->add_option(
      "--seed", a->seed,
      "The generated case's seed (default: the lesson's, or drawn and stored)");
  run->add_option("-o,--output", a->out_dir,
                  "Write the report here (default: the attempt's folder)");
  run->add_option(
      "--results", a->results,
      "Results folder (default: $SULCUS_RESULTS_DIR or ~/.local/share/sulcus)");
  run->add_flag("--no-store", a->no_store,
                "Do not store the attempt in the results database");
  run->add_flag("--quiet", a->quiet, "Print the score only, not every line");
  run->callback([a] { Finish(RunLesson(*a)); });

  struct CaseArgs {
    std::string lesson, out;
    std::int64_t seed = -1;
  };
  auto c = std::make_shared<CaseArgs>();
  CLI::App* drawn = lesson->add_subcommand(
      "case",
      "Write the scene of a lesson's generated case (its stage and extent, a seed) as "
      "a scene file of its own, an instructor's fixed case");
  drawn->add_option("FILE", c->lesson, "Lesson file with a case: (.yaml)")->required();
  drawn->add_option("--seed", c->seed, "The case's seed (default: drawn)");
  drawn->add_option("-o,--output", c->out, "The scene file to write (.yaml)")->required();
  drawn->callback([c] { Finish(WriteCase(c->lesson, c->seed, c->out)); });

  auto r = std::make_shared<ReportArgs>();
  CLI::App* report =
      lesson->add_subcommand("report",
                             "Rebuild an attempt's report from its recording and entries "
                             "(an attempt id from `results list`, or a recording file)");
  report->add_option("ATTEMPT_OR_RECORDING", r->what, "Attempt id, or a recording (.rec)")
      ->required();
  report->add_option("-o,--output", r->out_dir,
                     "Write the report here (default: beside the recording)");
  report->add_option("--lesson", r->lesson, "The lesson (for a recording)");
  report->add_option(
      "--answers", r->answers,
      "The entries (default: the attempt's, or answers.yaml beside the recording)");
  report->add_option("--seed", r->seed, "A generated case's seed (for a recording)");
  report->add_option("--results", r->results, "Results folder");
  report->callback([r] { Finish(Report(*r)); });

  auto recover_dir = std::make_shared<std::string>();
  CLI::App* recover = lesson->add_subcommand(
      "recover",
      "Keep the attempts that were started and never kept (the program stopped "
      "mid-lesson): each is "
      "rebuilt from its recording and entries and stored as incomplete");
  recover->add_option("--results", *recover_dir, "Results folder");
  recover->callback([recover_dir] {
    const ResultsPlace results = ResultsOf(*recover_dir);
    const std::vector<fs::path> dirs = UnfinishedAttempts(results.dir);
    if (dirs.empty()) std::printf("no unfinished attempts in %s\n", results.dir.c_str());
    int status = 0;
    for (const fs::path& d : dirs) {
      try {
        const RecoveredAttempt a =
            RecoverAttempt(d, results, DefaultCacheDir(), Progress());
        std::printf("kept %s as attempt %lld: %.1f / 100, %s\n", d.c_str(),
                    static_cast<long long>(a.id), a.result.total,
                    a.result.complete ? "complete"
                                      : ("incomplete (" + a.result.ended + ")").c_str());
      } catch (const std::exception& e) {
        std::fprintf(
            stderr, "error: %s cannot be rebuilt: %s (its files are left as they were)\n",
            d.c_str(), e.what());
        status = 1;  // the others are still tried
      }
    }
    Finish(status);
  });

  CLI::App* results = app.add_subcommand(
      "results", "Students' results: list, show, export as CSV, sync to the store");
  results->require_subcommand(1);
  auto q = std::make_shared<std::array<std::string, 4>>();  // student, lesson, output,
                                                            // results folder
  auto sites = std::make_shared<bool>(false);
  auto id = std::make_shared<std::int64_t>(0);
  CLI::App* list =
      results->add_subcommand("list", "Every attempt, or a student's or a lesson's");
  CLI::App* show = results->add_subcommand("show", "One attempt: its scores and sites");
  CLI::App* exp = results->add_subcommand(
      "export", "A student's or a cohort's attempts (or sites) as CSV");
  for (CLI::App* c : {list, exp}) {
    c->add_option("--student", (*q)[0], "Only this student");
    c->add_option("--lesson", (*q)[1], "Only this lesson file");
  }
  for (CLI::App* c : {list, show, exp}) AddResultsOption(c, &(*q)[3]);
  show->add_option("ATTEMPT", *id, "Attempt id")->required()->check(WholeNumber());
  exp->add_option("-o,--output", (*q)[2], "CSV file (default: standard output)");
  exp->add_flag("--sites", *sites, "One line per site instead of per attempt");
  list->callback([q] {
    const auto db = OpenResults(ResultsOf((*q)[3]));
    const auto rows = db->Attempts((*q)[0], (*q)[1]);
    std::printf("%6s  %-20s  %-16s  %-36s  %-8s  %6s  %8s  %s\n", "id", "started",
                "student", "lesson", "device", "score", "within1", "diagnosis declared");
    for (const AttemptRow& a : rows) {
      // An inspection has no sites and no diagnosis: its columns say so.
      const bool sites = a.sites_total > 0;
      char within[16];
      std::snprintf(within, sizeof within, "%.0f%%", a.within_1mm_pct);
      // Names and texts from the store as safe to read: a name cannot forge a
      // row, move the cursor or turn the line round.
      std::printf("%6lld  %-20s  %-16s  %-36s  %-8s  %6.1f  %8s  %s\n",
                  static_cast<long long>(a.id), TerminalSafe(a.started).c_str(),
                  TerminalSafe(a.student).c_str(),
                  TerminalSafe(a.lesson_name.substr(0, 36)).c_str(),
                  a.device.empty() ? "-" : TerminalSafe(a.device).c_str(), a.total,
                  sites ? within : "-",
                  TerminalSafe((sites ? a.declared_dx : std::string("-")) +
                               (a.complete ? "" : "  [incomplete: " + a.ended + "]"))
                      .c_str());
    }
    std::printf("%zu attempts in %s\n", rows.size(), db->where().c_str());
  });
  show->callback([q, id] {
    const auto db = OpenResults(ResultsOf((*q)[3]));
    const auto a = db->Attempt(*id);
    if (!a)
      throw std::invalid_argument("no attempt " + std::to_string(*id) + " in " +
                                  db->where());
    std::printf(
        "attempt %lld: %s, %s (%s), %s\nscore %.1f / 100; %d of %d sites probed, %d "
        "charted; within 1 mm %.0f %%, "
        "bias %+.2f mm; force in band %.0f %%; %.1f s\ndiagnosis: truth %s; chart %s; "
        "declared %s\n"
        "recording %s\nreport %s/report.html\n",
        static_cast<long long>(a->id), TerminalSafe(a->student).c_str(),
        TerminalSafe(a->lesson_name).c_str(), TerminalSafe(a->mode).c_str(),
        TerminalSafe(a->started).c_str(), a->total, a->sites_read, a->sites_total,
        a->sites_charted, a->within_1mm_pct, a->bias_mm, a->force_in_band_pct,
        a->duration_s, TerminalSafe(a->true_dx).c_str(),
        TerminalSafe(a->chart_dx).c_str(), TerminalSafe(a->declared_dx).c_str(),
        TerminalSafe(a->recording).c_str(), TerminalSafe(a->report_dir).c_str());
    if (!a->complete) std::printf("incomplete: %s\n", TerminalSafe(a->ended).c_str());
    if (!a->device.empty())
      std::printf(
          "taken with: %s%s\n", TerminalSafe(a->device).c_str(),
          a->device == "scripted" || a->device == "replay" ? " (a demonstration)" : "");
    for (const SiteRow& s : db->Sites(a->student, a->lesson_file)) {
      if (s.attempt != a->id) continue;
      std::printf("  %d %-2s truth %d  reached %s  entered %s  %.2f N\n", s.fdi,
                  SiteCode(s.site), s.truth_mm,
                  s.reached_mm ? std::to_string(*s.reached_mm).substr(0, 4).c_str() : "-",
                  s.entered_mm ? std::to_string(*s.entered_mm).c_str() : "-",
                  s.peak_force_n);
    }
  });
  // Demonstrations: scripted or replayed attempts under a student's name in a
  // lab's shared store, allowed or forbidden by the instructor (passphrase).
  auto demo = std::make_shared<std::array<std::string, 2>>();  // allow|forbid, results
  CLI::App* demos = results->add_subcommand(
      "demonstrations",
      "Allow or forbid scripted and replayed attempts under a student's name in the "
      "lab's shared store (the instructor's passphrase: $SULCUS_INSTRUCTOR_PASSPHRASE "
      "or typed)");
  demos->add_option("WHAT", (*demo)[0], "allow or forbid")
      ->required()
      ->check(CLI::IsMember({"allow", "forbid"}));
  AddResultsOption(demos, &(*demo)[1]);
  demos->callback([demo] {
    const ResultsPlace place = ResultsOf((*demo)[1]);
    RequireInstructor((*demo)[1]);
    OpenResults(place)->SetSetting(kDemonstrationsSetting,
                                   (*demo)[0] == "allow" ? "allowed" : "forbidden");
    std::printf("demonstrations %s in %s\n",
                (*demo)[0] == "allow" ? "allowed" : "forbidden",
                place.Describe().c_str());
  });
  // No change unseen: the attempts' hash chain recomputed.
  auto verify_dir = std::make_shared<std::string>();
  CLI::App* verify = results->add_subcommand(
      "verify",
      "Recompute the attempts' hash chain and name every row that was changed, or "
      "after a row that was changed or removed; print the chain's last hash");
  AddResultsOption(verify, verify_dir.get());
  verify->callback([verify_dir] {
    const auto db = OpenResults(ResultsOf(*verify_dir));
    const ChainCheck c = CheckChain(db->Chain());
    for (const ChainBreak& b : c.breaks)
      std::printf("attempt %lld: %s\n", static_cast<long long>(b.id), b.why.c_str());
    std::printf("%d attempts, %d in the chain (%d stored before it) in %s: %s\n", c.rows,
                c.chained, c.rows - c.chained, db->where().c_str(),
                c.breaks.empty() ? "the chain holds" : "the chain does NOT hold");
    if (!c.last_hash.empty())
      std::printf(
          "the chain's last hash: %s (keep it apart from the store: a later "
          "verify whose chain no longer passes through it was rewritten)\n",
          c.last_hash.c_str());
    if (!c.breaks.empty()) Finish(1);
  });
  // The lab's store set up once by the school's database administrator.
  auto owner = std::make_shared<std::string>();
  CLI::App* setup = results->add_subcommand(
      "setup",
      "Set up a lab's PostgreSQL store once, as its owner: the tables, and the roles "
      "sulcus_station (stores and reads attempts, nothing else) and sulcus_instructor "
      "(reads everything, writes the instructor's settings)");
  setup->add_option(
      "--owner", *owner,
      "The owner's URL without its password (default: "
      "$SULCUS_OWNER_URL, which may hold it; else PGPASSWORD or ~/.pgpass)");
  setup->callback([owner] {
    std::string url = *owner;
    if (!url.empty() && !UrlPassword(url).empty())
      throw std::invalid_argument(
          "--owner " + RedactUrl(url) +
          ": a password on the command line is shown to every user of this machine; "
          "give it in SULCUS_OWNER_URL, PGPASSWORD or a pgpass file instead");
    if (url.empty())
      if (const char* env = std::getenv("SULCUS_OWNER_URL")) url = env;
    if (!IsResultsUrl(url))
      throw std::invalid_argument(
          "results setup needs the owner's PostgreSQL URL (--owner or "
          "SULCUS_OWNER_URL), e.g. postgresql://sulcus@lab-server/sulcus");
    const auto env = [](const char* name) {
      const char* v = std::getenv(name);
      return std::string(v ? v : "");
    };
    const StoreSetup done = SetUpPostgresStore(url, env("SULCUS_STATION_PASSWORD"),
                                               env("SULCUS_INSTRUCTOR_PASSWORD"));
    std::printf("%s:\n", RedactUrl(url).c_str());
    for (const std::string& d : done.done) std::printf("  %s\n", d.c_str());
    // The passwords the administrator hands on (made here when not given).
    if (env("SULCUS_STATION_PASSWORD").empty())
      std::printf(
          "the stations' password (shown once; put it in each station's "
          "SULCUS_RESULTS_URL or ~/.pgpass, user %s): %s\n",
          kStationRole, done.station_password.c_str());
    if (env("SULCUS_INSTRUCTOR_PASSWORD").empty())
      std::printf(
          "the instructor's password (shown once; the instructor's view "
          "reads every attempt with it, user %s): %s\n",
          kInstructorRole, done.instructor_password.c_str());
  });
  AddRosterCommands(results);
  auto sync_dir = std::make_shared<std::string>();
  CLI::App* sync = results->add_subcommand(
      "sync",
      "Send what this station kept while the results store or the LRS could not be "
      "reached: the attempts (each stored once) and their xAPI statements");
  AddResultsOption(sync, sync_dir.get());
  sync->callback([sync_dir] {
    const ResultsPlace place = ResultsOf(*sync_dir);
    int status = 0;
    const std::vector<fs::path> waiting = UnfinishedAttempts(place.dir);
    std::printf("%zu attempt(s) waiting in %s for %s\n", waiting.size(),
                place.dir.c_str(), place.Describe().c_str());
    if (!waiting.empty()) {
      // Reached first: with the server still down nothing is rebuilt in vain.
      OpenResults(place);
      const auto t0 = std::chrono::steady_clock::now();
      int stored = 0;
      for (const fs::path& d : waiting) {
        try {
          const RecoveredAttempt a =
              RecoverAttempt(d, place, DefaultCacheDir(), Progress());
          std::printf("stored %s as attempt %lld (%.1f / 100)\n", d.c_str(),
                      static_cast<long long>(a.id), a.result.total);
          ++stored;
        } catch (const std::exception& e) {
          std::fprintf(stderr, "error: %s is still waiting: %s\n", d.c_str(), e.what());
          status = 1;
        }
      }
      std::printf(
          "%d of %zu stored in %.1f s\n", stored, waiting.size(),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    // The LMS's records that wait for the LRS.
    const std::vector<fs::path> records = WaitingStatements(place.dir);
    const XapiSettings lrs = XapiSettingsFromEnv();
    if (!records.empty() && !lrs.enabled()) {
      std::fprintf(
          stderr,
          "error: %zu attempt(s) have xAPI statements waiting, and no LRS is set "
          "(SULCUS_LRS_URL)\n",
          records.size());
      status = 1;
    }
    if (!records.empty() && lrs.enabled()) {
      int sent = 0;
      for (const fs::path& d : records) {
        std::string why;
        if (SendWaitingStatements(d, lrs, &why)) {
          ++sent;
        } else {
          std::fprintf(stderr, "error: %s: %s\n", d.c_str(), why.c_str());
          status = 1;
        }
      }
      std::printf("%d of %zu attempts' xAPI statements sent to %s\n", sent,
                  records.size(), RedactUrl(lrs.url).c_str());
    }
    Finish(status);
  });
  exp->callback([q, sites] {
    const ResultsPlace place = ResultsOf((*q)[3]);
    // Checked before the database is opened: an output onto the store would
    // empty it.
    if (!(*q)[2].empty() && place.url.empty())
      RefuseOverwrite((*q)[2], StoreFiles(place.sqlite_file()));
    const auto db = OpenResults(place);
    std::optional<AtomicFile> file;
    if (!(*q)[2].empty()) file.emplace((*q)[2]);
    std::ostream& out = file ? file->stream() : std::cout;
    if (*sites)
      ExportSitesCsv(db->Sites((*q)[0], (*q)[1]), out);
    else
      ExportAttemptsCsv(db->Attempts((*q)[0], (*q)[1]), out);
    if (file) {
      file->Commit();
      std::fprintf(stderr, "wrote %s\n", (*q)[2].c_str());
    } else {
      std::cout.flush();
      if (!std::cout) throw FileError("could not write the CSV to standard output");
    }
  });
}

}  // namespace sulcus::cli
