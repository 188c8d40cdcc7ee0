// The results database: attempts round-trip, schema versions, CSV export, and a
// writer killed with SIGKILL in the middle of its attempts loses nothing that
// was committed and leaves a sound database (a real child process).
#include "core/lesson/results.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/lesson/attempt.h"
#include "core/lesson/instructor.h"
#include "tests/common/output.h"
#include "tests/core/lesson/sample_result.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;
using test::Sample;

fs::path Fresh(const std::string& name) {
  return test::FreshOutputPath("results", name) / "results.db";
}

int Count(const fs::path& db, const std::string& sql) {
  sqlite3* h = nullptr;
  sqlite3_open(db.c_str(), &h);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(h, sql.c_str(), -1, &s, nullptr);
  const int n = sqlite3_step(s) == SQLITE_ROW ? sqlite3_column_int(s, 0) : -1;
  sqlite3_finalize(s);
  sqlite3_close(h);
  return n;
}

TEST(Results, IncompleteAttemptsKeepHowTheyEnded) {
  const fs::path file = Fresh("incomplete");
  ResultsDb db(file);
  LessonResult done = Sample("ada", 90);
  done.complete = true;
  LessonResult cut = Sample("ada", 40);
  cut.complete = false;
  cut.ended = "the window was closed before the last step";
  db.Store(done, "2026-12-01T10:00:00Z", "/a.rec", "/a.yaml", "/a");
  db.Store(cut, "2026-12-01T11:00:00Z", "/b.rec", "/b.yaml", "/b");
  const auto rows = db.Attempts("ada");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_TRUE(rows[0].complete);
  EXPECT_EQ(rows[0].ended, "");
  EXPECT_FALSE(rows[1].complete);
  EXPECT_EQ(rows[1].ended, cut.ended);
  std::ostringstream csv;
  ExportAttemptsCsv(rows, csv);
  EXPECT_NE(csv.str().find(",0,the window was closed before the last step,"),
            std::string::npos)
      << csv.str();
}

// A CSV cell a spreadsheet would run as a formula is led by an apostrophe.
TEST(Results, TheCsvExportNeutralisesFormulas) {
  const fs::path file = Fresh("formula");
  ResultsDb db(file);
  db.Store(Sample("=HYPERLINK(\"http://x\",\"a\")", 50), "2026-12-01T10:00:00Z", "/a.rec",
           "/a.yaml", "/a");
  db.Store(Sample("+1", 60), "2026-12-01T11:00:00Z", "/b.rec", "/b.yaml", "/b");
  db.Store(Sample("@SUM", 70), "2026-12-01T12:00:00Z", "/c.rec", "/c.yaml", "/c");
  std::ostringstream csv;
  ExportAttemptsCsv(db.Attempts("", ""), csv);
  const std::string text = csv.str();
  EXPECT_NE(text.find(",\"'=HYPERLINK(\"\"http://x\"\",\"\"a\"\")\","), std::string::npos)
      << text;
  EXPECT_NE(text.find(",'+1,"), std::string::npos) << text;
  EXPECT_NE(text.find(",'@SUM,"), std::string::npos) << text;
  EXPECT_EQ(text.find(",=HYPERLINK"), std::string::npos);
}

