// A lesson in the real window, under Xvfb: the start page lists the shipped
// lessons (and a broken one as broken); a scripted student drives the device
// (free-running, so the test waits for conditions, never for wall time) while
// the chart is filled through real key events; the diagnosis is declared; the
// report is shown, saved and stored. Practice shows the truth, assessment does
// not and locks the aids. Screenshots go to test-output/ui.
#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QElapsedTimer>
#include <QKeyEvent>
#include <QLineEdit>
#include <QMessageBox>
#include <QRegularExpression>
#include <QSurfaceFormat>
#include <QTabWidget>
#include <QTableWidget>
#include <QTextBrowser>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "core/haptics/recording.h"
#include "core/lesson/attempt.h"
#include "core/lesson/results.h"
#include "tests/common/output.h"
#include "tests/common/postgres_server.h"
#include "tests/core/lesson/sample_result.h"
#include "tests/ui/window_test.h"
#include "ui/chart_widget.h"
#include "ui/instructor_dialog.h"
#include "ui/main_window.h"
#include "ui/mouse_device.h"
#include "ui/odontogram_widget.h"
#include "ui/progress_dialog.h"
#include "ui/scene_view.h"
#include "ui/start_dialog.h"

namespace sulcus::ui {
namespace {

namespace fs = std::filesystem;

using window_test::Lessons;
using window_test::Out;
using window_test::WaitFor;

void Key(QWidget* w, int key, const QString& text,
         Qt::KeyboardModifiers mods = Qt::NoModifier) {
  QKeyEvent press(QEvent::KeyPress, key, mods, text);
  QApplication::sendEvent(w, &press);
  QKeyEvent release(QEvent::KeyRelease, key, mods, text);
  QApplication::sendEvent(w, &release);
}

bool Save(QWidget* w, const std::string& name) {
  return w->grab().save(QString::fromStdString(Out(name).string()));
}

// The sextant's practice lesson taken with the mouse and keys, as a person
// without a haptic device takes it.
MainWindow::LessonStart ByKeys(const std::string& student, const std::string& dir) {
  MainWindow::LessonStart start;
  start.lesson = Lessons() / "periodontal_probing.yaml";
  start.student = student;
  start.device = "mouse";
  start.mode = LessonSpec::Mode::kPractice;
  start.results_dir = Out(dir);
  return start;
}

TEST(StartPage, ListsTheLessonsAndABrokenOneAsBroken) {
  const fs::path extra = Out("instructor");
  fs::create_directories(extra);
  std::ofstream(extra / "broken.yaml")
      << "name: broken\nscene: nowhere.yaml\nsteps: [{instruction: x, complete: reed}]\n";
  StartDialog d({Lessons(), extra}, ResultsPlace(Out("start_results")));
  d.SetStudent("Ada");
  d.show();
  ASSERT_GE(d.items().size(), 3u);
  bool broken = false, shipped = false;
  for (const auto& it : d.items()) {
    if (it.file.filename() == "broken.yaml") {
      broken = it.broken;
      EXPECT_NE(it.errors.find("broken.yaml:3:"), std::string::npos) << it.errors;
    }
    if (it.file.filename() == "periodontal_probing.yaml")
      shipped = !it.broken && !it.description.empty();
  }
  EXPECT_TRUE(broken);
  EXPECT_TRUE(shipped);
  EXPECT_TRUE(d.SelectLesson(Lessons() / "periodontal_probing.yaml"));
  EXPECT_EQ(d.student(), "Ada");
  QApplication::processEvents();
  EXPECT_TRUE(Save(&d, "start_page.png"));
}

// A lesson that draws its case offers the case choice; one that does not, not.
TEST(StartPage, ALessonThatDrawsItsCaseOffersTheLastCaseAgainAndAGivenSeed) {
  const ResultsPlace place(Out("start_case_results"));
  const fs::path db_file = place.sqlite_file();
  fs::remove(db_file);
  const fs::path case_lesson =
      fs::absolute(Lessons() / "periodontal_probing_case.yaml").lexically_normal();
  {
    ResultsDb db(db_file);
    LessonResult r;
    r.lesson_name = "case";
    r.lesson_file = case_lesson.string();
    r.student = "Grace";
    r.mode = "practice";
    r.generated_case = true;
    r.case_seed = 4242;
    r.total = 71;
    r.complete = true;
    db.Store(r, "2026-12-01T10:00:00Z", "/a.rec", "/a.yaml", "/a");
  }
  StartDialog d({Lessons()}, place);
  d.SetStudent("Grace");
  d.show();
  ASSERT_TRUE(d.SelectLesson(Lessons() / "periodontal_probing.yaml"));
  QApplication::processEvents();
  EXPECT_FALSE(d.ChooseCase(StartDialog::CaseChoice::kSeed, 7))
      << "a lesson with a fixed scene has no case to choose";
  EXPECT_FALSE(d.seed().has_value());

  ASSERT_TRUE(d.SelectLesson(case_lesson));
  QApplication::processEvents();
  EXPECT_FALSE(d.seed().has_value())
      << "by default the lesson's own: a new case (seed: random)";
  ASSERT_TRUE(d.ChooseCase(StartDialog::CaseChoice::kLast));
  ASSERT_TRUE(d.seed().has_value());
  EXPECT_EQ(*d.seed(), 4242u) << "the student's last case again";
  ASSERT_TRUE(d.ChooseCase(StartDialog::CaseChoice::kSeed, 11));
  EXPECT_EQ(d.seed().value_or(0), 11u) << "the instructor's seed";
  EXPECT_TRUE(Save(&d, "start_page_case.png"));
  ASSERT_TRUE(d.ChooseCase(StartDialog::CaseChoice::kOwn));
  EXPECT_FALSE(d.seed().has_value());

  // Another student has no last case: that choice is refused, the own case kept.
  d.SetStudent("Ada");
  QApplication::processEvents();
  ASSERT_TRUE(d.SelectLesson(case_lesson));
  EXPECT_FALSE(d.ChooseCase(StartDialog::CaseChoice::kLast));
  EXPECT_FALSE(d.seed().has_value());
}

// The start page asks for the chosen lesson's scene a moment after the choice
// settles and shows how far it is, while the student goes on typing.
TEST(StartPage, TheChosenLessonIsPreparedWhileTheStudentTypes) {
  StartDialog d({Lessons()}, ResultsPlace(Out("start_prep_results")));
  std::vector<std::pair<fs::path, std::optional<std::uint64_t>>> asked;
  d.SetPreparation(
      [&](const fs::path& lesson, std::optional<std::uint64_t> seed) {
        asked.push_back({lesson, seed});
      },
      [] { return QString("Preparing the scene: trees of tooth 46 (43 %)"); });
  d.show();
  ASSERT_TRUE(d.SelectLesson(Lessons() / "periodontal_probing.yaml"));
  auto* name = d.findChild<QComboBox*>();
  ASSERT_NE(name, nullptr);
  name->setFocus();
  name->setCurrentText("");
  for (const QChar c : QString("Ada Lovelace"))
    Key(name->lineEdit(), c.unicode(), QString(c));
  QElapsedTimer t;
  t.start();
  WaitFor([&] { return t.elapsed() > 800; });
  ASSERT_FALSE(asked.empty()) << "nothing was prepared";
  EXPECT_EQ(asked.back().first,
            fs::absolute(Lessons() / "periodontal_probing.yaml").lexically_normal());
  EXPECT_FALSE(asked.back().second.has_value());
  EXPECT_EQ(d.student(), "Ada Lovelace") << "what was typed meanwhile is kept";
  EXPECT_TRUE(d.preparation_text().contains("43 %"))
      << d.preparation_text().toStdString();
  EXPECT_TRUE(Save(&d, "start_page_preparing.png"));
}

// Types the chart as the student reads it: each site's deepest reading to the
// nearest millimetre, B after the sites that bled.
void ChartEverything(MainWindow& w) {
  ChartWidget* chart = w.chart();
  chart->setFocus();
  const LessonResult sofar = w.lesson()->Finish();
  for (const SiteResult& s : sofar.sites) {
    const int pd = s.reached_mm ? static_cast<int>(std::lround(*s.reached_mm)) : 0;
    Key(chart, Qt::Key_0 + pd, QString::number(pd));
    if (s.bled) Key(chart, Qt::Key_B, "b");
  }
}

// The careful scripted student on the shipped lesson, as fast as the thread can go.
MainWindow::LessonStart CarefulStudent() {
  MainWindow::LessonStart s;
  s.lesson = Lessons() / "periodontal_probing.yaml";
  s.student = "Window Student";
  s.device = "student:careful";
  s.free_run = true;
  s.results_dir = Out("results");
  return s;
}

// A lesson whose scene was prepared on the start page starts with that
// preparation: it is not built a second time.
TEST(LessonWindow, ALessonPreparedOnTheStartPageStartsWithoutASecondBuild) {
  MainWindow w;
  w.show();
  const fs::path lesson = Lessons() / "periodontal_probing.yaml";
  w.PrepareLesson(lesson, std::nullopt);
  EXPECT_EQ(w.preparer().started(), 1);
  EXPECT_TRUE(WaitFor([&] { return w.preparer().Status().contains("ready"); }, 600000))
      << w.preparer().Status().toStdString();
  w.PrepareLesson(lesson, std::nullopt);  // the same choice again: nothing new
  EXPECT_EQ(w.preparer().started(), 1);
  MainWindow::LessonStart s = CarefulStudent();
  s.lesson = lesson;
  ASSERT_TRUE(w.StartLesson(s));
  EXPECT_EQ(w.preparer().started(), 1) << "the lesson built its scene again";
  EXPECT_TRUE(w.FinishLesson(false));
}

// A case drawn from a seed the student chose: prepared while the start page is
// open (only its gingiva is built: the teeth and the rest come from the cache),
// then taken on that case, whose truth the readings are scored against.
TEST(LessonWindow, ACaseFromAChosenSeedIsPreparedThenTakenOnThatCase) {
  MainWindow w;
  w.show();
  const fs::path lesson = Lessons() / "periodontal_probing_case.yaml";
  constexpr std::uint64_t kSeed = 90210;  // drawn by no other test: built here
  QElapsedTimer t;
  t.start();
  w.PrepareLesson(lesson, kSeed);
  ASSERT_TRUE(WaitFor([&] { return w.preparer().Status().contains("ready"); }, 600000))
      << w.preparer().Status().toStdString();
  std::printf("figure: a new case (seed %llu) prepared in the window in %.1f s\n",
              static_cast<unsigned long long>(kSeed), t.elapsed() / 1000.0);
  MainWindow::LessonStart s = CarefulStudent();
  s.lesson = lesson;
  s.seed = kSeed;
  s.student = "Case Student";
  ASSERT_TRUE(w.StartLesson(s));
  EXPECT_EQ(w.preparer().started(), 1) << "the case was built a second time";
  ASSERT_TRUE(WaitFor([&] { return w.lesson()->Finish().sites_read >= 4; }, 300000));
  ASSERT_TRUE(w.FinishLesson(false));
  ASSERT_TRUE(w.last_result());
  const LessonResult& r = *w.last_result();
  EXPECT_TRUE(r.generated_case);
  EXPECT_EQ(r.case_seed, kSeed);
  // The sites the student read and left (the lesson is finished while the
  // student probes on: the visit still open then, cut short as a person's
  // would be, ends at the last tick and is not among them).
  int read = 0;
  for (const SiteResult& x : r.sites)
    if (x.reached_mm && x.left_tick < r.last_tick) {
      ++read;
      EXPECT_LE(std::abs(*x.reached_mm - x.truth_mm), 1.0) << x.site.ToString();
    }
  EXPECT_GE(read, 3);
}

TEST(LessonWindow, APracticeLessonFromTheFirstSiteToTheReport) {
  MainWindow w;
  w.resize(1366, 768);
  w.show();
  {
    // A figure, not a check: display frames a second with the thread at 1 kHz (the mouse
    // device).
    MainWindow::LessonStart live = CarefulStudent();
    live.device = "mouse";
    live.free_run = false;
    ASSERT_TRUE(w.StartLesson(live));
    const std::uint64_t f0 = w.frames();
    QElapsedTimer t;
    t.start();
    WaitFor([&] { return t.elapsed() > 3000; });
    std::printf(
        "figure: %.1f display frames a second under Xvfb with the haptic thread at 1 "
        "kHz\n",
        (w.frames() - f0) * 1000.0 / t.elapsed());
    ASSERT_TRUE(w.FinishLesson(false));
  }
  ASSERT_TRUE(w.StartLesson(CarefulStudent()));
  // F1 helps with the lesson being taken: probing and charting here.
  EXPECT_TRUE(w.HelpHtml().contains("<b>Charting</b>"));
  EXPECT_FALSE(w.HelpHtml().contains("odontogram"));
  ASSERT_NE(w.lesson(), nullptr);
  EXPECT_FALSE(w.aids_locked());
  EXPECT_TRUE(WaitFor([&] { return w.lesson_text().contains("Step 1 of 4"); }))
      << w.lesson_text().toStdString();
  // Halfway round the buccal sulci: the lesson in progress.
  ASSERT_TRUE(WaitFor([&] { return w.lesson()->Finish().sites_read >= 6; }));
  EXPECT_TRUE(Save(&w, "lesson_in_progress.png"));
  ASSERT_TRUE(WaitFor([&] { return w.lesson()->current_step() >= 2; }))
      << "both probing steps done";
  ChartEverything(w);
  EXPECT_EQ(w.chart()->entered(), 24);
  EXPECT_EQ(w.lesson()->current_step(), 3)
      << "the chart step is done: on to the diagnosis; " << [&] {
           const LessonResult now = w.lesson()->Finish();
           std::string why = "ticks " + std::to_string(now.first_tick) + ".." +
                             std::to_string(now.last_tick) + ", charted " +
                             std::to_string(now.sites_charted) +
                             (now.complete ? "" : ", " + now.ended);
           for (const StepResult& st : now.steps)
             why += "; " + st.id +
                    (st.completed   ? " done"
                     : st.timed_out ? " timed out"
                                    : " open");
           for (const std::string& f : now.feedback) why += "; " + f;
           return why;
         }();
  EXPECT_TRUE(Save(&w, "lesson_charted.png"));
  bool truth_shown = false;
  for (const std::string& f : w.lesson()->feedback())
    truth_shown |= f.find("the true depth is") != std::string::npos;
  EXPECT_TRUE(truth_shown) << "practice: the truth after each site";
  EXPECT_TRUE(w.chart()->shows_truth()) << "practice: the chart's true-PD row";
  DeclaredDiagnosis d;
  d.stage = Stage::kIII;
  d.extent = Extent::kLocalized;
  ASSERT_TRUE(w.DeclareDiagnosis(d));
  QElapsedTimer finish;
  finish.start();
  ASSERT_TRUE(w.FinishLesson());
  std::printf(
      "figure: %lld ms from the last entry to the report on screen (scored, saved, "
      "stored)\n",
      static_cast<long long>(finish.elapsed()));
  ASSERT_TRUE(w.last_result());
  // The footer names the store the attempt went to, with nothing waiting.
  EXPECT_EQ(w.results_footer().toStdString(),
            "Results: SQLite " + (Out("results") / "results.db").string());
  const LessonResult& r = *w.last_result();
  EXPECT_EQ(r.sites_read, 24);
  EXPECT_EQ(r.sites_charted, 24);
  EXPECT_GE(r.total, 95.0);
  EXPECT_EQ(r.declared->Summary(), "periodontitis stage III, localized");
  for (const RubricLine& l : r.lines)
    EXPECT_NE(l.status, RubricLine::Status::kFail) << l.message;
  EXPECT_TRUE(fs::exists(w.last_report()));
  ASSERT_NE(w.report_dialog(), nullptr);
  EXPECT_TRUE(w.report_dialog()->isVisible());
  EXPECT_TRUE(
      w.report_dialog()->findChild<QTextBrowser*>("report")->toPlainText().contains(
          "Every line of the score"));
  QApplication::processEvents();
  EXPECT_TRUE(Save(w.report_dialog(), "lesson_report.png"));
  ResultsDb db(Out("results") / "results.db");
  const auto rows = db.Attempts("Window Student");
  ASSERT_FALSE(rows.empty());
  EXPECT_NEAR(rows.back().total, r.total, 1e-9);
  EXPECT_TRUE(fs::exists(rows.back().recording));

  // A rubric line's moment opens the replay there: the recorded tools at that tick.
  const RubricLine* line = nullptr;
  for (const RubricLine& l : r.lines)
    if (l.category == "force" && l.site && l.site->ToString() == "46 DB") line = &l;
  ASSERT_NE(line, nullptr);
  auto* browser = w.report_dialog()->findChild<QTextBrowser*>("report");
  emit browser->anchorClicked(QUrl(QString("#t%1").arg(line->tick)));
  ASSERT_TRUE(w.replaying());
  EXPECT_EQ(w.replay_tick(), line->tick);
  const Recording rec = ReadRecording(rows.back().recording);
  const TickRecord* frame = w.replay_frame();
  ASSERT_NE(frame, nullptr);
  EXPECT_EQ(frame->X_WG.translation(), rec.frames[line->tick].X_WG.translation())
      << "the recorded tool, at that tick";
  EXPECT_EQ(frame->sample.X_WH.translation(),
            rec.frames[line->tick].sample.X_WH.translation())
      << "and the ghost";
  w.report_dialog()->hide();
  QApplication::processEvents();
  EXPECT_GT(w.plot_rows(), 10) << "the force trace of the last seconds up to the cursor";
  EXPECT_LE(w.minimumSizeHint().height(), 740)
      << "with the replay's timeline the window still fits 768 px";
  EXPECT_TRUE(Save(&w, "replay_at_46DB.png"));
  w.SetReplayPlaying(true);
  const std::uint64_t from = w.replay_tick();
  EXPECT_TRUE(WaitFor([&] { return w.replay_tick() > from + 50; }, 60000)) << "it plays";
  w.CloseReplay();
  EXPECT_FALSE(w.replaying());

  // That attempt as a demonstration: its probe moves as a ghost beside the live one, tick
  // for tick.
  ASSERT_TRUE(w.SetDemonstration(rows.back().recording));
  ASSERT_TRUE(WaitFor(
      [&] { return w.last_snapshot().tick > 500 && w.ghost_pose().has_value(); }, 60000));
  const std::uint64_t now = w.last_snapshot().tick;
  EXPECT_EQ(
      w.ghost_pose()->translation(),
      rec.frames[std::min<std::size_t>(now, rec.frames.size() - 1)].X_WG.translation());
  EXPECT_TRUE(Save(&w, "demonstration_ghost.png"));
  ASSERT_TRUE(w.SetDemonstration({}));
  EXPECT_FALSE(w.ghost_pose().has_value());
}

// A person's hand, by keys: the mouse-and-keyboard device, no scripted hand.
// At each of the path's first four sites the student presses N (the probe over
// the next site), R twelve times (a press of 0.24 N along the probe: the tip
// goes down until the floor answers with it), waits until the gauge holds
// still, reads the depth and types it into the chart with the probe still at
// the floor, then lets go (X). Every site probed is read, within 1 mm of the
// truth, with its held force in the band; a replay of the recording with the
// entries gives the same readings. Prints the seconds per site.
TEST(LessonWindow, APersonProbesFourSitesByKeysAndEachIsScored) {
  MainWindow w;
  w.resize(1280, 800);
  w.show();
  const MainWindow::LessonStart start = ByKeys("Key Hand", "person");
  ASSERT_TRUE(w.StartLesson(start));
  QWidget* view = w.view_widget();
  ChartWidget* chart = w.chart();
  // The 3D view first: at least 60 % of the window's width, at 1280 x 800 and
  // at 1024 x 700, with the lesson's panel open.
  for (const QSize size : {QSize(1024, 700), QSize(1280, 800)}) {
    w.resize(size);
    WaitFor([] { return false; }, 400);  // the layout settles
    EXPECT_GE(view->width(), 0.6 * w.width())
        << size.width() << " x " << size.height() << ": the view is " << view->width()
        << " px of " << w.width();
    EXPECT_TRUE(Save(&w, "layout_" + std::to_string(size.width()) + ".png"));
  }
  std::vector<SiteRef> probed;
  for (int k = 0; k < 4; ++k) {
    QElapsedTimer t;
    t.start();
    ASSERT_TRUE(w.lesson()->next_site());
    const SiteRef site = *w.lesson()->next_site();
    view->setFocus();
    Key(view, Qt::Key_N, "n");
    for (int i = 0; i < 12; ++i) Key(view, Qt::Key_R, "r");
    EXPECT_NEAR(w.mouse()->press(), 0.24, 1e-9);
    // At the floor: in the site's sulcus, the gauge within 0.03 N of the press
    // for a second, as a person holds it (the reading's held force is the median
    // over the whole stay, the letting go included: on a loaded machine half a
    // second of holding was not always the larger part of it).
    QElapsedTimer still;
    bool holding = false;
    const bool rested = WaitFor(
        [&] {
          const bool in = w.lesson()->tip_site() == site && w.lesson()->tip_depth_mm() &&
                          std::abs(w.gauge_force() - 0.24) < 0.03;
          if (in && !holding) still.restart();
          holding = in;
          return in && still.elapsed() > 1000;
        },
        60000);
    ASSERT_TRUE(rested) << site.ToString() << ": tip at "
                        << (w.lesson()->tip_site() ? w.lesson()->tip_site()->ToString()
                                                   : std::string("no site"))
                        << ", gauge " << w.gauge_force() << " N";
    // The loupe shows where the margin crosses the markings while the tip is in.
    EXPECT_TRUE(w.loupe_shown()) << site.ToString();
    if (k == 0) {
      EXPECT_TRUE(Save(&w, "person_at_the_floor.png"));
    }
    // Read where the margin crosses the probe (the panel gives the depth in
    // tenths), and chart it with the probe still in.
    const int pd = static_cast<int>(std::lround(*w.lesson()->tip_depth_mm()));
    chart->setFocus();
    Key(chart, Qt::Key_0 + pd, QString::number(pd));
    view->setFocus();
    Key(view, Qt::Key_X, "x");
    probed.push_back(site);
    std::printf("figure: %s probed by keys in %.1f s (charted %d mm)\n",
                site.ToString().c_str(), t.elapsed() / 1000.0, pd);
  }
  ASSERT_TRUE(w.FinishLesson(false));
  ASSERT_TRUE(w.last_result());
  const LessonResult& r = *w.last_result();
  auto check = [&](const LessonResult& x, const char* what) {
    for (const SiteRef& site : probed) {
      const SiteResult* s = nullptr;
      for (const SiteResult& y : x.sites)
        if (y.site == site) s = &y;
      ASSERT_NE(s, nullptr);
      ASSERT_TRUE(s->reached_mm)
          << what << " " << site.ToString() << ": " << s->no_reading;
      EXPECT_LE(std::abs(*s->reached_mm - s->truth_mm), 1.0)
          << what << " " << site.ToString();
      EXPECT_GE(s->held_force_n, x.rubric.force_low_n) << what << " " << site.ToString();
      EXPECT_LE(s->held_force_n, x.rubric.force_high_n) << what << " " << site.ToString();
      EXPECT_EQ(s->insertions, 1) << what << " " << site.ToString();
      ASSERT_TRUE(s->entry && s->entry->pd_mm);
      EXPECT_LE(std::abs(*s->entry->pd_mm - s->truth_mm), 1) << what;
    }
  };
  check(r, "live");
  EXPECT_EQ(r.sites_read, 4) << "only the sites probed";
  // The recording and the entries, replayed headless: the same readings.
  ResultsDb db(Out("person") / "results.db");
  const auto rows = db.Attempts("Key Hand");
  ASSERT_FALSE(rows.empty());
  AttemptOptions o;
  o.student = "Key Hand";
  o.device = "replay:" + rows.back().recording;
  o.answers = rows.back().answers;
  o.mode = LessonSpec::Mode::kPractice;
  const AttemptOutcome again = RunAttempt(start.lesson, o);
  check(again.result, "replayed");
  for (const SiteRef& site : probed) {
    for (std::size_t i = 0; i < r.sites.size(); ++i) {
      if (r.sites[i].site != site) continue;
      EXPECT_EQ(again.result.sites[i].reached_mm, r.sites[i].reached_mm) << "bit for bit";
      EXPECT_EQ(again.result.sites[i].held_force_n, r.sites[i].held_force_n);
    }
  }
}

// At the probe's floor with the press held: in `site`, the gauge within 0.03 N
// of 0.24 N for `ms`.
bool RestAtTheFloor(MainWindow& w, const SiteRef& site, int ms, int limit_ms = 60000) {
  QElapsedTimer still;
  bool holding = false;
  return WaitFor(
      [&] {
        const bool in = w.lesson()->tip_site() == site && w.lesson()->tip_depth_mm() &&
                        std::abs(w.gauge_force() - 0.24) < 0.03;
        if (in && !holding) still.restart();
        holding = in;
        return in && still.elapsed() > ms;
      },
      limit_ms);
}

// An interdental site chosen on the chart (46 DB: next to 47, and it bleeds):
// N places the probe in its sulcus, R twelve times press it to the floor, the
// depth is charted with the probe in; T takes the tip along the sulcus under
// the contact and leans the probe, and the panel says "Under the contact"
// only where the score credits the col; blood appears at the margin and grows
// along it while the probe is still in (the screenshots show it, in the view
// and the loupe); T stands the probe up again.
TEST(LessonWindow, NAndTReachTheColAndTheBloodShowsAtTheMargin) {
  MainWindow w;
  w.resize(1280, 800);
  w.show();
  ASSERT_TRUE(w.StartLesson(ByKeys("Col Tilt", "col_tilt")));
  QWidget* view = w.view_widget();
  const SiteRef site{46, 2};
  ASSERT_TRUE(w.chart()->SelectSite(site));
  WaitFor([] { return false; }, 300);
  EXPECT_NE(w.lesson_text().indexOf("46 DB"), -1)
      << "the panel's next site follows the chart";
  view->setFocus();
  Key(view, Qt::Key_N, "n");
  for (int i = 0; i < 12; ++i) Key(view, Qt::Key_R, "r");
  ASSERT_TRUE(RestAtTheFloor(w, site, 500)) << "N goes to the chosen site, 46 DB";
  EXPECT_LT(*w.lesson()->tip_angle_deg(), 5.0) << "N places the probe along the tooth";
  const double depth = *w.lesson()->tip_depth_mm();
  const int pd = static_cast<int>(std::lround(depth));
  w.chart()->setFocus();
  Key(w.chart(), Qt::Key_0 + pd, QString::number(pd));
  // The probe's keys reach the probe from the chart too.
  Key(w.chart(), Qt::Key_T, "t");
  bool said_under = false;
  const bool under = WaitFor(
      [&] {
        said_under = said_under || w.lesson_text().contains("Under the contact");
        // Until the probe has turned: the tip can reach the col before the
        // tool, following the hand at the haptic rate, has finished its tilt.
        return w.lesson()->tip_under_contact() && w.lesson()->tip_site() == site &&
               said_under && w.lesson()->tip_angle_deg().value_or(0) > 12.0;
      },
      20000);
  EXPECT_TRUE(under) << w.lesson_text().toStdString();
  const double tilted = w.lesson()->tip_angle_deg().value_or(-1);
  EXPECT_GT(tilted, 12.0);
  EXPECT_TRUE(Save(&w, "col_tilt.png"));
  // The blood: a drop within a second or two of the floor, a line by 10 s.
  ASSERT_TRUE(WaitFor([&] { return w.view()->blood_beads() > 0; }, 15000))
      << "46 DB bleeds on probing";
  const int first = w.view()->blood_beads();
  WaitFor([] { return false; }, 6000);
  EXPECT_GT(w.view()->blood_beads(), first) << "it runs along the margin";
  EXPECT_TRUE(w.loupe_shown());
  EXPECT_TRUE(Save(&w, "blood_at_the_margin.png"));
  view->setFocus();
  Key(view, Qt::Key_T, "t");
  EXPECT_TRUE(WaitFor(
      [&] { return w.lesson()->tip_angle_deg() && *w.lesson()->tip_angle_deg() < 5.0; },
      20000))
      << "T again stands it back";
  std::printf(
      "figure: 46 DB read at %.1f mm, tilted into the col %.1f degrees, blood in "
      "%d then %d beads\n",
      depth, tilted, first, w.view()->blood_beads());
  Key(view, Qt::Key_X, "x");
  ASSERT_TRUE(w.FinishLesson(false));
  const LessonResult& r = *w.last_result();
  for (const SiteResult& s : r.sites) {
    if (s.site != site) continue;
    EXPECT_TRUE(s.col_reached) << "the panel said it was under the contact: credited";
    EXPECT_TRUE(s.bled);
    ASSERT_TRUE(s.reached_mm);
    EXPECT_LE(std::abs(*s.reached_mm - s.truth_mm), 1.0);
  }
}

// Assessment gives no depth: the panel says which sulcus the tip is in, not
// how deep (the student reads the markings in the loupe).
TEST(LessonWindow, AnAssessmentShowsNoDepth) {
  MainWindow w;
  w.resize(1280, 800);
  w.show();
  MainWindow::LessonStart start = ByKeys("Assessed", "assessed");
  start.mode = LessonSpec::Mode::kAssessment;
  ASSERT_TRUE(w.StartLesson(start));
  const SiteRef site = *w.lesson()->next_site();
  ASSERT_TRUE(w.PlaceProbeAt(site, 1.0));  // (N places nothing in an assessment)
  QWidget* view = w.view_widget();
  view->setFocus();
  for (int i = 0; i < 12; ++i) Key(view, Qt::Key_R, "r");
  ASSERT_TRUE(RestAtTheFloor(w, site, 300));
  const QString text = w.lesson_text();
  EXPECT_NE(text.indexOf("You are in the sulcus of"), -1) << text.toStdString();
  EXPECT_EQ(text.indexOf("mm below the margin"), -1) << text.toStdString();
  EXPECT_TRUE(w.loupe_shown()) << "the markings are read in the loupe";
  EXPECT_TRUE(Save(&w, "assessment_no_depth.png"));
  Key(view, Qt::Key_X, "x");
  ASSERT_TRUE(w.FinishLesson(false));
}

// The whole mouth by keys, on its palatal and lingual side: twelve sites
// chosen on the chart (the mesial ones where N once put the tip in the
// neighbour's sulcus, and both sides of the midline), each: N, R twelve times,
// the tip at the floor of that site's own sulcus, the camera on that side of
// the tooth, the depth charted. Every one is read; prints the seconds each.
TEST(LessonWindow, TwelvePalatalAndLingualSitesOfTheWholeMouthByKeys) {
  MainWindow w;
  w.resize(1280, 800);
  w.show();
  MainWindow::LessonStart start;
  start.lesson = Lessons() / "periodontal_examination.yaml";
  start.student = "Whole Mouth";
  start.device = "mouse";
  start.mode = LessonSpec::Mode::kPractice;
  start.results_dir = Out("whole_mouth_keys");
  ASSERT_TRUE(w.StartLesson(start));
  ASSERT_TRUE(WaitFor([&] { return w.lesson() != nullptr; }, 600000));
  QWidget* view = w.view_widget();
  const std::vector<SiteRef> sites = {{24, 3}, {14, 3}, {15, 3}, {21, 3},
                                      {11, 3}, {16, 4}, {26, 5}, {32, 3},
                                      {31, 3}, {41, 3}, {37, 3}, {46, 4}};
  std::vector<SiteRef> read;
  for (const SiteRef& site : sites) {
    if (!w.chart()->SelectSite(site)) continue;  // (a tooth the case left out)
    QElapsedTimer t;
    t.start();
    WaitFor([] { return false; }, 200);  // the camera follows the choice
    view->setFocus();
    Key(view, Qt::Key_N, "n");
    for (int i = 0; i < 12; ++i) Key(view, Qt::Key_R, "r");
    const bool rested = RestAtTheFloor(w, site, 500, 30000);
    if (!rested)
      std::printf("figure: %s not reached by keys: the tip is in %s\n",
                  site.ToString().c_str(),
                  w.lesson()->tip_site() ? w.lesson()->tip_site()->ToString().c_str()
                                         : "no site");
    // The camera looks at the side being probed: from inside the arch.
    const auto cam = w.view()->Camera();
    const ProbingSite* p = nullptr;
    for (const ProbingSite& q : w.scene()->effects.sites)
      if (q.fdi == site.fdi && q.site == site.site) p = &q;
    ASSERT_NE(p, nullptr);
    Vector3 out = p->margin_W - p->origin_W;
    out -= p->axis_W * out.dot(p->axis_W);
    EXPECT_GT((cam.eye - p->margin_W).dot(out.normalized()), 0)
        << site.ToString() << ": the camera is on the side being probed";
    if (site == SiteRef{24, 3} || site == SiteRef{31, 3}) {
      EXPECT_TRUE(Save(&w, "whole_mouth_" + site.ToString().substr(0, 2) + ".png"));
    }
    if (rested) {
      const int pd = static_cast<int>(std::lround(*w.lesson()->tip_depth_mm()));
      w.chart()->setFocus();
      Key(w.chart(), Qt::Key_0 + pd, QString::number(pd));
      read.push_back(site);
    }
    Key(view, Qt::Key_X, "x");
    std::printf("figure: %s by keys in %.1f s\n", site.ToString().c_str(),
                t.elapsed() / 1000.0);
  }
  ASSERT_TRUE(w.FinishLesson(false));
  const LessonResult& r = *w.last_result();
  // Every one of the twelve is read in its own sulcus within 1 mm of its
  // truth, 24 ML (a line the arch moved off the cut) and 37 ML (beside the
  // gap where 36 was) included.
  int within = 0, tried = 0;
  for (const SiteRef& site : sites)
    for (const SiteResult& s : r.sites)
      if (s.site == site) {
        ++tried;
        EXPECT_TRUE(s.reached_mm) << site.ToString() << ": " << s.no_reading;
        if (!s.reached_mm) continue;
        const double off = *s.reached_mm - s.truth_mm;
        within += std::abs(off) <= 1.0;
        if (std::abs(off) > 1.0)
          std::printf("figure: %s read %.1f mm off\n", site.ToString().c_str(), off);
      }
  std::printf("figure: %d of %d palatal and lingual sites read within 1 mm by keys\n",
              within, tried);
  EXPECT_EQ(tried, 12);
  EXPECT_EQ(within, tried);
}

// The inspection lesson in the window: the thorough scripted inspector drives
// the device through every step while the odontogram fills; the student adds
// a status code and takes back a finding with the keyboard, submits the
// findings, and the report shows the odontogram against the truth.
TEST(InspectionWindow, TheInspectionLessonFromItsStartToTheReport) {
  MainWindow w;
  w.resize(1600, 1000);
  w.show();
  MainWindow::LessonStart s;
  s.lesson = Lessons() / "oral_inspection.yaml";
  s.student = "Inspection Student";
  s.device = "student:thorough";
  s.free_run = true;
  s.results_dir = Out("results-inspection");
  ASSERT_TRUE(w.StartLesson(s));
  ASSERT_NE(w.lesson(), nullptr);
  ASSERT_NE(w.odontogram(), nullptr);
  EXPECT_TRUE(w.odontogram()->isVisible());
  // F1 helps with the examination: the order, gentle touch, the odontogram's keys,
  // submitting.
  for (const char* about :
       {"tooth by tooth", "0.5 N", "odontogram", "M D B L O", "Submit the findings"})
    EXPECT_TRUE(w.HelpHtml().contains(about)) << about;
  EXPECT_FALSE(w.HelpHtml().contains("<b>Charting</b>"));
  EXPECT_FALSE(w.chart()->isVisible()) << "no periodontal chart in an inspection";
  // (The hand may have finished the first step, the lips, before the window
  // has drawn its first frame: any step will do.)
  EXPECT_TRUE(WaitFor([&] {
    return w.lesson_text().contains(QRegularExpression("Step \\d+ of 11"));
  })) << w.lesson_text().toStdString();
  ASSERT_TRUE(WaitFor([&] { return w.lesson()->current_step() >= 7; }, 600000))
      << w.lesson_text().toStdString();
  QApplication::processEvents();
  EXPECT_TRUE(Save(&w, "inspection_in_progress.png"));
  // The hand has finished (the scripted moves take about 190 s of lesson time).
  ASSERT_TRUE(WaitFor([&] { return w.lesson()->last_tick() > 200000; }, 900000));
  EXPECT_FALSE(w.lesson()->findings().empty()) << "the inspector recorded what it found";
  QApplication::processEvents();
  OdontogramWidget* o = w.odontogram();
  o->setFocus();
  const int first = o->selected();
  Key(o, Qt::Key_0, "0");  // its status: sound
  Key(o, Qt::Key_G, "g");  // inflamed gingiva...
  Key(o, Qt::Key_G, "g");  // ...no: taken back
  const auto& f = w.lesson()->findings();
  ASSERT_GE(f.size(), 3u);
  EXPECT_EQ(f[f.size() - 3].ToString(), "status 0 (sound) at " + std::to_string(first));
  EXPECT_EQ(f.back().ToString(), "withdrawn: inflamed gingiva " + std::to_string(first));
  EXPECT_FALSE(w.lesson()->odontogram().Find(first)->inflamed);
  ASSERT_TRUE(w.SubmitFindings());
  EXPECT_TRUE(w.lesson()->done()) << "submitted: the examination is over";
  QApplication::processEvents();
  EXPECT_TRUE(Save(&w, "inspection_odontogram.png"));
  ASSERT_TRUE(w.FinishLesson());
  ASSERT_TRUE(w.last_result());
  const LessonResult& r = *w.last_result();
  EXPECT_EQ(r.kind, "inspection");
  ASSERT_TRUE(r.inspection.submitted_tick.has_value());
  EXPECT_FALSE(r.inspection.views.empty()) << "the window records its camera";
  int seen = 0;
  for (const InspectionUnit& u : r.inspection.units) seen += u.seen;
  EXPECT_GT(seen, 10) << "the camera followed the teeth the lesson asked for";
  for (const FindingScore& sc : r.inspection.scores) EXPECT_EQ(sc.fp, 0) << sc.kind;
  for (const RubricLine& l : r.lines)
    EXPECT_EQ(l.message.find("status"), std::string::npos)
        << "the status entered is right: " << l.message;
  ASSERT_NE(w.report_dialog(), nullptr);
  const QString text =
      w.report_dialog()->findChild<QTextBrowser*>("report")->toPlainText();
  EXPECT_TRUE(text.contains("Odontogram")) << text.left(400).toStdString();
  EXPECT_TRUE(text.contains("sensitivity"));
  QApplication::processEvents();
  EXPECT_TRUE(Save(w.report_dialog(), "inspection_report.png"));
  ResultsDb db(Out("results-inspection") / "results.db");
  const auto rows = db.Attempts("Inspection Student");
  ASSERT_FALSE(rows.empty());
  EXPECT_NEAR(rows.back().total, r.total, 1e-9);

  // A failed line's moment opens the replay there, as a probing line's does
  // (the thorough inspector leaves a step with a proximal surface unexamined).
  const RubricLine* line = nullptr;
  for (const RubricLine& l : r.lines)
    if (l.status == RubricLine::Status::kFail && l.tick > r.first_tick && !line)
      line = &l;
  ASSERT_NE(line, nullptr) << "no failed line with a moment";
  emit w.report_dialog()->findChild<QTextBrowser*>("report")->anchorClicked(
      QUrl(QString("#t%1").arg(line->tick)));
  ASSERT_TRUE(w.replaying());
  EXPECT_EQ(w.replay_tick(), line->tick);
  const Recording rec = ReadRecording(rows.back().recording);
  ASSERT_NE(w.replay_frame(), nullptr);
  EXPECT_EQ(w.replay_frame()->X_WG.translation(),
            rec.frames[line->tick].X_WG.translation());
  w.report_dialog()->hide();
  QApplication::processEvents();
  EXPECT_TRUE(Save(&w, "inspection_replay_at_line.png"));
  w.CloseReplay();
}

TEST(LessonWindow, ProgressOverAttempts) {
  // Three more attempts by the same student (headless, into the same database).
  for (const char* who : {"student:rough", "student:misreading", "student:careful"}) {
    AttemptOptions o;
    o.student = "Window Student";
    o.device = who;
    o.cache_dir = std::getenv("SULCUS_CACHE_DIR");
    const AttemptOutcome out = RunAttempt(Lessons() / "periodontal_probing.yaml", o);
    ResultsDb db(Out("results") / "results.db");
    db.Store(out.result, "2026-12-01T00:00:00Z", "", "", "");
  }
  MainWindow w;
  w.show();
  QDialog* d = w.ShowProgress("Window Student", Out("results"));
  auto* p = dynamic_cast<ProgressDialog*>(d);
  ASSERT_NE(p, nullptr);
  EXPECT_GE(p->attempts_shown(), 3);
  EXPECT_EQ(p->sites_table()->rowCount(), 24);
  // The misreader's three sites show +2 in its column.
  int plus_two = 0;
  for (int r = 0; r < p->sites_table()->rowCount(); ++r)
    for (int c = 0; c < p->sites_table()->columnCount(); ++c)
      plus_two += p->sites_table()->item(r, c)->text() == "+2";
  EXPECT_GE(plus_two, 3);
  QApplication::processEvents();
  EXPECT_TRUE(Save(d, "progress.png"));
}

// A lab on one shared PostgreSQL store set up with its roles (`results setup`):
// three stations store at once with the station's role, a fourth takes an
// attempt while the server is down and sends it with `sulcus-cli results sync`
// once it is back, and the instructor's view at a fifth station, with the
// instructor's role, shows all four students. (Students signing in at a
// station: ui.sign_in.)
TEST(Lab, TheInstructorsViewAtAnyStationShowsTheWholeLab) {
  test::PostgresServer server;
  // Set up as a school's administrator does: the stations use the station's
  // role, the instructor's view the instructor's.
  const std::string owner = server.FreshDatabase("lab");
  SetUpPostgresStore(owner, "station-pw", "instructor-pw");
  const std::string host = "@127.0.0.1:" + std::to_string(server.port()) + "/lab";
  const std::string url = std::string("postgresql://") + kStationRole + ":station-pw" +
                          host,
                    instructor_url = std::string("postgresql://") + kInstructorRole +
                                     ":instructor-pw" + host;
  // The stations' attempts are scripted students': demonstrations, as the
  // instructor allows them for a trial of the lab.
  OpenResults(ResultsPlace({}, instructor_url))
      ->SetSetting(kDemonstrationsSetting, "allowed");
  const fs::path lab = Out("lab");
  fs::remove_all(lab);
  EXPECT_EQ(test::RunStationsAtOnce(
                3,
                [&](int s) {
                  const std::string who = "student" + std::to_string(s);
                  const ResultsPlace place(lab / ("station" + std::to_string(s)), url);
                  const AttemptFolder f = NewAttemptFolder(place.dir, who);
                  OpenResults(place)->Store(test::Sample(who, 80 + s), f.started, "", "",
                                            "", AttemptUuid(f.dir));
                }),
            0);
  // The fourth station, with the server down: the attempt waits in its folder.
  server.Stop();
  const fs::path fourth = lab / "station3";
  const std::string cli = std::string("SULCUS_RESULTS_DIR=") + fourth.string() +
                          " SULCUS_RESULTS_URL='" + url + "' " + SULCUS_CLI + " ";
  const std::string run = cli + "lesson run " +
                          (Lessons() / "periodontal_probing.yaml").string() +
                          " --device student:spot --student dora --quiet >" +
                          Out("lab_run.log").string() + " 2>&1";
  EXPECT_NE(std::system(run.c_str()), 0) << "not stored: the server is down";
  ASSERT_EQ(UnfinishedAttempts(fourth).size(), 1u);
  server.Start();
  const std::string sync =
      cli + "results sync >" + Out("lab_sync.log").string() + " 2>&1";
  EXPECT_EQ(std::system(sync.c_str()), 0) << sync;
  EXPECT_TRUE(UnfinishedAttempts(fourth).empty());

  // A student at a fifth station is not offered the cohort's names: each types
  // their own and sees their own attempts.
  {
    StartDialog start({Lessons()}, ResultsPlace(lab / "station4", url));
    for (const std::string& name : start.offered_students())
      EXPECT_EQ(name.rfind("student", 0), std::string::npos) << name;
  }
  // The instructor at the fifth station, with the instructor's role.
  setenv("SULCUS_RESULTS_URL", instructor_url.c_str(), 1);
  {
    MainWindow w;
    w.show();
    QDialog* d = w.OpenInstructor("the lab's passphrase", lab / "station4");
    ASSERT_NE(d, nullptr);
    auto* view = dynamic_cast<InstructorDialog*>(d);
    EXPECT_EQ(view->students(), 4);
    EXPECT_EQ(view->attempts_table()->rowCount(), 4);
    EXPECT_NE(w.results_footer().indexOf(
                  "Results: PostgreSQL postgresql://sulcus_instructor:***@"),
              -1)
        << w.results_footer().toStdString();
    QApplication::processEvents();
    EXPECT_TRUE(Save(d, "instructor_lab.png"));
    d->close();
  }
  unsetenv("SULCUS_RESULTS_URL");
}

TEST(Instructor, RefusesAWrongPassphraseAndShowsEveryStudentWithTheRightOne) {
  const fs::path dir = Out("instructor_results");
  fs::remove_all(dir);
  {
    ResultsDb db(dir / "results.db");
    AttemptOptions o;
    o.device = "student:misreading";
    o.cache_dir = std::getenv("SULCUS_CACHE_DIR");
    for (const char* who : {"ada", "grace", "linus"}) {
      o.student = who;
      db.Store(RunAttempt(Lessons() / "periodontal_probing.yaml", o).result,
               "2026-12-01T00:00:00Z", "", "", "");
    }
  }
  MainWindow w;
  w.show();
  ASSERT_NE(w.OpenInstructor("the cohort's passphrase", dir), nullptr)
      << "first use sets it";
  for (QWidget* top : QApplication::topLevelWidgets())
    if (auto* d = dynamic_cast<InstructorDialog*>(top)) d->close();
  EXPECT_EQ(w.OpenInstructor("a student's guess", dir), nullptr);
  QDialog* d = w.OpenInstructor("the cohort's passphrase", dir);
  ASSERT_NE(d, nullptr);
  auto* view = dynamic_cast<InstructorDialog*>(d);
  EXPECT_EQ(view->students(), 3);
  EXPECT_EQ(view->attempts_table()->rowCount(), 3);
  // The misreader's three sites are the cohort's worst.
  ASSERT_GE(view->cohort_table()->rowCount(), 3);
  std::set<QString> worst;
  for (int r = 0; r < 3; ++r) worst.insert(view->cohort_table()->item(r, 0)->text());
  EXPECT_EQ(worst, (std::set<QString>{"47 DB", "46 DB", "45 DB"}));
  // Each misreader, 2 mm over at 3 of 24 sites, is short of the calibration
  // target (within 1 mm at 88 %), which the view says per student and in all.
  const QTableWidget* cal = view->calibration_table();
  ASSERT_EQ(cal->rowCount(), 3);
  for (int r = 0; r < 3; ++r) {
    EXPECT_EQ(cal->item(r, 1)->text(), "24");
    EXPECT_EQ(cal->item(r, 2)->text(), "88 %");
    EXPECT_EQ(cal->item(r, 5)->text(), "+0.38");
    EXPECT_EQ(cal->item(r, 7)->text(), "not met");
  }
  EXPECT_EQ(view->calibrated(), 0);
  QApplication::processEvents();
  EXPECT_TRUE(Save(d, "instructor.png"));
  if (auto* tabs = d->findChild<QTabWidget*>()) {
    tabs->setCurrentIndex(2);
    QApplication::processEvents();
    EXPECT_TRUE(Save(d, "instructor_calibration.png"));
    tabs->setCurrentIndex(0);
  }
  EXPECT_EQ(view->DeleteStudent("grace"), 1);
  EXPECT_EQ(view->students(), 2);

  // A case drawn on the practice lesson's teeth, previewed, saved as a scene.
  const fs::path lesson = Lessons() / "periodontal_probing.yaml";
  ASSERT_TRUE(view->DrawCase(lesson, Stage::kII, Extent::kGeneralized, 11));
  EXPECT_TRUE(view->case_summary().contains("periodontitis stage II, generalized"))
      << view->case_summary().toStdString();
  const LessonSpec spec = LoadLessonSpec(lesson);
  CaseSpec c;
  c.generated = true;
  c.stage = Stage::kII;
  c.extent = Extent::kGeneralized;
  const PerioChart truth =
      TrueChart(ApplyCase(LoadSceneSpec(spec.scene), spec.teeth, c, 11), spec.teeth);
  for (const ToothChart& t : truth.teeth)
    for (int site = 0; site < kSitesPerTooth; ++site) {
      EXPECT_EQ(view->case_chart()->depth({t.fdi, site}), t.sites[site].pd_mm)
          << t.fdi << " " << site;
      EXPECT_EQ(view->case_chart()->bleeding({t.fdi, site}), t.sites[site].bleeding)
          << t.fdi << " " << site;
    }
  if (auto* tabs = d->findChild<QTabWidget*>()) tabs->setCurrentIndex(tabs->count() - 1);
  QApplication::processEvents();
  EXPECT_TRUE(Save(d, "instructor_case.png"));
  const fs::path saved = Out("case_stage_ii.yaml");
  fs::remove(saved);
  ASSERT_TRUE(view->SaveCase(saved)) << view->case_summary().toStdString();
  EXPECT_EQ(Classify2017(TrueChart(LoadSceneSpec(saved), spec.teeth)).Summary(),
            "periodontitis stage II, generalized");
  // A new draw replaces the old one.
  ASSERT_TRUE(view->DrawCase(lesson, Stage::kIII, Extent::kLocalized, 5));
  EXPECT_TRUE(view->case_summary().contains("stage III, localized"))
      << view->case_summary().toStdString();
  EXPECT_FALSE(view->case_summary().contains("stage II,"));
  // Stage IV with a grade: the patient drawn with it, the preview says so, the
  // saved scene keeps the patient; stage III grade A is refused with the reason.
  ASSERT_TRUE(view->DrawCase(lesson, Stage::kIV, Extent::kGeneralized, 3, Grade::kC))
      << view->case_summary().toStdString();
  EXPECT_TRUE(
      view->case_summary().contains("periodontitis stage IV, generalized, grade C"))
      << view->case_summary().toStdString();
  QApplication::processEvents();
  EXPECT_TRUE(Save(d, "instructor_case_grade.png"));
  const fs::path graded = Out("case_stage_iv_c.yaml");
  fs::remove(graded);
  ASSERT_TRUE(view->SaveCase(graded));
  EXPECT_EQ(Classify2017(TrueChart(LoadSceneSpec(graded), spec.teeth)).Summary(),
            "periodontitis stage IV, generalized, grade C");
  EXPECT_FALSE(view->DrawCase(lesson, Stage::kIII, Extent::kLocalized, 3, Grade::kA));
  EXPECT_TRUE(view->case_summary().contains("No case drawn"))
      << view->case_summary().toStdString();
}

TEST(LessonWindow, AssessmentShowsNoTruthAndLocksTheAids) {
  MainWindow w;
  w.resize(1366, 768);
  w.show();
  MainWindow::LessonStart s = CarefulStudent();
  s.mode = LessonSpec::Mode::kAssessment;
  ASSERT_TRUE(w.StartLesson(s));
  EXPECT_TRUE(w.aids_locked());
  w.SetGingivaTranslucent(true);
  auto* translucent = w.findChild<QCheckBox*>();
  ASSERT_NE(translucent, nullptr);
  EXPECT_FALSE(translucent->isEnabled()) << "the aids cannot be turned on";
  ASSERT_TRUE(WaitFor([&] { return w.lesson()->current_step() >= 2; }));
  for (const std::string& f : w.lesson()->feedback())
    EXPECT_EQ(f.find("true depth"), std::string::npos) << f;
  EXPECT_FALSE(w.chart()->shows_truth()) << "assessment: no true-PD row";
  EXPECT_TRUE(Save(&w, "assessment_in_progress.png"));
  ChartEverything(w);
  ASSERT_TRUE(w.FinishLesson());
  const LessonResult& r = *w.last_result();
  EXPECT_EQ(r.mode, "assessment");
  EXPECT_EQ(r.sites_charted, 24);
  EXPECT_FALSE(r.declared) << "no diagnosis was declared";
  bool undeclared = false;
  for (const RubricLine& l : r.lines)
    undeclared |= l.category == "diagnosis" && l.message == "no diagnosis declared";
  EXPECT_TRUE(undeclared);
  EXPECT_FALSE(w.aids_locked()) << "the workbench again after the lesson";
}

TEST(LessonWindow, AClosedWindowKeepsTheAttemptAsIncompleteAndAStoppedOneIsRecovered) {
  const fs::path results = Out("results_closed");
  fs::remove_all(results);
  MainWindow::LessonStart s = CarefulStudent();
  s.student = "Closing Student";
  s.results_dir = results;
  fs::path folder;
  {
    MainWindow w;
    w.show();
    ASSERT_TRUE(w.StartLesson(s));
    ASSERT_TRUE(WaitFor([&] { return w.lesson()->Finish().sites_read >= 4; }));
    Key(w.chart(), Qt::Key_3, "3");
    Key(w.chart(), Qt::Key_2, "2");
    ASSERT_EQ(w.lesson()->entries().size(), 2u);
    EXPECT_TRUE(w.close());
  }
  ResultsDb db(results / "results.db");
  auto rows = db.Attempts("Closing Student");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_FALSE(rows[0].complete);
  EXPECT_EQ(rows[0].ended, "the window was closed before the last step");
  EXPECT_EQ(rows[0].sites_charted, 2);
  folder = fs::path(rows[0].recording).parent_path();
  EXPECT_TRUE(fs::exists(folder / "answers.yaml"));
  EXPECT_EQ(LoadAnswers(folder / "answers.yaml").entries.size(), 2u);
  EXPECT_TRUE(UnfinishedAttempts(results).empty())
      << "a kept attempt is not recovered again";

  // The same attempt as if Sulcus had stopped before keeping it: no report, no row.
  fs::remove(folder / "report.json");
  fs::remove(folder / "report.html");
  fs::remove(results / "results.db");
  fs::remove(results / "results.db-wal");
  fs::remove(results / "results.db-shm");
  MainWindow w;
  w.show();
  EXPECT_EQ(w.RecoverUnfinishedAttempts(results), 1);
  QMessageBox* box = w.findChild<QMessageBox*>("recovered");
  ASSERT_NE(box, nullptr);
  EXPECT_TRUE(box->text().contains("Closing Student")) << box->text().toStdString();
  EXPECT_TRUE(box->text().contains("(incomplete)")) << box->text().toStdString();
  QApplication::processEvents();
  EXPECT_TRUE(Save(box, "recovered_attempts.png"));
  box->close();
  ResultsDb again(results / "results.db");
  rows = again.Attempts("Closing Student");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_FALSE(rows[0].complete);
  EXPECT_NE(rows[0].ended.find("rebuilt from its recording"), std::string::npos)
      << rows[0].ended;
  EXPECT_EQ(rows[0].sites_charted, 2);
  EXPECT_EQ(w.RecoverUnfinishedAttempts(results), 0);
}

// A device the test unplugs and plugs back in, around the scripted student's hand.
class UnpluggableDevice final : public Device {
 public:
  UnpluggableDevice(std::unique_ptr<Device> hand, std::atomic<bool>* unplugged)
      : hand_(std::move(hand)), unplugged_(unplugged) {}
  const DeviceCaps& caps() const override { return hand_->caps(); }
  void Start() override { hand_->Start(); }
  void Stop() noexcept override { hand_->Stop(); }
  // The hand waits while the device is unplugged: its script resumes where it was.
  bool Read(double t_s, DeviceSample* out) noexcept override {
    const bool gone = unplugged_->load();
    if (gone && !gone_) since_s_ = t_s;
    if (!gone && gone_) paused_s_ += t_s - since_s_;
    gone_ = gone;
    return !gone_ && hand_->Read(t_s - paused_s_, out);
  }
  void Write(const Vector3& f, const Vector3& t) noexcept override {
    if (gone_ && f.norm() > 0) pushed_while_gone_ = true;
    hand_->Write(f, t);
  }
  bool finished() const noexcept override { return hand_->finished(); }
  bool lost() const noexcept override { return gone_; }
  static inline std::atomic<bool> pushed_while_gone_{false};

