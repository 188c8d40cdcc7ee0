#pragma once
// The results database (SQLite, embedded): students, lessons, attempts, their
// per-site rows, category scores and rubric lines, the recording's path and the
// case seed. WAL journal, a schema version (PRAGMA user_version) with
// migrations applied in order on open, and every attempt written in one
// transaction: a writer killed mid-attempt loses nothing that was committed and
// leaves a database that passes `PRAGMA integrity_check`.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/lesson/lesson.h"

struct sqlite3;

namespace sulcus {

inline constexpr int kResultsSchemaVersion = 2;

class ResultsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct AttemptRow {
  std::int64_t id = 0;
  std::string student, lesson_name, lesson_file, scene_file, mode, started;
  std::uint64_t case_seed = 0;
  bool generated_case = false;
  double total = 0, duration_s = 0, within_1mm_pct = 0, bias_mm = 0,
         force_in_band_pct = 0;
  int sites_total = 0, sites_read = 0, sites_charted = 0;
  std::string true_dx, chart_dx, declared_dx;
  std::string recording, answers, report_dir;
  bool complete = true;
  std::string ended;  // how an incomplete attempt ended
};

struct SiteRow {
  std::int64_t attempt = 0;
  std::string student, started;
  int fdi = 0, site = 0, truth_mm = 0;
  std::optional<double> reached_mm;
  std::optional<int> entered_mm;
  double peak_force_n = 0;
};

class ResultsDb {
 public:
  /// Opens (creating) the database and migrates it to the current schema.
  /// Throws ResultsError naming the file and what went wrong; a database of a
  /// newer schema than this build knows is refused, never rewritten.
  explicit ResultsDb(const std::filesystem::path& file);
  ~ResultsDb();
  ResultsDb(const ResultsDb&) = delete;
  ResultsDb& operator=(const ResultsDb&) = delete;

  /// Stores one attempt in one transaction; returns its id.
  std::int64_t Store(const LessonResult& r, const std::string& started,
                     const std::string& recording, const std::string& answers,
                     const std::string& report_dir);
  /// Sets where an attempt's report lives (after it was written with the id in it).
  void SetReportDir(std::int64_t id, const std::string& dir);

  std::vector<AttemptRow> Attempts(const std::string& student = "",
                                   const std::string& lesson_file = "") const;
  std::optional<AttemptRow> Attempt(std::int64_t id) const;
  std::vector<SiteRow> Sites(const std::string& student = "",
                             const std::string& lesson_file = "") const;
  std::vector<std::string> Students() const;
  /// Deletes every attempt of a student and the student (one transaction);
  /// returns how many attempts went. Their recordings and reports stay on disk.
  int DeleteStudent(const std::string& student);
  int schema_version() const;
  /// "ok" when the database is sound.
  std::string IntegrityCheck() const;
  const std::filesystem::path& file() const { return file_; }

 private:
  // BEGIN IMMEDIATE on construction, ROLLBACK on destruction unless Commit().
  class Transaction {
   public:
    explicit Transaction(const ResultsDb& db);
    ~Transaction();
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void Commit();

   private:
    const ResultsDb& db_;
    bool committed_ = false;
  };
  void Exec(const std::string& sql) const;
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
};

/// One line per attempt, with a header (RFC 4180 quoting).
void ExportAttemptsCsv(const std::vector<AttemptRow>& rows, std::ostream& out);
/// One line per site of each attempt.
void ExportSitesCsv(const std::vector<SiteRow>& rows, std::ostream& out);

/// Where results live by default: $SULCUS_RESULTS_DIR, else
/// $XDG_DATA_HOME/sulcus, else ~/.local/share/sulcus.
std::filesystem::path DefaultResultsDir();

}  // namespace sulcus
