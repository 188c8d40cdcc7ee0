// The results store on a real PostgreSQL server (started by the test in a folder
// of its own, as a lab's server would run): migrations from an empty and from an
// older schema, the same rows as the SQLite file, twenty stations storing at once,
// a server stopped in the middle of the writes and started again, a wrong password
// or host, and a station that stored while the server was down and syncs later.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>

#include "core/lesson/attempt.h"
#include "core/lesson/instructor.h"
#include "core/lesson/results.h"
#include "core/lesson/sign_in.h"
#include "tests/common/kill_sweep.h"
#include "tests/common/output.h"
#include "tests/common/postgres_server.h"
#include "tests/core/lesson/sample_result.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;
using test::PostgresServer;
using test::Sample;

// One server for the process (ctest runs each test in a process of its own);
// stopped and removed when the process exits.
PostgresServer& Server() {
  static PostgresServer server;
  return server;
}

// A database of its own per test, so that tests run in one process do not see
// each other's rows. Its attempts are made by scripted students: the
// instructor's allowing demonstrations is set, unless `demonstrations` is false.
std::string FreshDatabase(const std::string& name, bool demonstrations = true) {
  const std::string url = Server().FreshDatabase(name);
  if (demonstrations)
    OpenPostgresResults(url)->SetSetting(kDemonstrationsSetting, "allowed");
  return url;
}

std::string Uuid(int station, int k) {
  char b[64];
  std::snprintf(b, sizeof b, "00000000-0000-4000-8000-%06d%06d", station % 1000000,
                k % 1000000);
  return b;
}

TEST(ResultsPg, MigratesFromEmptyAndFromAnOlderSchemaAndKeepsTheSameRowsAsSqlite) {
  const std::string url = FreshDatabase("migrations", false);
  {
    const auto v2 = OpenPostgresResults(url, 2);
    EXPECT_EQ(v2->schema_version(), 2);
  }
  const auto pg = OpenPostgresResults(url);
  EXPECT_EQ(pg->schema_version(), kResultsSchemaVersion);
  EXPECT_EQ(OpenPostgresResults(url)->schema_version(), kResultsSchemaVersion)
      << "opened again: nothing to migrate";
  const fs::path file = test::FreshOutputPath("results_pg", "same") / "results.db";
  ResultsDb lite(file);
  for (ResultsStore* store :
       {static_cast<ResultsStore*>(pg.get()), static_cast<ResultsStore*>(&lite)}) {
    LessonResult r = Sample("ada", 87.5);
    r.complete = false;
    r.ended = "the window was closed";
    const std::int64_t id =
        store->Store(r, "2026-12-01T10:00:00Z", "/a.rec", "/a.yaml", "/a", Uuid(0, 1));
    EXPECT_EQ(
        store->Store(r, "2026-12-01T10:00:00Z", "/a.rec", "/a.yaml", "/a", Uuid(0, 1)),
        id)
        << "a retry with the same UUID is the same attempt";
    store->Store(Sample("bo", 60), "2026-12-01T11:00:00Z", "/b.rec", "/b.yaml", "/b");
    store->SetReportDir(id, "/elsewhere");
  }
  // Every column the same, on both backends.
  const auto a = pg->Attempts(), b = lite.Attempts();
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  std::ostringstream csv_a, csv_b, sites_a, sites_b;
  ExportAttemptsCsv(a, csv_a);
  ExportAttemptsCsv(b, csv_b);
  EXPECT_EQ(csv_a.str(), csv_b.str());
  ExportSitesCsv(pg->Sites("ada"), sites_a);
  ExportSitesCsv(lite.Sites("ada"), sites_b);
  EXPECT_EQ(sites_a.str(), sites_b.str());
  EXPECT_EQ(a[0].uuid, Uuid(0, 1));
  EXPECT_EQ(a[0].report_dir, "/elsewhere");
  EXPECT_FALSE(a[0].complete);
  EXPECT_EQ(pg->Students(), (std::vector<std::string>{"ada", "bo"}));
  EXPECT_EQ(pg->DeleteStudent("bo"), 1);
  EXPECT_EQ(pg->Attempts().size(), 1u);
}

