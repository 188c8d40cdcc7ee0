// The window: a lesson from the start page to its report (the lesson panel, the
// chart and odontogram entries, the diagnosis, help, recovery).

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDesktopServices>
#include <QDialogButtonBox>
#include <QDockWidget>
#include <QFormLayout>
#include <QLabel>
#include <QListWidget>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>
#include <QRadioButton>
#include <QSettings>
#include <QSpinBox>
#include <QStatusBar>
#include <QTextBrowser>
#include <QUrl>
#include <QVBoxLayout>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <ctime>
#include <fstream>
#include <set>
#include <sstream>

#include "core/lesson/answers.h"
#include "core/lesson/attempt.h"
#include "core/lesson/report.h"
#include "core/lesson/results.h"
#include "core/lesson/sign_in.h"
#include "core/spheretree/cache.h"
#include "ui/chart_widget.h"
#include "ui/force_gauge.h"
#include "ui/main_window.h"
#include "ui/main_window_parts.h"
#include "ui/odontogram_widget.h"
#include "ui/progress_dialog.h"
#include "ui/scene_view.h"
#include "ui/start_dialog.h"

namespace sulcus::ui {

void MainWindow::BuildLessonDock() {
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);
  step_label_ = new QLabel;
  step_label_->setWordWrap(true);
  step_label_->setTextFormat(Qt::RichText);
  step_label_->setStyleSheet("font-size: 14px;");
  banner_ = new QLabel;
  banner_->setWordWrap(true);
  banner_->setStyleSheet(
      "background: #fbe3c8; border-left: 4px solid #c86400; padding: 6px; font-size: "
      "13px;");
  banner_->hide();
  lesson_gauge_ = new ForceGauge;  // the instrument tab's figure, beside the chart
  layout->addWidget(banner_);
  layout->addWidget(step_label_);
  next_label_ = new QLabel;
  tip_label_ = new QLabel;
  tilt_label_ = new QLabel;
  tilt_label_->setToolTip(
      "The probe's tilt from the tooth's long axis: keep it under 5 degrees at the "
      "mid-sites");
  for (QLabel* l : {next_label_, tip_label_, tilt_label_}) {
    l->setTextFormat(Qt::RichText);
    l->setWordWrap(true);  // the panel is narrow: the 3D view comes first
    layout->addWidget(l);
  }
  chart_ = new ChartWidget;
  chart_->on_entry = [this](ChartEntry e) {
    if (!lesson_) return;
    e.tick = lesson_->last_tick() + 1;  // the moment it was entered
    lesson_->Enter(e);
    SaveEntriesSoFar();
  };
  layout->addWidget(chart_);
  odontogram_ = new OdontogramWidget;
  odontogram_->on_finding = [this](Finding f) {
    if (!lesson_) return;
    f.tick = lesson_->last_tick() + 1;  // the moment it was recorded
    lesson_->Record(f);
    SaveEntriesSoFar();
    feedback_->insertItem(0, Q("recorded: " + f.ToString()));
  };
  odontogram_->hide();
  layout->addWidget(odontogram_);
  feedback_ = new QListWidget;
  feedback_->setMaximumHeight(110);
  feedback_->setToolTip(
      "What the lesson tells you as you go (in practice mode the truth after each site, "
      "or at each "
      "surface and region you examine)");
  layout->addWidget(feedback_);
  auto* buttons = new QVBoxLayout;  // stacked: the panel is narrow
  diagnose_button_ = new QPushButton("Declare the diagnosis...");
  finish_button_ = new QPushButton("Finish and see the report");
  diagnose_button_->setToolTip(
      "Stage and extent of periodontitis from your chart (2017 classification)");
  finish_button_->setToolTip(
      "Ends the lesson (whatever is left undone counts as not done) and shows your "
      "report");
  connect(diagnose_button_, &QPushButton::clicked, this, [this] {
    if (lesson_spec_ && lesson_spec_->inspection())
      SubmitFindings();
    else
      AskDiagnosis();
  });
  connect(finish_button_, &QPushButton::clicked, this, [this] { FinishLesson(); });
  buttons->addWidget(diagnose_button_);
  buttons->addWidget(finish_button_);
  layout->addLayout(buttons);
  lesson_dock_ = new QDockWidget("Lesson", this);
  lesson_dock_->setObjectName("lesson");
  // The gauge above the scrolling panel: in view at every step, however far
  // the panel scrolls to the chart's lower arch.
  auto* dock_body = new QWidget;
  auto* pinned = new QVBoxLayout(dock_body);
  pinned->setContentsMargins(0, 0, 0, 0);
  pinned->addWidget(lesson_gauge_);
  pinned->addWidget(Scrolling(panel), 1);
  lesson_dock_->setWidget(dock_body);
  // Beside the instrument panel as a tab (the lesson's own gauge is on it), so
  // the 3D view keeps the window's width.
  addDockWidget(Qt::RightDockWidgetArea, lesson_dock_);
  if (instrument_dock_) tabifyDockWidget(instrument_dock_, lesson_dock_);
  lesson_dock_->hide();
}

