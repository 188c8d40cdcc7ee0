#pragma once
// Records for a school's learning management system: each kept attempt as xAPI
// (Experience API 1.0.3) statements, sent to the Learning Record Store the
// settings name, with HTTP basic authentication. The profile (verbs, activity
// ids, extensions) is in docs/xapi.md. An attempt's statements are written into
// its folder (xapi.json) when it is kept and sent from there: an LRS that cannot
// be reached leaves them waiting (xapi-waiting.txt), and `sulcus-cli results
// sync` sends them later. Each statement's id is derived from the attempt's UUID
// and a random key kept in its folder (xapi-key), so a statement sent twice is
// refused by the LRS as a duplicate, never stored twice, and no one who knows
// the UUID can post under one of its ids first; a 409 is checked against what
// the LRS holds.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/lesson/lesson.h"

namespace sulcus {

class XapiError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct XapiSettings {
  /// The LRS's xAPI endpoint (statements are at <url>/statements); empty: no LRS.
  std::string url;
  std::string user, password;
  /// The home page of the students' accounts (the actor's account.homePage) and
  /// the base of Sulcus's activity and verb ids.
  std::string homepage = "https://sulcus.invalid";
  /// Plain http (no TLS) is refused unless the station allows it
  /// (SULCUS_LRS_ALLOW_HTTP=1: an LRS on the station itself or a closed network).
  bool allow_http = false;
  bool enabled() const { return !url.empty(); }
};

/// From the environment: SULCUS_LRS_URL, SULCUS_LRS_USER, SULCUS_LRS_PASSWORD,
/// SULCUS_XAPI_HOMEPAGE, SULCUS_LRS_ALLOW_HTTP.
XapiSettings XapiSettingsFromEnv();

/// The attempt's statements as a JSON array: the attempt completed (its score,
/// passed or failed, complete or not, its duration), one per site probed (the
/// depth reached and charted, the force and the angle as result extensions), and
/// the diagnosis declared. `registration` is the attempt's UUID; `id_key` the
/// attempt's StatementKey (empty only for a preview: ids anyone can derive).
std::string XapiStatements(const LessonResult& r, const std::string& registration,
                           const std::string& started, const std::string& homepage,
                           const std::string& id_key = "");

/// The attempt's random key for its statements' ids (64 hex digits), made once
/// and kept in its folder (xapi-key).
std::string StatementKey(const std::filesystem::path& attempt_dir);

/// Throws XapiError unless the LRS's URL is https (or http where allowed, said
/// once as a warning on standard error).
void CheckLrsScheme(const XapiSettings& lrs);

/// POSTs a JSON array of statements. A 409 (the LRS holds some of these ids) is
/// success only when the LRS holds each of them for the same attempt, student,
/// verb and object (they were sent before); else a conflict. Throws XapiError
/// naming the LRS (never the password) and what it answered.
void SendStatements(const XapiSettings& lrs, const std::string& statements);

/// GETs the statements of a registration (the LRS's JSON, `more` pages included).
std::string FetchStatements(const XapiSettings& lrs, const std::string& registration);

/// Writes the attempt's statements into its folder and, when an LRS is set,
/// sends them; what could not be sent waits (xapi-waiting.txt says why).
/// Returns "" when sent or no LRS is set, else why they wait. Throws only when
/// they are neither sent nor kept whole and waiting (a full disk): the attempt
/// then stays waiting for the store too, so that a sync makes and sends them.
std::string QueueStatements(const std::filesystem::path& attempt_dir,
                            const LessonResult& r, const std::string& registration,
                            const std::string& started, const XapiSettings& lrs);

/// The attempt folders under `results`/attempts whose statements wait.
std::vector<std::filesystem::path> WaitingStatements(
    const std::filesystem::path& results);

/// Sends one folder's waiting statements; true when sent (the marker removed).
bool SendWaitingStatements(const std::filesystem::path& attempt_dir,
                           const XapiSettings& lrs, std::string* why);

}  // namespace sulcus
