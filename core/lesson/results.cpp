#include "core/lesson/results.h"

#include <sodium.h>
#include <sqlite3.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include "core/base/names.h"
#include "core/base/text.h"
#include "core/lesson/results_schema.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

using results_schema::Dialect;

// What went wrong with the results database, in the user's words: what it
// means and what to do, with SQLite's own text only as a last resort and
// never the SQL.
ResultsError DbError(const fs::path& file, sqlite3* db, int rc) {
  const std::string where = file.string() + ": ";
  const std::string text = db ? sqlite3_errmsg(db) : "";
  switch (rc & 0xff) {
    case SQLITE_CANTOPEN:
      return ResultsError(where +
                          "the results database cannot be opened or made there (does "
                          "the folder exist and may Sulcus write in it?); set "
                          "SULCUS_RESULTS_DIR to a writable folder");
    case SQLITE_READONLY:
    case SQLITE_PERM:
    case SQLITE_AUTH:
      return ResultsError(where +
                          "the results database cannot be written (the file or its "
                          "folder is read-only); nothing was stored, nothing is lost");
    case SQLITE_FULL:
      return ResultsError(
          where +
          "the disk holding the results database is full; free some "
          "space and store the attempt again (sulcus-cli lesson recover)");
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return ResultsError(where +
                          "the results database is in use by another Sulcus for more "
                          "than 5 s; try again");
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB:
      return ResultsError(where +
                          "not a Sulcus results database, or a damaged one; it is left "
                          "untouched (move it aside to start a new one)");
    case SQLITE_IOERR:
      return ResultsError(where +
                          "the results database could not be read or written "
                          "(a disk error); nothing is lost");
    case SQLITE_ERROR:
      if (text.find("no such table") != std::string::npos ||
          text.find("no such column") != std::string::npos)
        return ResultsError(where +
                            "not a results database of a form this Sulcus knows (its "
                            "tables differ); it is left untouched");
      break;
    default:
      break;
  }
  return ResultsError(where + "the results database failed: " + Shorten(text));
}

