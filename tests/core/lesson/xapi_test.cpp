// Records for the LMS: an attempt's xAPI statements, sent to a real Learning
// Record Store (Ralph, started by the test), read back by the attempt's
// registration, sent again without duplicates, kept waiting while the LRS cannot
// be reached and sent later, and refused with a clear message for a wrong password.
#include "core/lesson/xapi.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <set>

#include "tests/common/kill_sweep.h"
#include "tests/common/lrs_server.h"
#include "tests/common/output.h"
#include "tests/common/postgres_server.h"
#include "tests/core/lesson/sample_result.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;
using test::LrsServer;

constexpr const char* kRegistration = "5b1f2c3d-4e5f-4a6b-8c7d-9e0f1a2b3c4d";

LessonResult Attempt() {
  LessonResult r = test::Sample("ada", 82.5);
  r.lesson_name = "Periodontal probing";
  r.kind = "probing";
  r.duration_s = 149.35;
  r.pass_mark = 70;
  DeclaredDiagnosis d;
  d.periodontitis = true;
  d.stage = Stage::kIII;
  d.extent = Extent::kLocalized;
  r.declared = d;
  return r;
}

XapiSettings Lrs(const LrsServer& server) {
  XapiSettings s;
  s.url = server.url();
  s.user = LrsServer::kUser;
  s.password = LrsServer::kPassword;
  s.homepage = "https://dental-school.example.org";
  s.allow_http = true;  // the test's LRS listens on 127.0.0.1 without TLS
  return s;
}

// An LRS of its own for each test: Ralph's file backend (the one that needs no
// database server) takes a single bulk write in its life (it creates its file
// once), which is all a test needs.
class Xapi : public ::testing::Test {
 protected:
  LrsServer& Server() {
    if (!server_) server_ = std::make_unique<LrsServer>(fs::path(SULCUS_LRS_VENV));
    return *server_;
  }

 private:
  std::unique_ptr<LrsServer> server_;
};

TEST_F(Xapi, AnAttemptIsOneCompletedStatementOnePerSiteAndTheDiagnosis) {
  const LessonResult r = Attempt();
  const std::string json =
      XapiStatements(r, kRegistration, "2026-12-01T10:00:00Z", "https://school.example");
  const YAML::Node s = YAML::Load(json);  // JSON is YAML: read back with yaml-cpp
  ASSERT_TRUE(s.IsSequence());
  ASSERT_EQ(s.size(), 1u + 24u + 1u);
  std::set<std::string> ids;
  for (const YAML::Node& st : s) {
    ids.insert(st["id"].as<std::string>());
    EXPECT_EQ(st["actor"]["account"]["name"].as<std::string>(), "ada");
    EXPECT_EQ(st["context"]["registration"].as<std::string>(), kRegistration);
  }
  EXPECT_EQ(ids.size(), s.size()) << "every statement its own id";
  const YAML::Node done = s[0];
  EXPECT_EQ(done["verb"]["id"].as<std::string>(),
            "http://adlnet.gov/expapi/verbs/completed");
  EXPECT_EQ(done["object"]["id"].as<std::string>(),
            "https://school.example/xapi/lessons/periodontal_probing");
  EXPECT_DOUBLE_EQ(done["result"]["score"]["raw"].as<double>(), 82.5);
  EXPECT_DOUBLE_EQ(done["result"]["score"]["scaled"].as<double>(), 0.825);
  EXPECT_TRUE(done["result"]["success"].as<bool>()) << "82.5 passes at 70";
  EXPECT_EQ(done["result"]["duration"].as<std::string>(), "PT149.35S");
  const YAML::Node site = s[1];
  EXPECT_EQ(site["object"]["id"].as<std::string>(),
            "https://school.example/xapi/lessons/periodontal_probing/sites/47-MB");
  const YAML::Node ext = site["result"]["extensions"];
  EXPECT_DOUBLE_EQ(
      ext["https://school.example/xapi/extensions/depth-reached-mm"].as<double>(), 3.1);
  EXPECT_EQ(ext["https://school.example/xapi/extensions/depth-charted-mm"].as<int>(), 3);
  EXPECT_DOUBLE_EQ(ext["https://school.example/xapi/extensions/force-n"].as<double>(),
                   0.22);
  const YAML::Node dx = s[25];
  EXPECT_EQ(dx["verb"]["id"].as<std::string>(),
            "http://adlnet.gov/expapi/verbs/answered");
  EXPECT_EQ(dx["result"]["response"].as<std::string>(),
            "periodontitis stage III, localized");
  // The same attempt, the same ids: a second send is a duplicate, never a copy.
  EXPECT_EQ(json, XapiStatements(r, kRegistration, "2026-12-01T10:00:00Z",
                                 "https://school.example"));
  LessonResult failed = r;
  failed.total = 55;
  EXPECT_FALSE(YAML::Load(XapiStatements(failed, kRegistration, "",
                                         "https://s.example"))[0]["result"]["success"]
                   .as<bool>());
}