TEST(Results, VersionOneDatabaseIsMigratedKeepingItsAttempts) {
  const fs::path file = Fresh("migrate1");
  {
    ResultsDb db(file);
    db.Store(Sample("ada", 88), "2026-12-01T10:00:00Z", "/a.rec", "/a.yaml", "/a");
  }
  {  // Make it what a version-1 Sulcus wrote: no complete/ended columns, no
     // UUIDs, no shared settings, no device.
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &h), SQLITE_OK);
    char* err = nullptr;
    ASSERT_EQ(
        sqlite3_exec(h,
                     "DROP TABLE sign_in_failures; DROP TABLE sign_ins; DROP TABLE "
                     "student_keys; ALTER TABLE attempts DROP COLUMN signed_in; ALTER "
                     "TABLE students DROP COLUMN name_key; ALTER TABLE students DROP "
                     "COLUMN on_roster; "
                     "DROP VIEW public_settings; ALTER TABLE attempts DROP COLUMN "
                     "row_hash; ALTER TABLE attempts DROP COLUMN prev_hash; ALTER "
                     "TABLE attempts DROP COLUMN "
                     "device; ALTER TABLE attempts DROP COLUMN complete; ALTER TABLE "
                     "attempts DROP COLUMN ended; DROP INDEX attempts_by_uuid; "
                     "ALTER TABLE attempts DROP COLUMN uuid; DROP TABLE settings; "
                     "PRAGMA user_version=1",
                     nullptr, nullptr, &err),
        SQLITE_OK)
        << (err ? err : "");
    sqlite3_close(h);
  }
  EXPECT_EQ(Count(file, "PRAGMA user_version"), 1);
  ResultsDb db(file);
  EXPECT_EQ(db.schema_version(), kResultsSchemaVersion);
  EXPECT_TRUE(db.SetSettingOnce("k", "v")) << "the settings table was made";
  const auto rows = db.Attempts("ada");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0].total, 88);
  EXPECT_TRUE(rows[0].complete);  // what version 1 kept was complete
  EXPECT_EQ(rows[0].uuid, "") << "attempts from before UUIDs have none";
  EXPECT_EQ(rows[0].device, "") << "nor a device";
}

// No change unseen: every attempt's hash is chained to the one before; a row
// changed afterwards, or removed, is named by the check (and the rows after a
// removed one), while the untouched chain holds.
TEST(Results, TheHashChainNamesARowChangedOrRemoved) {
  const fs::path file = Fresh("chain");
  ResultsDb db(file);
  for (int k = 0; k < 4; ++k)
    db.Store(Sample("ada", 60 + k), "2026-12-01T10:00:0" + std::to_string(k) + "Z",
             "/a.rec", "/a.yaml", "/a",
             "00000000-0000-4000-8000-00000000000" + std::to_string(k));
  ChainCheck c = CheckChain(db.Chain());
  EXPECT_EQ(c.rows, 4);
  EXPECT_EQ(c.chained, 4);
  EXPECT_TRUE(c.breaks.empty());
  EXPECT_EQ(c.last_hash.size(), 64u);
  const std::string end = c.last_hash;
  {
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &h), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(h, "UPDATE attempts SET total = 98.5 WHERE id = 2", nullptr,
                           nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(h);
  }
  c = CheckChain(db.Chain());
  ASSERT_EQ(c.breaks.size(), 1u);
  EXPECT_EQ(c.breaks[0].id, 2) << "the changed row, named";
  EXPECT_EQ(c.last_hash, end);
  {
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &h), SQLITE_OK);
    ASSERT_EQ(
        sqlite3_exec(h,
                     "UPDATE attempts SET total = 61 WHERE id = 2; DELETE FROM "
                     "attempt_lines WHERE attempt_id = 3; DELETE FROM attempt_scores "
                     "WHERE attempt_id = 3; DELETE FROM attempt_sites WHERE "
                     "attempt_id = 3; DELETE FROM attempts WHERE id = 3",
                     nullptr, nullptr, nullptr),
        SQLITE_OK);
    sqlite3_close(h);
  }
  c = CheckChain(db.Chain());
  ASSERT_EQ(c.breaks.size(), 1u);
  EXPECT_EQ(c.breaks[0].id, 4) << "the row after the one removed";
}