void MainWindow::SetAidsLocked(bool locked) {
  aids_locked_ = locked;
  // Assessment: no aids, and they cannot be turned on.
  if (locked) {
    translucent_->setChecked(false);
    sphere_level_->setValue(-1);
  }
  translucent_->setEnabled(!locked);
  sphere_level_->setEnabled(!locked);
  events_->setVisible(!locked);
  device_box_->setEnabled(!lesson_spec_);
}

bool MainWindow::StartLesson(const LessonStart& start) {
  LessonSpec spec;
  try {
    spec = LoadLessonSpec(start.lesson);
  } catch (const LoadError& e) {
    QString details;
    for (const ErrorAt& err : e.errors()) details += Q(err.ToString()) + "\n";
    ShowErrors("Lesson has errors",
               QString("The lesson file %1 does not load: %2 error(s), listed below.")
                   .arg(Q(start.lesson.string()))
                   .arg(e.errors().size()),
               details);
    return false;
  }
  if (start.mode) spec.mode = *start.mode;
  const std::uint64_t seed = LessonSeed(spec, start.lesson, start.seed);
  SceneSpec scene;
  try {
    scene = LessonScene(spec, seed);
    FitLessonToCase(&spec, scene);
  } catch (const std::exception& e) {
    ShowErrors("Lesson", "The lesson's scene cannot be made.", Q(e.what()));
    return false;
  }
  // A scripted or replayed attempt under a student's name: a lab's shared store
  // takes it only when the instructor allows demonstrations (asked first).
  if (const std::string why = DemonstrationRefusal(ResultsPlaceFor(start.results_dir),
                                                   DeviceKindOf(start.device));
      !why.empty()) {
    ShowErrors("Lesson", "This attempt would not be stored.", Q(why));
    return false;
  }
  if (lesson_) LeaveLesson("the student started another lesson");
  // The attempt's folder: its recording, entries and report.
  const std::filesystem::path results =
      start.results_dir.empty() ? DefaultResultsDir() : start.results_dir;
  AttemptFolder folder;
  try {
    folder = NewAttemptFolder(results, start.student);
    if (!start.sign_in.empty()) KeepSignIn(folder.dir, start.sign_in);
  } catch (const std::exception& e) {
    ShowErrors("Lesson", "The attempt's folder cannot be made.", Q(e.what()));
    return false;
  }
  StopSession();
  lesson_spec_ = spec;
  lesson_start_ = start;
  lesson_start_.results_dir = results;
  UpdateResultsFooter();
  lesson_seed_ = seed;
  attempt_ = folder;
  lesson_.reset();
  device_name_ = start.device;
  recording_file_ = folder.recording();
  QSettings().setValue("student/last", Q(start.student));
  SetAidsLocked(!spec.practice());
  if (!OpenSpec(scene, spec.scene, true, LessonKey(start.lesson, seed)) || !lesson_) {
    lesson_spec_.reset();
    lesson_.reset();
    recording_file_.clear();
    SetAidsLocked(false);
    return false;
  }
  try {
    WriteAttemptMarker(attempt_, {spec.file, start.student, ToString(spec.mode), seed,
                                  attempt_.started});
  } catch (const std::exception& e) {
    feedback_->insertItem(
        0,
        QString("This attempt cannot be rebuilt if Sulcus stops: %1").arg(Q(e.what())));
  }
  device_was_lost_ = false;
  banner_->hide();
  setWindowTitle(QString("Sulcus - %1 - %2 (%3)")
                     .arg(Q(spec.name), Q(start.student), Q(ToString(spec.mode))));
  if (spec.inspection())
    odontogram_->setFocus();
  else
    chart_->setFocus();
  return true;
}