// Twenty stations (processes) store five attempts each at once, each retrying
// its first: all 100 arrive, none twice.
TEST(ResultsPg, TwentyStationsStoringAtOnceLoseNothingAndDuplicateNothing) {
  const std::string url = FreshDatabase("lab");
  { OpenPostgresResults(url); }  // the empty tables, to measure what attempts add
  const auto size = [] {
    return std::stod(Server().Sql("lab", "SELECT pg_database_size(current_database())"));
  };
  const double empty_bytes = size();
  constexpr int kStations = 20, kEach = 5;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(
      test::RunStationsAtOnce(kStations,
                              [&](int s) {
                                // Each station opens the store itself: the
                                // empty schema is migrated once, under the
                                // store's lock, whoever comes first.
                                const auto store = OpenPostgresResults(url);
                                const std::string who = "station" + std::to_string(s);
                                for (int k = 0; k < kEach; ++k)
                                  store->Store(Sample(who, k), "2026-12-01T10:00:00Z",
                                               "r", "a", "d", Uuid(s, k));
                                store->Store(Sample(who, 0), "2026-12-01T10:00:00Z", "r",
                                             "a", "d", Uuid(s, 0));
                              }),
      0);
  const double s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto store = OpenPostgresResults(url);
  const auto rows = store->Attempts();
  std::printf(
      "figure: %d stations stored %zu attempts (24 sites, 120 lines each) in %.2f s: "
      "%.0f attempts a second\n",
      kStations, rows.size(), s, rows.size() / s);
  EXPECT_EQ(rows.size(), static_cast<std::size_t>(kStations * kEach));
  std::set<std::string> uuids;
  for (const AttemptRow& r : rows) uuids.insert(r.uuid);
  EXPECT_EQ(uuids.size(), rows.size());
  EXPECT_EQ(store->Sites().size(), rows.size() * 24) << "every attempt whole";
  Server().Sql("lab", "CHECKPOINT");
  const double per_1000 = (size() - empty_bytes) / rows.size() * 1000;
  // The same attempts in a station's SQLite file.
  const fs::path file = test::FreshOutputPath("results_pg", "size") / "results.db";
  {
    ResultsDb lite(file);
    for (const AttemptRow& r : rows)
      lite.Store(Sample(r.student, r.total), r.started, "r", "a", "d", r.uuid);
  }
  std::printf(
      "figure: store size per 1,000 attempts: PostgreSQL %.1f MB, SQLite %.1f MB\n",
      per_1000 / 1e6,
      fs::file_size(file) / static_cast<double>(rows.size()) * 1000 / 1e6);
  EXPECT_GT(per_1000, 0);
}

// The server stops (as a crash would) while a station is writing: what was
// committed is there and whole, the attempt being written is not there at all,
// and storing it again after the restart stores it once.
TEST(ResultsPg, AServerStoppedMidWriteLosesNothingCommittedAndARetryStoresOnce) {
  const std::string url = FreshDatabase("crash");
  { OpenPostgresResults(url); }
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(fds[0]);
    try {
      const auto store = OpenPostgresResults(url);
      for (int k = 0;; ++k) {
        store->Store(Sample("writer", k), "2026-12-01T10:00:00Z", "r", "a", "d",
                     Uuid(1, k));
        if (write(fds[1], &k, sizeof k) != sizeof k) _exit(2);
      }
    } catch (const ResultsError& e) {
      // The station keeps the attempt (its folder and the outbox) and says why.
      std::fprintf(stderr, "writer: %s\n", e.what());
      _exit(3);
    }
  }
  close(fds[1]);
  int k = -1, committed = 0;
  while (committed < 10 && read(fds[0], &k, sizeof k) == sizeof k) ++committed;
  Server().Stop(true);
  int status = 0;
  waitpid(child, &status, 0);
  while (read(fds[0], &k, sizeof k) == sizeof k) committed = k + 1;
  close(fds[0]);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3)
      << "the writer is told the store is gone";
  Server().Start();
  const auto store = OpenPostgresResults(url);
  const auto rows = store->Attempts("writer");
  EXPECT_GE(static_cast<int>(rows.size()), committed);
  EXPECT_LE(static_cast<int>(rows.size()), committed + 1)
      << "at most the one whose commit reached the server before it stopped";
  EXPECT_EQ(store->Sites("writer").size(), rows.size() * 24) << "no half attempt";
  // The station retries the attempt it could not store: once.
  const int retried = static_cast<int>(rows.size());
  store->Store(Sample("writer", retried), "2026-12-01T10:00:00Z", "r", "a", "d",
               Uuid(1, retried));
  store->Store(Sample("writer", retried), "2026-12-01T10:00:00Z", "r", "a", "d",
               Uuid(1, retried));
  EXPECT_EQ(store->Attempts("writer").size(), rows.size() + 1);
}

