#pragma once
// The results store: students, lessons, attempts, their per-site rows, category
// scores and rubric lines, the recording's path and the case seed. One interface
// (ResultsStore) with two backends and the same tables and migrations on both:
// the embedded SQLite file of a station (ResultsDb: WAL journal, the schema
// version in PRAGMA user_version) and a lab's shared PostgreSQL server
// (results_pg.cpp, through libpq), used when a libpq URL is given
// (SULCUS_RESULTS_URL or --results URL). Every attempt is written in one
// transaction and carries a UUID, so storing it again (a retry, a sync after the
// server came back) never makes a second row: a writer killed mid-attempt loses
// nothing that was committed.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/lesson/lesson.h"

struct sqlite3;

namespace sulcus {

// 1: the tables; 2: complete and ended; 3: an attempt's UUID; 4: settings shared
// by every station (the instructor's passphrase hash); 5: the attempt's device;
// 6: the settings a station may read (public_settings); 7: the attempts' hash chain;
// 8: the roster and its students' sign-in.
inline constexpr int kResultsSchemaVersion = 8;

/// The shared setting by which a store asks every student's attempt to come
/// from that student, signed in ("required"); otherwise (unset, "off") a
/// station may store attempts of students who did not sign in, marked so.
inline constexpr const char* kSignInSetting = "sign_in";

/// The shared settings every station may read; the rest (the instructor's
/// passphrase hash) only the instructor's role of a lab's store.
inline bool PublicSetting(const std::string& key) {
  return key == "demonstrations" || key == kSignInSetting;
}

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
  std::string ended;       // how an incomplete attempt ended
  std::string uuid;        // empty for attempts stored before UUIDs
  std::string device;      // haptic, keys, scripted or replay ('' before they were kept)
  bool signed_in = false;  // stored by its student, signed in (the store decided)
};

/// What an attempt's hash covers, and its hash (ChainText).
struct ChainRow {
  std::int64_t id = 0;
  std::optional<std::string> row_hash;  // none for attempts stored before the chain
  std::string prev_hash;                // the hash it follows ("": the first)
  std::string uuid, student, lesson_file, started, mode, declared_dx, device;
  double total = 0;
  bool complete = true;
  bool signed_in = false;
};
/// The text an attempt's hash is the SHA-256 of: the hash before it (or "") and
/// the row's UUID, student, lesson file, start, mode, score (in thousandths,
/// rounded half to even), whether complete, the declared diagnosis and device,
/// one a line, and "signed in" when its student signed in. The shared store's
/// trigger makes the same text.
std::string ChainText(const std::string& previous, const ChainRow& r);
/// SHA-256, as lower-case hex.
std::string Sha256Hex(const std::string& text);
/// Where the chain does not hold: the row, and why.
struct ChainBreak {
  std::int64_t id = 0;
  std::string why;
};
struct ChainCheck {
  std::vector<ChainBreak> breaks;
  int rows = 0, chained = 0;
  std::string
      last_hash;  // keep it elsewhere: a later check shows the chain still ends there
};
/// Recomputes each row's hash from the hash it follows and names every row
/// whose hash does not hold (changed), and every row whose predecessor is not
/// there (removed) or shared with another (a row put in); the chain is followed
/// from its start to its last hash.
ChainCheck CheckChain(const std::vector<ChainRow>& rows);

struct SiteRow {
  std::int64_t attempt = 0;
  std::string student, started;
  int fdi = 0, site = 0, truth_mm = 0;
  std::optional<double> reached_mm;
  std::optional<int> entered_mm;
  double peak_force_n = 0;
};

