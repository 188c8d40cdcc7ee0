// The results store on a lab's PostgreSQL server, through libpq: the same tables,
// migrations and queries as the SQLite file (results_schema.h), in PostgreSQL's
// types. The
// schema version is kept in `sulcus_schema`; migrations run under an advisory
// lock, so twenty stations starting at once migrate an empty database once.
#include <libpq-fe.h>

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <utility>
#include <vector>

#include "core/base/names.h"
#include "core/base/text.h"
#include "core/lesson/results.h"
#include "core/lesson/results_schema.h"

namespace sulcus {
namespace {

using results_schema::Dialect;

constexpr long long kMigrationLock = 0x5375'6c63'7573;  // "Sulcus"

// A query's parameters as text (libpq's text format), NULL as nullopt.
class Params {
 public:
  Params& Add(const std::string& v) {
    values_.push_back(v);
    return *this;
  }
  Params& Add(std::int64_t v) { return Add(std::to_string(v)); }
  Params& Add(int v) { return Add(std::to_string(v)); }
  Params& Add(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return Add(std::string(b));
  }
  Params& Null() {
    values_.push_back(std::nullopt);
    return *this;
  }
  std::vector<const char*> Pointers() const {
    std::vector<const char*> p;
    for (const auto& v : values_) p.push_back(v ? v->c_str() : nullptr);
    return p;
  }

 private:
  std::vector<std::optional<std::string>> values_;
};

// A result, cleared on scope exit.
class Result {
 public:
  explicit Result(PGresult* r) : r_(r) {}
  ~Result() { PQclear(r_); }
  Result(Result&& o) noexcept : r_(std::exchange(o.r_, nullptr)) {}
  Result(const Result&) = delete;
  Result& operator=(const Result&) = delete;
  int rows() const { return PQntuples(r_); }
  bool IsNull(int row, int c) const { return PQgetisnull(r_, row, c) != 0; }
  std::string Text(int row, int c) const { return PQgetvalue(r_, row, c); }
  std::int64_t Int(int row, int c) const {
    return std::strtoll(PQgetvalue(r_, row, c), nullptr, 10);
  }
  double Real(int row, int c) const {
    return std::strtod(PQgetvalue(r_, row, c), nullptr);
  }
  const char* affected() const { return PQcmdTuples(r_); }
  bool ok() const {
    const ExecStatusType st = PQresultStatus(r_);
    return r_ && (st == PGRES_COMMAND_OK || st == PGRES_TUPLES_OK);
  }

 private:
  PGresult* r_;
};

class PgResults final : public ResultsStore {
 public:
  PgResults(const std::string& url, int version) : url_(url), shown_(RedactUrl(url)) {
    // A server that hangs or a table held locked ends in an error after these
    // (the attempt waits in its folder), never a station that waits for ever.
    const char* keys[] = {"connect_timeout", "options", "dbname", nullptr};
    const char* values[] = {"5", "-c statement_timeout=15000 -c lock_timeout=10000",
                            url.c_str(), nullptr};
    pg_ = PQconnectdbParams(keys, values, 1);
    if (!pg_ || PQstatus(pg_) != CONNECTION_OK) {
      const std::string why =
          pg_ ? RedactPassword(FirstLine(PQerrorMessage(pg_)), url) : "out of memory";
      PQfinish(pg_);
      pg_ = nullptr;
      throw ResultsError("PostgreSQL results store " + shown_ +
                         ": cannot connect: " + why +
                         "; attempts made meanwhile are kept on this station and sent "
                         "by `sulcus-cli results sync`");
    }
    Exec("SET client_min_messages = warning");
    Migrate(version);
  }
  ~PgResults() override { PQfinish(pg_); }