TEST(ResultsPg, AWrongPasswordOrHostIsSaidWithTheUrlButNotThePassword) {
  const std::string bad = Server().url("not-the-password");
  try {
    OpenPostgresResults(bad);
    FAIL() << "connected with a wrong password";
  } catch (const ResultsError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("postgresql://sulcus:***@127.0.0.1:"), std::string::npos) << m;
    EXPECT_EQ(m.find("not-the-password"), std::string::npos) << m;
    EXPECT_NE(m.find("password authentication failed"), std::string::npos) << m;
  }
  const std::string nowhere =
      "postgresql://sulcus:" + std::string(PostgresServer::kPassword) +
      "@127.0.0.1:" + std::to_string(test::FreePort()) + "/postgres";
  try {
    OpenPostgresResults(nowhere);
    FAIL() << "connected to nothing";
  } catch (const ResultsError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cannot connect"), std::string::npos) << m;
    EXPECT_EQ(m.find(PostgresServer::kPassword), std::string::npos) << m;
    EXPECT_NE(m.find("results sync"), std::string::npos) << m;
  }
  EXPECT_EQ(RedactUrl("postgres://u:p@h/db?password=q&sslmode=require"),
            "postgres://u:***@h/db?password=***&sslmode=require");
  // A raw '@' in the password: the user information ends at the last '@'.
  EXPECT_EQ(RedactUrl("postgresql://u:pa@ss@h:5432/db"), "postgresql://u:***@h:5432/db");
  EXPECT_EQ(UrlPassword("postgresql://u:pa@ss@h/db"), "pa@ss");
  EXPECT_EQ(UrlPassword("postgresql://u:p%40%zz@h/db"), "p@%zz");
  EXPECT_EQ(UrlPassword("postgresql://u@h/db"), "");
  // A library's message that repeats the password, as written or decoded.
  EXPECT_EQ(RedactPassword("invalid percent-encoded token: \"p%40%zz\"",
                           "postgresql://u:p%40%zz@h/db"),
            "invalid percent-encoded token: \"***\"");
  EXPECT_EQ(RedactPassword("user u password p@%zz", "postgresql://u:p%40%zz@h/db"),
            "user u password ***");
}