/// Where results go: the attempts' folders (recordings, reports) always live in
/// `dir`; the rows go to the PostgreSQL server `url` names, or, when it is empty,
/// to the SQLite file dir/results.db.
struct ResultsPlace {
  explicit ResultsPlace(std::filesystem::path d = {}, std::string u = {})
      : dir(std::move(d)), url(std::move(u)) {}
  std::filesystem::path dir;
  std::string url;
  /// The sign-in of the student a station shows (SignIn's token): a lab's
  /// store that asks for sign-in shows a station only that student's attempts.
  std::string sign_in;
  std::filesystem::path sqlite_file() const { return dir / "results.db"; }
  /// For messages and the window's footer: the file, or the URL without its password.
  std::string Describe() const;
};
/// `dir` with the URL of $SULCUS_RESULTS_URL (empty when unset).
ResultsPlace ResultsPlaceFor(const std::filesystem::path& dir);
/// A libpq URL with its password (user:password@, password=...) replaced by ***.
std::string RedactUrl(const std::string& url);
/// The password a results URL holds (user information or ?password=),
/// percent-decoded; "" when it holds none.
std::string UrlPassword(const std::string& url);
/// `message` with the URL's password, as written and decoded, replaced by ***
/// wherever it appears (a server's or a library's message can repeat it).
std::string RedactPassword(std::string message, const std::string& url);
/// True for a libpq URL (postgresql://, postgres://).
bool IsResultsUrl(const std::string& text);

class ResultsStore {
 public:
  virtual ~ResultsStore() = default;
  /// Stores one attempt in one transaction; returns its id. An attempt whose
  /// `uuid` is already stored is not stored again: its id is returned.
  /// `sign_in`: the token of the student's sign-in (SignIn), "" for none: the
  /// store marks the attempt as its student's only when the token is theirs,
  /// and refuses one without when it asks for sign-in (kSignInSetting).
  virtual std::int64_t Store(const LessonResult& r, const std::string& started,
                             const std::string& recording, const std::string& answers,
                             const std::string& report_dir, const std::string& uuid = "",
                             const std::string& sign_in = "") = 0;
  /// Sets where an attempt's report lives (after it was written with the id in it).
  virtual void SetReportDir(std::int64_t id, const std::string& dir) = 0;
  virtual std::vector<AttemptRow> Attempts(const std::string& student = "",
                                           const std::string& lesson_file = "") const = 0;
  virtual std::optional<AttemptRow> Attempt(std::int64_t id) const = 0;
  virtual std::vector<SiteRow> Sites(const std::string& student = "",
                                     const std::string& lesson_file = "") const = 0;
  virtual std::vector<std::string> Students() const = 0;
  /// Deletes every attempt of a student and the student (one transaction);
  /// returns how many attempts went. Their recordings and reports stay on disk.
  virtual int DeleteStudent(const std::string& student) = 0;
  virtual int schema_version() const = 0;
  /// The store in words (its file, or its URL without the password).
  virtual std::string where() const = 0;
  /// A setting every station shares (`settings` table), if set.
  virtual std::optional<std::string> Setting(const std::string& key) const = 0;
  /// Sets a setting that is not set yet; false (and nothing written) when it is.
  virtual bool SetSettingOnce(const std::string& key, const std::string& value) = 0;
  /// Every attempt's chained hash and what it covers, in order.
  virtual std::vector<ChainRow> Chain() const = 0;
  /// Sets (or replaces) a shared setting: what the instructor decides.
  virtual void SetSetting(const std::string& key, const std::string& value) = 0;

  // The class's roster and its students' sign-in (sign_in.h does the
  // passphrase's side).
  /// The names on the roster, sorted.
  virtual std::vector<std::string> Roster() const = 0;
  /// Puts a name on the roster (the instructor's): false when it was there.
  /// The name must be normal (NormalName) and no look-alike of another
  /// student's (`look_alike_key`, NameLookAlikeKey): ResultsError otherwise.
  virtual bool AddToRoster(const std::string& name,
                           const std::string& look_alike_key) = 0;
  /// Forgets a student's passphrase (the instructor's): set again at the next
  /// sign-in. False for a name not on the roster.
  virtual bool ResetPassphrase(const std::string& name) = 0;
  /// The salt of a student's passphrase, "" when it is not set yet (or the
  /// name is not on the roster).
  virtual std::string PassphraseSalt(const std::string& name) const = 0;
  /// Sets a student's passphrase at first use (the key SignIn derives): false
  /// when it is set already or the name is not on the roster.
  virtual bool SetPassphraseKey(const std::string& name, const std::string& salt,
                                const std::string& key) = 0;
  /// A sign-in's token for the right key, "" for a wrong one. Throws
  /// ResultsError after too many wrong ones within a quarter of an hour.
  virtual std::string SignInWithKey(const std::string& name, const std::string& key) = 0;
  /// Reads as the student of this sign-in: a station's role of a lab's store
  /// reads attempts only through the store's functions, which show a student's
  /// own attempts (all of a name's when the store does not ask for sign-in).
  /// A station's own file and the instructor's role read everything.
  virtual void ReadAs(const std::string& sign_in) { (void)sign_in; }
};