  // Every attempt goes through the store's own function (sulcus_store_attempt,
  // results_schema.h), which decides whether it is its signed-in student's:
  // a station's role may insert nothing itself.
  std::int64_t Store(const LessonResult& r, const std::string& started,
                     const std::string& recording, const std::string& answers,
                     const std::string& report_dir, const std::string& uuid,
                     const std::string& sign_in) override {
    const auto num = [](double v) {
      char b[40];
      std::snprintf(b, sizeof b, "%.17g", v);
      return JsonQuote(b);
    };
    const auto whole = [](std::int64_t v) { return JsonQuote(std::to_string(v)); };
    std::string doc =
        "{\"uuid\": " + JsonQuote(uuid) + ", \"student\": " + JsonQuote(r.student) +
        ", \"name_key\": " + JsonQuote(NameLookAlikeKey(r.student)) +
        ", \"device\": " + JsonQuote(r.device_kind) +
        ", \"lesson_file\": " + JsonQuote(r.lesson_file) +
        ", \"lesson_name\": " + JsonQuote(r.lesson_name) +
        ", \"started\": " + JsonQuote(started) + ", \"mode\": " + JsonQuote(r.mode) +
        ", \"scene_file\": " + JsonQuote(r.scene_file) +
        ", \"generated_case\": " + whole(r.generated_case ? 1 : 0) +
        ", \"case_seed\": " + whole(static_cast<std::int64_t>(r.case_seed)) +
        ", \"total\": " + num(r.total) + ", \"duration_s\": " + num(r.duration_s) +
        ", \"sites_total\": " + whole(r.sites_total) +
        ", \"sites_read\": " + whole(r.sites_read) +
        ", \"sites_charted\": " + whole(r.sites_charted) +
        ", \"within_1mm_pct\": " + num(r.within_1mm_pct) +
        ", \"bias_mm\": " + num(r.bias_mm) +
        ", \"force_in_band_pct\": " + num(r.force_in_band_pct) +
        ", \"true_dx\": " + JsonQuote(r.true_dx.Summary()) +
        ", \"chart_dx\": " + JsonQuote(r.chart_dx.Summary()) + ", \"declared_dx\": " +
        JsonQuote(r.declared ? r.declared->Summary() : "nothing") +
        ", \"recording\": " + JsonQuote(recording) +
        ", \"answers\": " + JsonQuote(answers) +
        ", \"report_dir\": " + JsonQuote(report_dir) +
        ", \"complete\": " + whole(r.complete ? 1 : 0) +
        ", \"ended\": " + JsonQuote(r.ended) + ", \"sites\": [";
    for (std::size_t i = 0; i < r.sites.size(); ++i) {
      const SiteResult& x = r.sites[i];
      doc +=
          std::string(i ? ", " : "") + "{\"fdi\": " + whole(x.site.fdi) +
          ", \"site\": " + whole(x.site.site) + ", \"truth_mm\": " + whole(x.truth_mm) +
          ", \"reached_mm\": " + (x.reached_mm ? num(*x.reached_mm) : "null") +
          ", \"entered_mm\": " +
          (x.entry && x.entry->pd_mm ? whole(*x.entry->pd_mm) : "null") +
          ", \"peak_force_n\": " + num(x.peak_force_n) +
          ", \"angle_deg\": " + num(x.angle_deg) +
          ", \"col_reached\": " + whole(x.col_reached ? 1 : 0) +
          ", \"bled\": " + whole(x.bled ? 1 : 0) +
          ", \"bleeding_charted\": " + whole(x.entry && x.entry->bleeding ? 1 : 0) +
          ", \"reading_tick\": " + whole(static_cast<std::int64_t>(x.reading_tick)) + "}";
    }
    doc += "], \"scores\": [";
    bool first = true;
    for (const auto& [cat, credit] : r.category_credit) {
      doc += std::string(first ? "" : ", ") + "{\"category\": " + JsonQuote(cat) +
             ", \"credit\": " + num(credit) +
             ", \"weight\": " + num(r.category_weight.at(cat)) + "}";
      first = false;
    }
    doc += "], \"lines\": [";
    int seq = 0;
    for (const RubricLine& l : r.lines) {
      doc += std::string(seq ? ", " : "") + "{\"seq\": " + whole(seq) +
             ", \"category\": " + JsonQuote(l.category) + ", \"fdi\": " + whole(l.fdi) +
             ", \"site\": " + (l.site ? whole(l.site->site) : std::string("null")) +
             ", \"status\": " + JsonQuote(ToString(l.status)) +
             ", \"credit\": " + num(l.credit) +
             ", \"tick\": " + whole(static_cast<std::int64_t>(l.tick)) +
             ", \"message\": " + JsonQuote(l.message) + "}";
      ++seq;
    }
    doc += "]}";
    Params p;
    p.Add(doc);
    if (sign_in.empty())
      p.Null();
    else
      p.Add(sign_in);
    const Result id = Query("SELECT sulcus_store_attempt($1::jsonb, $2)", p);
    return id.Int(0, 0);
  }

  std::vector<std::string> Roster() const override {
    const Result r =
        Query("SELECT name FROM students WHERE on_roster = 1 ORDER BY name", Params());
    std::vector<std::string> out;
    for (int i = 0; i < r.rows(); ++i) out.push_back(r.Text(i, 0));
    return out;
  }