std::string MainWindow::LessonKey(const std::filesystem::path& lesson,
                                  std::uint64_t seed) {
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(lesson, ec);
  return "lesson:" + (ec ? lesson : canonical).string() + "#" + std::to_string(seed);
}

std::uint64_t MainWindow::LessonSeed(const LessonSpec& spec,
                                     const std::filesystem::path& lesson,
                                     std::optional<std::uint64_t> chosen) {
  if (chosen) return *chosen;
  if (!spec.case_spec.generated || !spec.case_spec.random_seed)
    return spec.case_spec.seed;
  // A new case: drawn once for this lesson, so that the case prepared while the
  // start page was open is the one the lesson starts with.
  const std::string key = LessonKey(lesson, 0);
  if (drawn_seed_ && drawn_seed_->first == key) return drawn_seed_->second;
  const std::uint64_t seed = static_cast<std::uint64_t>(std::time(nullptr)) & 0xffffff;
  drawn_seed_ = {key, seed};
  return seed;
}

void MainWindow::PrepareLesson(const std::filesystem::path& lesson,
                               std::optional<std::uint64_t> seed) {
  try {
    const LessonSpec spec = LoadLessonSpec(lesson);
    const std::uint64_t s = LessonSeed(spec, lesson, seed);
    preparer_.Prepare(LessonScene(spec, s), LessonKey(lesson, s));
  } catch (const std::exception&) {
    // A broken lesson is shown as broken on the start page; nothing to prepare.
  }
}

bool MainWindow::ShowStartPage() {
  // A lesson in progress is left only when the student says so, and kept as
  // the student left it (never taken for an attempt cut short by a crash).
  if (lesson_) {
    const auto answer = QMessageBox::question(
        this, "Leave the lesson?",
        "A lesson is in progress. Leave it for another? Your attempt is kept as you "
        "leave it: scored as far as it went and stored.",
        QMessageBox::Yes | QMessageBox::No, QMessageBox::No);
    if (answer != QMessageBox::Yes) return false;
    LeaveLesson("the student left it for another lesson");
  }
  RecoverUnfinishedAttempts();
  StartDialog dialog(lesson_dirs_, ResultsPlaceFor(DefaultResultsDir()), this);
  dialog.SetPreparation(
      [this](const std::filesystem::path& lesson, std::optional<std::uint64_t> seed) {
        PrepareLesson(lesson, seed);
      },
      [this] { return preparer_.Status(); });
  if (dialog.exec() != QDialog::Accepted || dialog.lesson().empty()) return false;
  LessonStart s;
  s.lesson = dialog.lesson();
  s.student = dialog.student();
  s.sign_in = dialog.sign_in_token();
  s.mode = dialog.mode();
  s.seed = dialog.seed();
  s.device = "mouse";
  const bool started = StartLesson(s);
  drawn_seed_.reset();  // the next new case is drawn anew
  return started;
}

