#pragma once
// The results store's schema and queries, shared by its two backends (results.cpp:
// SQLite, results_pg.cpp: PostgreSQL), so that both hold the same tables and read
// the same columns. Private to core/lesson.

#include <string>

#include "core/lesson/results.h"

namespace sulcus::results_schema {

// Migrations, in order: migration i takes the schema from version i to i + 1.
// Written once for both backends: {ID}, {BIG}, {REAL} and {NOW} are spelled by
// each (MigrationSql).
inline constexpr const char* kMigrations[] = {
    R"sql(
CREATE TABLE students (
  id {ID},
  name TEXT NOT NULL UNIQUE,
  created TEXT NOT NULL DEFAULT {NOW}
);
CREATE TABLE lessons (
  id {ID},
  file TEXT NOT NULL UNIQUE,
  name TEXT NOT NULL
);
CREATE TABLE attempts (
  id {ID},
  student_id {BIG} NOT NULL REFERENCES students(id),
  lesson_id {BIG} NOT NULL REFERENCES lessons(id),
  started TEXT NOT NULL,
  mode TEXT NOT NULL,
  scene_file TEXT NOT NULL,
  generated_case INTEGER NOT NULL,
  case_seed {BIG} NOT NULL,
  total {REAL} NOT NULL,
  duration_s {REAL} NOT NULL,
  sites_total INTEGER NOT NULL,
  sites_read INTEGER NOT NULL,
  sites_charted INTEGER NOT NULL,
  within_1mm_pct {REAL} NOT NULL,
  bias_mm {REAL} NOT NULL,
  force_in_band_pct {REAL} NOT NULL,
  true_dx TEXT NOT NULL,
  chart_dx TEXT NOT NULL,
  declared_dx TEXT NOT NULL,
  recording TEXT NOT NULL,
  answers TEXT NOT NULL,
  report_dir TEXT NOT NULL
);
CREATE TABLE attempt_sites (
  attempt_id {BIG} NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  fdi INTEGER NOT NULL,
  site INTEGER NOT NULL,
  truth_mm INTEGER NOT NULL,
  reached_mm {REAL},
  entered_mm INTEGER,
  peak_force_n {REAL} NOT NULL,
  angle_deg {REAL} NOT NULL,
  col_reached INTEGER NOT NULL,
  bled INTEGER NOT NULL,
  bleeding_charted INTEGER NOT NULL,
  reading_tick {BIG} NOT NULL,
  PRIMARY KEY (attempt_id, fdi, site)
);
CREATE TABLE attempt_scores (
  attempt_id {BIG} NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  category TEXT NOT NULL,
  credit {REAL} NOT NULL,
  weight {REAL} NOT NULL,
  PRIMARY KEY (attempt_id, category)
);
CREATE TABLE attempt_lines (
  attempt_id {BIG} NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  seq INTEGER NOT NULL,
  category TEXT NOT NULL,
  fdi INTEGER NOT NULL,
  site INTEGER,
  status TEXT NOT NULL,
  credit {REAL} NOT NULL,
  tick {BIG} NOT NULL,
  message TEXT NOT NULL,
  PRIMARY KEY (attempt_id, seq)
);
CREATE INDEX attempts_by_student ON attempts(student_id, started);
)sql",
    // 2: whether the attempt reached its last step, and how it ended when it did not.
    R"sql(
ALTER TABLE attempts ADD COLUMN complete INTEGER NOT NULL DEFAULT 1;
ALTER TABLE attempts ADD COLUMN ended TEXT NOT NULL DEFAULT '';
)sql",
    // 3: the attempt's UUID, so that storing it again finds it (NULL before).
    R"sql(
ALTER TABLE attempts ADD COLUMN uuid TEXT;
CREATE UNIQUE INDEX attempts_by_uuid ON attempts(uuid);
)sql",
    // 4: settings every station shares.
    R"sql(
CREATE TABLE settings (key TEXT PRIMARY KEY, value TEXT NOT NULL);
)sql",
    // 5: what the attempt was taken with: haptic, keys, scripted or replay ('' before).
    R"sql(