// A station keeps an attempt while the server is down (its folder, marked as
// waiting), and `results sync` (RecoverAttempt over the waiting folders) stores it
// when the server is back: once, with its UUID.
TEST(ResultsPg, AnAttemptMadeWhileTheServerWasDownIsSyncedOnce) {
  const std::string url = FreshDatabase("outbox");
  const fs::path results = test::FreshOutputPath("results_pg", "station");
  const ResultsPlace place(results, url);
  const AttemptFolder folder = NewAttemptFolder(results, "cleo");
  AttemptOptions o;
  o.student = "cleo";
  o.device = "student:spot";
  o.cache_dir = fs::path(SULCUS_TEST_OUTPUT) / "probing-cache";
  o.record = folder.recording();
  o.keep_in = &folder;
  const AttemptOutcome out =
      RunAttempt(fs::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing.yaml", o);
  Server().Stop();
  try {
    KeepAttempt(out.result, folder, folder.dir, place);
    FAIL() << "stored with the server down";
  } catch (const ResultsError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot connect"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::exists(folder.dir / kUnstoredFile));
  EXPECT_TRUE(fs::exists(folder.dir / "report.json")) << "the report is kept";
  ASSERT_EQ(UnfinishedAttempts(results), std::vector<fs::path>{folder.dir});
  Server().Start();
  const RecoveredAttempt kept = RecoverAttempt(folder.dir, place, o.cache_dir);
  EXPECT_TRUE(UnfinishedAttempts(results).empty());
  const auto store = OpenPostgresResults(url);
  const auto rows = store->Attempts("cleo");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].id, kept.id);
  EXPECT_EQ(rows[0].uuid, AttemptUuid(folder.dir));
  EXPECT_DOUBLE_EQ(rows[0].total, out.result.total) << "the same attempt, rebuilt";
  // Stored again (a second sync, another station's retry): still once.
  KeepAttempt(out.result, folder, folder.dir, place);
  EXPECT_EQ(store->Attempts("cleo").size(), 1u);
}

// The kill sweep against a real server: a station stopped at each step of
// keeping an attempt (SIGKILL, SIGTERM, SIGINT in turn) and at timed instants
// within it; after a sync every attempt is in the server's store exactly once.
TEST(ResultsPg, AKeepingStoppedAtAnyInstantIsStoredExactlyOnceAfterASync) {
  const fs::path cache = fs::path(SULCUS_TEST_OUTPUT) / "probing-cache";
  const test::MadeAttempt m = test::MakeSpotAttempt(
      test::OutputPath("results_pg", "sweep-template"), "sam", cache);
  const AttemptFolder& made = m.folder;
  const AttemptOutcome& out = m.out;
  int waited = 0, n = 0;
  for (const test::SweepStop& st : test::SweepStops({1000, 5000, 20000, 60000})) {
    const std::string url = FreshDatabase("sweep" + std::to_string(n));
    const ResultsPlace place(
        test::FreshOutputPath("results_pg", "sweep-" + std::to_string(n++)), url);
    waited += test::StopAndSync(made, out.result, place, st, cache);
    EXPECT_EQ(OpenPostgresResults(url)->Attempts("sam").size(), 1u)
        << st.What() << ": exactly once";
  }
  EXPECT_GE(waited, 5);
}

// A disk that fills while a station keeps an attempt for a real server (the
// station's results folder on a small disk filled but 0 bytes to 1 MB): each
// time the attempt is in the server's store or waiting, and after a sync it is
// in the store exactly once.
TEST(ResultsPg, ADiskThatFillsWhileAnAttemptIsKeptLosesNothing) {
  const fs::path cache = fs::path(SULCUS_TEST_OUTPUT) / "probing-cache";
  const test::MadeAttempt m = test::MakeSpotAttempt(
      test::OutputPath("results_pg", "full-disk-template"), "fay", cache);
  const AttemptFolder& made = m.folder;
  const AttemptOutcome& out = m.out;
  test::SmallDisk disk(test::OutputPath("results_pg", "full-disk"), 4);
  int waited = 0, n = 0;
  for (const std::uintmax_t free : {0, 16384, 131072, 262144, 393216, 1048576}) {
    const std::string url = FreshDatabase("disk" + std::to_string(n));
    const ResultsPlace place(disk.dir() / ("case-" + std::to_string(n++)), url);
    const auto rows = [&] {
      return static_cast<int>(OpenPostgresResults(url)->Attempts("fay").size());
    };
    waited += test::FullDiskAndSync(made, out.result, disk, place, free, cache, rows);
    EXPECT_EQ(rows(), 1) << free << " bytes free: exactly once";
    fs::remove_all(place.dir);
  }
  // A file-size limit (where no tmpfs can be mounted) stops fewer writes.
  EXPECT_GE(waited, disk.mounted() ? 3 : 2);
}