QString MainWindow::lesson_text() const {
  if (!lesson_) return {};
  return step_label_->text() + "\n" + next_label_->text() + "\n" + tip_label_->text() +
         "\n" + tilt_label_->text();
}

QString MainWindow::banner_text() const {
  return banner_->isVisible() ? banner_->text() : QString();
}

void MainWindow::UpdateLessonPanel() {
  LessonRun& l = *lesson_;
  if (l.device_lost() != device_was_lost_) {
    device_was_lost_ = l.device_lost();
    if (device_was_lost_) {
      banner_->setText(
          "<b>The device stopped answering.</b> Nothing is lost: your attempt and "
          "entries are kept. "
          "Reconnect it and go on (the force ramps in gently), or finish to keep the "
          "attempt as "
          "incomplete.");
      banner_->show();
      l.SetEnding(
          "the device stopped answering and the lesson was finished before the last "
          "step");
    } else {
      banner_->hide();
      l.SetEnding("");
      feedback_->insertItem(0,
                            "The device is back: the force ramps in over half a second.");
    }
  }
  const auto& steps = lesson_spec_->steps;
  if (l.done()) {
    step_label_->setText(
        l.current_step() >= static_cast<int>(steps.size())
            ? "<b>All steps done.</b> Finish the lesson to see your report."
            : "<b>Time is up.</b> Finish the lesson to see your report.");
  } else {
    const StepSpec& st = steps[static_cast<std::size_t>(l.current_step())];
    step_label_->setText(QString("<b>Step %1 of %2</b>: %3")
                             .arg(l.current_step() + 1)
                             .arg(steps.size())
                             .arg(Q(st.instruction).toHtmlEscaped()));
  }
  // A wrapped label in a scroll area keeps the height of its first layout:
  // the whole instruction, however narrow the panel.
  step_label_->setMinimumHeight(
      step_label_->heightForWidth(std::max(200, step_label_->width())));
  if (lesson_spec_->inspection()) {
    // What is left of this step, where the tip is, what has been examined.
    const InspectionTracker& in = *l.inspection();
    std::vector<std::string> left = l.pending(), examined;
    QString todo;
    for (std::size_t i = 0; i < left.size() && i < 6; ++i) {
      const bool tooth =
          !left[i].empty() && std::isdigit(static_cast<unsigned char>(left[i][0]));
      todo += (i ? ", " : "") + Q(tooth ? left[i] : RegionLabel(left[i]));
    }
    if (left.size() > 6) todo += QString(" and %1 more").arg(left.size() - 6);
    next_label_->setText(left.empty()
                             ? QString()
                             : "Still to examine: <b>" + todo.toHtmlEscaped() + "</b>");
    int touching = 0;
    QString on = "The tip is not resting on anything the lesson examines";
    if (const int u = in.tip_unit(); u >= 0) {
      const InspectionUnit& unit = in.units()[static_cast<std::size_t>(u)];
      touching = unit.fdi;
      on = "The tip is on <b>" +
           Q(unit.region.empty() ? unit.Name() : RegionLabel(unit.region))
               .toHtmlEscaped() +
           "</b>";
    }
    tip_label_->setText(on);
    for (const InspectionUnit& u : in.units())
      if (u.touched) examined.push_back(u.Name());
    // What the view shows: the camera, each time it has moved (at most ten times a
    // second).
    const SceneView::CameraPose cam = view_->Camera();
    if (views_sent_ == 0 || (cam.eye - last_view_.eye).norm() > 0.5 ||
        (cam.focal - last_view_.focal).norm() > 0.5 ||
        std::abs(cam.view_angle_deg - last_view_.view_angle_deg) > 0.5) {
      if (views_sent_ == 0 || l.last_tick() >= last_view_.tick + 100) {
        ViewSample v;
        v.tick = l.last_tick();
        v.eye = cam.eye;
        v.focal = cam.focal;
        v.up = cam.up;
        v.view_angle_deg = cam.view_angle_deg;
        l.View(v);
        last_view_ = v;
        if (++views_sent_ % 20 == 0)
          SaveEntriesSoFar();  // the views are kept as the attempt goes too
      }
    }
    for (const InspectionUnit& u : in.units())
      if (u.seen && !u.touched) examined.push_back("seen:" + u.Name());
    odontogram_->SetExamined(examined);
    if (l.findings().size() != shown_findings_) {
      shown_findings_ = l.findings().size();
      odontogram_->Show(l.odontogram());
    }
    odontogram_->SetTouching(touching);
    // The camera to the first tooth the step still asks for.
    for (const std::string& u : left)
      if (!u.empty() && std::isdigit(static_cast<unsigned char>(u[0]))) {
        const int fdi = std::stoi(u);
        if (fdi != looked_at_) {
          looked_at_ = fdi;
          LookAtTooth(fdi);
        }
        break;
      }
  }
  const std::optional<SiteRef> next =
      lesson_spec_->inspection() ? std::nullopt : ProbeTarget();
  next_label_->setText(next ? QString("Next: <b>%1</b>").arg(Q(next->ToString()))
                            : QString());
  // The camera to the tooth and the side the student probes next (the side
  // being probed: buccal, or lingual and palatal from inside the arch).
  if (const std::optional<SiteRef> target = ProbeTarget();
      target && !lesson_spec_->inspection()) {
    const bool lingual = target->site >= 3;
    if (target->fdi != looked_at_ || lingual != looked_lingual_) {
      looked_at_ = target->fdi;
      looked_lingual_ = lingual;
      LookAtTooth(target->fdi, lingual);
    }
  }
  const std::optional<SiteRef> tip = l.tip_site();
  if (!lesson_spec_->inspection()) {
    QString where =
        tip ? QString("You are in the sulcus of <b>%1</b>").arg(Q(tip->ToString()))
            : QString("The tip is not in a sulcus");
    // Practice only: an assessment tests reading the probe's markings.
    if (tip && l.tip_depth_mm() && !aids_locked_)
      where += QString(", %1 mm below the margin").arg(*l.tip_depth_mm(), 0, 'f', 1);
    tip_label_->setText(where + HeldBackText());
  }
  chart_->SetProbing(tip);
  UpdateLoupe(tip);
  ShowBlood(l.blood_shown());
  {
    std::set<std::pair<int, int>> probed;
    for (const SiteResult& x : l.sites())
      if (x.reached_mm) probed.insert({x.site.fdi, x.site.site});
    chart_->SetProbed(probed);
  }
  if (const auto angle = l.tip_angle_deg()) {
    // The panel says what the score will: at an interdental site with a
    // contact the col under it (the tip locator's one rule), elsewhere the
    // angle against the rubric's limits.
    const SiteResult* at = nullptr;
    for (const SiteResult& x : l.sites())
      if (tip && x.site == *tip) at = &x;
    const int bars = std::min(20, static_cast<int>(*angle));
    QString text = QString("Tilt from the long axis: <b>%1&deg;</b> %2")
                       .arg(*angle, 0, 'f', 0)
                       .arg(QString(bars, QChar(0x2588)));
    if (at && at->interproximal_contact) {
      const double to = l.tip_location().to_contact_mm;
      if (l.tip_under_contact())
        text +=
            "<br><span style='color:#2a8a3a'><b>Under the contact: the col is "
            "reached</b></span>";
      else if (l.tip_location().depth_mm < TipLocator::kColDepthMm)
        text += QString(
                    "<br><span style='color:#c88a00'>Go deeper (%1 mm at least) to "
                    "reach the col under the contact</span>")
                    .arg(TipLocator::kColDepthMm, 0, 'f', 1);
      else
        text += QString(
                    "<br><span style='color:#c88a00'>%1 mm from the contact: the col "
                    "is within %2 mm (T tilts the tip under it)</span>")
                    .arg(to, 0, 'f', 1)
                    .arg(lesson_spec_->rubric.col_reach_mm, 0, 'f', 1);
    } else {
      const RubricLine::Status st = AngleStatus(*angle, lesson_spec_->rubric);
      const QString colour = st == RubricLine::Status::kPass      ? "#2a8a3a"
                             : st == RubricLine::Status::kPartial ? "#c88a00"
                                                                  : "#c02020";
      text = QString(
                 "Tilt from the long axis: <span style='color:%1'><b>%2&deg;</b> "
                 "%3</span>")
                 .arg(colour)
                 .arg(*angle, 0, 'f', 0)
                 .arg(QString(bars, QChar(0x2588)));
    }
    tilt_label_->setText(text);
  } else {
    tilt_label_->setText("Tilt from the long axis: -");
  }
  for (; feedback_shown_ < l.feedback().size(); ++feedback_shown_) {
    feedback_->insertItem(0, Q(l.feedback()[feedback_shown_]));
    while (feedback_->count() > 50) delete feedback_->takeItem(feedback_->count() - 1);
  }
}