  bool AddToRoster(const std::string& name, const std::string& look_alike_key) override {
    Transaction t(this);
    const Result like =
        Query("SELECT name FROM students WHERE name_key = $1 AND name <> $2",
              Params().Add(look_alike_key).Add(name));
    if (like.rows() > 0)
      throw ResultsError("PostgreSQL results store " + shown_ + ": \"" + name +
                         "\" looks like \"" + like.Text(0, 0) +
                         "\", a student already there: one of the two names must differ "
                         "in more than the look of a letter");
    const Result r = Query(
        "INSERT INTO students(name, name_key, on_roster) VALUES ($1, $2, 1) ON CONFLICT "
        "(name) DO UPDATE SET on_roster = 1, name_key = excluded.name_key WHERE "
        "students.on_roster = 0",
        Params().Add(name).Add(look_alike_key));
    const bool added = std::string(r.affected()) == "1";
    t.Commit();
    return added;
  }

  bool ResetPassphrase(const std::string& name) override {
    const Result r = Query(
        "DELETE FROM student_keys WHERE student_id = (SELECT id FROM students WHERE name "
        "= $1 AND on_roster = 1)",
        Params().Add(name));
    return std::string(r.affected()) == "1";
  }

  std::string PassphraseSalt(const std::string& name) const override {
    const Result r = Query("SELECT sulcus_salt($1)", Params().Add(name));
    return r.IsNull(0, 0) ? "" : r.Text(0, 0);
  }

  bool SetPassphraseKey(const std::string& name, const std::string& salt,
                        const std::string& key) override {
    const Result r = Query("SELECT sulcus_set_passphrase($1, $2, $3)",
                           Params().Add(name).Add(salt).Add(key));
    return r.Text(0, 0) == "t";
  }

  std::string SignInWithKey(const std::string& name, const std::string& key) override {
    const Result r = Query("SELECT sulcus_sign_in($1, $2)", Params().Add(name).Add(key));
    return r.IsNull(0, 0) ? "" : r.Text(0, 0);
  }

  void SetReportDir(std::int64_t id, const std::string& dir) override {
    Query("UPDATE attempts SET report_dir = $1 WHERE id = $2", Params().Add(dir).Add(id));
  }

  void ReadAs(const std::string& sign_in) override { sign_in_ = sign_in; }

  // A station's role reads attempts only through the store's functions
  // (sulcus_attempts_of, sulcus_attempt, sulcus_sites_of), a student's own.
  bool ReadsAll() const {
    if (!reads_all_)
      reads_all_ = Query("SELECT has_table_privilege('attempts', 'SELECT')", Params())
                       .Text(0, 0) == "t";
    return *reads_all_;
  }
  std::vector<AttemptRow> Attempts(const std::string& student,
                                   const std::string& lesson_file) const override {
    if (!ReadsAll()) {
      std::vector<AttemptRow> out;
      if (student.empty()) return out;  // (a station shows one student's)
      Params p;
      p.Add(student).Add(lesson_file).Add(sign_in_);
      const Result r = Query("SELECT * FROM sulcus_attempts_of($1, $2, $3)", p);
      for (int i = 0; i < r.rows(); ++i)
        out.push_back(results_schema::ReadAttempt(RowColumns{r, i}));
      return out;
    }
    const Result r = Query(std::string(results_schema::kSelectAttempts) +
                               results_schema::kByStudentAndLesson + "ORDER BY a.id",
                           Params().Add(student).Add(lesson_file));
    std::vector<AttemptRow> out;
    for (int i = 0; i < r.rows(); ++i)
      out.push_back(results_schema::ReadAttempt(RowColumns{r, i}));
    return out;
  }

  std::optional<AttemptRow> Attempt(std::int64_t id) const override {
    const Result r =
        ReadsAll()
            ? Query(std::string(results_schema::kSelectAttempts) + "WHERE a.id = $1",
                    Params().Add(id))
            : Query("SELECT * FROM sulcus_attempt($1, $2)",
                    Params().Add(id).Add(sign_in_));
    if (r.rows() == 0) return std::nullopt;
    return results_schema::ReadAttempt(RowColumns{r, 0});
  }

  std::vector<SiteRow> Sites(const std::string& student,
                             const std::string& lesson_file) const override {
    if (!ReadsAll() && student.empty()) return {};
    const Result r =
        ReadsAll()
            ? Query(results_schema::kSelectSites, Params().Add(student).Add(lesson_file))
            : Query("SELECT * FROM sulcus_sites_of($1, $2, $3)",
                    Params().Add(student).Add(lesson_file).Add(sign_in_));
    std::vector<SiteRow> out;
    for (int i = 0; i < r.rows(); ++i)
      out.push_back(results_schema::ReadSite(RowColumns{r, i}));
    return out;
  }

