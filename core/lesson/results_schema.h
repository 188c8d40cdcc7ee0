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
    // 8: the class's roster and its students' sign-in: each name's look-alike
    // key (NameLookAlikeKey), whether the instructor put it on the roster; a
    // student's passphrase as the store keeps it (a salt and the SHA-256 of
    // the Argon2id key a station derives from it: no station reads either),
    // sign-ins (the SHA-256 of each token) and wrong passphrases; whether an
    // attempt was stored by its signed-in student (the store decides). On
    // PostgreSQL the functions through which a station signs a student in and
    // stores an attempt ({PG_SIGN_IN}).
    R"sql(
ALTER TABLE students ADD COLUMN name_key TEXT NOT NULL DEFAULT '';
ALTER TABLE students ADD COLUMN on_roster INTEGER NOT NULL DEFAULT 0;
CREATE TABLE student_keys (
  student_id {BIG} PRIMARY KEY REFERENCES students(id) ON DELETE CASCADE,
  salt TEXT NOT NULL,
  key_hash TEXT NOT NULL,
  set_at TEXT NOT NULL DEFAULT {NOW}
);
CREATE TABLE sign_ins (
  token_hash TEXT PRIMARY KEY,
  student_id {BIG} NOT NULL REFERENCES students(id) ON DELETE CASCADE,
  at TEXT NOT NULL DEFAULT {NOW}
);
CREATE TABLE sign_in_failures (
  student_id {BIG} NOT NULL REFERENCES students(id) ON DELETE CASCADE,
  at TEXT NOT NULL DEFAULT {NOW}
);
ALTER TABLE attempts ADD COLUMN signed_in INTEGER NOT NULL DEFAULT 0;
DROP VIEW public_settings;
CREATE VIEW public_settings AS
  SELECT key, value FROM settings WHERE key IN ('demonstrations', 'sign_in');
{PG_SIGN_IN}
)sql",
};
static_assert(sizeof(kMigrations) / sizeof(kMigrations[0]) == kResultsSchemaVersion);

enum class Dialect { kSqlite, kPostgres };

/// The store's own trigger function that chains each new attempt (ChainText),
/// under a lock, from the chain's head; from schema 8 on it covers whether the
/// attempt was stored by its signed-in student (a line only when it was, so
/// that the hashes of earlier attempts hold as they were).
inline std::string PgChainFunction(bool signed_in) {
  return std::string(R"sql(
CREATE OR REPLACE FUNCTION sulcus_chain() RETURNS trigger LANGUAGE plpgsql
SECURITY DEFINER SET search_path = public, pg_temp AS $chain$
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
      NEW.declared_dx || E'\n' || NEW.device)sql") +
         (signed_in ? R"sql( ||
      CASE WHEN NEW.signed_in = 1 THEN E'\nsigned in' ELSE '' END)sql"
                    : "") +
         R"sql(, 'UTF8')), 'hex');
  UPDATE chain_head SET hash = NEW.row_hash;
  RETURN NEW;
END
$chain$;
)sql";
}

/// How long a sign-in's token stores attempts (an attempt kept waiting longer
/// is stored as not signed in), and how many wrong passphrases a name may be
/// given within a quarter of an hour.
inline constexpr int kSignInHours = 24;
inline constexpr int kWrongPassphrases = 10;

/// The functions a station calls (SECURITY DEFINER, their search_path
/// pinned): a student's salt; setting a passphrase at first use; signing in
/// (a token, or NULL for a wrong key); a student's attempts and sites (only
/// with a sign-in of that student when the store asks for sign-in: a station
/// reads no other attempt); storing an attempt. The attempt's row
/// says it was stored by its signed-in student only when the token is one of
/// that student's sign-ins, made within kSignInHours (an attempt that waited
/// longer on its station is stored, not as signed in); when the store asks
/// for sign-in (the `sign_in` setting "required") an attempt without a
/// sign-in of its student is refused, as a scripted or replayed one is unless
/// demonstrations are allowed (never a signed-in student's either).
inline constexpr const char* kPgSignIn = R"sql(
CREATE FUNCTION sulcus_salt(p_name TEXT) RETURNS TEXT LANGUAGE sql STABLE
SECURITY DEFINER SET search_path = public, pg_temp AS $f$
  SELECT k.salt FROM student_keys k JOIN students s ON s.id = k.student_id
  WHERE s.name = p_name AND s.on_roster = 1