bool MainWindow::DeclareDiagnosis(const DeclaredDiagnosis& d) {
  if (!lesson_) return false;
  DeclaredDiagnosis stamped = d;
  stamped.tick = lesson_->last_tick() + 1;
  lesson_->Declare(stamped);
  SaveEntriesSoFar();
  feedback_->insertItem(0, Q("declared: " + d.Summary()));
  return true;
}

bool MainWindow::SubmitFindings() {
  if (!lesson_ || !lesson_spec_ || !lesson_spec_->inspection()) return false;
  lesson_->Submit(lesson_->last_tick() + 1);
  SaveEntriesSoFar();
  feedback_->insertItem(
      0, "Findings submitted. You may still change them until you finish the lesson.");
  return true;
}

void MainWindow::SaveEntriesSoFar() {
  if (!lesson_) return;
  // Rewritten whole (atomically) after every entry: a program that stops loses
  // nothing the student entered; RecoverUnfinishedAttempts rebuilds from it.
  Answers a;
  a.entries = lesson_->entries();
  a.diagnosis = lesson_->declared();
  a.findings = lesson_->findings();
  a.submitted = lesson_->submitted();
  a.views = lesson_->views();
  try {
    SaveAnswers(a, attempt_.answers());
  } catch (const std::exception& e) {
    feedback_->insertItem(
        0, QString("Your entries cannot be saved as you go: %1").arg(Q(e.what())));
  }
}

