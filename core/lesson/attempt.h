#pragma once
// One attempt at a lesson, headless, from start to result: the lesson's scene
// (with its generated case, when it asks for one), a device (a scripted
// student, a scripted trajectory or a recording), the session run offline, the
// lesson over its tick stream, the student's entries (from the scripted student
// or an answers file) and the result. Every attempt is recorded, and its
// entries saved beside the recording, so that it can be rebuilt exactly.

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/lesson/answers.h"
#include "core/lesson/lesson.h"
#include "core/lesson/results.h"

namespace sulcus {

/// A new attempt's folder, `results`/attempts/<UTC time>-<student>, created, and
/// when it started (ISO 8601, UTC). Throws std::filesystem::filesystem_error.
struct AttemptFolder {
  std::filesystem::path dir;
  std::string started;
  std::filesystem::path recording() const { return dir / "recording.rec"; }
  std::filesystem::path answers() const { return dir / "answers.yaml"; }
};
AttemptFolder NewAttemptFolder(const std::filesystem::path& results,
                               const std::string& student);

struct AttemptOptions {
  std::string student = "student";
  /// student:NAME (ScriptedStudentNames), scripted:NAME|FILE.csv, replay:FILE.
  std::string device = "student:careful";
  std::filesystem::path
      answers;  // an answers file (overrides a scripted student's entries)
  std::optional<std::uint64_t>
      seed;  // a generated case's seed (default: the lesson's, or drawn)
  std::filesystem::path record;     // where to record the attempt (empty: no recording)
  std::filesystem::path cache_dir;  // meshes and sphere-trees
  BuildProgress progress;           // the scene's build progress
  std::optional<LessonSpec::Mode> mode;  // the lesson's own unless given
  std::string
      ending;  // how it ended, if it ends before its last step (LessonRun::SetEnding)
  /// Kept as it goes: the attempt's marker is written in this folder when it
  /// starts and its entries (answers.yaml) are rewritten after each one, so that
  /// an attempt cut short by a stopped program can be rebuilt (RecoverAttempt).
  /// Not owned; null: nothing is written before the attempt ends.
  const AttemptFolder* keep_in = nullptr;
  /// A replay that rebuilds an attempt (RecoverAttempt) keeps the kind of the
  /// device the attempt was taken with (the recording's), not "replay".
  bool kind_of_recording = false;
  /// More consumers of the tick stream, after the lesson and the student. Not owned.
  std::vector<TickConsumer*> consumers;
};

struct AttemptOutcome {
  LessonSpec spec;
  std::unique_ptr<CompiledScene> scene;
  LessonResult result;
  Answers answers;  // what was entered, with ticks
  std::uint64_t seed = 0;
  std::uint64_t ticks = 0;
  double run_s = 0;  // wall time of the run (not the lesson's own time)
  double compile_s = 0;
  std::vector<std::string> notes;
};

/// Throws LoadError, std::invalid_argument, RecordingError, std::runtime_error.
AttemptOutcome RunAttempt(const std::filesystem::path& lesson_file,
                          const AttemptOptions& options);

/// What the student entered, every tick resolved: each site's entry and the declaration.
Answers AnswersOf(const LessonResult& r);

/// Keeps a finished attempt, write-ahead: the folder is marked waiting
/// (kUnstoredFile, flushed to the disk) first; then its entries and its report
/// (in `report_dir`), its row in the results store of `results` (with the
/// attempt's UUID, so that storing it again finds it), the mark removed once
/// the row is committed, the xAPI statements, and the report again naming the
/// attempt. So a stop at any instant, or a store that fails or cannot be
/// reached, loses nothing: the folder says it waits until `sulcus-cli results
/// sync` stores it, once. Returns the attempt's id. Throws ResultsError
/// (store) or std::runtime_error (files). `step`, when given, is called with
/// the name of each step as it is reached (the kill sweep's test stops there).
/// The shared setting by which the instructor allows demonstrations ("allowed").
inline constexpr const char* kDemonstrationsSetting = "demonstrations";
/// Why an attempt taken with a device of `device_kind` (DeviceKindOf) may not be
/// stored under a student's name at `place` ("" when it may): a shared store
/// (PostgreSQL, a lab's) takes a scripted or replayed attempt only when the
/// instructor has allowed demonstrations; a station's own file always does. A
/// store that cannot be reached says nothing here (it is asked again when the
/// attempt is stored).
std::string DemonstrationRefusal(const ResultsPlace& place,
                                 const std::string& device_kind);

std::int64_t KeepAttempt(const LessonResult& r, const AttemptFolder& folder,
                         const std::filesystem::path& report_dir,
                         const ResultsPlace& results,
                         const std::function<void(const char*)>& step = {});

/// The attempt's UUID (version 4), made once and kept in its folder (`uuid`).
std::string AttemptUuid(const std::filesystem::path& dir);

/// What an attempt in progress needs to be rebuilt if the program stops before
/// it is kept: written as `attempt.yaml` in its folder when it starts. The
/// recording and the entries (answers.yaml, rewritten after each entry) are
/// written as the attempt goes.
struct AttemptMarker {
  std::filesystem::path lesson;
  std::string student, mode;  // mode: practice or assessment
  std::uint64_t seed = 0;
  std::string started;
};
/// Throws std::runtime_error naming the file.
void WriteAttemptMarker(const AttemptFolder& folder, const AttemptMarker& m);
/// Throws LoadError (file:line:column) for a marker that does not read.
AttemptMarker ReadAttemptMarker(const std::filesystem::path& dir);

/// The file in an attempt's folder saying its report is kept there but its row
/// never reached the results database (it was corrupt, full or newer).
inline constexpr const char* kUnstoredFile = "not-in-database.txt";

/// Attempt folders under `results`/attempts that were started (a marker) and
/// never kept (no report), or kept in the folder but not in the database
/// (kUnstoredFile), oldest first; those whose recovery failed before (a
/// recovery.txt saying why) are left out.
std::vector<std::filesystem::path> UnfinishedAttempts(
    const std::filesystem::path& results);

/// Rebuilds an unfinished attempt from its recording and entries, scores it as
/// far as it went (incomplete unless every step was done), and keeps it in the
/// folder and in `results`/results.db. Returns its id. On failure writes the
/// reason to recovery.txt in the folder (so it is not tried at every start;
/// nothing in the folder is deleted) and throws.
struct RecoveredAttempt {
  std::int64_t id = 0;
  LessonResult result;
};
RecoveredAttempt RecoverAttempt(const std::filesystem::path& dir,
                                const ResultsPlace& results,
                                const std::filesystem::path& cache_dir,
                                const BuildProgress& progress = {});

/// The scene a lesson runs on for a seed (its case applied when it has one).
SceneSpec LessonScene(const LessonSpec& spec, std::uint64_t seed);

}  // namespace sulcus