$f$;

CREATE FUNCTION sulcus_set_passphrase(p_name TEXT, p_salt TEXT, p_key TEXT)
RETURNS BOOLEAN LANGUAGE plpgsql SECURITY DEFINER
SET search_path = public, pg_temp AS $f$
DECLARE sid BIGINT;
BEGIN
  SELECT id INTO sid FROM students WHERE name = p_name AND on_roster = 1;
  IF sid IS NULL OR length(p_salt) < 32 OR length(p_key) < 64 THEN RETURN false; END IF;
  INSERT INTO student_keys(student_id, salt, key_hash)
    VALUES (sid, p_salt, encode(sha256(convert_to(p_key, 'UTF8')), 'hex'))
    ON CONFLICT (student_id) DO NOTHING;
  RETURN FOUND;
END
$f$;

CREATE FUNCTION sulcus_sign_in(p_name TEXT, p_key TEXT) RETURNS TEXT LANGUAGE plpgsql
SECURITY DEFINER SET search_path = public, pg_temp AS $f$
DECLARE sid BIGINT; want TEXT; token TEXT;
  since TEXT := to_char((now() - interval '15 minutes') AT TIME ZONE 'UTC',
                        'YYYY-MM-DD"T"HH24:MI:SS"Z"');
BEGIN
  SELECT s.id, k.key_hash INTO sid, want FROM students s
    JOIN student_keys k ON k.student_id = s.id WHERE s.name = p_name AND s.on_roster = 1;
  IF sid IS NULL THEN RETURN NULL; END IF;
  IF (SELECT count(*) FROM sign_in_failures WHERE student_id = sid AND at > since)
      >= {WRONG} THEN
    RAISE EXCEPTION 'sulcus: too many wrong passphrases for %: wait a quarter of '
                    'an hour, or ask the instructor to reset it', p_name;
  END IF;
  IF want <> encode(sha256(convert_to(p_key, 'UTF8')), 'hex') THEN
    INSERT INTO sign_in_failures(student_id) VALUES (sid);
    RETURN NULL;
  END IF;
  token := replace(gen_random_uuid()::text || gen_random_uuid()::text, '-', '');
  INSERT INTO sign_ins(token_hash, student_id)
    VALUES (encode(sha256(convert_to(token, 'UTF8')), 'hex'), sid);
  RETURN token;
END
$f$;

CREATE VIEW attempt_rows AS
  SELECT a.id, s.name AS student, l.name AS lesson_name, l.file AS lesson_file,
    a.scene_file, a.mode, a.started, a.case_seed, a.generated_case, a.total,
    a.duration_s, a.within_1mm_pct, a.bias_mm, a.force_in_band_pct, a.sites_total,
    a.sites_read, a.sites_charted, a.true_dx, a.chart_dx, a.declared_dx, a.recording,
    a.answers, a.report_dir, a.complete, a.ended, a.uuid, a.device, a.signed_in
  FROM attempts a JOIN students s ON s.id = a.student_id
    JOIN lessons l ON l.id = a.lesson_id;
CREATE VIEW site_rows AS
  SELECT t.attempt_id, s.name AS student, a.started, t.fdi, t.site, t.truth_mm,
    t.reached_mm, t.entered_mm, t.peak_force_n, l.file AS lesson_file
  FROM attempt_sites t JOIN attempts a ON a.id = t.attempt_id
    JOIN students s ON s.id = a.student_id JOIN lessons l ON l.id = a.lesson_id;

CREATE FUNCTION sulcus_may_read(p_name TEXT, p_token TEXT) RETURNS BOOLEAN
LANGUAGE sql STABLE SECURITY DEFINER SET search_path = public, pg_temp AS $f$
  SELECT coalesce((SELECT value FROM settings WHERE key = 'sign_in'), '') <> 'required'
    OR EXISTS (SELECT 1 FROM sign_ins i JOIN students s ON s.id = i.student_id
      WHERE s.name = p_name AND i.token_hash =
          encode(sha256(convert_to(coalesce(p_token, ''), 'UTF8')), 'hex')
        AND i.at > to_char((now() - interval '{HOURS} hours') AT TIME ZONE 'UTC',
                           'YYYY-MM-DD"T"HH24:MI:SS"Z"'))
$f$;