// Scripted and replayed attempts are not a student's: a station of a shared
// store refuses to keep one under a student's name until the instructor allows
// demonstrations; then it is stored, marked with its device, as a person's
// attempt is with theirs. A station's own SQLite file takes every kind.
TEST(ResultsPg, AScriptedAttemptIsRefusedByASharedStoreUnlessDemonstrationsAreAllowed) {
  const std::string url = FreshDatabase("demonstrations", false);
  const fs::path dir = test::FreshOutputPath("results_pg", "demonstrations");
  const ResultsPlace place(dir, url);
  EXPECT_EQ(DemonstrationRefusal(place, "keys"), "");
  EXPECT_EQ(DemonstrationRefusal(place, "haptic"), "");
  EXPECT_NE(DemonstrationRefusal(place, "replay"), "");
  EXPECT_EQ(DemonstrationRefusal(ResultsPlace(dir), "scripted"), "") << "a station's own";
  const std::string why = DemonstrationRefusal(place, "scripted");
  EXPECT_NE(why.find("allows demonstrations"), std::string::npos) << why;

  LessonResult scripted = test::Sample("alice", 100.0);
  scripted.device_kind = "scripted";
  const AttemptFolder a = NewAttemptFolder(dir, "alice");
  EXPECT_THROW(KeepAttempt(scripted, a, a.dir, place), std::runtime_error);
  EXPECT_TRUE(OpenPostgresResults(url)->Attempts("alice").empty()) << "not stored";
  EXPECT_FALSE(fs::exists(a.dir / kUnstoredFile)) << "and not marked as waiting";

  LessonResult person = test::Sample("alice", 62.5);
  person.device_kind = "keys";
  const AttemptFolder b = NewAttemptFolder(dir, "alice");
  KeepAttempt(person, b, b.dir, place);

  OpenPostgresResults(url)->SetSetting(kDemonstrationsSetting, "allowed");
  EXPECT_EQ(DemonstrationRefusal(place, "scripted"), "");
  const AttemptFolder c = NewAttemptFolder(dir, "alice");
  KeepAttempt(scripted, c, c.dir, place);
  const auto rows = OpenPostgresResults(url)->Attempts("alice");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].device, "keys");
  EXPECT_EQ(rows[1].device, "scripted") << "marked, for the instructor's view";
  OpenPostgresResults(url)->SetSetting(kDemonstrationsSetting, "forbidden");
  EXPECT_NE(DemonstrationRefusal(place, "scripted"), "");
}