TEST(Results, AttemptsRoundTripAndExport) {
  const fs::path file = Fresh("roundtrip");
  {
    ResultsDb db(file);
    EXPECT_EQ(db.schema_version(), kResultsSchemaVersion);
    EXPECT_EQ(
        db.Store(Sample("ada", 91.5), "2026-12-01T10:00:00Z", "/a.rec", "/a.yaml", "/a"),
        1);
    EXPECT_EQ(
        db.Store(Sample("ada", 95.0), "2026-12-02T10:00:00Z", "/b.rec", "/b.yaml", "/b"),
        2);
    EXPECT_EQ(db.Store(Sample("grace", 70.25), "2026-12-02T11:00:00Z", "/c.rec",
                       "/c.yaml", "/c"),
              3);
  }
  ResultsDb db(file);  // reopened: nothing to migrate
  EXPECT_EQ(db.Students(), (std::vector<std::string>{"ada", "grace"}));
  const auto ada = db.Attempts("ada");
  ASSERT_EQ(ada.size(), 2u);
  EXPECT_DOUBLE_EQ(ada[1].total, 95.0);
  EXPECT_EQ(ada[1].recording, "/b.rec");
  EXPECT_EQ(db.Attempts("", "/lessons/periodontal_probing.yaml").size(), 3u);
  const auto one = db.Attempt(3);
  ASSERT_TRUE(one);
  EXPECT_EQ(one->student, "grace");
  EXPECT_FALSE(db.Attempt(99));
  const auto sites = db.Sites("grace");
  ASSERT_EQ(sites.size(), 24u);
  EXPECT_EQ(Count(file, "SELECT COUNT(*) FROM attempt_lines"), 360);
  std::ostringstream csv;
  ExportAttemptsCsv(db.Attempts(), csv);
  const std::string text = csv.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4)
      << "a header and three attempts";
  EXPECT_NE(csv.str().find("3,grace,Periodontal probing,"), std::string::npos)
      << csv.str();
  std::ostringstream scsv;
  ExportSitesCsv(sites, scsv);
  EXPECT_NE(scsv.str().find(",46,DB,3,3.1,5,2,"), std::string::npos)
      << "signed error per site";
  EXPECT_EQ(db.IntegrityCheck(), "ok");
}

TEST(Results, DeletingAStudentTakesTheirAttemptsWithThem) {
  const fs::path file = Fresh("delete");
  ResultsDb db(file);
  db.Store(Sample("ada", 90), "2026-12-01T10:00:00Z", "", "", "");
  db.Store(Sample("ada", 91), "2026-12-01T11:00:00Z", "", "", "");
  db.Store(Sample("grace", 80), "2026-12-01T12:00:00Z", "", "", "");
  EXPECT_EQ(db.DeleteStudent("ada"), 2);
  EXPECT_EQ(db.Students(), (std::vector<std::string>{"grace"}));
  EXPECT_EQ(Count(file, "SELECT COUNT(*) FROM attempt_sites"), 24)
      << "the sites went with their attempts";
  EXPECT_EQ(Count(file, "SELECT COUNT(*) FROM attempt_lines"), 120);
  EXPECT_EQ(db.DeleteStudent("nobody"), 0);
}

TEST(Instructor, ThePassphraseIsKeptOnlyAsAHash) {
  const fs::path file = Fresh("lock").parent_path() / "instructor.pwhash";
  InstructorLock lock(file);
  EXPECT_FALSE(lock.is_set());
  EXPECT_FALSE(lock.Check("anything at all"));
  EXPECT_THROW(lock.Set("short"), std::runtime_error);
  lock.Set("correct horse battery");
  EXPECT_TRUE(lock.is_set());
  EXPECT_TRUE(lock.Check("correct horse battery"));
  EXPECT_FALSE(lock.Check("correct horse batterY"));
  EXPECT_FALSE(lock.Check(""));
  EXPECT_THROW(lock.Set("another passphrase"), std::runtime_error) << "set once";
  std::ifstream in(file);
  const std::string stored((std::istreambuf_iterator<char>(in)),
                           std::istreambuf_iterator<char>());
  EXPECT_EQ(stored.find("horse"), std::string::npos);
  EXPECT_EQ(stored.rfind("$argon2id$", 0), 0u) << stored;
  EXPECT_TRUE(InstructorLock(file).Check("correct horse battery"))
      << "another process reads the same hash";
}