CREATE FUNCTION sulcus_attempts_of(p_name TEXT, p_lesson TEXT, p_token TEXT)
RETURNS SETOF attempt_rows LANGUAGE sql STABLE SECURITY DEFINER
SET search_path = public, pg_temp AS $f$
  SELECT * FROM attempt_rows WHERE student = p_name AND
    (p_lesson = '' OR lesson_file = p_lesson) AND sulcus_may_read(p_name, p_token)
  ORDER BY id
$f$;

CREATE FUNCTION sulcus_attempt(p_id BIGINT, p_token TEXT) RETURNS SETOF attempt_rows
LANGUAGE sql STABLE SECURITY DEFINER SET search_path = public, pg_temp AS $f$
  SELECT * FROM attempt_rows WHERE id = p_id AND sulcus_may_read(student, p_token)
$f$;

CREATE FUNCTION sulcus_sites_of(p_name TEXT, p_lesson TEXT, p_token TEXT)
RETURNS SETOF site_rows LANGUAGE sql STABLE SECURITY DEFINER
SET search_path = public, pg_temp AS $f$
  SELECT * FROM site_rows WHERE student = p_name AND
    (p_lesson = '' OR lesson_file = p_lesson) AND sulcus_may_read(p_name, p_token)
  ORDER BY attempt_id, fdi, site
$f$;

CREATE FUNCTION sulcus_store_attempt(doc JSONB, p_token TEXT) RETURNS BIGINT
LANGUAGE plpgsql SECURITY DEFINER SET search_path = public, pg_temp AS $f$
DECLARE aid BIGINT; sid BIGINT; lid BIGINT; signed INTEGER := 0; signed_at TEXT;
  who TEXT := doc->>'student'; dev TEXT := coalesce(doc->>'device', '');
  since TEXT := to_char((now() - interval '{HOURS} hours') AT TIME ZONE 'UTC',
                        'YYYY-MM-DD"T"HH24:MI:SS"Z"');