// Roles made by Sulcus: after `results setup` (its owner's URL), a station's role
// stores, syncs and shows attempts as before, and every other thing a student
// holding the station's credentials tried is refused by the server: changing or
// removing attempts, reading or replacing the instructor's passphrase, DDL, a
// trigger, another role. A station never migrates an older store.
TEST(ResultsPg, AStationsRoleStoresAndReadsAttemptsAndNothingElse) {
  const std::string owner = FreshDatabase("roles", false);
  const StoreSetup setup = SetUpPostgresStore(owner, "station-pw-17", "");
  EXPECT_EQ(setup.station_password, "station-pw-17");
  EXPECT_EQ(setup.instructor_password.size(), 24u) << "made when not given";
  const std::string host = "@127.0.0.1:" + std::to_string(Server().port()) + "/roles";
  const std::string station = std::string("postgresql://") + kStationRole +
                              ":station-pw-17" + host,
                    instructor = std::string("postgresql://") + kInstructorRole + ":" +
                                 setup.instructor_password + host;
  // The instructor's role sets the passphrase; the station stores and shows.
  InstructorLock(ResultsPlace({}, instructor)).Set("the lab's passphrase");
  // The instructor keeps the roster; a look-alike of a name on it is refused.
  {
    const auto teacher = OpenPostgresResults(instructor);
    std::vector<std::string> refused;
    EXPECT_EQ(AddNamesToRoster(*teacher, {"bea", " cal", "Bea"}, &refused), 2);
    ASSERT_EQ(refused.size(), 1u);
    EXPECT_NE(refused[0].find("looks like"), std::string::npos) << refused[0];
    EXPECT_EQ(teacher->Roster(), (std::vector<std::string>{"bea", "cal"}));
    teacher->SetSetting(kSignInSetting, "required");  // (a new store: off)
  }
  const fs::path dir = test::FreshOutputPath("results_pg", "roles");
  const ResultsPlace place(dir, station);
  LessonResult mine = Sample("bea", 71.5);
  mine.device_kind = "keys";
  const AttemptFolder f = NewAttemptFolder(dir, "bea");
  // Not signed in: refused by the store, and kept waiting in its folder.
  try {
    KeepAttempt(mine, f, f.dir, place);
    ADD_FAILURE() << "an attempt stored for a student who did not sign in";
  } catch (const ResultsError& e) {
    EXPECT_NE(std::string(e.what()).find("bea is not signed in"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::exists(f.dir / kUnstoredFile)) << "the attempt waits";
  const auto at_station = OpenPostgresResults(station);
  const SignInResult bea = SignIn(*at_station, "bea", "bea's own passphrase");
  EXPECT_TRUE(bea.first_use);
  EXPECT_THROW(SignIn(*at_station, "bea", "bea's own passphrasE"), ResultsError);
  EXPECT_THROW(SignIn(*at_station, "dan", "dan's passphrase"), ResultsError)
      << "not on the roster";
  EXPECT_FALSE(SignIn(*at_station, "bea", "bea's own passphrase").first_use);
  KeepSignIn(f.dir, bea.token);
  const std::int64_t id = KeepAttempt(mine, f, f.dir, place);
  EXPECT_EQ(KeepAttempt(mine, f, f.dir, place), id) << "a retry: once";
  EXPECT_FALSE(fs::exists(f.dir / kUnstoredFile));
  EXPECT_TRUE(at_station->Attempts("bea").empty())
      << "a station reads a student's attempts only with that student's sign-in";
  ResultsPlace as_bea = place;
  as_bea.sign_in = bea.token;
  const auto rows = OpenResults(as_bea)->Attempts("bea");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0].total, 71.5);
  EXPECT_TRUE(rows[0].signed_in);
  EXPECT_EQ(OpenResults(as_bea)->Sites("bea").size(), 24u);
  EXPECT_TRUE(OpenResults(as_bea)->Attempt(rows[0].id).has_value());
  EXPECT_TRUE(OpenResults(as_bea)->Attempts("cal").empty()) << "nor another's with it";
  EXPECT_TRUE(OpenResults(as_bea)->Attempts().empty()) << "nor everyone's";
  // Bea's sign-in does not store an attempt for cal.
  LessonResult forged = Sample("cal", 99.0);
  forged.device_kind = "keys";
  EXPECT_THROW(at_station->Store(forged, "2026-12-01T10:00:00Z", "", "", "", Uuid(9, 1),
                                 bea.token),
               ResultsError);
  EXPECT_NE(DemonstrationRefusal(place, "scripted"), "") << "the public setting is read";
  try {
    InstructorLock(place).is_set();
    ADD_FAILURE() << "a station read the passphrase's hash";
  } catch (const ResultsError& e) {
    EXPECT_NE(std::string(e.what()).find("instructor's role"), std::string::npos)
        << e.what();
  }
  // What a student with the station's credentials tried, each refused.
  for (const char* sql :
       {"UPDATE attempts SET total = 98.5",
        "DELETE FROM attempts",
        "DELETE FROM students",
        "TRUNCATE attempts CASCADE",
        "SELECT value FROM settings",
        "UPDATE settings SET value = 'x' WHERE key = 'instructor_pwhash'",
        "INSERT INTO settings VALUES ('demonstrations', 'allowed')",
        "CREATE TABLE evil (x INTEGER)",
        "DROP TABLE attempt_lines",
        "ALTER TABLE attempts ADD COLUMN evil INTEGER",
        "CREATE TRIGGER evil BEFORE INSERT ON attempts FOR EACH ROW EXECUTE FUNCTION "
        "suppress_redundant_updates_trigger()",
        "ALTER ROLE sulcus_instructor PASSWORD 'mine'",
        "ALTER ROLE sulcus_station SUPERUSER",
        "CREATE ROLE evil LOGIN",
        "GRANT sulcus_instructor TO sulcus_station",
        "INSERT INTO students(name) VALUES ('mallory')",
        "UPDATE students SET on_roster = 1",
        "SELECT name_key FROM students",
        "INSERT INTO attempts(student_id, lesson_id, started, mode, scene_file, "
        "generated_case, case_seed, total, duration_s, sites_total, sites_read, "
        "sites_charted, within_1mm_pct, bias_mm, force_in_band_pct, true_dx, chart_dx, "
        "declared_dx, recording, answers, report_dir) SELECT student_id, lesson_id, "
        "started, mode, scene_file, generated_case, case_seed, 100, duration_s, "
        "sites_total, sites_read, sites_charted, within_1mm_pct, bias_mm, "
        "force_in_band_pct, true_dx, chart_dx, declared_dx, recording, answers, "
        "report_dir FROM attempts",
        "INSERT INTO attempt_lines SELECT * FROM attempt_lines",
        "SELECT key_hash FROM student_keys",
        "SELECT salt FROM student_keys",
        "DELETE FROM student_keys",
        "SELECT * FROM sign_ins",
        "INSERT INTO sign_ins(token_hash, student_id) SELECT 'x', id FROM students",
        "DELETE FROM sign_in_failures",
        "UPDATE chain_head SET hash = ''",
        "SELECT sulcus_store_attempt('{\"student\": \"cal\", \"device\": "
        "\"keys\"}'::jsonb, NULL)",
        "SELECT total FROM attempts",
        "SELECT * FROM attempt_sites",
        "SELECT * FROM attempt_rows",
        "SELECT sulcus_may_read('bea', NULL)",
        "CREATE OR REPLACE FUNCTION sulcus_salt(p_name TEXT) RETURNS TEXT LANGUAGE sql "
        "AS $$ SELECT 'x' $$"}) {
    std::string said;
    EXPECT_NE(Server().Try(station, sql, &said), 0) << sql << ": " << said;
    EXPECT_NE(said.find("ERROR"), std::string::npos) << sql << ": " << said;
  }
  std::string said;
  ASSERT_EQ(Server().Try(owner, "SELECT total FROM attempts", &said), 0) << said;
  EXPECT_EQ(said, "71.5\n") << "the row as it was stored";
  // The instructor resets a forgotten passphrase: set again at the next sign-in.
  EXPECT_TRUE(OpenPostgresResults(instructor)->ResetPassphrase("bea"));
  EXPECT_TRUE(SignIn(*at_station, "bea", "a new passphrase").first_use);
  // The instructor's role reads everything and writes the settings.
  EXPECT_TRUE(InstructorLock(ResultsPlace({}, instructor)).Check("the lab's passphrase"));
  OpenPostgresResults(instructor)->SetSetting(kDemonstrationsSetting, "allowed");
  EXPECT_EQ(DemonstrationRefusal(place, "scripted"), "");
  // A store older than this Sulcus: the station says so and changes nothing.
  Server().Sql("roles", "UPDATE sulcus_schema SET version = 5");
  try {
    OpenPostgresResults(station);
    ADD_FAILURE() << "a station migrated the store";
  } catch (const ResultsError& e) {
    EXPECT_NE(std::string(e.what()).find("results setup"), std::string::npos) << e.what();
  }
  EXPECT_EQ(Server().Sql("roles", "SELECT version FROM sulcus_schema"), "5");
}