// The results store this window keeps attempts in, and what waits for it.
QString MainWindow::results_footer() const {
  return results_footer_ ? results_footer_->text() : QString();
}

void MainWindow::UpdateResultsFooter() {
  if (!results_footer_) {
    results_footer_ = new QLabel;
    results_footer_->setObjectName("results-footer");
    statusBar()->addPermanentWidget(results_footer_);
  }
  const ResultsPlace place =
      ResultsPlaceFor(lesson_start_.results_dir.empty() ? DefaultResultsDir()
                                                        : lesson_start_.results_dir);
  const std::size_t waiting = UnfinishedAttempts(place.dir).size();
  QString text = "Results: " + Q(place.Describe());
  if (waiting > 0)
    text += QString(" - %1 attempt%2 waiting to be stored")
                .arg(waiting)
                .arg(waiting == 1 ? "" : "s");
  results_footer_->setText(text);
  results_footer_->setToolTip(
      "Where attempts are stored. An attempt the store could not take is kept on this "
      "station and stored at the next start or by `sulcus-cli results sync`.");
}

void MainWindow::LeaveLesson(const std::string& why) {
  if (!lesson_) return;
  if (!lesson_->done()) lesson_->SetEnding(why);
  FinishLesson(/*show_report=*/false);
}

int MainWindow::RecoverUnfinishedAttempts(const std::filesystem::path& results_dir) {
  const std::filesystem::path results =
      results_dir.empty() ? DefaultResultsDir() : results_dir;
  std::vector<std::filesystem::path> dirs = UnfinishedAttempts(results);
  // Never the attempt being taken now: it is not unfinished, it is going on.
  if (lesson_)
    dirs.erase(std::remove(dirs.begin(), dirs.end(), attempt_.dir), dirs.end());
  if (dirs.empty()) return 0;
  const ResultsPlace place = ResultsPlaceFor(results);
  try {
    OpenResults(place);  // a store that cannot be reached: the attempts wait
  } catch (const ResultsError&) {
    UpdateResultsFooter();
    return 0;
  }
  QProgressDialog progress(
      QString(
          "Keeping %1 attempt(s) that Sulcus did not finish keeping when it stopped...")
          .arg(dirs.size()),
      QString(), 0, static_cast<int>(dirs.size()), this);
  progress.setWindowTitle("Recovering attempts");
  progress.setMinimumDuration(0);
  progress.setValue(0);
  QString kept, failed;
  int n = 0;
  for (const std::filesystem::path& d : dirs) {
    QApplication::processEvents();
    try {
      const RecoveredAttempt a = RecoverAttempt(d, place, DefaultCacheDir());
      kept += QString("%1: %2, %3 / 100%4\n")
                  .arg(Q(a.result.student), Q(a.result.lesson_name))
                  .arg(a.result.total, 0, 'f', 1)
                  .arg(a.result.complete ? "" : " (incomplete)");
      ++n;
    } catch (const std::exception& e) {
      failed += QString("%1: %2\n").arg(Q(d.string()), Q(e.what()));
    }
    progress.setValue(progress.value() + 1);
  }
  UpdateResultsFooter();
  if (!kept.isEmpty()) {
    auto* box =
        new QMessageBox(QMessageBox::Information, "Attempts kept",
                        "Sulcus stopped before these attempts were kept. Each was "
                        "rebuilt from its recording "
                        "and your entries and is kept, scored as far as it went:\n\n" +
                            kept,
                        QMessageBox::Ok, this);
    box->setObjectName("recovered");
    box->setAttribute(Qt::WA_DeleteOnClose);
    box->show();
  }
  if (!failed.isEmpty())
    ShowErrors("Recovering attempts",
               "These attempts could not be rebuilt; their files are left as they were.",
               failed);
  return n;
}

