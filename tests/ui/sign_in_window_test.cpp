// A lab's station as a student meets it, against a real PostgreSQL server set
// up with the roles (`results setup`): the instructor's role puts the class on
// the roster and asks every student to sign in; at a station (the station's
// role) the start page offers the roster's names and a passphrase; a wrong
// passphrase keeps the page open with the reason; the student's first sign-in
// sets it; the lesson taken in the window is stored as the signed-in
// student's. An attempt started without signing in is refused by the store
// and waits in its folder. Screenshots go to test-output/ui.
#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QSurfaceFormat>
#include <QTableWidget>
#include <cstdlib>
#include <filesystem>

#include "core/lesson/attempt.h"
#include "core/lesson/results.h"
#include "core/lesson/sign_in.h"
#include "tests/common/postgres_server.h"
#include "tests/ui/window_test.h"
#include "ui/instructor_dialog.h"
#include "ui/main_window.h"
#include "ui/start_dialog.h"

namespace sulcus::ui {
namespace {

namespace fs = std::filesystem;

using window_test::Lessons;
using window_test::Out;
using window_test::WaitFor;

TEST(SignIn, AStudentOnTheRosterSignsInAtAStationAndTheAttemptIsTheirs) {
  test::PostgresServer server;
  const std::string owner = server.FreshDatabase("signin");
  const StoreSetup setup = SetUpPostgresStore(owner, "station-pw", "instructor-pw");
  const std::string host = "@127.0.0.1:" + std::to_string(server.port()) + "/signin";
  const std::string station = std::string("postgresql://") + kStationRole +
                              ":station-pw" + host,
                    instructor = std::string("postgresql://") + kInstructorRole +
                                 ":instructor-pw" + host;
  {
    const auto teacher = OpenPostgresResults(instructor);
    EXPECT_EQ(AddNamesToRoster(*teacher, {"Ada Okafor", "Grace Lin"}, nullptr), 2);
    teacher->SetSetting(kSignInSetting, "required");
  }
  setenv("SULCUS_RESULTS_URL", station.c_str(), 1);
  const fs::path dir = Out("sign_in_station");
  fs::remove_all(dir);
  const ResultsPlace place = ResultsPlaceFor(dir);

  StartDialog d({Lessons()}, place);
  d.show();
  EXPECT_TRUE(d.signs_in());
  EXPECT_EQ(d.offered_students(), (std::vector<std::string>{"Ada Okafor", "Grace Lin"}));
  d.SetStudent("Grace Lin");
  ASSERT_TRUE(d.SelectLesson(Lessons() / "periodontal_probing.yaml"));
  d.SetPassphrase("short");
  EXPECT_FALSE(d.TryStart()) << "a first passphrase of 5 characters";
  EXPECT_NE(d.name_problem().indexOf("at least 8"), -1) << d.name_problem().toStdString();
  d.SetPassphrase("grace's passphrase");
  ASSERT_TRUE(d.TryStart()) << d.name_problem().toStdString();
  const std::string token = d.sign_in_token();
  EXPECT_FALSE(token.empty());
  // Another day: a wrong passphrase says so and keeps the page open.
  StartDialog again({Lessons()}, place);
  again.show();
  again.SetStudent("Grace Lin");
  ASSERT_TRUE(again.SelectLesson(Lessons() / "periodontal_probing.yaml"));
  again.SetPassphrase("grace's passphrasE");
  EXPECT_FALSE(again.TryStart());
  EXPECT_NE(again.name_problem().indexOf("not Grace Lin's"), -1)
      << again.name_problem().toStdString();
  QApplication::processEvents();
  EXPECT_TRUE(again.grab().save(QString::fromStdString(Out("sign_in.png").string())));

  // The lesson in the window, signed in: stored as hers.
  MainWindow w;
  w.resize(1280, 800);
  w.show();
  MainWindow::LessonStart start;
  start.lesson = Lessons() / "periodontal_probing.yaml";
  start.student = "Grace Lin";
  start.device = "mouse";
  start.results_dir = dir;
  start.sign_in = token;
  ASSERT_TRUE(w.StartLesson(start));
  ASSERT_TRUE(WaitFor([&] { return w.lesson() != nullptr; }, 600000));
  ASSERT_TRUE(w.FinishLesson(false));
  // Not signed in (Ada never did): refused by the store, waiting in its folder.
  start.student = "Ada Okafor";
  start.sign_in.clear();
  ASSERT_TRUE(w.StartLesson(start));
  ASSERT_TRUE(WaitFor([&] { return w.lesson() != nullptr; }, 600000));
  w.FinishLesson(false);
  const auto rows = OpenPostgresResults(instructor)->Attempts();
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].student, "Grace Lin");
  EXPECT_TRUE(rows[0].signed_in);
  EXPECT_EQ(rows[0].device, "keys");
  EXPECT_EQ(UnfinishedAttempts(dir).size(), 1u) << "Ada's attempt waits, not lost";
  // The instructor's view (the instructor's role) says she signed in.
  setenv("SULCUS_RESULTS_URL", instructor.c_str(), 1);
  QDialog* view = w.OpenInstructor("the lab's passphrase", dir);
  ASSERT_NE(view, nullptr);
  const QTableWidget* table = dynamic_cast<InstructorDialog*>(view)->attempts_table();
  ASSERT_EQ(table->rowCount(), 1);
  EXPECT_EQ(table->item(0, 5)->text(), "keys, signed in");
  QApplication::processEvents();
  EXPECT_TRUE(
      view->grab().save(QString::fromStdString(Out("sign_in_instructor.png").string())));
  view->close();
  unsetenv("SULCUS_RESULTS_URL");
}

}  // namespace
}  // namespace sulcus::ui

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("SulcusTests");
  QApplication::setApplicationName("sign_in_window_test");
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