// The store over TLS as a school sets it up (a server certificate from the
// school's CA, every connection required to use TLS): a station that verifies
// the server (sslmode=verify-full with the CA) stores over TLS; one given
// another CA is refused, the password not shown; one without TLS is refused.
TEST(ResultsPg, OverTlsTheServerIsVerifiedAndAnotherCertificateRefused) {
  test::PostgresServer server;
  const fs::path ca = server.EnableTls(), other = server.OtherCa();
  const std::string base = server.FreshDatabase("tls");
  const std::string url = base + "?sslmode=verify-full&sslrootcert=" + ca.string();
  const auto store = OpenPostgresResults(url);
  LessonResult r = Sample("tess", 90.0);
  r.device_kind = "keys";
  store->Store(r, "2026-12-01T10:00:00Z", "", "", "", Uuid(7, 1));
  EXPECT_EQ(store->Attempts("tess").size(), 1u);
  std::string said;
  ASSERT_EQ(
      server.Try(url, "SELECT ssl FROM pg_stat_ssl WHERE pid = pg_backend_pid()", &said),
      0)
      << said;
  EXPECT_EQ(said, "t\n") << "the connection is TLS";
  try {
    OpenPostgresResults(base + "?sslmode=verify-full&sslrootcert=" + other.string());
    ADD_FAILURE() << "a server the station cannot verify was trusted";
  } catch (const ResultsError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("certificate"), std::string::npos) << m;
    EXPECT_EQ(m.find(test::PostgresServer::kPassword), std::string::npos) << m;
  }
  EXPECT_THROW(OpenPostgresResults(base + "?sslmode=disable"), ResultsError)
      << "the server takes no connection without TLS";
}