ALTER TABLE attempts ADD COLUMN device TEXT NOT NULL DEFAULT '';
)sql",
    // 6: the settings a station may read (never the instructor's passphrase hash).
    R"sql(
CREATE VIEW public_settings AS
  SELECT key, value FROM settings WHERE key IN ('demonstrations');
)sql",
    // 7: each attempt's hash, chained to the one before it (ChainText), with
    // the hash it follows; on PostgreSQL made by the store's own trigger, under
    // a lock, from the chain's head (chain_head).
    R"sql(
ALTER TABLE attempts ADD COLUMN row_hash TEXT;
ALTER TABLE attempts ADD COLUMN prev_hash TEXT;
{PG_CHAIN}
)sql",
};
static_assert(sizeof(kMigrations) / sizeof(kMigrations[0]) == kResultsSchemaVersion);

enum class Dialect { kSqlite, kPostgres };

/// Migration i in a dialect's spelling.
inline std::string MigrationSql(int i, Dialect d) {
  const bool pg = d == Dialect::kPostgres;
  std::string sql = kMigrations[i];
  const auto put = [&](const std::string& key, const std::string& value) {
    for (std::size_t at = sql.find(key); at != std::string::npos; at = sql.find(key, at))
      sql.replace(at, key.size(), value);
  };
  put("{ID}", pg ? "BIGSERIAL PRIMARY KEY" : "INTEGER PRIMARY KEY");
  put("{BIG}", pg ? "BIGINT" : "INTEGER");
  put("{REAL}", pg ? "DOUBLE PRECISION" : "REAL");
  put("{PG_CHAIN}", pg ? R"sql(
CREATE TABLE chain_head (hash TEXT NOT NULL);
INSERT INTO chain_head VALUES ('');
CREATE FUNCTION sulcus_chain() RETURNS trigger LANGUAGE plpgsql SECURITY DEFINER
SET search_path = public, pg_temp AS $chain$
DECLARE prev TEXT;
BEGIN
  PERFORM pg_advisory_xact_lock(5375636861);
  IF EXISTS (SELECT 1 FROM attempts WHERE uuid = NEW.uuid) THEN
    RETURN NEW;  -- stored before: ON CONFLICT inserts nothing, the head stays
  END IF;
  SELECT hash INTO prev FROM chain_head;
  NEW.prev_hash := prev;
  NEW.row_hash := encode(sha256(convert_to(
      prev || E'\n' || coalesce(NEW.uuid, '') || E'\n' ||
      coalesce((SELECT name FROM students WHERE id = NEW.student_id), '') || E'\n' ||
      coalesce((SELECT file FROM lessons WHERE id = NEW.lesson_id), '') || E'\n' ||
      NEW.started || E'\n' || NEW.mode || E'\n' ||
      round(NEW.total * 1000)::bigint::text || E'\n' || NEW.complete::text || E'\n' ||
      NEW.declared_dx || E'\n' || NEW.device, 'UTF8')), 'hex');
  UPDATE chain_head SET hash = NEW.row_hash;
  RETURN NEW;
END
$chain$;
CREATE TRIGGER attempts_chain BEFORE INSERT ON attempts FOR EACH ROW
EXECUTE FUNCTION sulcus_chain();
)sql"
                       : "");
  put("{NOW}", pg ? "to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS\"Z\"')"
                  : "(strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))");
  return sql;
}

/// A query with parameters $1, $2...: PostgreSQL's spelling; SQLite's is ?1, ?2.
inline std::string Query(std::string sql, Dialect d) {
  if (d == Dialect::kSqlite)
    for (char& c : sql)
      if (c == '$') c = '?';
  return sql;
}

/// The chain's rows in order: what each attempt's hash covers.
inline constexpr const char* kSelectChain =
    "SELECT a.id, a.row_hash, a.uuid, s.name, l.file, a.started, a.mode, a.total, "
    "a.complete, a.declared_dx, a.device, a.prev_hash FROM attempts a JOIN students s ON "
    "s.id = "
    "a.student_id JOIN lessons l ON l.id = a.lesson_id ORDER BY a.id";

