// `sulcus-cli lesson validate|run|report`, `sulcus-cli results list|show|export`:
// lessons headless, their reports and the results database.

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "app/cli/commands.h"
#include "core/lesson/attempt.h"
#include "core/lesson/scripted_student.h"
#include "core/spheretree/cache.h"

namespace sulcus::cli {
namespace {

namespace fs = std::filesystem;

void PrintResult(const LessonResult& r) {
  std::printf("lesson: %s (%s), student %s\n", r.lesson_name.c_str(), r.mode.c_str(), r.student.c_str());
  for (const RubricLine& l : r.lines)
    std::printf("  %-8s %-12s %9.3f s  %s\n", ToString(l.status), l.category.c_str(),
                static_cast<double>(l.tick) / r.rate_hz, l.message.c_str());
  std::printf("categories:");
  for (const auto& [cat, credit] : r.category_credit) std::printf(" %s %.0f%%", cat.c_str(), 100 * credit);
  std::printf("\nscore %.1f / 100; %d of %d sites probed, %d charted; within 1 mm %.0f %%, exact %.0f %%, bias %+.2f mm "
              "(interdental %+.2f mm); force in band %.0f %%; %.1f s\n",
              r.total, r.sites_read, r.sites_total, r.sites_charted, r.within_1mm_pct, r.exact_pct, r.bias_mm,
              r.bias_proximal_mm, r.force_in_band_pct, r.duration_s);
  std::printf("diagnosis: truth %s; the student's chart %s; declared %s\n", r.true_dx.Summary().c_str(),
              r.chart_dx.Summary().c_str(), r.declared ? r.declared->Summary().c_str() : "nothing");
}

struct RunArgs {
  std::string lesson, device = "student:careful", student = "student", answers, out_dir, record;
  std::int64_t seed = -1;
  bool quiet = false;
};

int RunLesson(const RunArgs& a) {
  AttemptOptions o;
  o.student = a.student;
  o.device = a.device;
  o.answers = a.answers;
  if (a.seed >= 0) o.seed = static_cast<std::uint64_t>(a.seed);
  o.cache_dir = DefaultCacheDir();
  o.record = a.record;
  std::fprintf(stderr, "building the lesson's scene ...\n");
  const AttemptOutcome out = RunAttempt(a.lesson, o);
  for (const std::string& n : out.notes) std::fprintf(stderr, "%s\n", n.c_str());
  std::fprintf(stderr, "compiled in %.2f s; ran %" PRIu64 " ticks in %.2f s\n", out.compile_s, out.ticks, out.run_s);
  if (!a.quiet) PrintResult(out.result);
  return 0;
}

}  // namespace

void AddLessonCommands(CLI::App& app) {
  CLI::App* lesson = app.add_subcommand("lesson", "Lessons: check a lesson file, run it headless, report an attempt");
  lesson->require_subcommand(1);

  auto file = std::make_shared<std::string>();
  CLI::App* validate = lesson->add_subcommand("validate", "Check a lesson file and its scene; every error as file:line:column");
  validate->add_option("FILE", *file, "Lesson file (.yaml)")->required();
  validate->callback([file] {
    try {
      const LessonSpec s = LoadLessonSpec(*file);
      std::printf("%s: valid: '%s', %s, scene %s, %zu teeth, %zu sites, %zu steps\n", file->c_str(), s.name.c_str(),
                  ToString(s.mode), s.scene.string().c_str(), s.teeth.size(), s.path.size(), s.steps.size());
    } catch (const SceneLoadError& e) {
      std::fprintf(stderr, "%s\n", e.what());
      ExitStatus() = 1;
    }
  });

  auto a = std::make_shared<RunArgs>();
  CLI::App* run = lesson->add_subcommand("run", "Take a lesson headless with a scripted or replayed device, score it, "
                                               "write its report and store the attempt");
  run->add_option("FILE", a->lesson, "Lesson file (.yaml)")->required();
  std::string students;
  for (const std::string& n : ScriptedStudentNames()) students += (students.empty() ? "" : ", ") + n;
  run->add_option("--device", a->device,
                  "student:NAME (a scripted student: " + students + "), scripted:NAME|FILE.csv, or replay:FILE")
      ->capture_default_str();
  run->add_option("--student", a->student, "Who takes the lesson")->capture_default_str();
  run->add_option("--answers", a->answers, "An answers file: what the student charted and declared")
      ->check(CLI::ExistingFile);
  run->add_option("--seed", a->seed, "The generated case's seed (default: the lesson's, or drawn and stored)");
  run->add_option("--record", a->record, "Record the attempt to this file");
  run->add_flag("--quiet", a->quiet, "Print the summary only");
  run->callback([a] { ExitStatus() = RunLesson(*a); });
}

}  // namespace sulcus::cli
