// The window: a recorded attempt replayed, a demonstration played as a ghost,
// the student's progress and the instructor's view.

#include <QVTKOpenGLNativeWidget.h>
#include <vtkRenderWindow.h>

#include <QComboBox>
#include <QDockWidget>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSlider>
#include <QStatusBar>
#include <QVBoxLayout>
#include <algorithm>
#include <chrono>

#include "core/lesson/instructor.h"
#include "core/lesson/results.h"
#include "ui/force_gauge.h"
#include "ui/force_plot.h"
#include "ui/instructor_dialog.h"
#include "ui/main_window.h"
#include "ui/main_window_parts.h"
#include "ui/progress_dialog.h"
#include "ui/scene_view.h"
#include "ui/start_dialog.h"

namespace sulcus::ui {

void MainWindow::BuildReplayDock() {
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);
  replay_label_ = new QLabel;
  layout->addWidget(replay_label_);
  replay_slider_ = new QSlider(Qt::Horizontal);
  replay_slider_->setToolTip("Scrub through the recorded attempt (a click jumps there)");
  // A click on the track jumps there (not a page of ten ticks of a million).
  auto* jump = new JumpSliderStyle;  // over the application's own style
  jump->setParent(replay_slider_);
  replay_slider_->setStyle(jump);
  layout->addWidget(replay_slider_);
  connect(replay_slider_, &QSlider::valueChanged, this, [this](int v) {
    if (!replay_ || replay_playing_) return;
    replay_index_ = static_cast<std::size_t>(
        std::clamp(v, 0, static_cast<int>(replay_->frames.size()) - 1));
    replay_position_ = static_cast<double>(replay_index_);
  });
  auto* row = new QHBoxLayout;
  auto* back = new QPushButton("<");
  replay_play_ = new QPushButton("Play");
  auto* step = new QPushButton(">");
  back->setToolTip("One tick back");
  step->setToolTip("One tick on");
  auto* speed = new QComboBox;
  for (const char* sp : {"0.1x", "0.25x", "0.5x", "1x", "2x", "4x"}) speed->addItem(sp);
  speed->setCurrentText("1x");
  speed->setToolTip("Playback speed");
  auto* close = new QPushButton("Close the replay");
  for (QWidget* w : {static_cast<QWidget*>(back), static_cast<QWidget*>(replay_play_),
                     static_cast<QWidget*>(step), static_cast<QWidget*>(speed),
                     static_cast<QWidget*>(close)})
    row->addWidget(w);
  layout->addLayout(row);
  connect(replay_play_, &QPushButton::clicked, this,
          [this] { SetReplayPlaying(!replay_playing_); });
  auto nudge = [this](int d) {
    if (!replay_) return;
    SetReplayPlaying(false);
    const long long i =
        std::clamp<long long>(static_cast<long long>(replay_index_) + d, 0,
                              static_cast<long long>(replay_->frames.size()) - 1);
    replay_index_ = static_cast<std::size_t>(i);
    replay_position_ = static_cast<double>(i);
  };
  connect(back, &QPushButton::clicked, this, [nudge] { nudge(-1); });
  connect(step, &QPushButton::clicked, this, [nudge] { nudge(1); });
  connect(speed, &QComboBox::currentTextChanged, this,
          [this](const QString& t) { replay_speed_ = t.chopped(1).toDouble(); });
  connect(close, &QPushButton::clicked, this, [this] { CloseReplay(); });
  replay_dock_ = new QDockWidget("Replay", this);
  replay_dock_->setObjectName("replay");
  replay_dock_->setWidget(panel);
  addDockWidget(Qt::BottomDockWidgetArea, replay_dock_);
  replay_dock_->hide();
}

bool MainWindow::OpenReplay(const std::filesystem::path& recording, std::uint64_t tick) {
  if (!scene_) return false;
  std::unique_ptr<Recording> rec;
  try {
    rec = std::make_unique<Recording>(ReadRecording(recording));
  } catch (const RecordingError& e) {
    ShowErrors("Replay", "The recording cannot be replayed.", Q(e.what()));
    return false;
  }
  if (rec->frames.empty()) {
    ShowErrors("Replay", "The recording has no ticks.", Q(recording.string()));
    return false;
  }
  if (lesson_) FinishLesson();  // a lesson in progress is kept, never dropped
  StopSession();
  replay_ = std::move(rec);
  // The frame of that tick (frames are in tick order).
  const auto it =
      std::lower_bound(replay_->frames.begin(), replay_->frames.end(), tick,
                       [](const TickRecord& f, std::uint64_t t) { return f.tick < t; });
  replay_index_ = static_cast<std::size_t>(
      std::min<std::ptrdiff_t>(it - replay_->frames.begin(),
                               static_cast<std::ptrdiff_t>(replay_->frames.size()) - 1));
  replay_position_ = static_cast<double>(replay_index_);
  replay_slider_->setRange(0, static_cast<int>(replay_->frames.size()) - 1);
  replay_dock_->show();
  SetReplayPlaying(false);
  ShowReplayFrame();
  statusBar()->showMessage(QString("Replaying %1").arg(Q(recording.string())));
  return true;
}

