#include "core/lesson/xapi.h"

#include <curl/curl.h>
#include <sodium.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "core/base/files.h"
#include "core/base/text.h"
#include "core/lesson/chart.h"
#include "core/lesson/results.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStatementsFile = "xapi.json";
constexpr const char* kWaitingFile = "xapi-waiting.txt";

std::string Num(double v) {
  if (!std::isfinite(v)) return "null";
  char b[40];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

constexpr const char* kKeyFile = "xapi-key";

// A statement's id: the attempt's UUID and the statement's place, hashed with
// the attempt's own random key (kept in its folder), in UUID form: the same
// attempt always sends the same ids, and no one who only knows the UUID (the
// store shows it) can post a statement under one of them first.
std::string StatementId(const std::string& registration, int index,
                        const std::string& id_key) {
  if (sodium_init() < 0) throw XapiError("libsodium could not be initialised");
  const std::string text = registration + "/" + std::to_string(index);
  unsigned char h[16];
  crypto_generichash(
      h, sizeof h, reinterpret_cast<const unsigned char*>(text.data()), text.size(),
      id_key.empty() ? nullptr : reinterpret_cast<const unsigned char*>(id_key.data()),
      std::min<std::size_t>(id_key.size(), crypto_generichash_KEYBYTES_MAX));
  h[6] = static_cast<unsigned char>((h[6] & 0x0f) | 0x80);  // version 8: custom
  h[8] = static_cast<unsigned char>((h[8] & 0x3f) | 0x80);
  char t[37];
  std::snprintf(t, sizeof t,
                "%02x%02x%02x%02x-%02x%02x-%02x%02x-%02x%02x-%02x%02x%02x%02x%02x%02x",
                h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7], h[8], h[9], h[10], h[11],
                h[12], h[13], h[14], h[15]);
  return t;
}

std::string LessonActivityId(const LessonResult& r, const std::string& base) {
  std::string stem = fs::path(r.lesson_file).stem().string();
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return base + "/xapi/lessons/" + stem;
}

class Statements {
 public:
  Statements(const LessonResult& r, std::string registration, std::string started,
             const std::string& homepage, std::string id_key)
      : r_(r),
        id_key_(std::move(id_key)),
        registration_(std::move(registration)),
        started_(std::move(started)),
        base_(homepage),
        lesson_id_(LessonActivityId(r, homepage)) {}

  std::string Build() {
    Completed();
    for (const SiteResult& s : r_.sites)
      if (s.reached_mm || s.entry) Site(s);
    if (r_.declared) Declared();
    return "[" + out_ + "\n]\n";
  }

 private:
  void Begin(const std::string& verb, const std::string& display) {
    out_ += out_.empty() ? "\n" : ",\n";
    out_ += "{\"id\": " + JsonQuote(StatementId(registration_, n_++, id_key_)) +
            ", \"actor\": {\"objectType\": \"Agent\", \"account\": {\"homePage\": " +
            JsonQuote(base_) + ", \"name\": " + JsonQuote(r_.student) +
            "}}, \"verb\": {\"id\": " + JsonQuote(verb) +
            ", \"display\": {\"en-US\": " + JsonQuote(display) + "}}";
  }
  void Object(const std::string& id, const std::string& name, const std::string& type) {
    out_ += ", \"object\": {\"objectType\": \"Activity\", \"id\": " + JsonQuote(id) +
            ", \"definition\": {\"name\": {\"en-US\": " + JsonQuote(name) +
            "}, \"type\": " + JsonQuote(type) + "}}";
  }
  void End(bool with_parent) {
    out_ += ", \"context\": {\"registration\": " + JsonQuote(registration_) +
            ", \"platform\": \"Sulcus\"";
    if (with_parent)
      out_ +=
          ", \"contextActivities\": {\"parent\": [{\"objectType\": \"Activity\", "
          "\"id\": " +
          JsonQuote(lesson_id_) + "}]}";
    out_ += ", \"extensions\": {" + JsonQuote(base_ + "/xapi/extensions/mode") + ": " +
            JsonQuote(r_.mode);
    if (r_.generated_case)
      out_ += ", " + JsonQuote(base_ + "/xapi/extensions/case-seed") + ": " +
              std::to_string(r_.case_seed);
    out_ += "}}";
    if (!started_.empty()) out_ += ", \"timestamp\": " + JsonQuote(started_);
    out_ += "}";
  }
  std::string Ext(const std::string& name) const {
    return JsonQuote(base_ + "/xapi/extensions/" + name);
  }