  std::vector<std::string> Students() const override {
    const Result r = Query("SELECT name FROM students ORDER BY name", Params());
    std::vector<std::string> out;
    for (int i = 0; i < r.rows(); ++i) out.push_back(r.Text(i, 0));
    return out;
  }

  int DeleteStudent(const std::string& student) override {
    Transaction t(this);
    const Result d = Query(
        "DELETE FROM attempts WHERE student_id = (SELECT id FROM students WHERE name = "
        "$1)",
        Params().Add(student));
    const int n = std::atoi(d.affected());
    Query("DELETE FROM students WHERE name = $1", Params().Add(student));
    t.Commit();
    return n;
  }

  int schema_version() const override {
    const Result r = Query("SELECT version FROM sulcus_schema", Params());
    return r.rows() > 0 ? static_cast<int>(r.Int(0, 0)) : 0;
  }

  std::string where() const override { return shown_; }

  std::optional<std::string> Setting(const std::string& key) const override {
    // A station's role reads only the public ones (through the owner's view).
    if (!PublicSetting(key) &&
        Query("SELECT has_table_privilege('settings', 'SELECT')", Params()).Text(0, 0) !=
            "t")
      throw ResultsError("PostgreSQL results store " + shown_ +
                         ": this station's role may not read the instructor's settings "
                         "(the passphrase); the instructor's view reads them with the "
                         "instructor's role (" +
                         kInstructorRole + " in SULCUS_RESULTS_URL)");
    const Result r =
        Query(PublicSetting(key) ? "SELECT value FROM public_settings WHERE key = $1"
                                 : "SELECT value FROM settings WHERE key = $1",
              Params().Add(key));
    if (r.rows() == 0) return std::nullopt;
    return r.Text(0, 0);
  }

  bool SetSettingOnce(const std::string& key, const std::string& value) override {
    const Result r = Query(
        "INSERT INTO settings(key, value) VALUES ($1, $2) ON CONFLICT (key) DO NOTHING",
        Params().Add(key).Add(value));
    return std::string(r.affected()) == "1";
  }

  std::vector<ChainRow> Chain() const override {
    const Result r = Query(results_schema::kSelectChain, Params());
    std::vector<ChainRow> out;
    for (int i = 0; i < r.rows(); ++i)
      out.push_back(results_schema::ReadChain(RowColumns{r, i}));
    return out;
  }

  void SetSetting(const std::string& key, const std::string& value) override {
    Query(
        "INSERT INTO settings(key, value) VALUES ($1, $2) ON CONFLICT (key) DO UPDATE "
        "SET value = excluded.value",
        Params().Add(key).Add(value));
  }

 private:
  // One row of a result as the shared readers see it.
  struct RowColumns {
    const Result& r;
    int i;
    std::string Text(int c) const { return r.Text(i, c); }
    std::int64_t Int(int c) const { return r.Int(i, c); }
    double Real(int c) const { return r.Real(i, c); }
    bool IsNull(int c) const { return r.IsNull(i, c); }
  };

  // libpq's message, to the point: "connection to server at ... failed: FATAL:
  // password authentication failed for user ..." says its cause after FATAL.
  static std::string FirstLine(const char* text) {
    std::string s = text ? text : "";
    if (const std::size_t f = s.find("FATAL:"); f != std::string::npos) {
      s = s.substr(f + 6);
      s.erase(0, s.find_first_not_of(' '));
    }
    if (const std::size_t nl = s.find('\n'); nl != std::string::npos) s.resize(nl);
    while (!s.empty() && s.back() == ' ') s.pop_back();
    if (s.size() > 240) s = s.substr(0, 240) + "...";
    return s;
  }

  [[noreturn]] void Fail(const char* what) const {
    const std::string why = RedactPassword(FirstLine(PQerrorMessage(pg_)), url_);
    // The store's own refusals (its functions' RAISE) say what they mean.
    if (const std::size_t at = why.find("sulcus: "); at != std::string::npos)
      throw ResultsError("PostgreSQL results store " + shown_ + ": " +
                         why.substr(at + 8));
    if (PQstatus(pg_) != CONNECTION_OK)
      throw ResultsError("PostgreSQL results store " + shown_ +
                         ": the connection was lost (" + why +
                         "); nothing of this attempt was stored; it is kept on this "
                         "station and sent by `sulcus-cli results sync`");
    throw ResultsError("PostgreSQL results store " + shown_ + ": " + what +
                       " failed: " + why);
  }