// No change unseen on the shared store: the chain is made by the store's own
// trigger (the station sends no hash), holds for attempts stored by twenty
// stations at once, and names the row the owner changed.
TEST(ResultsPg, TheStoresHashChainNamesTheRowItsOwnerChanged) {
  const std::string url = FreshDatabase("chain", false);
  EXPECT_EQ(test::RunStationsAtOnce(
                6,
                [&](int s) {
                  const auto store = OpenPostgresResults(url);
                  for (int k = 0; k < 3; ++k)
                    store->Store(Sample("s" + std::to_string(s), 50 + k + 0.1234),
                                 "2026-12-01", "", "", "", Uuid(s, k));
                }),
            0);
  ChainCheck c = CheckChain(OpenPostgresResults(url)->Chain());
  EXPECT_EQ(c.rows, 18);
  EXPECT_EQ(c.chained, 18);
  EXPECT_TRUE(c.breaks.empty()) << c.breaks.front().id << ": " << c.breaks.front().why;
  const std::string id = Server().Sql("chain", "SELECT min(id) + 7 FROM attempts");
  Server().Sql("chain", "UPDATE attempts SET total = 99.9 WHERE id = " + id);
  c = CheckChain(OpenPostgresResults(url)->Chain());
  ASSERT_EQ(c.breaks.size(), 1u);
  EXPECT_EQ(std::to_string(c.breaks[0].id), id);
}

// The instructor's passphrase set at one station opens the instructor's view at
// another: its hash is in the shared store, not in a station's folder.
TEST(ResultsPg, TheInstructorsPassphraseIsTheSameOnEveryStation) {
  const std::string url = FreshDatabase("passphrase");
  const fs::path a = test::FreshOutputPath("results_pg", "station-a"),
                 b = test::FreshOutputPath("results_pg", "station-b");
  {
    InstructorLock first(ResultsPlace(a, url));
    EXPECT_FALSE(first.is_set());
    first.Set("correct horse battery");
  }
  EXPECT_FALSE(fs::exists(a / "instructor.pwhash")) << "not in the station's folder";
  InstructorLock other(ResultsPlace(b, url));
  EXPECT_TRUE(other.is_set());
  EXPECT_TRUE(other.Check("correct horse battery"));
  EXPECT_FALSE(other.Check("wrong horse battery"));
  EXPECT_THROW(other.Set("another passphrase"), std::runtime_error) << "set once";
  const auto store = OpenPostgresResults(url);
  const std::string hash = store->Setting("instructor_pwhash").value_or("");
  EXPECT_EQ(hash.rfind("$argon2id$", 0), 0u) << "only the hash is stored";
}

}  // namespace
}  // namespace sulcus