TEST_F(Xapi, TheLrsAcceptsEveryStatementAndReturnsThemByTheRegistration) {
  const XapiSettings lrs = Lrs(Server());
  const std::string json =
      XapiStatements(Attempt(), kRegistration, "2026-12-01T10:00:00Z", lrs.homepage);
  SendStatements(lrs, json);
  const YAML::Node back = YAML::Load(FetchStatements(lrs, kRegistration))["statements"];
  ASSERT_TRUE(back.IsSequence());
  EXPECT_EQ(back.size(), 26u);
  // Sent again (a retry after a lost answer): accepted as already there.
  EXPECT_NO_THROW(SendStatements(lrs, json));
  EXPECT_EQ(YAML::Load(FetchStatements(lrs, kRegistration))["statements"].size(), 26u);
  // Another attempt's registration does not return these.
  EXPECT_EQ(YAML::Load(FetchStatements(
                lrs, "6b1f2c3d-4e5f-4a6b-8c7d-9e0f1a2b3c4d"))["statements"]
                .size(),
            0u);
}

TEST_F(Xapi, StatementsWaitWhileTheLrsCannotBeReachedAndAreSentLater) {
  const fs::path results = test::FreshOutputPath("xapi", "station");
  const fs::path dir = results / "attempts" / "20261201-100000-ada";
  fs::create_directories(dir);
  XapiSettings nowhere = Lrs(Server());
  nowhere.url = "http://127.0.0.1:" + std::to_string(test::FreePort()) + "/xAPI";
  const std::string registration = "7b1f2c3d-4e5f-4a6b-8c7d-9e0f1a2b3c4d";
  const std::string why =
      QueueStatements(dir, Attempt(), registration, "2026-12-01T10:00:00Z", nowhere);
  EXPECT_NE(why.find("cannot reach it"), std::string::npos) << why;
  EXPECT_TRUE(fs::exists(dir / "xapi.json"));
  ASSERT_EQ(WaitingStatements(results), std::vector<fs::path>{dir});
  // The LRS is back (here: the real one): the sync sends them, once.
  std::string again;
  ASSERT_TRUE(SendWaitingStatements(dir, Lrs(Server()), &again)) << again;
  EXPECT_TRUE(WaitingStatements(results).empty());
  EXPECT_EQ(YAML::Load(FetchStatements(Lrs(Server()), registration))["statements"].size(),
            26u);
}

// A full disk (the attempt's folder on a filled tmpfs): the statements cannot be
// written, so they are sent from memory; when the LRS cannot be reached either,
// QueueStatements says so by throwing (KeepAttempt then leaves the attempt
// waiting for a sync), never by returning as if they waited.
TEST_F(Xapi, OnAFullDiskTheStatementsAreSentFromMemoryOrSaidLost) {
  test::SmallDisk disk(test::OutputPath("xapi", "full-disk"), 1);
  if (!disk.mounted()) GTEST_SKIP() << "no tmpfs can be mounted here (not root)";
  const fs::path dir = disk.dir() / "attempts" / "20261201-100000-ada";
  fs::create_directories(dir);
  disk.LeaveFree(0);
  XapiSettings nowhere = Lrs(Server());
  nowhere.url = "http://127.0.0.1:" + std::to_string(test::FreePort()) + "/xAPI";
  const std::string registration = "8b1f2c3d-4e5f-4a6b-8c7d-9e0f1a2b3c4d";
  try {
    QueueStatements(dir, Attempt(), registration, "2026-12-01T10:00:00Z", nowhere);
    ADD_FAILURE() << "returned as if the statements waited";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be kept"), std::string::npos)
        << e.what() << ": without its key kept, no id can be sent";
  }
  // With the key kept (KeepAttempt makes it with the UUID) and the LRS away.
  disk.Empty();
  StatementKey(dir);
  disk.LeaveFree(0);
  try {
    QueueStatements(dir, Attempt(), registration, "2026-12-01T10:00:00Z", nowhere);
    ADD_FAILURE() << "returned as if the statements waited";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("neither be sent"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "xapi.json")) << "no file cut short";
  EXPECT_EQ(QueueStatements(dir, Attempt(), registration, "2026-12-01T10:00:00Z",
                            Lrs(Server())),
            "");
  EXPECT_EQ(YAML::Load(FetchStatements(Lrs(Server()), registration))["statements"].size(),
            26u);
}