BEGIN
  IF coalesce(who, '') = '' THEN
    RAISE EXCEPTION 'sulcus: an attempt needs its student';
  END IF;
  SELECT id INTO aid FROM attempts WHERE uuid = doc->>'uuid';
  IF FOUND THEN RETURN aid; END IF;  -- stored before: once
  SELECT id INTO sid FROM students WHERE name = who;
  IF dev IN ('scripted', 'replay') THEN
    IF coalesce((SELECT value FROM settings WHERE key = 'demonstrations'), '')
        <> 'allowed' THEN
      RAISE EXCEPTION 'sulcus: a % attempt is not %''s own: this store takes it '
                      'only when the instructor allows demonstrations', dev, who;
    END IF;
  ELSE
    SELECT max(at) INTO signed_at FROM sign_ins WHERE student_id = sid AND
      token_hash = encode(sha256(convert_to(coalesce(p_token, ''), 'UTF8')), 'hex');
    IF signed_at > since THEN
      signed := 1;
    ELSIF signed_at IS NULL AND
        coalesce((SELECT value FROM settings WHERE key = 'sign_in'), '') = 'required' THEN
      RAISE EXCEPTION 'sulcus: % is not signed in: this store takes a student''s '
                      'attempt only from that student, signed in', who;
    END IF;  -- (a sign-in older than {HOURS} hours: stored, not as signed in)
  END IF;
  IF sid IS NULL THEN
    IF coalesce(doc->>'name_key', '') <> '' AND EXISTS (
        SELECT 1 FROM students WHERE name_key = doc->>'name_key') THEN
      RAISE EXCEPTION 'sulcus: the name % looks like another student''s', who;
    END IF;
    INSERT INTO students(name, name_key) VALUES (who, coalesce(doc->>'name_key', ''))
      RETURNING id INTO sid;
  END IF;
  INSERT INTO lessons(file, name) VALUES (doc->>'lesson_file', doc->>'lesson_name')
    ON CONFLICT (file) DO NOTHING;
  SELECT id INTO lid FROM lessons WHERE file = doc->>'lesson_file';
  INSERT INTO attempts(student_id, lesson_id, started, mode, scene_file,
      generated_case, case_seed, total, duration_s, sites_total, sites_read,
      sites_charted, within_1mm_pct, bias_mm, force_in_band_pct, true_dx, chart_dx,
      declared_dx, recording, answers, report_dir, complete, ended, uuid, device,
      signed_in)
    VALUES (sid, lid, doc->>'started', doc->>'mode', doc->>'scene_file',
      (doc->>'generated_case')::int, (doc->>'case_seed')::bigint,
      (doc->>'total')::float8, (doc->>'duration_s')::float8,
      (doc->>'sites_total')::int, (doc->>'sites_read')::int,
      (doc->>'sites_charted')::int, (doc->>'within_1mm_pct')::float8,
      (doc->>'bias_mm')::float8, (doc->>'force_in_band_pct')::float8,
      doc->>'true_dx', doc->>'chart_dx', doc->>'declared_dx', doc->>'recording',
      doc->>'answers', doc->>'report_dir', (doc->>'complete')::int, doc->>'ended',
      nullif(doc->>'uuid', ''), dev, signed)
    ON CONFLICT (uuid) DO NOTHING RETURNING id INTO aid;
  IF aid IS NULL THEN  -- another station stored it at the same moment
    SELECT id INTO aid FROM attempts WHERE uuid = doc->>'uuid';
    RETURN aid;
  END IF;
  INSERT INTO attempt_sites(attempt_id, fdi, site, truth_mm, reached_mm, entered_mm,
      peak_force_n, angle_deg, col_reached, bled, bleeding_charted, reading_tick)
    SELECT aid, x.fdi, x.site, x.truth_mm, x.reached_mm, x.entered_mm, x.peak_force_n,
      x.angle_deg, x.col_reached, x.bled, x.bleeding_charted, x.reading_tick
    FROM jsonb_to_recordset(coalesce(doc->'sites', '[]')) AS x(fdi INT, site INT,
      truth_mm INT, reached_mm FLOAT8, entered_mm INT, peak_force_n FLOAT8,
      angle_deg FLOAT8, col_reached INT, bled INT, bleeding_charted INT,
      reading_tick BIGINT);
  INSERT INTO attempt_scores(attempt_id, category, credit, weight)
    SELECT aid, x.category, x.credit, x.weight
    FROM jsonb_to_recordset(coalesce(doc->'scores', '[]'))
      AS x(category TEXT, credit FLOAT8, weight FLOAT8);
  INSERT INTO attempt_lines(attempt_id, seq, category, fdi, site, status, credit,
      tick, message)
    SELECT aid, x.seq, x.category, x.fdi, x.site, x.status, x.credit, x.tick, x.message
    FROM jsonb_to_recordset(coalesce(doc->'lines', '[]')) AS x(seq INT, category TEXT,
      fdi INT, site INT, status TEXT, credit FLOAT8, tick BIGINT, message TEXT);
  RETURN aid;
END
$f$;
)sql";

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
  put("{PG_CHAIN}", pg ? std::string(R"sql(
CREATE TABLE chain_head (hash TEXT NOT NULL);
INSERT INTO chain_head VALUES ('');
)sql") + PgChainFunction(false) +
                             R"sql(
CREATE TRIGGER attempts_chain BEFORE INSERT ON attempts FOR EACH ROW
EXECUTE FUNCTION sulcus_chain();
)sql"
                       : "");
  put("{PG_SIGN_IN}", pg ? PgChainFunction(true) + kPgSignIn : "");
  put("{HOURS}", std::to_string(kSignInHours));
  put("{WRONG}", std::to_string(kWrongPassphrases));
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
    "a.complete, a.declared_dx, a.device, a.prev_hash, a.signed_in FROM attempts a JOIN "
    "students s ON "
    "s.id = "
    "a.student_id JOIN lessons l ON l.id = a.lesson_id ORDER BY a.id";

/// Attempts with their student and lesson; a WHERE clause follows.
inline constexpr const char* kSelectAttempts =
    "SELECT a.id, s.name, l.name, l.file, a.scene_file, a.mode, a.started, a.case_seed, "
    "a.generated_case, a.total, a.duration_s, a.within_1mm_pct, a.bias_mm, "
    "a.force_in_band_pct, a.sites_total, a.sites_read, a.sites_charted, a.true_dx, "
    "a.chart_dx, a.declared_dx, a.recording, a.answers, a.report_dir, a.complete, "
    "a.ended, a.uuid, a.device, a.signed_in FROM attempts a JOIN students s ON s.id = "
    "a.student_id "
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
  a.signed_in = c.Int(27) != 0;
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
  r.signed_in = c.Int(12) != 0;
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