// A prepared statement, finalized on scope exit.
class Stmt {
 public:
  Stmt(sqlite3* db, const char* sql, const fs::path& file) : db_(db) {
    if (const int rc = sqlite3_prepare_v2(db, sql, -1, &s_, nullptr); rc != SQLITE_OK)
      throw DbError(file, db, rc);
  }
  ~Stmt() { sqlite3_finalize(s_); }
  Stmt& Bind(int i, const std::string& v) {
    sqlite3_bind_text(s_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Stmt& Bind(int i, double v) {
    sqlite3_bind_double(s_, i, v);
    return *this;
  }
  Stmt& Bind(int i, std::int64_t v) {
    sqlite3_bind_int64(s_, i, v);
    return *this;
  }
  Stmt& Bind(int i, int v) { return Bind(i, static_cast<std::int64_t>(v)); }
  Stmt& BindNull(int i) {
    sqlite3_bind_null(s_, i);
    return *this;
  }
  bool Step(const fs::path& file) {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw DbError(file, db_, rc);
  }
  void Reset() {
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }
  std::string Text(int c) const {
    const auto* t = sqlite3_column_text(s_, c);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  double Real(int c) const { return sqlite3_column_double(s_, c); }
  std::int64_t Int(int c) const { return sqlite3_column_int64(s_, c); }
  bool IsNull(int c) const { return sqlite3_column_type(s_, c) == SQLITE_NULL; }

 private:
  sqlite3* db_;
  sqlite3_stmt* s_ = nullptr;
};

std::string DeclaredText(const LessonResult& r) {
  return r.declared ? r.declared->Summary() : "nothing";
}

// A text cell: quoted when it must be, and a cell a spreadsheet would read as
// a formula (beginning with = + - @, a tab or a carriage return) led by an
// apostrophe, as OWASP's CSV-injection advice has it.
std::string Csv(const std::string& text) {
  std::string s = text;
  if (!s.empty() && std::string("=+-@\t\r").find(s[0]) != std::string::npos) s = "'" + s;
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

}  // namespace

bool IsResultsUrl(const std::string& text) {
  return text.rfind("postgresql://", 0) == 0 || text.rfind("postgres://", 0) == 0;
}

namespace {

// scheme://user:password@host/...: where the password is in `url` (begin,
// length), or npos. The user information ends at the last '@' before the
// path, so a password holding a raw '@' is found whole.
std::pair<std::size_t, std::size_t> PasswordSpan(const std::string& url) {
  const std::size_t scheme = url.find("://");
  if (scheme == std::string::npos) return {std::string::npos, 0};
  const std::size_t from = scheme + 3;
  std::size_t end = url.find_first_of("/?", from);
  if (end == std::string::npos) end = url.size();
  const std::size_t at = url.rfind('@', end == 0 ? 0 : end - 1);
  if (at == std::string::npos || at < from) return {std::string::npos, 0};
  const std::size_t colon = url.find(':', from);
  if (colon == std::string::npos || colon > at) return {std::string::npos, 0};
  return {colon + 1, at - colon - 1};
}

std::string PercentDecoded(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() &&
        std::isxdigit(static_cast<unsigned char>(text[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
      out += static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

std::string UrlPassword(const std::string& url) {
  std::string out;
  if (const auto [at, len] = PasswordSpan(url); at != std::string::npos)
    out = PercentDecoded(url.substr(at, len));
  for (std::size_t p = url.find("password="); p != std::string::npos;
       p = url.find("password=", p + 1)) {
    const std::size_t from = p + 9, to = url.find('&', from);
    out = PercentDecoded(
        url.substr(from, (to == std::string::npos ? url.size() : to) - from));
  }
  return out;
}

std::string RedactUrl(const std::string& url) {
  std::string out = url;
  if (const auto [at, len] = PasswordSpan(out); at != std::string::npos)
    out.replace(at, len, "***");
  // ...?password=secret&...
  for (std::size_t p = out.find("password="); p != std::string::npos;
       p = out.find("password=", p + 1)) {
    const std::size_t from = p + 9, to = out.find('&', from);
    out.replace(from, (to == std::string::npos ? out.size() : to) - from, "***");
  }
  return out;
}

std::string RedactPassword(std::string message, const std::string& url) {
  const std::string raw_password = [&] {
    const auto [at, len] = PasswordSpan(url);
    return at == std::string::npos ? std::string() : url.substr(at, len);
  }();
  for (const std::string& secret : {UrlPassword(url), raw_password}) {
    if (secret.empty()) continue;
    for (std::size_t p = message.find(secret); p != std::string::npos;
         p = message.find(secret, p + 3))
      message.replace(p, secret.size(), "***");
  }
  return message;
}

std::string ResultsPlace::Describe() const {
  return url.empty() ? "SQLite " + sqlite_file().string()
                     : "PostgreSQL " + RedactUrl(url);
}

ResultsPlace ResultsPlaceFor(const fs::path& dir) {
  const char* u = std::getenv("SULCUS_RESULTS_URL");
  return ResultsPlace(dir, u ? u : "");
}

std::unique_ptr<ResultsStore> OpenResults(const ResultsPlace& place) {
  std::unique_ptr<ResultsStore> store;
  if (!place.url.empty())
    store = OpenPostgresResults(place.url);
  else
    store = std::make_unique<ResultsDb>(place.sqlite_file());
  store->ReadAs(place.sign_in);
  return store;
}

fs::path DefaultResultsDir() {
  if (const char* d = std::getenv("SULCUS_RESULTS_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x)
    return fs::path(x) / "sulcus";
  if (const char* h = std::getenv("HOME"); h && *h)
    return fs::path(h) / ".local/share/sulcus";
  return fs::temp_directory_path() / "sulcus-results";
}

ResultsDb::ResultsDb(const fs::path& file) : file_(file) {
  std::error_code ec;
  if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
  if (const int rc = sqlite3_open_v2(
          file.string().c_str(), &db_,
          SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr);
      rc != SQLITE_OK) {
    const ResultsError e = DbError(file, db_, db_ ? sqlite3_extended_errcode(db_) : rc);
    sqlite3_close(db_);
    db_ = nullptr;
    throw e;
  }
  sqlite3_busy_timeout(db_, 5000);
  try {
    Exec("PRAGMA journal_mode=WAL");
    Exec("PRAGMA synchronous=FULL");
    Exec("PRAGMA foreign_keys=ON");
    const int version = schema_version();
    if (version > kResultsSchemaVersion)
      throw ResultsError(file.string() + ": the results database has schema version " +
                         std::to_string(version) + "; this Sulcus knows up to " +
                         std::to_string(kResultsSchemaVersion) +
                         " (it was written by a newer Sulcus; it is left untouched)");
    for (int v = version; v < kResultsSchemaVersion; ++v) {
      Transaction t(*this);
      Exec(results_schema::MigrationSql(v, Dialect::kSqlite));
      Exec("PRAGMA user_version=" + std::to_string(v + 1));
      t.Commit();
    }
  } catch (const ResultsError&) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

ResultsDb::~ResultsDb() { sqlite3_close(db_); }

ResultsDb::Transaction::Transaction(const ResultsDb& db) : db_(db) {
  db_.Exec("BEGIN IMMEDIATE");
}

ResultsDb::Transaction::~Transaction() {
  if (committed_) return;
  // Rolled back on the way out of an error: the first error is the one to
  // report, so a failing rollback is not.
  sqlite3_exec(db_.db_, "ROLLBACK", nullptr, nullptr, nullptr);
}

void ResultsDb::Transaction::Commit() {
  db_.Exec("COMMIT");
  committed_ = true;
}

void ResultsDb::Exec(const std::string& sql) const {
  if (const int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, nullptr);
      rc != SQLITE_OK)
    throw DbError(file_, db_, sqlite3_extended_errcode(db_));
}

int ResultsDb::schema_version() const {
  Stmt s(db_, "PRAGMA user_version", file_);
  return s.Step(file_) ? static_cast<int>(s.Int(0)) : 0;
}

std::string ResultsDb::IntegrityCheck() const {
  Stmt s(db_, "PRAGMA integrity_check", file_);
  std::string out;
  while (s.Step(file_)) out += (out.empty() ? "" : "; ") + s.Text(0);
  return out;
}

std::int64_t ResultsDb::Store(const LessonResult& r, const std::string& started,
                              const std::string& recording, const std::string& answers,
                              const std::string& report_dir, const std::string& uuid,
                              const std::string& sign_in) {
  Transaction t(*this);
  if (!uuid.empty()) {
    Stmt s(db_, "SELECT id FROM attempts WHERE uuid = ?", file_);
    if (s.Bind(1, uuid).Step(file_)) return s.Int(0);  // stored before: once
  }
  // The same rule as the shared store's (sulcus_store_attempt).
  const bool demonstration = r.device_kind == "scripted" || r.device_kind == "replay";
  bool signed_in = false, known = false;
  if (!demonstration && !sign_in.empty()) {
    Stmt s(db_,
           "SELECT i.at > strftime('%Y-%m-%dT%H:%M:%SZ', 'now', ?) FROM sign_ins i JOIN "
           "students s ON s.id = i.student_id WHERE s.name = ? AND i.token_hash = ?",
           file_);
    known = s.Bind(1, "-" + std::to_string(results_schema::kSignInHours) + " hours")
                .Bind(2, r.student)
                .Bind(3, Sha256Hex(sign_in))
                .Step(file_);
    signed_in = known && s.Int(0) != 0;
  }
  if (!demonstration && !known && Setting(kSignInSetting) == "required")
    throw ResultsError(file_.string() + ": " + r.student +
                       " is not signed in: this store takes a student's attempt only "
                       "from that student, signed in");
  {
    Stmt s(db_, "INSERT OR IGNORE INTO students(name, name_key) VALUES (?, ?)", file_);
    s.Bind(1, r.student).Bind(2, NameLookAlikeKey(r.student)).Step(file_);
  }
  {
    Stmt s(db_,
           "INSERT INTO lessons(file, name) VALUES (?, ?) ON CONFLICT(file) DO UPDATE "
           "SET name = excluded.name",
           file_);
    s.Bind(1, r.lesson_file).Bind(2, r.lesson_name).Step(file_);
  }
  Stmt a(db_,
         "INSERT INTO attempts(student_id, lesson_id, started, mode, scene_file, "
         "generated_case, case_seed, total, "
         "duration_s, sites_total, sites_read, sites_charted, within_1mm_pct, bias_mm, "
         "force_in_band_pct, true_dx, "
         "chart_dx, declared_dx, recording, answers, report_dir, complete, ended, uuid, "
         "device, row_hash, prev_hash, signed_in) VALUES ((SELECT id FROM students "
         "WHERE name = ?), (SELECT id FROM lessons WHERE file = ?), ?, ?, ?, ?, ?, ?, "
         "?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, "
         "?, ?, ?, ?, ?, ?, ?, ?, ?)",
         file_);
  a.Bind(1, r.student)
      .Bind(2, r.lesson_file)
      .Bind(3, started)
      .Bind(4, r.mode)
      .Bind(5, r.scene_file);
  a.Bind(6, r.generated_case ? 1 : 0)
      .Bind(7, static_cast<std::int64_t>(r.case_seed))
      .Bind(8, r.total);
  a.Bind(9, r.duration_s)
      .Bind(10, r.sites_total)
      .Bind(11, r.sites_read)
      .Bind(12, r.sites_charted);
  a.Bind(13, r.within_1mm_pct)
      .Bind(14, r.bias_mm)
      .Bind(15, r.force_in_band_pct)
      .Bind(16, r.true_dx.Summary());
  a.Bind(17, r.chart_dx.Summary())
      .Bind(18, DeclaredText(r))
      .Bind(19, recording)
      .Bind(20, answers);
  a.Bind(21, report_dir).Bind(22, r.complete ? 1 : 0).Bind(23, r.ended);
  if (uuid.empty())
    a.BindNull(24);
  else
    a.Bind(24, uuid);
  a.Bind(25, r.device_kind);
  {
    // The chain: this row's hash over the one before (one writer: SQLite's lock).
    Stmt last(db_,
              "SELECT row_hash FROM attempts WHERE row_hash IS NOT NULL ORDER BY id DESC "
              "LIMIT 1",
              file_);
    const std::string previous = last.Step(file_) && !last.IsNull(0) ? last.Text(0) : "";
    ChainRow c;
    c.uuid = uuid;
    c.student = r.student;
    c.lesson_file = r.lesson_file;
    c.started = started;
    c.mode = r.mode;
    c.total = r.total;
    c.complete = r.complete;
    c.declared_dx = DeclaredText(r);
    c.device = r.device_kind;
    c.signed_in = signed_in;
    a.Bind(26, Sha256Hex(ChainText(previous, c)));
    a.Bind(27, previous);
    a.Bind(28, signed_in ? 1 : 0);
  }
  a.Step(file_);
  const std::int64_t id = sqlite3_last_insert_rowid(db_);
  Stmt site(db_,
            "INSERT INTO attempt_sites(attempt_id, fdi, site, truth_mm, reached_mm, "
            "entered_mm, peak_force_n, "
            "angle_deg, col_reached, bled, bleeding_charted, reading_tick) VALUES (?, "
            "?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
            file_);
  for (const SiteResult& s : r.sites) {
    site.Bind(1, id).Bind(2, s.site.fdi).Bind(3, s.site.site).Bind(4, s.truth_mm);
    if (s.reached_mm)
      site.Bind(5, *s.reached_mm);
    else
      site.BindNull(5);
    if (s.entry && s.entry->pd_mm)
      site.Bind(6, *s.entry->pd_mm);
    else
      site.BindNull(6);
    site.Bind(7, s.peak_force_n)
        .Bind(8, s.angle_deg)
        .Bind(9, s.col_reached ? 1 : 0)
        .Bind(10, s.bled ? 1 : 0);
    site.Bind(11, s.entry && s.entry->bleeding ? 1 : 0)
        .Bind(12, static_cast<std::int64_t>(s.reading_tick));
    site.Step(file_);
    site.Reset();
  }
  Stmt score(db_,
             "INSERT INTO attempt_scores(attempt_id, category, credit, weight) VALUES "
             "(?, ?, ?, ?)",
             file_);
  for (const auto& [cat, credit] : r.category_credit) {
    score.Bind(1, id)
        .Bind(2, cat)
        .Bind(3, credit)
        .Bind(4, r.category_weight.at(cat))
        .Step(file_);
    score.Reset();
  }
  Stmt line(db_,
            "INSERT INTO attempt_lines(attempt_id, seq, category, fdi, site, status, "
            "credit, tick, message) VALUES "
            "(?, ?, ?, ?, ?, ?, ?, ?, ?)",
            file_);
  int seq = 0;
  for (const RubricLine& l : r.lines) {
    line.Bind(1, id).Bind(2, seq++).Bind(3, l.category).Bind(4, l.fdi);
    if (l.site)
      line.Bind(5, l.site->site);
    else
      line.BindNull(5);
    line.Bind(6, std::string(ToString(l.status)))
        .Bind(7, l.credit)
        .Bind(8, static_cast<std::int64_t>(l.tick));
    line.Bind(9, l.message).Step(file_);
    line.Reset();
  }
  t.Commit();
  return id;
}

void ResultsDb::SetReportDir(std::int64_t id, const std::string& dir) {
  Stmt s(db_, "UPDATE attempts SET report_dir = ? WHERE id = ?", file_);
  s.Bind(1, dir).Bind(2, id).Step(file_);
}

std::vector<AttemptRow> ResultsDb::Attempts(const std::string& student,
                                            const std::string& lesson_file) const {
  Stmt s(db_,
         results_schema::Query(std::string(results_schema::kSelectAttempts) +
                                   results_schema::kByStudentAndLesson + "ORDER BY a.id",
                               Dialect::kSqlite)
             .c_str(),
         file_);
  s.Bind(1, student).Bind(2, lesson_file);
  std::vector<AttemptRow> out;
  while (s.Step(file_)) out.push_back(results_schema::ReadAttempt(s));
  return out;
}

std::optional<AttemptRow> ResultsDb::Attempt(std::int64_t id) const {
  Stmt s(db_, (std::string(results_schema::kSelectAttempts) + "WHERE a.id = ?").c_str(),
         file_);
  s.Bind(1, id);
  if (!s.Step(file_)) return std::nullopt;
  return results_schema::ReadAttempt(s);
}

std::vector<SiteRow> ResultsDb::Sites(const std::string& student,
                                      const std::string& lesson_file) const {
  Stmt s(db_,
         results_schema::Query(results_schema::kSelectSites, Dialect::kSqlite).c_str(),
         file_);
  s.Bind(1, student).Bind(2, lesson_file);
  std::vector<SiteRow> out;
  while (s.Step(file_)) out.push_back(results_schema::ReadSite(s));
  return out;
}

std::vector<std::string> ResultsDb::Students() const {
  Stmt s(db_, "SELECT name FROM students ORDER BY name", file_);
  std::vector<std::string> out;
  while (s.Step(file_)) out.push_back(s.Text(0));
  return out;
}

int ResultsDb::DeleteStudent(const std::string& student) {
  Transaction t(*this);
  Stmt d(db_,
         "DELETE FROM attempts WHERE student_id = (SELECT id FROM students WHERE name "
         "= ?)",
         file_);
  d.Bind(1, student).Step(file_);
  const int n = sqlite3_changes(db_);
  Stmt s(db_, "DELETE FROM students WHERE name = ?", file_);
  s.Bind(1, student).Step(file_);
  t.Commit();
  return n;
}

std::optional<std::string> ResultsDb::Setting(const std::string& key) const {
  Stmt s(db_, "SELECT value FROM settings WHERE key = ?", file_);
  if (!s.Bind(1, key).Step(file_)) return std::nullopt;
  return s.Text(0);
}

bool ResultsDb::SetSettingOnce(const std::string& key, const std::string& value) {
  Stmt s(db_, "INSERT OR IGNORE INTO settings(key, value) VALUES (?, ?)", file_);
  s.Bind(1, key).Bind(2, value).Step(file_);
  return sqlite3_changes(db_) == 1;
}

void ResultsDb::SetSetting(const std::string& key, const std::string& value) {
  Stmt s(db_, "INSERT OR REPLACE INTO settings(key, value) VALUES (?, ?)", file_);
  s.Bind(1, key).Bind(2, value).Step(file_);
}

std::vector<std::string> ResultsDb::Roster() const {
  Stmt s(db_, "SELECT name FROM students WHERE on_roster = 1 ORDER BY name", file_);
  std::vector<std::string> out;
  while (s.Step(file_)) out.push_back(s.Text(0));
  return out;
}

bool ResultsDb::AddToRoster(const std::string& name, const std::string& look_alike_key) {
  Transaction t(*this);
  {
    Stmt s(db_, "SELECT name FROM students WHERE name_key = ? AND name <> ?", file_);
    if (s.Bind(1, look_alike_key).Bind(2, name).Step(file_))
      throw ResultsError(file_.string() + ": \"" + name + "\" looks like \"" + s.Text(0) +
                         "\", a student already there: one of the two names " +
                         "must differ in more than the look of a letter");
  }
  Stmt s(db_,
         "INSERT INTO students(name, name_key, on_roster) VALUES (?, ?, 1) ON "
         "CONFLICT(name) DO UPDATE SET on_roster = 1, name_key = excluded.name_key "
         "WHERE on_roster = 0",
         file_);
  s.Bind(1, name).Bind(2, look_alike_key).Step(file_);
  const bool added = sqlite3_changes(db_) == 1;
  t.Commit();
  return added;
}

bool ResultsDb::ResetPassphrase(const std::string& name) {
  Stmt s(db_,
         "DELETE FROM student_keys WHERE student_id = (SELECT id FROM students WHERE "
         "name = ? AND on_roster = 1)",
         file_);
  s.Bind(1, name).Step(file_);
  return sqlite3_changes(db_) == 1;
}

std::string ResultsDb::PassphraseSalt(const std::string& name) const {
  Stmt s(db_,
         "SELECT k.salt FROM student_keys k JOIN students s ON s.id = k.student_id "
         "WHERE s.name = ? AND s.on_roster = 1",
         file_);
  return s.Bind(1, name).Step(file_) ? s.Text(0) : "";
}

bool ResultsDb::SetPassphraseKey(const std::string& name, const std::string& salt,
                                 const std::string& key) {
  Stmt s(db_,
         "INSERT OR IGNORE INTO student_keys(student_id, salt, key_hash) SELECT id, ?, ? "
         "FROM students WHERE name = ? AND on_roster = 1",
         file_);
  s.Bind(1, salt).Bind(2, Sha256Hex(key)).Bind(3, name).Step(file_);
  return sqlite3_changes(db_) == 1;
}

std::string ResultsDb::SignInWithKey(const std::string& name, const std::string& key) {
  Transaction t(*this);
  Stmt k(db_,
         "SELECT s.id, k.key_hash FROM students s JOIN student_keys k ON k.student_id = "
         "s.id WHERE s.name = ? AND s.on_roster = 1",
         file_);
  if (!k.Bind(1, name).Step(file_)) return "";
  const std::int64_t id = k.Int(0);
  const std::string want = k.Text(1);
  {
    Stmt f(db_,
           "SELECT COUNT(*) FROM sign_in_failures WHERE student_id = ? AND at > "
           "strftime('%Y-%m-%dT%H:%M:%SZ', 'now', '-15 minutes')",
           file_);
    f.Bind(1, id).Step(file_);
    if (f.Int(0) >= results_schema::kWrongPassphrases)
      throw ResultsError(
          file_.string() + ": too many wrong passphrases for " + name +
          ": wait a quarter of an hour, or ask the instructor to reset it");
  }
  if (Sha256Hex(key) != want) {
    Stmt f(db_, "INSERT INTO sign_in_failures(student_id) VALUES (?)", file_);
    f.Bind(1, id).Step(file_);
    t.Commit();
    return "";
  }
  unsigned char raw[32];
  randombytes_buf(raw, sizeof raw);
  char hex[2 * sizeof raw + 1];
  sodium_bin2hex(hex, sizeof hex, raw, sizeof raw);
  Stmt in(db_, "INSERT INTO sign_ins(token_hash, student_id) VALUES (?, ?)", file_);
  in.Bind(1, Sha256Hex(hex)).Bind(2, id).Step(file_);
  t.Commit();
  return hex;
}

std::string ChainText(const std::string& previous, const ChainRow& r) {
  return previous + "\n" + r.uuid + "\n" + r.student + "\n" + r.lesson_file + "\n" +
         r.started + "\n" + r.mode + "\n" + std::to_string(std::llrint(r.total * 1000)) +
         "\n" + (r.complete ? "1" : "0") + "\n" + r.declared_dx + "\n" + r.device +
         (r.signed_in ? "\nsigned in" : "");
}

std::string Sha256Hex(const std::string& text) {
  if (sodium_init() < 0) throw ResultsError("libsodium could not be initialised");
  unsigned char h[crypto_hash_sha256_BYTES];
  crypto_hash_sha256(h, reinterpret_cast<const unsigned char*>(text.data()), text.size());
  char hex[2 * crypto_hash_sha256_BYTES + 1];
  sodium_bin2hex(hex, sizeof hex, h, sizeof h);
  return hex;
}

ChainCheck CheckChain(const std::vector<ChainRow>& rows) {
  ChainCheck c;
  std::map<std::string, int> follows;  // a hash -> how many rows follow it
  std::set<std::string> hashes;
  for (const ChainRow& r : rows) {
    ++c.rows;
    if (!r.row_hash) continue;
    ++c.chained;
    hashes.insert(*r.row_hash);
    ++follows[r.prev_hash];
  }
  for (const ChainRow& r : rows) {
    if (!r.row_hash) continue;
    if (Sha256Hex(ChainText(r.prev_hash, r)) != *r.row_hash)
      c.breaks.push_back({r.id, "its hash does not hold: the row was changed"});
    else if (!r.prev_hash.empty() && !hashes.count(r.prev_hash))
      c.breaks.push_back({r.id, "the attempt it follows is not there: removed"});
    else if (follows[r.prev_hash] > 1)
      c.breaks.push_back(
          {r.id, "another attempt follows the same one: a row was put in"});
  }
  // The last hash: the chained row no row follows.
  for (const ChainRow& r : rows)
    if (r.row_hash && !follows.count(*r.row_hash)) c.last_hash = *r.row_hash;
  return c;
}

std::vector<ChainRow> ResultsDb::Chain() const {
  Stmt s(db_, results_schema::kSelectChain, file_);
  std::vector<ChainRow> out;
  while (s.Step(file_)) out.push_back(results_schema::ReadChain(s));
  return out;
}

void ExportAttemptsCsv(const std::vector<AttemptRow>& rows, std::ostream& o) {
  o << "attempt,student,lesson,lesson_file,mode,started,case_seed,total,duration_s,sites_"
       "total,sites_read,"
       "sites_charted,within_1mm_pct,bias_mm,force_in_band_pct,true_dx,chart_dx,declared_"
       "dx,complete,ended,recording,report_dir\n";
  for (const AttemptRow& a : rows)
    o << a.id << ',' << Csv(a.student) << ',' << Csv(a.lesson_name) << ','
      << Csv(a.lesson_file) << ',' << a.mode << ',' << a.started << ',' << a.case_seed
      << ',' << a.total << ',' << a.duration_s << ',' << a.sites_total << ','
      << a.sites_read << ',' << a.sites_charted << ',' << a.within_1mm_pct << ','
      << a.bias_mm << ',' << a.force_in_band_pct << ',' << Csv(a.true_dx) << ','
      << Csv(a.chart_dx) << ',' << Csv(a.declared_dx) << ',' << (a.complete ? 1 : 0)
      << ',' << Csv(a.ended) << ',' << Csv(a.recording) << ',' << Csv(a.report_dir)
      << '\n';
}

void ExportSitesCsv(const std::vector<SiteRow>& rows, std::ostream& o) {
  o << "attempt,student,started,tooth,site,truth_mm,reached_mm,entered_mm,signed_error_"
       "mm,peak_force_n\n";
  for (const SiteRow& r : rows) {
    o << r.attempt << ',' << Csv(r.student) << ',' << r.started << ',' << r.fdi << ','
      << SiteCode(r.site) << ',' << r.truth_mm << ',';
    if (r.reached_mm) o << *r.reached_mm;
    o << ',';
    if (r.entered_mm) o << *r.entered_mm;
    o << ',';
    if (r.entered_mm) o << (*r.entered_mm - r.truth_mm);
    o << ',' << r.peak_force_n << '\n';
  }
}

}  // namespace sulcus