void MainWindow::SetReplayPlaying(bool on) {
  replay_playing_ = on && replay_;
  replay_clock_ = std::chrono::steady_clock::now();
  if (replay_play_) replay_play_->setText(replay_playing_ ? "Pause" : "Play");
}

void MainWindow::ShowReplayFrame() {
  if (!replay_) return;
  const TickRecord& f = replay_->frames[replay_index_];
  HapticSnapshot s;
  s.tick = f.tick;
  s.time_s = f.time_s;
  s.X_WH = f.sample.X_WH;
  s.X_WG = f.X_WG;
  s.force_W = f.force_W;
  s.torque_W = f.torque_W;
  s.output_scale = 1;
  snapshot_ = s;
  view_->Update(s);
  gauge_->SetForce(TipLocator::ProbingForce(f.force_W, f.X_WG));
  // The force trace of the last 5 s up to the cursor (every 10 ms).
  std::vector<std::array<double, 3>> trace;
  const std::size_t span = static_cast<std::size_t>(5 * replay_->header.rate_hz);
  const std::size_t every =
      std::max<std::size_t>(1, static_cast<std::size_t>(replay_->header.rate_hz / 100));
  for (std::size_t i = replay_index_ > span ? replay_index_ - span : 0;
       i <= replay_index_; i += every) {
    const TickRecord& g = replay_->frames[i];
    trace.push_back(
        {g.time_s, TipLocator::ProbingForce(g.force_W, g.X_WG), g.torque_W.norm()});
  }
  plot_->SetSamples(trace);
  if (replay_slider_->value() != static_cast<int>(replay_index_)) {
    const QSignalBlocker block(replay_slider_);
    replay_slider_->setValue(static_cast<int>(replay_index_));
  }
  status_->setText(QString("Replay of a recording (%1)\nThe blue tool is the device as "
                           "it was, the white one the rendered "
                           "probe.\nTick %2, %3 s\nForce %4 N")
                       .arg(Q(replay_->header.device_name))
                       .arg(f.tick)
                       .arg(f.time_s, 0, 'f', 3)
                       .arg(f.force_W.norm(), 0, 'f', 3));
  replay_label_->setText(QString("Tick %1 of %2, %3 s; force %4 N")
                             .arg(f.tick)
                             .arg(replay_->frames.back().tick)
                             .arg(f.time_s, 0, 'f', 3)
                             .arg(f.force_W.norm(), 0, 'f', 3));
  vtk_widget_->renderWindow()->Render();
}

std::uint64_t MainWindow::replay_tick() const {
  return replay_ ? replay_->frames[replay_index_].tick : 0;
}

const TickRecord* MainWindow::replay_frame() const {
  return replay_ ? &replay_->frames[replay_index_] : nullptr;
}

void MainWindow::CloseReplay() {
  if (!replay_) return;
  replay_.reset();
  replay_playing_ = false;
  replay_dock_->hide();
  StartSession();
}

QDialog* MainWindow::ShowProgress(const std::string& student,
                                  const std::filesystem::path& results_dir) {
  const std::filesystem::path dir =
      results_dir.empty() ? DefaultResultsDir() : results_dir;
  ResultsPlace place = ResultsPlaceFor(dir);
  // The student signed in for the lesson sees their own attempts at a store
  // that shows a station nothing else.
  if (student == lesson_start_.student) place.sign_in = lesson_start_.sign_in;
  auto* d = new ProgressDialog(place, student, this);
  d->setAttribute(Qt::WA_DeleteOnClose);
  d->show();
  return d;
}

QDialog* MainWindow::OpenInstructor(const std::string& passphrase,
                                    const std::filesystem::path& results_dir) {
  const std::filesystem::path dir =
      results_dir.empty() ? DefaultResultsDir() : results_dir;
  try {
    InstructorLock lock(ResultsPlaceFor(dir));  // a shared store's, or this station's
    if (!lock.is_set()) lock.Set(passphrase);
    if (!lock.Check(passphrase)) {
      ShowErrors("Instructor", "Wrong passphrase.",
                 "The instructor's view stays closed.");
      return nullptr;
    }
    auto* d = new InstructorDialog(ResultsPlaceFor(dir), lesson_dirs_, this);
    d->setAttribute(Qt::WA_DeleteOnClose);
    d->show();
    return d;
  } catch (const std::exception& e) {
    ShowErrors("Instructor", "The instructor's view cannot be opened.", Q(e.what()));
    return nullptr;
  }
}

bool MainWindow::SetDemonstration(const std::filesystem::path& recording) {
  if (recording.empty()) {
    demonstration_.reset();
    view_->ShowGhost(std::nullopt);
    return true;
  }
  try {
    demonstration_ = std::make_unique<Recording>(ReadRecording(recording));
  } catch (const RecordingError& e) {
    ShowErrors("Demonstration", "The demonstration cannot be played.", Q(e.what()));
    return false;
  }
  StartSession();  // from its first tick, beside the student's
  statusBar()->showMessage(
      QString("The green probe is the demonstration %1").arg(Q(recording.string())));
  return true;
}

const std::optional<RigidTransform>& MainWindow::ghost_pose() const {
  return view_->ghost();
}

}  // namespace sulcus::ui