/// Attempts with their student and lesson; a WHERE clause follows.
inline constexpr const char* kSelectAttempts =
    "SELECT a.id, s.name, l.name, l.file, a.scene_file, a.mode, a.started, a.case_seed, "
    "a.generated_case, a.total, a.duration_s, a.within_1mm_pct, a.bias_mm, "
    "a.force_in_band_pct, a.sites_total, a.sites_read, a.sites_charted, a.true_dx, "
    "a.chart_dx, a.declared_dx, a.recording, a.answers, a.report_dir, a.complete, "
    "a.ended, a.uuid, a.device FROM attempts a JOIN students s ON s.id = a.student_id "
    "JOIN lessons "
    "l ON l.id = a.lesson_id ";
inline constexpr const char* kByStudentAndLesson =
    "WHERE ($1 = '' OR s.name = $1) AND ($2 = '' OR l.file = $2) ";
/// Every site of the attempts of a student and a lesson ($1, $2; '' for all).
inline constexpr const char* kSelectSites =
    "SELECT t.attempt_id, s.name, a.started, t.fdi, t.site, t.truth_mm, t.reached_mm, "
    "t.entered_mm, t.peak_force_n FROM attempt_sites t JOIN attempts a ON a.id = "
    "t.attempt_id JOIN students s ON s.id = a.student_id JOIN lessons l ON l.id = "
    "a.lesson_id WHERE ($1 = '' OR s.name = $1) AND ($2 = '' OR l.file = $2) ORDER BY "
    "t.attempt_id, t.fdi, t.site";

/// A row of kSelectAttempts, from any reader of columns (Text, Int, Real by index).
template <class Columns>
AttemptRow ReadAttempt(const Columns& c) {
  AttemptRow a;
  a.id = c.Int(0);
  a.student = c.Text(1);
  a.lesson_name = c.Text(2);
  a.lesson_file = c.Text(3);
  a.scene_file = c.Text(4);
  a.mode = c.Text(5);
  a.started = c.Text(6);
  a.case_seed = static_cast<std::uint64_t>(c.Int(7));
  a.generated_case = c.Int(8) != 0;
  a.total = c.Real(9);
  a.duration_s = c.Real(10);
  a.within_1mm_pct = c.Real(11);
  a.bias_mm = c.Real(12);
  a.force_in_band_pct = c.Real(13);
  a.sites_total = static_cast<int>(c.Int(14));
  a.sites_read = static_cast<int>(c.Int(15));
  a.sites_charted = static_cast<int>(c.Int(16));
  a.true_dx = c.Text(17);
  a.chart_dx = c.Text(18);
  a.declared_dx = c.Text(19);
  a.recording = c.Text(20);
  a.answers = c.Text(21);
  a.report_dir = c.Text(22);
  a.complete = c.Int(23) != 0;
  a.ended = c.Text(24);
  a.uuid = c.Text(25);
  a.device = c.Text(26);
  return a;
}

/// A row of kSelectChain.
template <class Columns>
ChainRow ReadChain(const Columns& c) {
  ChainRow r;
  r.id = c.Int(0);
  if (!c.IsNull(1)) r.row_hash = c.Text(1);
  r.uuid = c.IsNull(2) ? "" : c.Text(2);
  r.student = c.Text(3);
  r.lesson_file = c.Text(4);
  r.started = c.Text(5);
  r.mode = c.Text(6);
  r.total = c.Real(7);
  r.complete = c.Int(8) != 0;
  r.declared_dx = c.Text(9);
  r.device = c.Text(10);
  r.prev_hash = c.IsNull(11) ? "" : c.Text(11);
  return r;
}

/// A row of kSelectSites (IsNull by index too).
template <class Columns>
SiteRow ReadSite(const Columns& c) {
  SiteRow r;
  r.attempt = c.Int(0);
  r.student = c.Text(1);
  r.started = c.Text(2);
  r.fdi = static_cast<int>(c.Int(3));
  r.site = static_cast<int>(c.Int(4));
  r.truth_mm = static_cast<int>(c.Int(5));
  if (!c.IsNull(6)) r.reached_mm = c.Real(6);
  if (!c.IsNull(7)) r.entered_mm = static_cast<int>(c.Int(7));
  r.peak_force_n = c.Real(8);
  return r;
}

}  // namespace sulcus::results_schema