  void Completed() {
    Begin("http://adlnet.gov/expapi/verbs/completed", "completed");
    Object(lesson_id_, r_.lesson_name, "http://adlnet.gov/expapi/activities/assessment");
    char duration[48];
    std::snprintf(duration, sizeof duration, "PT%.2fS", std::max(0.0, r_.duration_s));
    out_ += ", \"result\": {\"score\": {\"scaled\": " + Num(r_.total / 100) +
            ", \"raw\": " + Num(r_.total) + ", \"min\": 0, \"max\": 100}, \"success\": " +
            (r_.total >= r_.pass_mark ? "true" : "false") +
            ", \"completion\": " + (r_.complete ? "true" : "false") +
            ", \"duration\": " + JsonQuote(duration) + ", \"extensions\": {" +
            Ext("pass-mark") + ": " + Num(r_.pass_mark) + ", " + Ext("sites-probed") +
            ": " + std::to_string(r_.sites_read) + ", " + Ext("sites-charted") + ": " +
            std::to_string(r_.sites_charted) + ", " + Ext("sites-total") + ": " +
            std::to_string(r_.sites_total) + ", " + Ext("within-1mm-pct") + ": " +
            Num(r_.within_1mm_pct) + ", " + Ext("force-in-band-pct") + ": " +
            Num(r_.force_in_band_pct) + "}}";
    End(false);
  }

  void Site(const SiteResult& s) {
    Begin(base_ + "/xapi/verbs/probed", "probed");
    const std::string code = SiteCode(s.site.site);
    Object(lesson_id_ + "/sites/" + std::to_string(s.site.fdi) + "-" + code,
           "tooth " + std::to_string(s.site.fdi) + ", site " + code,
           base_ + "/xapi/activities/probing-site");
    out_ += ", \"result\": {\"extensions\": {" + Ext("true-depth-mm") + ": " +
            std::to_string(s.truth_mm);
    if (s.reached_mm) out_ += ", " + Ext("depth-reached-mm") + ": " + Num(*s.reached_mm);
    if (s.entry && s.entry->pd_mm)
      out_ += ", " + Ext("depth-charted-mm") + ": " + std::to_string(*s.entry->pd_mm);
    out_ += ", " + Ext("force-n") + ": " + Num(s.peak_force_n) + ", " + Ext("angle-deg") +
            ": " + Num(s.angle_deg) + ", " + Ext("bleeding") + ": " +
            (s.bled ? "true" : "false") + "}}";
    End(true);
  }

  void Declared() {
    Begin("http://adlnet.gov/expapi/verbs/answered", "answered");
    Object(lesson_id_ + "/diagnosis", "the diagnosis (2017 classification)",
           "http://adlnet.gov/expapi/activities/cmi.interaction");
    out_ += ", \"result\": {\"response\": " + JsonQuote(r_.declared->Summary()) +
            ", \"extensions\": {" + Ext("true-diagnosis") + ": " +
            JsonQuote(r_.true_dx.Summary()) + "}}";
    End(true);
  }

  const LessonResult& r_;
  std::string id_key_;
  std::string registration_, started_, base_, lesson_id_;
  std::string out_;
  int n_ = 0;
};

std::size_t Collect(char* data, std::size_t size, std::size_t n, void* to) {
  static_cast<std::string*>(to)->append(data, size * n);
  return size * n;
}

struct Reply {
  long status = 0;
  std::string body;
};

Reply Http(const XapiSettings& lrs, const std::string& url, const std::string* post) {
  static std::once_flag once;
  std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
  CURL* c = curl_easy_init();
  if (!c) throw XapiError("LRS " + RedactUrl(lrs.url) + ": cannot start an HTTP client");
  Reply reply;
  curl_slist* headers = nullptr;
  headers = curl_slist_append(headers, "X-Experience-API-Version: 1.0.3");
  headers = curl_slist_append(headers, "Content-Type: application/json");
  curl_easy_setopt(c, CURLOPT_URL, url.c_str());
  curl_easy_setopt(c, CURLOPT_HTTPHEADER, headers);
  curl_easy_setopt(c, CURLOPT_CONNECTTIMEOUT, 5L);
  curl_easy_setopt(c, CURLOPT_TIMEOUT, 30L);
  curl_easy_setopt(c, CURLOPT_NOSIGNAL, 1L);
  curl_easy_setopt(c, CURLOPT_WRITEFUNCTION, Collect);
  curl_easy_setopt(c, CURLOPT_WRITEDATA, &reply.body);
  if (!lrs.user.empty()) {
    curl_easy_setopt(c, CURLOPT_HTTPAUTH, CURLAUTH_BASIC);
    curl_easy_setopt(c, CURLOPT_USERNAME, lrs.user.c_str());
    curl_easy_setopt(c, CURLOPT_PASSWORD, lrs.password.c_str());
  }
  if (post) {
    curl_easy_setopt(c, CURLOPT_POSTFIELDS, post->c_str());
    curl_easy_setopt(c, CURLOPT_POSTFIELDSIZE, static_cast<long>(post->size()));
  }
  const CURLcode rc = curl_easy_perform(c);
  curl_easy_getinfo(c, CURLINFO_RESPONSE_CODE, &reply.status);
  curl_slist_free_all(headers);
  curl_easy_cleanup(c);
  if (rc != CURLE_OK)
    throw XapiError("LRS " + RedactUrl(lrs.url) + ": cannot reach it (" +
                    curl_easy_strerror(rc) + ")");
  return reply;
}