TEST(Results, ANewerSchemaIsRefusedAndLeftAlone) {
  const fs::path file = Fresh("newer");
  { ResultsDb db(file); }
  {
    sqlite3* h = nullptr;
    sqlite3_open(file.c_str(), &h);
    sqlite3_exec(h, "PRAGMA user_version=99", nullptr, nullptr, nullptr);
    sqlite3_close(h);
  }
  try {
    ResultsDb db(file);
    FAIL();
  } catch (const ResultsError& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 99"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(Count(file, "PRAGMA user_version"), 99);
  const fs::path junk = Fresh("junk");
  std::ofstream(junk) << "this is not a database, it is a text file that someone renamed";
  try {
    ResultsDb db(junk);
    FAIL() << "opened a text file as a database";
  } catch (const ResultsError& e) {
    EXPECT_NE(
        std::string(e.what()).find("not a Sulcus results database, or a damaged one; "
                                   "it is left untouched"),
        std::string::npos)
        << e.what();
  }
}

TEST(Results, ErrorsSayWhatIsWrongWithoutSqliteOrSql) {
  // A database whose tables are not Sulcus's (user_version says 2): neither
  // "no such table" nor the statement is shown.
  const fs::path file = Fresh("foreign");
  {
    sqlite3* h = nullptr;
    sqlite3_open(file.c_str(), &h);
    sqlite3_exec(h, "CREATE TABLE other(x); PRAGMA user_version=2", nullptr, nullptr,
                 nullptr);
    sqlite3_close(h);
  }
  try {
    ResultsDb db(file);
    db.Attempts();
    FAIL() << "read attempts from a foreign database";
  } catch (const ResultsError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("not a results database of a form this Sulcus knows"),
              std::string::npos)
        << what;
    EXPECT_EQ(what.find("SELECT"), std::string::npos) << what;
    EXPECT_EQ(what.find("no such table"), std::string::npos) << what;
  }
}

TEST(Results, AVeryLongStudentNameStillMakesAnAttemptFolder) {
  const fs::path results = Fresh("long-name").parent_path();
  const std::string name(300, 'n');
  const AttemptFolder f = NewAttemptFolder(results, name);
  EXPECT_TRUE(fs::is_directory(f.dir));
  EXPECT_LE(f.dir.filename().string().size(), 100u) << f.dir;
  // A file where the attempts' folder should be: said in words.
  const fs::path blocked = Fresh("blocked").parent_path();
  std::ofstream(blocked / "attempts") << "x";
  try {
    NewAttemptFolder(blocked, "someone");
    FAIL() << "made a folder inside a file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("a file stands where a folder is needed"),
              std::string::npos)
        << e.what();
  }
}

TEST(Results, AWriterKilledMidAttemptLosesNothingCommitted) {
  const fs::path file = Fresh("killed");
  { ResultsDb db(file); }  // created before the child, so the child only writes
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(fds[0]);
    ResultsDb db(file);
    for (int i = 0;; ++i) {
      const std::int64_t id =
          db.Store(Sample("writer", i), "2026-12-01T00:00:00Z", "r", "a", "d");
      if (write(fds[1], &id, sizeof id) != sizeof id)
        _exit(2);  // committed: tell the parent
    }
  }
  close(fds[1]);
  std::vector<std::int64_t> committed;
  std::int64_t id = 0;
  while (committed.size() < 25 && read(fds[0], &id, sizeof id) == sizeof id)
    committed.push_back(id);
  usleep(1500);  // into the middle of the next attempt
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  ASSERT_EQ(committed.size(), 25u);
  // What the child said it committed after those 25, before it was killed.
  while (read(fds[0], &id, sizeof id) == sizeof id) committed.push_back(id);
  close(fds[0]);

  ResultsDb db(file);
  EXPECT_EQ(db.IntegrityCheck(), "ok");
  const auto rows = db.Attempts("writer");
  ASSERT_GE(rows.size(), committed.size()) << "every committed attempt is there";
  EXPECT_LE(rows.size(), committed.size() + 1)
      << "at most the one being committed when killed";
  for (std::int64_t c : committed) EXPECT_TRUE(db.Attempt(c)) << "attempt " << c;
  // Whole or absent: no attempt without all its sites and lines.
  EXPECT_EQ(Count(file,
                  "SELECT COUNT(*) FROM attempts a WHERE (SELECT COUNT(*) FROM "
                  "attempt_sites s WHERE "
                  "s.attempt_id = a.id) != 24 OR (SELECT COUNT(*) FROM attempt_lines l "
                  "WHERE l.attempt_id = a.id) "
                  "!= 120"),
            0);
  EXPECT_GT(db.Store(Sample("after", 1), "2026-12-01T00:00:01Z", "r", "a", "d"), 0)
      << "and it takes new attempts";
}

}  // namespace
}  // namespace sulcus