 private:
  std::unique_ptr<Device> hand_;
  std::atomic<bool>* unplugged_;
  bool gone_ = false;
  double since_s_ = 0, paused_s_ = 0;
};

TEST(LessonWindow, ADeviceUnpluggedMidLessonShowsTheBannerKeepsTheAttemptAndResumes) {
  MainWindow w;
  w.resize(1366, 768);
  w.show();
  std::atomic<bool> unplugged{false};
  w.SetDeviceWrapper([&](std::unique_ptr<Device> d) -> std::unique_ptr<Device> {
    return std::make_unique<UnpluggableDevice>(std::move(d), &unplugged);
  });
  ASSERT_TRUE(w.StartLesson(CarefulStudent()));
  ASSERT_TRUE(WaitFor([&] { return w.lesson()->Finish().sites_read >= 3; }));
  EXPECT_TRUE(w.banner_text().isEmpty());
  unplugged = true;
  ASSERT_TRUE(WaitFor([&] { return w.banner_text().contains("stopped answering"); }));
  EXPECT_TRUE(w.banner_text().contains("Nothing is lost"))
      << w.banner_text().toStdString();
  EXPECT_TRUE(Save(&w, "device_unplugged.png"));
  unplugged = false;
  ASSERT_TRUE(WaitFor([&] { return w.banner_text().isEmpty(); }));
  EXPECT_FALSE(UnpluggableDevice::pushed_while_gone_.load())
      << "no force went out while it was unplugged";
  const LessonResult sofar = w.lesson()->Finish();
  ASSERT_EQ(sofar.interruptions.size(), 1u);
  EXPECT_GT(sofar.interruptions[0].back_tick, sofar.interruptions[0].lost_tick);
  // The lesson goes on after the device is back: more sites are read.
  const int read_before = sofar.sites_read;
  EXPECT_TRUE(WaitFor([&] { return w.lesson()->Finish().sites_read > read_before; }));
  ASSERT_TRUE(w.FinishLesson(false));
}

}  // namespace
}  // namespace sulcus::ui

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("SulcusTests");
  QApplication::setApplicationName("lesson_window_test");
  ::testing::InitGoogleTest(&argc, argv);
  std::filesystem::remove_all(
      sulcus::test::OutputPath("ui", "results"));  // every run starts with no attempts
  return RUN_ALL_TESTS();
}