  Result Query(const std::string& sql, const Params& p) const {
    const std::vector<const char*> values = p.Pointers();
    Result r(PQexecParams(pg_, sql.c_str(), static_cast<int>(values.size()), nullptr,
                          values.data(), nullptr, nullptr, 0));
    if (!r.ok()) Fail("a query");
    return r;
  }

  void Exec(const std::string& sql) const {
    const Result r(PQexec(pg_, sql.c_str()));
    if (!r.ok()) Fail("a statement");
  }

  class Transaction {
   public:
    explicit Transaction(const PgResults* db) : db_(db) { db_->Exec("BEGIN"); }
    ~Transaction() {
      if (!committed_) PQclear(PQexec(db_->pg_, "ROLLBACK"));
    }
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void Commit() {
      db_->Exec("COMMIT");
      committed_ = true;
    }

   private:
    const PgResults* db_;
    bool committed_ = false;
  };

  // What `results setup` does as the owner (SetUpPostgresStore).
 public:
  StoreSetup SetUpRoles(std::string station_pw, std::string instructor_pw) {
    StoreSetup out;
    auto made = [&](std::string* pw) {
      if (!pw->empty()) return;
      const Result r = Query(
          "SELECT "
          "string_agg(substr('abcdefghijkmnpqrstuvwxyzABCDEFGHJKLMNPQRSTUVWXYZ23456789', "
          "1 + floor(random() * 56)::int, 1), '') FROM generate_series(1, 24)",
          Params());
      *pw = r.Text(0, 0);
    };
    made(&station_pw);
    made(&instructor_pw);
    Transaction t(this);
    for (const auto& [role, pw] :
         {std::pair{std::string(kStationRole), station_pw},
          std::pair{std::string(kInstructorRole), instructor_pw}}) {
      const bool exists =
          Query("SELECT 1 FROM pg_roles WHERE rolname = $1", Params().Add(role)).rows() >
          0;
      const Result sql = Query(
          std::string("SELECT format('") + (exists ? "ALTER" : "CREATE") +
              " ROLE %I WITH LOGIN NOSUPERUSER NOCREATEDB NOCREATEROLE NOREPLICATION "
              "NOBYPASSRLS PASSWORD %L', $1::text, $2::text)",
          Params().Add(role).Add(pw));
      Exec(sql.Text(0, 0));
      out.done.push_back(std::string(exists ? "reset" : "made") + " the role " + role);
    }
    const std::string both = std::string(kStationRole) + ", " + kInstructorRole;
    const std::string station = kStationRole, instructor = kInstructorRole;
    const char* attempt_tables =
        "students, lessons, attempts, attempt_sites, attempt_scores, attempt_lines";
    const char* functions =
        "sulcus_salt(text), sulcus_set_passphrase(text, text, text), "
        "sulcus_sign_in(text, text), sulcus_store_attempt(jsonb, text), "
        "sulcus_attempts_of(text, text, text), sulcus_attempt(bigint, text), "
        "sulcus_sites_of(text, text, text)";
    for (const std::string& sql : std::vector<std::string>{
             "REVOKE CREATE ON SCHEMA public FROM PUBLIC",
             "REVOKE ALL ON ALL TABLES IN SCHEMA public FROM PUBLIC, " + both,
             "REVOKE ALL ON ALL SEQUENCES IN SCHEMA public FROM PUBLIC, " + both,
             "REVOKE ALL ON ALL FUNCTIONS IN SCHEMA public FROM PUBLIC, " + both,
             "GRANT USAGE ON SCHEMA public TO " + both,
             // A station stores attempts and signs students in only through
             // the owner's functions; it reads the attempts a station shows
             // and the public settings, no secret, and changes nothing.
             std::string("GRANT EXECUTE ON FUNCTION ") + functions + " TO " + both,
             "GRANT SELECT ON lessons, sulcus_schema, public_settings TO " + station,
             "GRANT SELECT (id, name, on_roster, created) ON students TO " + station,
             // The instructor reads everything but the passphrases and
             // sign-ins; keeps the roster (adds names, resets a passphrase),
             // the settings, and removes a student's results.
             "GRANT SELECT ON " + std::string(attempt_tables) +
                 ", sulcus_schema, public_settings, settings, chain_head TO " +
                 instructor,
             "GRANT SELECT (student_id, set_at) ON student_keys TO " + instructor,
             "GRANT INSERT, UPDATE ON settings TO " + instructor,
             "GRANT INSERT, UPDATE (name, name_key, on_roster) ON students TO " +
                 instructor,
             "GRANT USAGE ON SEQUENCE students_id_seq TO " + instructor,
             "GRANT DELETE ON student_keys TO " + instructor,
             std::string("GRANT DELETE ON ") + attempt_tables + " TO " + instructor}) {
      Exec(sql);
    }
    out.done.push_back(
        "granted the station only the store's functions (store an attempt, sign a "
        "student in, read a student's own attempts) and SELECT on the lessons, the "
        "students' names and the public settings: no INSERT, UPDATE, DELETE or DDL, "
        "no passphrase, no other student's attempt");
    out.done.push_back(
        "granted the instructor SELECT on every table but the passphrases, the roster, "
        "the settings and removing a student's results");
    t.Commit();
    out.station_password = station_pw;
    out.instructor_password = instructor_pw;
    return out;
  }