// Ids that cannot be pre-empted: they hash the attempt's UUID with a random key
// kept in its folder, so knowing the UUID (the store shows it) is not enough to
// post under them; and a statement posted under one of them first (here by a
// test that knows the key) is a conflict, never taken as sent: they wait.
TEST_F(Xapi, AStatementPostedFirstUnderAnAttemptsIdIsAConflictNotSent) {
  const fs::path results = test::FreshOutputPath("xapi", "preempted");
  const fs::path dir = results / "attempts" / "20261201-100000-ada";
  fs::create_directories(dir);
  const std::string registration = "9b1f2c3d-4e5f-4a6b-8c7d-9e0f1a2b3c4d";
  const std::string key = StatementKey(dir);
  EXPECT_EQ(key.size(), 64u);
  EXPECT_EQ(StatementKey(dir), key) << "kept: the same ids on every retry";
  const auto first_id = [&](const std::string& k) {
    return YAML::Load(
               XapiStatements(Attempt(), registration, "", "https://x", k))[0]["id"]
        .as<std::string>();
  };
  EXPECT_NE(first_id(key), first_id("")) << "not the id anyone can derive";
  EXPECT_NE(first_id(key), first_id(std::string(64, '0')));
  // Someone posts a statement of their own under the attempt's first id.
  const XapiSettings lrs = Lrs(Server());
  YAML::Node forged = YAML::Load(
      XapiStatements(Attempt(), registration, "2026-12-01T10:00:00Z", lrs.homepage, key));
  YAML::Node one(YAML::NodeType::Sequence);
  forged[0]["actor"]["account"]["name"] = "mallory";
  forged[0]["context"]["registration"] = "0b1f2c3d-4e5f-4a6b-8c7d-9e0f1a2b3c4d";
  one.push_back(forged[0]);
  YAML::Emitter json;
  json << YAML::DoubleQuoted << YAML::Flow << one;
  ASSERT_NO_THROW(SendStatements(lrs, json.c_str()));
  const std::string why =
      QueueStatements(dir, Attempt(), registration, "2026-12-01T10:00:00Z", lrs);
  EXPECT_NE(why.find("conflict"), std::string::npos) << why;
  EXPECT_EQ(WaitingStatements(results), std::vector<fs::path>{dir})
      << "never taken as sent";
}

// The LRS over https only: a plain http URL is refused (before anything is
// sent) unless the station allows it, and the statements wait, with the reason.
TEST(XapiScheme, PlainHttpIsRefusedUnlessTheStationAllowsIt) {
  XapiSettings lrs;
  lrs.url = "http://lms.example.org/xAPI";
  lrs.password = "lrs-secret";
  try {
    CheckLrsScheme(lrs);
    ADD_FAILURE() << "plain http accepted";
  } catch (const XapiError& e) {
    EXPECT_NE(std::string(e.what()).find("give its https URL"), std::string::npos)
        << e.what();
    EXPECT_EQ(std::string(e.what()).find("lrs-secret"), std::string::npos);
  }
  EXPECT_THROW(SendStatements(lrs, "[]"), XapiError);
  lrs.allow_http = true;
  EXPECT_NO_THROW(CheckLrsScheme(lrs));
  lrs.url = "https://lms.example.org/xAPI";
  lrs.allow_http = false;
  EXPECT_NO_THROW(CheckLrsScheme(lrs));
  lrs.url = "ftp://lms.example.org/xAPI";
  EXPECT_THROW(CheckLrsScheme(lrs), XapiError);
  const fs::path dir = test::FreshOutputPath("xapi", "plain-http") / "attempts" / "a";
  fs::create_directories(dir);
  lrs.url = "http://lms.example.org/xAPI";
  const std::string why = QueueStatements(dir, Attempt(), kRegistration, "", lrs);
  EXPECT_NE(why.find("https"), std::string::npos) << "waiting, with the reason: " << why;
}

TEST_F(Xapi, AWrongPasswordIsRefusedWithTheLrsNamedAndThePasswordNot) {
  XapiSettings lrs = Lrs(Server());
  lrs.password = "not-the-lrs-password";
  try {
    SendStatements(lrs, XapiStatements(Attempt(), kRegistration, "", lrs.homepage));
    FAIL() << "sent with a wrong password";
  } catch (const XapiError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("refused the statements: HTTP 401"), std::string::npos) << m;
    EXPECT_NE(m.find(Server().url()), std::string::npos) << m;
    EXPECT_EQ(m.find("not-the-lrs-password"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace sulcus