void MainWindow::AskDiagnosis() {
  if (!lesson_) return;
  QDialog dialog(this);
  dialog.setWindowTitle("Your diagnosis");
  auto* layout = new QVBoxLayout(&dialog);
  layout->addWidget(new QLabel("From your chart, by the 2017 classification:"));
  auto* none = new QRadioButton("no periodontitis");
  auto* perio = new QRadioButton("periodontitis");
  perio->setChecked(true);
  layout->addWidget(none);
  layout->addWidget(perio);
  auto* form = new QFormLayout;
  auto* stage = new QComboBox;
  stage->addItems({"I", "II", "III", "IV"});
  auto* extent = new QComboBox;
  extent->addItems({"localized", "generalized", "molar-incisor"});
  extent->setToolTip(
      "molar-incisor: the attachment loss is at first molars and incisors only");
  auto* grade = new QComboBox;
  grade->addItems({"not assessed", "A", "B", "C"});
  grade->setToolTip(
      "The rate of progression: bone loss over age, then smoking and HbA1c (only when "
      "the patient's history is given)");
  form->addRow("Stage", stage);
  form->addRow("Extent", extent);
  form->addRow("Grade", grade);
  layout->addLayout(form);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  layout->addWidget(buttons);
  connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  if (dialog.exec() != QDialog::Accepted) return;
  DeclaredDiagnosis d;
  d.periodontitis = perio->isChecked();
  if (d.periodontitis) {
    d.stage = *StageFromString(stage->currentText().toStdString());
    d.extent = *ExtentFromString(extent->currentText().toStdString());
    d.grade = GradeFromString(grade->currentText().toStdString()).value_or(Grade::kNone);
  }
  DeclareDiagnosis(d);
}