 private:
  void Migrate(int target) {
    // A store already at the version asked for opens without a lock or any DDL:
    // a station's role, which may create nothing, opens it. A station never
    // migrates: an older store waits for its owner's `results setup`.
    if (Query("SELECT to_regclass('sulcus_schema') IS NOT NULL", Params()).Text(0, 0) ==
        "t") {
      const int v = schema_version();
      if (v > kResultsSchemaVersion)
        throw ResultsError("PostgreSQL results store " + shown_ +
                           ": the store has schema version " + std::to_string(v) +
                           "; this Sulcus knows up to " +
                           std::to_string(kResultsSchemaVersion) +
                           " (it was written by a newer Sulcus; it is left untouched)");
      if (v >= target) return;
      if (v < target && !CanMigrate())
        throw ResultsError("PostgreSQL results store " + shown_ +
                           ": the store has schema version " + std::to_string(v) +
                           " and this Sulcus needs " + std::to_string(target) +
                           "; a station does not change the store: its owner runs "
                           "`sulcus-cli results setup` once");
    } else if (!CanMigrate()) {
      throw ResultsError("PostgreSQL results store " + shown_ +
                         ": the store has no tables yet and this role may not make "
                         "them: its owner runs `sulcus-cli results setup` once");
    }
    Transaction t(this);
    Exec("SELECT pg_advisory_xact_lock(" + std::to_string(kMigrationLock) + ")");
    Exec("CREATE TABLE IF NOT EXISTS sulcus_schema (version INTEGER NOT NULL)");
    int version = schema_version();
    if (version > kResultsSchemaVersion)
      throw ResultsError("PostgreSQL results store " + shown_ +
                         ": the store has schema version " + std::to_string(version) +
                         "; this Sulcus knows up to " +
                         std::to_string(kResultsSchemaVersion) +
                         " (it was written by a newer Sulcus; it is left untouched)");
    if (version == 0 && schema_rows() == 0) Exec("INSERT INTO sulcus_schema VALUES (0)");
    for (; version < target; ++version) {
      Exec(results_schema::MigrationSql(version, Dialect::kPostgres));
      Exec("UPDATE sulcus_schema SET version = " + std::to_string(version + 1));
    }
    t.Commit();
  }

  bool CanMigrate() const {
    return Query("SELECT has_schema_privilege(current_schema(), 'CREATE')", Params())
               .Text(0, 0) == "t";
  }

  int schema_rows() const {
    const Result r = Query("SELECT COUNT(*) FROM sulcus_schema", Params());
    return static_cast<int>(r.Int(0, 0));
  }

  std::string url_, shown_;
  std::string sign_in_;                    // ReadAs
  mutable std::optional<bool> reads_all_;  // (asked once)
  PGconn* pg_ = nullptr;
};

}  // namespace

std::unique_ptr<ResultsStore> OpenPostgresResults(const std::string& url, int version) {
  return std::make_unique<PgResults>(url, version);
}

StoreSetup SetUpPostgresStore(const std::string& owner_url,
                              const std::string& station_password,
                              const std::string& instructor_password) {
  PgResults owner(owner_url, kResultsSchemaVersion);  // migrated by its owner
  StoreSetup out = owner.SetUpRoles(station_password, instructor_password);
  out.done.insert(out.done.begin(),
                  "the schema at version " + std::to_string(kResultsSchemaVersion));
  return out;
}

}  // namespace sulcus