/// The roles `results setup` makes in a lab's PostgreSQL store: stations store
/// and read attempts (INSERT and SELECT, nothing else), the instructor reads
/// everything and writes what the instructor's view writes.
inline constexpr const char* kStationRole = "sulcus_station";
inline constexpr const char* kInstructorRole = "sulcus_instructor";
struct StoreSetup {
  std::string station_password, instructor_password;  // made when not given
  std::vector<std::string> done;                      // what was done, in words
};
/// Run once by the school's database administrator with the URL of the role that
/// owns the database (and may create roles): migrates the schema and makes (or,
/// given passwords, resets) the station and instructor roles and their rights.
/// An empty password is made (24 random characters) and returned.
StoreSetup SetUpPostgresStore(const std::string& owner_url,
                              const std::string& station_password,
                              const std::string& instructor_password);

/// Opens the store of a place (PostgreSQL when it has a URL, else SQLite).
/// Throws ResultsError naming the file or the URL (never its password).
std::unique_ptr<ResultsStore> OpenResults(const ResultsPlace& place);
/// The PostgreSQL backend, migrated up to `version` (tests stop at older ones).
std::unique_ptr<ResultsStore> OpenPostgresResults(const std::string& url,
                                                  int version = kResultsSchemaVersion);

class ResultsDb final : public ResultsStore {
 public:
  /// Opens (creating) the database and migrates it to the current schema.
  /// Throws ResultsError naming the file and what went wrong; a database of a
  /// newer schema than this build knows is refused, never rewritten.
  explicit ResultsDb(const std::filesystem::path& file);
  ~ResultsDb() override;
  ResultsDb(const ResultsDb&) = delete;
  ResultsDb& operator=(const ResultsDb&) = delete;

  std::int64_t Store(const LessonResult& r, const std::string& started,
                     const std::string& recording, const std::string& answers,
                     const std::string& report_dir, const std::string& uuid = "",
                     const std::string& sign_in = "") override;
  void SetReportDir(std::int64_t id, const std::string& dir) override;
  std::vector<AttemptRow> Attempts(const std::string& student = "",
                                   const std::string& lesson_file = "") const override;
  std::optional<AttemptRow> Attempt(std::int64_t id) const override;
  std::vector<SiteRow> Sites(const std::string& student = "",
                             const std::string& lesson_file = "") const override;
  std::vector<std::string> Students() const override;
  int DeleteStudent(const std::string& student) override;
  int schema_version() const override;
  std::string where() const override { return file_.string(); }
  std::optional<std::string> Setting(const std::string& key) const override;
  bool SetSettingOnce(const std::string& key, const std::string& value) override;
  void SetSetting(const std::string& key, const std::string& value) override;
  std::vector<ChainRow> Chain() const override;
  std::vector<std::string> Roster() const override;
  bool AddToRoster(const std::string& name, const std::string& look_alike_key) override;
  bool ResetPassphrase(const std::string& name) override;
  std::string PassphraseSalt(const std::string& name) const override;
  bool SetPassphraseKey(const std::string& name, const std::string& salt,
                        const std::string& key) override;
  std::string SignInWithKey(const std::string& name, const std::string& key) override;
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