bool MainWindow::FinishLesson(bool show_report) {
  if (!lesson_ || !lesson_spec_) return false;
  StopSession();  // the recording is written out
  LessonResult r = lesson_->Finish();
  // The window's own keys and mouse, else what the device's name says.
  r.device_kind = mouse_ ? "keys" : DeviceKindOf(device_name_);
  QString problems;
  try {
    KeepAttempt(r, attempt_, attempt_.dir, ResultsPlaceFor(lesson_start_.results_dir));
  } catch (const std::exception& e) {
    problems = Q(e.what());
  }
  UpdateResultsFooter();
  last_result_ = r;
  last_report_ = attempt_.dir / "report.html";
  last_recording_ = attempt_.recording();
  lesson_.reset();
  lesson_spec_.reset();
  scripted_student_.reset();
  recording_file_.clear();
  SetAidsLocked(false);
  view_->ShowBlood({});
  lesson_dock_->hide();
  if (!problems.isEmpty())
    ShowErrors("Lesson",
               QString("Your attempt is kept in %1, but:").arg(Q(attempt_.dir.string())),
               problems);
  if (show_report) ShowReport(r, last_report_);
  device_name_ = "mouse";
  StartSession();  // the workbench goes on, without the lesson
  return true;
}

void MainWindow::ShowReport(const LessonResult& r, const std::filesystem::path& html) {
  if (!report_dialog_) {
    report_dialog_ = new QDialog(this);
    report_dialog_->setWindowTitle("Your report");
    report_dialog_->resize(980, 720);
    auto* layout = new QVBoxLayout(report_dialog_);
    auto* browser = new QTextBrowser;
    browser->setObjectName("report");
    browser->setOpenLinks(false);  // a moment of the report opens the replay there
    connect(browser, &QTextBrowser::anchorClicked, this, [this](const QUrl& url) {
      const QString f = url.fragment();
      bool ok = false;
      const std::uint64_t tick = f.startsWith('t') ? f.mid(1).toULongLong(&ok) : 0;
      if (ok && !last_recording_.empty()) OpenReplay(last_recording_, tick);
    });
    layout->addWidget(browser);
    // Where the report is, always: a student may have no browser set up.
    auto* where = new QLabel;
    where->setObjectName("report_path");
    where->setTextInteractionFlags(Qt::TextSelectableByMouse);
    where->setWordWrap(true);
    layout->addWidget(where);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
    auto* open = buttons->addButton("Open the full report (pictures, force traces)",
                                    QDialogButtonBox::ActionRole);
    layout->addWidget(buttons);
    connect(buttons, &QDialogButtonBox::rejected, report_dialog_, &QDialog::hide);
    connect(open, &QPushButton::clicked, this, [this, where] {
      const QString path = Q(last_report_.string());
      if (!QDesktopServices::openUrl(QUrl::fromLocalFile(path)))
        where->setText(QString("<b>No program here opens web pages.</b> The full report "
                               "is the file <code>%1</code>: open it in any web browser, "
                               "or copy the folder.")
                           .arg(path.toHtmlEscaped()));
    });
  }
  // The page itself (Qt shows its tables and text; the pictures are SVG, in the browser).
  std::ifstream in(html);
  std::stringstream text;
  text << in.rdbuf();
  auto* browser = report_dialog_->findChild<QTextBrowser*>("report");
  browser->setHtml(Q(text.str()));
  report_dialog_->findChild<QLabel*>("report_path")
      ->setText(QString("The full report (with its pictures) is saved as <code>%1</code>")
                    .arg(Q(html.string()).toHtmlEscaped()));
  report_dialog_->setWindowTitle(
      QString("Your report: %1 / 100").arg(r.total, 0, 'f', 1));
  report_dialog_->show();
}

}  // namespace sulcus::ui