std::string Endpoint(const XapiSettings& lrs) {
  std::string u = lrs.url;
  while (!u.empty() && u.back() == '/') u.pop_back();
  return u + "/statements";
}

std::string Slurp(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

XapiSettings XapiSettingsFromEnv() {
  XapiSettings s;
  const auto env = [](const char* name) {
    const char* v = std::getenv(name);
    return std::string(v ? v : "");
  };
  s.url = env("SULCUS_LRS_URL");
  s.user = env("SULCUS_LRS_USER");
  s.password = env("SULCUS_LRS_PASSWORD");
  if (const std::string h = env("SULCUS_XAPI_HOMEPAGE"); !h.empty()) s.homepage = h;
  s.allow_http = env("SULCUS_LRS_ALLOW_HTTP") == "1";
  while (!s.homepage.empty() && s.homepage.back() == '/') s.homepage.pop_back();
  return s;
}

std::string XapiStatements(const LessonResult& r, const std::string& registration,
                           const std::string& started, const std::string& homepage,
                           const std::string& id_key) {
  return Statements(r, registration, started, homepage, id_key).Build();
}

std::string StatementKey(const fs::path& dir) {
  const fs::path file = dir / kKeyFile;
  {
    std::ifstream in(file);
    std::string kept;
    if (in >> kept && kept.size() == 64) return kept;
  }
  if (sodium_init() < 0) throw XapiError("libsodium could not be initialised");
  unsigned char b[32];
  randombytes_buf(b, sizeof b);
  char hex[65];
  sodium_bin2hex(hex, sizeof hex, b, sizeof b);
  AtomicFile out(file);
  out.stream() << hex << "\n";
  out.Commit();
  return hex;
}

namespace {

// After a 409: the LRS holds statements with some of these ids. They were sent
// before (a retry) only if the LRS holds each of them, under this attempt's
// registration, for the same student, verb and object; anything else is a
// statement posted under one of these ids by someone else.
void CheckStoredAreOurs(const XapiSettings& lrs, const std::string& statements) {
  YAML::Node ours;
  try {
    ours = YAML::Load(statements);
  } catch (const YAML::Exception& e) {
    throw XapiError(std::string("the statements are not JSON: ") + e.what());
  }
  if (!ours.IsSequence() || ours.size() == 0) return;
  const std::string registration = ours[0]["context"]["registration"].as<std::string>("");
  const YAML::Node held = YAML::Load(FetchStatements(lrs, registration))["statements"];
  auto key = [](const YAML::Node& s) {
    return s["actor"]["account"]["name"].as<std::string>("") + "\n" +
           s["verb"]["id"].as<std::string>("") + "\n" +
           s["object"]["id"].as<std::string>("");
  };
  std::map<std::string, std::string> stored;
  if (held && held.IsSequence())
    for (const YAML::Node& s : held) stored[s["id"].as<std::string>("")] = key(s);
  for (const YAML::Node& s : ours) {
    const std::string id = s["id"].as<std::string>("");
    const auto it = stored.find(id);
    if (it == stored.end() || it->second != key(s))
      throw XapiError("LRS " + RedactUrl(lrs.url) + " holds another statement with id " +
                      id +
                      " (not this attempt's): a conflict, not sent; tell the "
                      "school's LRS administrator");
  }
}

}  // namespace

void CheckLrsScheme(const XapiSettings& lrs) {
  std::string scheme = lrs.url.substr(0, lrs.url.find(':'));
  for (char& c : scheme)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (scheme == "https") return;
  if (scheme == "http" && lrs.allow_http) {
    static std::once_flag said;
    std::call_once(said, [&] {
      std::fprintf(stderr,
                   "warning: the LRS %s is plain http: the students' results and the "
                   "LRS password go unencrypted (SULCUS_LRS_ALLOW_HTTP=1)\n",
                   RedactUrl(lrs.url).c_str());
    });
    return;
  }
  throw XapiError("LRS " + RedactUrl(lrs.url) +
                  (scheme == "http"
                       ? ": plain http would send the students' results and the LRS "
                         "password unencrypted; give its https URL (or, for an LRS on "
                         "this station or a closed network, set SULCUS_LRS_ALLOW_HTTP=1)"
                       : ": not an http(s) URL"));
}

void SendStatements(const XapiSettings& lrs, const std::string& statements) {
  CheckLrsScheme(lrs);
  const Reply reply = Http(lrs, Endpoint(lrs), &statements);
  if (reply.status == 200 || reply.status == 204) return;
  if (reply.status == 409) return CheckStoredAreOurs(lrs, statements);
  throw XapiError("LRS " + RedactUrl(lrs.url) + " refused the statements: HTTP " +
                  std::to_string(reply.status) + " " + Shorten(reply.body, 200));
}

std::string FetchStatements(const XapiSettings& lrs, const std::string& registration) {
  CheckLrsScheme(lrs);
  const Reply reply =
      Http(lrs, Endpoint(lrs) + "?limit=1000&registration=" + registration, nullptr);
  if (reply.status != 200)
    throw XapiError("LRS " + RedactUrl(lrs.url) +
                    " did not return the statements: HTTP " +
                    std::to_string(reply.status) + " " + Shorten(reply.body, 200));
  return reply.body;
}

std::string QueueStatements(const fs::path& dir, const LessonResult& r,
                            const std::string& registration, const std::string& started,
                            const XapiSettings& lrs) {
  std::string id_key;
  try {
    id_key = StatementKey(dir);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("the xAPI statements' key cannot be kept: ") +
                             e.what());
  }
  const std::string json = XapiStatements(r, registration, started, lrs.homepage, id_key);
  // Write-ahead: marked waiting (durably) before the statements are written
  // and sent, unmarked once the LRS has them; each file whole or not at all.
  // A stop at any moment leaves them sent, or waiting for `results sync`.
  auto mark = [&](const std::string& why) {
    try {
      AtomicFile w(dir / kWaitingFile);
      w.stream() << "The xAPI statements in " << kStatementsFile
                 << " wait for the LRS: " << why
                 << "\n`sulcus-cli results sync` sends them.\n";
      w.Commit();
      return true;
    } catch (const std::exception&) {
      return false;  // a full disk
    }
  };
  bool marked = lrs.enabled() && mark("not sent yet (the station stopped while sending)");
  std::string unwritten;
  try {
    AtomicFile out(dir / kStatementsFile, true);
    out.stream() << json;
    out.Commit();
  } catch (const std::exception& e) {
    unwritten = e.what();
  }
  if (!lrs.enabled()) {
    if (!unwritten.empty()) throw std::runtime_error(unwritten);
    return "";
  }
  // Sent from memory when the file could not be written (a full disk).
  std::string why;
  try {
    SendStatements(lrs, json);
    std::error_code ec;
    fs::remove(dir / kWaitingFile, ec);
    return "";
  } catch (const XapiError& e) {
    why = e.what();
  }
  marked = mark(why) || marked;
  if (!marked || !unwritten.empty())
    throw std::runtime_error("the xAPI statements could neither be sent (" + why +
                             ") nor kept waiting" +
                             (unwritten.empty() ? "" : " (" + unwritten + ")"));
  return why;
}

std::vector<fs::path> WaitingStatements(const fs::path& results) {
  std::vector<fs::path> out;
  std::error_code ec;
  const fs::path attempts = results / "attempts";
  if (!fs::is_directory(attempts, ec)) return out;
  for (const fs::directory_entry& d : fs::directory_iterator(attempts, ec))
    if (!d.is_symlink(ec) && d.is_directory(ec) &&
        fs::exists(d.path() / kWaitingFile, ec) &&
        fs::exists(d.path() / kStatementsFile, ec))
      out.push_back(d.path());
  std::sort(out.begin(), out.end());
  return out;
}

bool SendWaitingStatements(const fs::path& dir, const XapiSettings& lrs,
                           std::string* why) {
  try {
    SendStatements(lrs, Slurp(dir / kStatementsFile));
  } catch (const XapiError& e) {
    *why = e.what();
    return false;
  }
  std::error_code ec;
  fs::remove(dir / kWaitingFile, ec);
  return true;
}

}  // namespace sulcus
