#include "ui/main_window.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDesktopServices>
#include <QDialogButtonBox>
#include <QDockWidget>
#include <QEventLoop>
#include <QFileDialog>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QMouseEvent>
#include <QProgressDialog>
#include <QProxyStyle>
#include <QPushButton>
#include <QRadioButton>
#include <QScrollArea>
#include <QSettings>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QTextBrowser>
#include <QTimer>
#include <QUrl>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <set>
#include <sstream>

#include "core/haptics/devices/usb_discovery.h"
#include "core/haptics/scripted_device.h"
#include "core/lesson/answers.h"
#include "core/lesson/attempt.h"
#include "core/lesson/instructor.h"
#include "core/lesson/report.h"
#include "core/lesson/results.h"
#include "core/spheretree/cache.h"
#include "ui/chart_widget.h"
#include "ui/force_gauge.h"
#include "ui/force_plot.h"
#include "ui/instructor_dialog.h"
#include "ui/mouse_device.h"
#include "ui/odontogram_widget.h"
#include "ui/progress_dialog.h"
#include "ui/scene_view.h"
#include "ui/start_dialog.h"

namespace sulcus::ui {
namespace {

QString Q(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  BuildUi();
  QSettings settings;
  restoreGeometry(settings.value("window/geometry").toByteArray());
  // The docks' layout as the student left it, if it is this version's (the
  // lesson and instrument panels share the right side as tabs since version 2).
  restoreState(settings.value("window/state").toByteArray(), kDockLayoutVersion);
  timer_ = new QTimer(this);
  connect(timer_, &QTimer::timeout, this, [this] { Tick(); });
  timer_->start(16);
}

MainWindow::~MainWindow() { StopSession(); }

namespace {
class JumpSliderStyle final : public QProxyStyle {
 public:
  using QProxyStyle::QProxyStyle;
  int styleHint(StyleHint hint, const QStyleOption* option, const QWidget* widget,
                QStyleHintReturn* returned) const override {
    if (hint == QStyle::SH_Slider_AbsoluteSetButtons)
      return Qt::LeftButton | Qt::MiddleButton;
    return QProxyStyle::styleHint(hint, option, widget, returned);
  }
};

constexpr int kPanelWidth = 380;  // px: the side docks', so the 3D view keeps 60 %
// A side panel that scrolls when the screen is short (a 1366 x 768 laptop)
// instead of holding the window taller than the screen.
QScrollArea* Scrolling(QWidget* panel) {
  auto* scroll = new QScrollArea;
  scroll->setWidget(panel);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAsNeeded);
  // The 3D view comes first: a panel is at most kPanelWidth wide (its chart
  // and odontogram scale to fit).
  scroll->setMinimumWidth(std::min(panel->sizeHint().width() + 16, kPanelWidth));
  scroll->setMaximumWidth(std::max(kPanelWidth, 300));
  return scroll;
}
}  // namespace

void MainWindow::BuildUi() {
  setWindowTitle("Sulcus");
  resize(1280, 800);
  vtk_widget_ = new QVTKOpenGLNativeWidget(this);
  auto window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  vtk_widget_->setRenderWindow(window);
  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  window->AddRenderer(renderer);
  renderer_ = renderer;
  view_ = std::make_unique<SceneView>(renderer_);
  setCentralWidget(vtk_widget_);
  vtk_widget_->installEventFilter(this);  // the tool keys reach the mouse device, not VTK

  // The side panel: gauge, status, controls, events.
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);
  gauge_ = new ForceGauge;
  layout->addWidget(gauge_);
  plot_ = new ForcePlot;
  layout->addWidget(plot_);
  status_ = new QLabel("No scene loaded.");
  status_->setTextFormat(Qt::PlainText);
  status_->setWordWrap(true);
  status_->setMinimumHeight(150);
  status_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  layout->addWidget(status_);
  auto* form = new QFormLayout;
  device_box_ = new QComboBox;
  device_box_->addItem("mouse");
  for (const std::string& n : ScriptNames()) device_box_->addItem(Q("scripted:" + n));
  // Hardware that is plugged in, with what it needs (no hardware backend is built here).
  const auto known = ScanUsb().known;
  for (const UsbDeviceInfo& d : known) {
    device_box_->addItem(Q(d.name + " (needs: " + d.backend + ")"));
    if (auto* model = qobject_cast<QStandardItemModel*>(device_box_->model()))
      model->item(device_box_->count() - 1)->setEnabled(false);
  }
  if (known.empty()) {
    device_box_->addItem("no Phantom or Touch found (USB)");
    if (auto* model = qobject_cast<QStandardItemModel*>(device_box_->model()))
      model->item(device_box_->count() - 1)->setEnabled(false);
  }
  device_box_->setToolTip(
      "The mouse and keyboard, a developer's scripted probe, or a haptic device when one "
      "is plugged in");
  form->addRow("Device", device_box_);
  connect(device_box_, &QComboBox::textActivated, this,
          [this](const QString& d) { SetDevice(d.toStdString()); });
  sphere_level_ = new QSpinBox;
  sphere_level_->setRange(-1, 7);
  sphere_level_->setSpecialValueText("off");
  sphere_level_->setValue(-1);
  form->addRow("Sphere-tree level", sphere_level_);
  connect(sphere_level_, qOverload<int>(&QSpinBox::valueChanged), this,
          [this](int l) { ShowSpheres(l); });
  translucent_ = new QCheckBox("translucent gingiva");
  lips_hidden_ = new QCheckBox("hide lips and cheeks");
  lips_hidden_->setToolTip(
      "Take the lips and cheeks out of the picture, as a retractor would; "
      "the instrument still meets them");
  auto* see_row = new QHBoxLayout;
  see_row->addWidget(translucent_);
  see_row->addWidget(lips_hidden_);
  form->addRow("", see_row);
  connect(lips_hidden_, &QCheckBox::toggled, this, [this](bool on) {
    view_->SetLipsAndCheeksHidden(on);
    vtk_widget_->renderWindow()->Render();
  });
  connect(translucent_, &QCheckBox::toggled, this, [this](bool on) {
    view_->SetGingivaTranslucent(on);
    vtk_widget_->renderWindow()->Render();
  });
  auto* look = new QSpinBox;
  look->setRange(11, 48);
  look->setValue(46);
  auto* look_button = new QPushButton("Look at tooth");
  connect(look_button, &QPushButton::clicked, this,
          [this, look] { LookAtTooth(look->value()); });
  auto* look_row = new QHBoxLayout;
  look_row->addWidget(look);
  look_row->addWidget(look_button);
  form->addRow("Camera", look_row);
  auto* views = new QHBoxLayout;
  auto* occlusal_views = new QHBoxLayout;
  for (auto [label, side] : {std::pair{"Buccal", SceneView::Side::kBuccal},
                             std::pair{"Lingual", SceneView::Side::kLingual},
                             std::pair{"Front", SceneView::Side::kFront},
                             std::pair{"Lower arch", SceneView::Side::kOcclusal},
                             std::pair{"Upper arch", SceneView::Side::kUpperOcclusal}}) {
    auto* b = new QPushButton(label);
    connect(b, &QPushButton::clicked, this, [this, side = side] {
      view_->View(side);
      vtk_widget_->renderWindow()->Render();
    });
    (side == SceneView::Side::kOcclusal || side == SceneView::Side::kUpperOcclusal
         ? occlusal_views
         : views)
        ->addWidget(b);
  }
  form->addRow("View", views);
  form->addRow("Occlusal", occlusal_views);
  auto* reset = new QPushButton("Reset tool");
  reset->setToolTip(
      "Brings the tool back to a free pose: with the mouse and keyboard, 6 mm above the "
      "site the tip is in (or the next site)");
  connect(reset, &QPushButton::clicked, this, [this] {
    if (!session_) return;
    std::optional<SiteRef> site = lesson_ ? lesson_->tip_site() : std::nullopt;
    if (!site && lesson_) site = lesson_->next_site();
    if (mouse_ && site && PlaceProbeAt(*site, 6.0)) return;
    session_->loop().Send({HapticCommand::Kind::kResetTool});
  });
  auto* pause = new QPushButton("Pause");
  pause->setCheckable(true);
  pause->setToolTip(
      "Pause the force (the tool stays where it is); press again to resume");
  connect(pause, &QPushButton::toggled, this, [this, pause](bool on) {
    pause->setText(on ? "Resume" : "Pause");
    if (session_)
      session_->loop().Send(
          {on ? HapticCommand::Kind::kPause : HapticCommand::Kind::kResume});
  });
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(reset);
  buttons->addWidget(pause);
  form->addRow("Tool", buttons);
  layout->addLayout(form);
  layout->addWidget(new QLabel("Events"));
  events_ = new QListWidget;
  layout->addWidget(events_, 1);
  device_help_ = new QLabel;
  device_help_->setWordWrap(true);
  layout->addWidget(device_help_);
  auto* dock = new QDockWidget("Instrument", this);
  instrument_dock_ = dock;
  dock->setObjectName("instrument");
  dock->setWidget(Scrolling(panel));
  dock->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetFloatable);
  addDockWidget(Qt::RightDockWidgetArea, dock);

  // Menus.
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction(
      "&Open scene...", this,
      [this] {
        const QString f = QFileDialog::getOpenFileName(
            this, "Open scene", Q(scene_file_.parent_path().string()),
            "Scenes (*.yaml *.yml)");
        if (!f.isEmpty()) OpenScene(f.toStdString());
      },
      QKeySequence::Open);
  QAction* record = file->addAction("&Record session");
  record->setCheckable(true);
  connect(record, &QAction::toggled, this, [this, record](bool on) {
    if (!on) {
      StopRecording();
      return;
    }
    const QString f = QFileDialog::getSaveFileName(this, "Record to", "session.rec",
                                                   "Recordings (*.rec)");
    if (f.isEmpty() || !StartRecording(f.toStdString())) record->setChecked(false);
  });
  file->addAction("Replay a recording...", this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Replay", "", "Recordings (*.rec)");
    if (!f.isEmpty()) SetDevice("replay:" + f.toStdString());
  });
  file->addAction("Save &screenshot...", this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Screenshot", "sulcus.png", "PNG (*.png)");
    if (!f.isEmpty()) SaveScreenshot(f.toStdString());
  });
  file->addSeparator();
  file->addAction("&Quit", this, &QWidget::close, QKeySequence::Quit);
  BuildLessonDock();
  BuildReplayDock();
  auto* lessons = menuBar()->addMenu("&Lesson");
  lessons->addAction(
      "&Start a lesson...", this, [this] { ShowStartPage(); }, QKeySequence("Ctrl+L"));
  lessons->addAction("&Declare the diagnosis...", this, [this] { AskDiagnosis(); });
  lessons->addAction("&Finish the lesson", this, [this] { FinishLesson(); });
  lessons->addAction("My &progress...", this, [this] {
    ShowProgress(QSettings().value("student/last", "student").toString().toStdString());
  });
  lessons->addAction("&Instructor...", this, [this] {
    const std::filesystem::path lock_file = DefaultResultsDir() / "instructor.pwhash";
    const bool first = !InstructorLock(lock_file).is_set();
    bool ok = false;
    const QString pass =
        QInputDialog::getText(this, "Instructor",
                              first ? "Set the instructor's passphrase (at least 8 "
                                      "characters; students must not know it):"
                                    : "The instructor's passphrase:",
                              QLineEdit::Password, "", &ok);
    if (!ok) return;
    if (first) {
      const QString again = QInputDialog::getText(
          this, "Instructor", "The same passphrase again:", QLineEdit::Password, "", &ok);
      if (!ok) return;
      if (again != pass) {
        QMessageBox::warning(this, "Instructor",
                             "The two passphrases differ; nothing was set.");
        return;
      }
    }
    OpenInstructor(pass.toStdString());
  });
  lessons->addAction("Play a &demonstration as a ghost...", this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "A recorded demonstration",
                                                   Q(DefaultResultsDir().string()),
                                                   "Recordings (*.rec)");
    SetDemonstration(f.toStdString());
  });
  lessons->addAction("&Replay a recording...", this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Replay a recording",
                                                   Q(DefaultResultsDir().string()),
                                                   "Recordings (*.rec)");
    if (!f.isEmpty()) OpenReplay(f.toStdString());
  });
  auto* help_menu = menuBar()->addMenu("&Help");
  help_menu->addAction(
      "&Help for this lesson", this,
      [this] { QMessageBox::information(this, "Sulcus help", HelpHtml()); },
      QKeySequence::HelpContents);
  help_menu->addAction("How to &probe and chart", this, [this] {
    QMessageBox::information(this, "Sulcus help", HelpHtml(HelpTopic::kProbing));
  });
  help_menu->addAction("How to &examine the mouth", this, [this] {
    QMessageBox::information(this, "Sulcus help", HelpHtml(HelpTopic::kInspection));
  });
  statusBar()->showMessage(
      "Start a lesson (Lesson > Start, Ctrl+L) or open a scene (File > Open scene).");
}

void MainWindow::ShowErrors(const QString& title, const QString& text,
                            const QString& details) {
  if (!error_dialog_) {
    error_dialog_ = new QMessageBox(this);
    error_dialog_->setIcon(QMessageBox::Critical);
    error_dialog_->setStandardButtons(QMessageBox::Ok);
  }
  error_dialog_->setWindowTitle(title);
  error_dialog_->setText(text);
  error_dialog_->setInformativeText(details);
  error_dialog_->show();
}

bool MainWindow::OpenScene(const std::filesystem::path& file, bool wait) {
  SceneSpec spec;
  try {
    spec = LoadSceneSpec(file);
  } catch (const SceneLoadError& e) {
    QString details;
    for (const SceneError& err : e.errors()) details += Q(err.ToString()) + "\n";
    ShowErrors("Scene has errors",
               QString("%1 has %2 error(s); the current scene stays loaded.")
                   .arg(Q(file.string()))
                   .arg(e.errors().size()),
               details);
    return false;
  }
  return OpenSpec(spec, file, wait);
}

bool MainWindow::OpenSpec(const SceneSpec& spec, const std::filesystem::path& file,
                          bool wait) {
  // Compile off the UI thread; the dialog shows progress and can cancel.
  struct Job {
    std::mutex mutex;
    std::string stage;
    double fraction = 0;
    std::atomic<bool> cancel{false}, done{false};
    std::unique_ptr<CompiledScene> result;
    SeenGingiva seen;  // the gingiva as drawn (the engine's is the felt one)
    std::string error;
  };
  auto job = std::make_shared<Job>();
  std::thread worker([job, spec] {
    try {
      std::unique_ptr<CompiledScene> scene =
          CompileScene(spec, DefaultCacheDir(), [job](std::string_view stage, double f) {
            std::lock_guard lock(job->mutex);
            job->stage = stage;
            job->fraction = 0.85 * f;
            return !job->cancel.load();
          });
      job->seen = BuildSeenGingiva(
          *scene, DefaultCacheDir(), [job](std::string_view stage, double f) {
            std::lock_guard lock(job->mutex);
            job->stage = "the gingiva as drawn, " + std::string(stage);
            job->fraction = 0.85 + 0.15 * f;
            return !job->cancel.load();
          });
      job->result = std::move(scene);
    } catch (const BuildCancelled&) {
      job->error = "cancelled";
    } catch (const std::exception& e) {
      job->error = e.what();
    }
    job->done = true;
  });
  worker.detach();  // it only touches `job`, which it shares
  auto* progress = new QProgressDialog(QString("Building %1 ...").arg(Q(spec.name)),
                                       "Cancel", 0, 1000, this);
  progress->setWindowModality(Qt::WindowModal);
  progress->setMinimumDuration(300);
  auto* poll = new QTimer(progress);
  QEventLoop* waiter = wait ? new QEventLoop(this) : nullptr;
  connect(progress, &QProgressDialog::canceled, this, [job] { job->cancel = true; });
  connect(poll, &QTimer::timeout, this, [this, job, progress, poll, file, waiter] {
    {
      std::lock_guard lock(job->mutex);
      progress->setValue(static_cast<int>(job->fraction * 1000));
      progress->setLabelText(QString("Preparing the scene (the first time only: its "
                                     "collision spheres and its drawing): %1")
                                 .arg(Q(job->stage)));
    }
    if (!job->done) return;
    poll->stop();  // once: deleteLater may wait for an event loop that never comes back
    progress->hide();
    progress->deleteLater();
    if (job->result) {
      StopSession();
      scene_ = std::move(job->result);
      scene_file_ = file;
      view_->Load(*scene_, &job->seen);
      sphere_level_->setValue(-1);
      QSettings().setValue("scene/last", Q(file.string()));
      StartSession();
      setWindowTitle(QString("Sulcus - %1").arg(Q(scene_->spec.name)));
    } else if (job->error != "cancelled") {
      ShowErrors("Scene could not be built",
                 QString("%1 could not be built; the current scene stays loaded.")
                     .arg(Q(file.string())),
                 Q(job->error));
    }
    if (waiter) waiter->quit();
  });
  poll->start(50);
  if (waiter) {
    waiter->exec();
    waiter->deleteLater();
    return scene_ && scene_file_ == file;
  }
  return true;
}

bool MainWindow::SetDevice(const std::string& device) {
  device_name_ = device;
  if (const int i = device_box_->findText(Q(device)); i >= 0)
    device_box_->setCurrentIndex(i);
  QSettings().setValue("device/last", Q(device));
  if (!scene_) return true;
  StartSession();
  return device_error_.empty();
}

void MainWindow::StopSession() {
  if (session_) {
    const bool recorded = session_->recorder() != nullptr;
    try {
      session_
          ->Stop();  // a session's end ends its recording: everything recorded is written
      if (recorded)
        statusBar()->showMessage(
            QString("Recorded %1 ticks").arg(session_->recorder()->written()));
    } catch (const std::exception& e) {
      ShowErrors("Recording", "The recording failed.", Q(e.what()));
    }
  }
  session_.reset();
  tap_.events.clear();
  mouse_ = nullptr;
}

void MainWindow::StartSession() {
  StopSession();
  BeginSession();
}

void MainWindow::BeginSession() {
  device_error_.clear();
  if (!scene_) return;
  auto use_mouse = [this] {
    // The tool starts above a crown, working end along its axis: in a lesson the
    // crown of its first tooth, else the first lower tooth.
    int first = -1;
    if (lesson_spec_ && !lesson_spec_->path.empty())
      for (int i = 0; i < static_cast<int>(scene_->spec.objects.size()); ++i)
        if (scene_->spec.objects[i].kind == ObjectSpec::Kind::kTooth &&
            scene_->spec.objects[i].fdi == lesson_spec_->path.front().fdi)
          first = i;
    const ScriptTarget top = FindScriptTarget(*scene_, "poke", first);
    auto mouse = std::make_unique<MouseKeyboardDevice>(RigidTransform(
        Quaternion::FromTwoVectors(Vector3::UnitZ(), top.n_W), top.p_W + 4.0 * top.n_W));
    mouse_ = mouse.get();
    DeviceSpec d;
    d.device = std::move(mouse);
    d.name = "mouse";
    return d;
  };
  DeviceSpec device;
  if (lesson_spec_ && device_name_.rfind("student:", 0) == 0) {
    try {
      scripted_student_ =
          MakeScriptedHand(device_name_.substr(8), *lesson_spec_, *scene_);
      device.device = scripted_student_->MakeDevice();
      device.name = device_name_;
    } catch (const std::exception& e) {
      device_error_ = e.what();
      ShowErrors("Device", QString("The device %1 cannot be used.").arg(Q(device_name_)),
                 Q(device_error_));
    }
  } else if (device_name_.rfind("scripted:", 0) == 0 ||
             device_name_.rfind("replay:", 0) == 0) {
    try {
      device = MakeDevice(device_name_, *scene_, 600.0);
    } catch (const std::exception& e) {
      device_error_ = e.what();
      ShowErrors("Device", QString("The device %1 cannot be used.").arg(Q(device_name_)),
                 Q(device_error_));
    }
  }
  if (!device.device) device = use_mouse();
  if (device_wrapper_) device.device = device_wrapper_(std::move(device.device));
  session_device_ = device.device->caps().name;
  UpdateDeviceHelp(device.name);
  snapshot_ =
      HapticSnapshot{};  // nothing from the previous session is shown as this one's
  gauge_->Clear();
  lesson_gauge_->Clear();
  plot_->Clear();
  events_->clear();
  last_reading_.clear();
  SessionOptions so;
  so.record = recording_file_;
  so.device_name = device_name_;
  so.stop_when_device_finished = false;
  so.free_run = lesson_spec_ && lesson_start_.free_run;
  so.realtime = !so.free_run;
  try {
    session_ = std::make_unique<Session>(*scene_, std::move(device), so);
  } catch (const std::exception& e) {
    // The recording cannot be written: say so and go on without it.
    ShowErrors("Recording", "The recording cannot be written.", Q(e.what()));
    recording_file_.clear();
    so.record.clear();
    session_ = std::make_unique<Session>(*scene_, use_mouse(), so);
  }
  session_->AddConsumer(&tap_);
  if (lesson_spec_ && !lesson_) {
    // The lesson follows this session's ticks from its first.
    lesson_ =
        std::make_unique<LessonRun>(*lesson_spec_, *scene_, lesson_start_.student,
                                    lesson_spec_->case_spec.generated ? lesson_seed_ : 0);
    const bool inspection = lesson_spec_->inspection();
    for (ForceGauge* g : {gauge_, lesson_gauge_})
      g->SetBand(lesson_spec_->rubric.force_low_n, lesson_spec_->rubric.force_high_n);
    plot_->SetBand(lesson_spec_->rubric.force_low_n, lesson_spec_->rubric.force_high_n);
    chart_->setVisible(!inspection);
    odontogram_->setVisible(inspection);
    tilt_label_->setVisible(!inspection);
    diagnose_button_->setText(inspection ? "Submit the findings"
                                         : "Declare the diagnosis...");
    diagnose_button_->setToolTip(
        inspection
            ? "Says your odontogram is complete (you may still change it until you "
              "finish)"
            : "Stage and extent of periodontitis from your chart (2017 classification)");
    if (inspection) odontogram_->SetLesson(lesson_spec_->teeth, lesson_spec_->regions);
    // The odontogram is shorter than the chart: what the dock has to spare goes
    // to the list of what the lesson says, not between the labels.
    feedback_->setMaximumHeight(inspection ? QWIDGETSIZE_MAX : 110);
    if (auto* box = qobject_cast<QBoxLayout*>(feedback_->parentWidget()->layout()))
      box->setStretchFactor(feedback_, inspection ? 1 : 0);
    std::map<std::pair<int, int>, double> recession;
    for (const SiteRef& site : lesson_spec_->path)
      recession[{site.fdi, site.site}] = lesson_->recession_mm(site);
    chart_->SetLesson(lesson_spec_->teeth, lesson_spec_->path, recession);
    if (lesson_spec_->practice() && !inspection) {
      // Practice: the true depth of each site appears once the student has entered it.
      std::map<std::pair<int, int>, int> truth;
      for (const ToothChart& t : TrueChart(scene_->spec, lesson_spec_->teeth).teeth)
        for (int s = 0; s < kSitesPerTooth; ++s)
          if (t.sites[s].pd_mm) truth[{t.fdi, s}] = *t.sites[s].pd_mm;
      chart_->SetTruth(truth);
    }
    feedback_->clear();
    feedback_shown_ = 0;
    shown_findings_ = 0;
    views_sent_ = 0;
    looked_at_ = 0;
    lesson_dock_->show();
    lesson_dock_->raise();
  }
  if (lesson_) session_->AddConsumer(lesson_.get());
  if (lesson_ && scripted_student_ && lesson_spec_->inspection()) {
    // A scripted inspector records what it examines as it goes, as a student
    // would (a scripted prober's chart is the window's to enter).
    scripted_student_->Attach(lesson_.get());
    session_->AddConsumer(scripted_student_.get());
  }
  try {
    session_->Start();
  } catch (const std::exception& e) {
    device_error_ = e.what();
    ShowErrors("Device", QString("The device %1 cannot be started.").arg(Q(device_name_)),
               Q(device_error_));
    session_.reset();
    session_ = std::make_unique<Session>(*scene_, use_mouse(), so);
    session_->AddConsumer(&tap_);
    session_->Start();
  }
  statusBar()->showMessage(
      QString("%1 on %2%3")
          .arg(Q(session_device_), Q(scene_file_.string()),
               session_->recorder() ? QString(", recording") : QString()));
}

void MainWindow::UpdateDeviceHelp(const std::string& device) {
  // What moves the tool now: the footer describes the device that runs, not always the
  // mouse.
  QString text;
  if (device == "mouse") {
    text =
        "Mouse and keyboard: W/S, A/D, Q/E move the probe as the screen shows it "
        "(Shift: turn); N to the next site; R/F press harder/lighter along the probe, X "
        "lets go; comma/period walk along the sulcus. Ctrl+drag moves the tool. F1 for "
        "more.";
  } else if (device.rfind("student:", 0) == 0) {
    text = QString(
               "A scripted student (%1) holds the probe: watch it work. Drag moves the "
               "camera.")
               .arg(Q(device.substr(8)));
  } else if (device.rfind("scripted:", 0) == 0 || device.rfind("replay", 0) == 0) {
    text = QString(
               "The tool follows %1, not your hand. Drag moves the camera; choose the "
               "mouse under Device to take "
               "it back.")
               .arg(Q(device));
  } else {
    text = QString("The tool follows the %1 in your hand. Drag moves the camera.")
               .arg(Q(session_device_));
  }
  device_help_->setText(text + " F1: help.");
}

QString MainWindow::device_help() const {
  return device_help_ ? device_help_->text() : QString();
}

bool MainWindow::StartRecording(const std::filesystem::path& file) {
  if (!scene_) return false;
  StopSession();
  recording_file_ = file;
  BeginSession();
  return session_ && session_->recorder() != nullptr;
}

void MainWindow::StopRecording() {
  if (recording_file_.empty()) return;
  recording_file_.clear();
  StartSession();  // ending the session writes the recording out
}

void MainWindow::Tick() {
  ++frames_;
  if (replay_) {
    if (replay_playing_) {
      const auto now = std::chrono::steady_clock::now();
      const double dt = std::chrono::duration<double>(now - replay_clock_).count();
      replay_clock_ = now;
      replay_position_ += dt * replay_speed_ * replay_->header.rate_hz;
      const double last = static_cast<double>(replay_->frames.size() - 1);
      if (replay_position_ >= last) {
        replay_position_ = last;
        SetReplayPlaying(false);
      }
      replay_index_ = static_cast<std::size_t>(replay_position_);
    }
    ShowReplayFrame();
    return;
  }
  if (!session_) return;
  HapticLoop& loop = session_->loop();
  if (loop.snapshots().Acquire()) snapshot_ = loop.snapshots().front();
  view_->Update(snapshot_);
  if (demonstration_ && !demonstration_->frames.empty()) {
    const std::size_t i =
        std::min<std::size_t>(snapshot_.tick, demonstration_->frames.size() - 1);
    view_->ShowGhost(demonstration_->frames[i].X_WG);
  }
  {
    // The gauge shows what a lesson scores and its band is for: the force
    // along the probe (pressing on the pocket floor), not the side force of
    // the tip on the tooth or of the sulcus' soft wall on the shank. The
    // plot below it holds the whole force.
    const double along = TipLocator::ProbingForce(snapshot_.force_W, snapshot_.X_WG);
    for (ForceGauge* g : {gauge_, lesson_gauge_}) {
      g->SetLabel("Probing force");
      g->SetForce(along);
      g->SetPress(mouse_ ? mouse_->press() : 0.0);
    }
    // The plot holds the same quantity of the same snapshot.
    plot_->Push(snapshot_.time_s, along, snapshot_.torque_W.norm());
  }
  session_->Pump();
  for (const HapticEvent& e : tap_.events) {
    const QString what = Q(DescribeEvent(scene_->spec, e));
    if (e.kind == EventKind::kProbeReading) last_reading_ = what;
    events_->insertItem(
        0, QString("%1 s  %2").arg(e.tick / scene_->spec.rate_hz, 0, 'f', 2).arg(what));
    while (events_->count() > 200) delete events_->takeItem(events_->count() - 1);
  }
  tap_.events.clear();
  if (lesson_) UpdateLessonPanel();
  status_->setText(status_text());
  vtk_widget_->renderWindow()->Render();
}

QString MainWindow::status_text() const {
  if (!session_ || !session_->thread()) return "No scene loaded.";
  const HapticThread& thread = *session_->thread();
  const TimingStats& st = thread.stats();
  const HapticSnapshot& s = snapshot_;
  QString text;
  text += QString("Device: %1%2\n")
              .arg(Q(session_device_), s.device_ok ? "" : " (NOT ANSWERING)");
  text += QString("Haptic rate %1 Hz, %2 ticks%3\n")
              .arg(thread.rate_hz(), 0, 'f', 0)
              .arg(st.ticks.load())
              .arg(s.paused ? ", paused" : "");
  text += QString("Step p50 %1 us, p99 %2 us; deadline misses %3\n")
              .arg(st.step_us.Percentile(0.5), 0, 'f', 0)
              .arg(st.step_us.Percentile(0.99), 0, 'f', 0)
              .arg(st.misses.load());
  text += QString("Contacts: %1 pairs, %2 active; solver %3 iterations\n")
              .arg(s.num_pairs)
              .arg(s.active_contacts)
              .arg(s.qp_iterations);
  text += QString("Penetration %1 mm\n").arg(s.max_penetration_mm, 0, 'g', 2);
  if (!last_reading_.isEmpty()) text += "Last " + last_reading_ + "\n";
  text += QString("Faults %1 (engine %2, overruns %3, device stalls %4)")
              .arg(s.faults.total())
              .arg(s.faults.engine)
              .arg(s.faults.overruns)
              .arg(s.faults.device_stalls);
  if (const std::string notes = thread.notes(); !notes.empty()) text += "\n" + Q(notes);
  return text;
}

double MainWindow::gauge_force() const { return gauge_->force(); }

int MainWindow::plot_rows() const { return plot_->rows(); }

void MainWindow::ShowSpheres(int level) {
  if (sphere_level_->value() != level)
    sphere_level_->setValue(level);  // re-enters through the signal
  if (view_->spheres_shown() != level) {
    view_->ShowSpheres(level);
    vtk_widget_->renderWindow()->Render();
  }
}

QWidget* MainWindow::view_widget() const { return vtk_widget_; }

void MainWindow::SetGingivaTranslucent(bool on) { translucent_->setChecked(on); }
void MainWindow::SetLipsAndCheeksHidden(bool hidden) { lips_hidden_->setChecked(hidden); }

bool MainWindow::LookAtTooth(int fdi) {
  const bool ok = view_->LookAtTooth(fdi);
  if (!ok) statusBar()->showMessage(QString("Tooth %1 is not in this scene").arg(fdi));
  vtk_widget_->renderWindow()->Render();
  return ok;
}

bool MainWindow::SaveScreenshot(const std::filesystem::path& png) {
  vtk_widget_->renderWindow()->Render();
  return grab().save(Q(png.string()), "PNG");
}

MainWindow::ViewAxes MainWindow::CameraAxes() const {
  vtkCamera* cam = renderer_->GetActiveCamera();
  double pos[3], focal[3], up[3];
  cam->GetPosition(pos);
  cam->GetFocalPoint(focal);
  cam->GetViewUp(up);
  const Vector3 eye(pos[0], pos[1], pos[2]), at(focal[0], focal[1], focal[2]);
  ViewAxes v;
  v.into = (at - eye).normalized();
  const Vector3 u(up[0], up[1], up[2]);
  v.up = (u - u.dot(v.into) * v.into).normalized();
  v.right = v.into.cross(v.up);
  v.eye = eye;
  return v;
}

QString MainWindow::HeldBackText() const {
  // The hand far from the probe it holds: say so, and why.
  const double gap = (snapshot_.X_WH.translation() - snapshot_.X_WG.translation()).norm();
  if (gap <= kHeldBackMm) return {};
  return QString(
             "<br><span style='color:#c86400'>Your hand is <b>%1 mm</b> from the "
             "probe: a tooth or the tissue holds the probe back. Move back toward "
             "it, or press Reset tool.</span>")
      .arg(gap, 0, 'f', 1);
}

const ProbingSite* MainWindow::SceneSite(const SiteRef& s) const {
  if (!scene_) return nullptr;
  for (const ProbingSite& p : scene_->effects.sites)
    if (p.fdi == s.fdi && p.site == s.site) return &p;
  return nullptr;
}

bool MainWindow::PlaceProbeAt(const SiteRef& site, double above_margin_mm) {
  const ProbingSite* p = SceneSite(site);
  if (!mouse_ || !p) return false;
  const Vector3 down = (p->floor_W - p->margin_W).normalized();
  // Along the site's line (parallel to the long axis), the tip above the margin.
  mouse_->Set(RigidTransform(Quaternion::FromTwoVectors(Vector3::UnitZ(), -down),
                             p->margin_W - above_margin_mm * down));
  statusBar()->showMessage(
      QString("The probe is over %1, %2 mm above the margin: press R to push it down")
          .arg(Q(site.ToString()))
          .arg(above_margin_mm, 0, 'f', 1),
      6000);
  return true;
}

void MainWindow::keyPressEvent(QKeyEvent* e) {
  if (!mouse_) {
    QMainWindow::keyPressEvent(e);
    return;
  }
  // Moves relative to the view (right, up, into the screen, whatever the
  // camera), mm and rad per press; turns about the tip. With Alt, fine: 0.02 mm
  // is 0.04 N at the pocket floor (2 N/mm).
  const bool fine = e->modifiers() & Qt::AltModifier;
  const double step = fine ? 0.02 : 0.1, turn = fine ? 0.01 : 0.05;
  const ViewAxes v = CameraAxes();
  Vector3 d = Vector3::Zero();
  switch (e->key()) {
    case Qt::Key_D:
      d = v.right;
      break;
    case Qt::Key_A:
      d = -v.right;
      break;
    case Qt::Key_W:
      d = v.up;
      break;
    case Qt::Key_S:
      d = -v.up;
      break;
    case Qt::Key_Q:
      d = v.into;
      break;
    case Qt::Key_E:
      d = -v.into;
      break;
    case Qt::Key_R:
    case Qt::Key_F: {
      // The press: the force the hand pushes with along the probe, 0.02 N a key.
      const double press = std::clamp(
          mouse_->press() + (e->key() == Qt::Key_R ? kPressStepN : -kPressStepN), 0.0,
          MouseKeyboardDevice::kPressMaxN);
      mouse_->SetPress(press < 1e-9 ? 0.0 : press);
      gauge_->SetPress(mouse_->press());
      lesson_gauge_->SetPress(mouse_->press());
      return;
    }
    case Qt::Key_X:  // let go: no press
      mouse_->SetPress(0);
      gauge_->SetPress(0);
      lesson_gauge_->SetPress(0);
      return;
    case Qt::Key_Comma:
    case Qt::Key_Period: {
      // The walking stroke: along the sulcus round the tooth the tip is in,
      // 0.3 mm a press (the press keeps the tip at the floor meanwhile).
      const std::optional<SiteRef> at = lesson_ ? lesson_->tip_site() : std::nullopt;
      const ProbingSite* p = at ? SceneSite(*at) : nullptr;
      if (!p) {
        statusBar()->showMessage(
            "Walking needs the tip in a sulcus: press N to place the probe at the "
            "next site, then R to push it down",
            6000);
        return;
      }
      const Vector3 tip = mouse_->pose().translation();
      Vector3 around = p->axis_W.cross(tip - p->origin_W);
      if (around.norm() < 1e-9) return;
      // Comma walks to the screen's left, period to its right.
      around.normalize();
      if (around.dot(v.right) < 0) around = -around;
      mouse_->Nudge((e->key() == Qt::Key_Period ? 0.3 : -0.3) * around, Vector3::Zero());
      return;
    }
    case Qt::Key_N: {
      const std::optional<SiteRef> next = lesson_ ? lesson_->next_site() : std::nullopt;
      if (!next) {
        statusBar()->showMessage("No site is next in this lesson", 4000);
      } else if (aids_locked_) {
        statusBar()->showMessage(
            "An assessment places nothing for you: move the probe to the site", 5000);
      } else {
        PlaceProbeAt(*next, 1.0);
      }
      return;
    }
    default:
      QMainWindow::keyPressEvent(e);
      return;
  }
  if (e->modifiers() & Qt::ShiftModifier) {
    mouse_->Nudge(Vector3::Zero(), turn * d);
  } else {
    mouse_->Nudge(step * d, Vector3::Zero());
  }
}

bool MainWindow::eventFilter(QObject* watched, QEvent* e) {
  // Ctrl + drag moves the tool in the view plane, Ctrl + Shift + drag turns it,
  // Ctrl + wheel moves it along the view; without Ctrl the camera moves.
  if (watched == vtk_widget_ && mouse_ &&
      (e->type() == QEvent::MouseButtonPress || e->type() == QEvent::MouseMove ||
       e->type() == QEvent::MouseButtonRelease || e->type() == QEvent::Wheel)) {
    vtkCamera* cam = renderer_->GetActiveCamera();
    const ViewAxes axes = CameraAxes();
    const Vector3 &eye = axes.eye, &view = axes.into, &v_up = axes.up,
                  &right = axes.right;
    // Millimetres per pixel at the tool's distance from the camera.
    const double depth = std::max(1.0, (mouse_->pose().translation() - eye).dot(view));
    const double mm_per_px = 2 * depth *
                             std::tan(cam->GetViewAngle() * 0.5 * M_PI / 180) /
                             std::max(1, vtk_widget_->height());
    if (e->type() == QEvent::Wheel) {
      auto* w = static_cast<QWheelEvent*>(e);
      if (!(w->modifiers() & Qt::ControlModifier))
        return QMainWindow::eventFilter(watched, e);
      const double per_notch =
          (w->modifiers() & Qt::AltModifier) ? 0.02 : 0.2;  // mm; Alt: fine
      mouse_->Nudge(-per_notch * (w->angleDelta().y() / 120.0) * view, Vector3::Zero());
      return true;
    }
    auto* m = static_cast<QMouseEvent*>(e);
    if (e->type() == QEvent::MouseButtonPress && (m->modifiers() & Qt::ControlModifier)) {
      dragging_ = true;
      drag_from_ = m->pos();
      return true;
    }
    if (e->type() == QEvent::MouseButtonRelease && dragging_) {
      dragging_ = false;
      return true;
    }
    if (e->type() == QEvent::MouseMove && dragging_) {
      const QPoint d = m->pos() - drag_from_;
      drag_from_ = m->pos();
      if (m->modifiers() & Qt::ShiftModifier) {
        mouse_->Nudge(Vector3::Zero(), 0.01 * (d.x() * v_up + d.y() * right));
      } else {
        mouse_->Nudge(mm_per_px * (d.x() * right - d.y() * v_up), Vector3::Zero());
      }
      return true;
    }
  }
  if (watched == vtk_widget_ && e->type() == QEvent::KeyPress && mouse_) {
    auto* k = static_cast<QKeyEvent*>(e);
    switch (k->key()) {
      case Qt::Key_W:
      case Qt::Key_A:
      case Qt::Key_S:
      case Qt::Key_D:
      case Qt::Key_Q:
      case Qt::Key_E:
      case Qt::Key_R:
      case Qt::Key_F:
      case Qt::Key_X:
      case Qt::Key_N:
      case Qt::Key_Comma:
      case Qt::Key_Period:
        keyPressEvent(k);
        return true;
      default:
        break;
    }
  }
  return QMainWindow::eventFilter(watched, e);
}

void MainWindow::closeEvent(QCloseEvent* e) {
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState(kDockLayoutVersion));
  // A lesson in progress is kept: scored as far as it went, stored, its report written.
  if (lesson_) {
    if (!lesson_->done())
      lesson_->SetEnding("the window was closed before the last step");
    FinishLesson(/*show_report=*/false);
  }
  StopSession();
  QMainWindow::closeEvent(e);
}

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
  layout->addWidget(lesson_gauge_);
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
  lesson_dock_->setWidget(Scrolling(panel));
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
  } catch (const SceneLoadError& e) {
    QString details;
    for (const SceneError& err : e.errors()) details += Q(err.ToString()) + "\n";
    ShowErrors("Lesson has errors",
               QString("%1 has %2 error(s).")
                   .arg(Q(start.lesson.string()))
                   .arg(e.errors().size()),
               details);
    return false;
  }
  if (start.mode) spec.mode = *start.mode;
  std::uint64_t seed = spec.case_spec.seed;
  if (start.seed)
    seed = *start.seed;
  else if (spec.case_spec.generated && spec.case_spec.random_seed)
    seed = static_cast<std::uint64_t>(std::time(nullptr)) & 0xffffff;
  SceneSpec scene;
  try {
    scene = LessonScene(spec, seed);
  } catch (const std::exception& e) {
    ShowErrors("Lesson", "The lesson's scene cannot be made.", Q(e.what()));
    return false;
  }
  if (lesson_) FinishLesson();
  // The attempt's folder: its recording, entries and report.
  const std::filesystem::path results =
      start.results_dir.empty() ? DefaultResultsDir() : start.results_dir;
  AttemptFolder folder;
  try {
    folder = NewAttemptFolder(results, start.student);
  } catch (const std::exception& e) {
    ShowErrors("Lesson", "The attempt's folder cannot be made.", Q(e.what()));
    return false;
  }
  StopSession();
  lesson_spec_ = spec;
  lesson_start_ = start;
  lesson_start_.results_dir = results;
  lesson_seed_ = seed;
  attempt_ = folder;
  lesson_.reset();
  device_name_ = start.device;
  recording_file_ = folder.recording();
  QSettings().setValue("student/last", Q(start.student));
  SetAidsLocked(!spec.practice());
  if (!OpenSpec(scene, spec.scene, true) || !lesson_) {
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

void MainWindow::ShowStartPage() {
  RecoverUnfinishedAttempts();
  StartDialog dialog(lesson_dirs_, DefaultResultsDir() / "results.db", this);
  if (dialog.exec() != QDialog::Accepted || dialog.lesson().empty()) return;
  LessonStart s;
  s.lesson = dialog.lesson();
  s.student = dialog.student();
  s.mode = dialog.mode();
  s.seed = dialog.seed();
  s.device = "mouse";
  StartLesson(s);
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
      lesson_spec_->inspection() ? std::nullopt : l.next_site();
  next_label_->setText(next ? QString("Next: <b>%1</b>").arg(Q(next->ToString()))
                            : QString());
  if (next && next->fdi != looked_at_ && !lesson_spec_->inspection()) {
    looked_at_ = next->fdi;
    LookAtTooth(next->fdi);  // the camera to the tooth the lesson asks for
  }
  const std::optional<SiteRef> tip = l.tip_site();
  if (!lesson_spec_->inspection()) {
    QString where =
        tip ? QString("You are in the sulcus of <b>%1</b>").arg(Q(tip->ToString()))
            : QString("The tip is not in a sulcus");
    if (tip && l.tip_depth_mm())
      where += QString(", %1 mm below the margin").arg(*l.tip_depth_mm(), 0, 'f', 1);
    tip_label_->setText(where + HeldBackText());
  }
  chart_->SetProbing(tip);
  {
    std::set<std::pair<int, int>> probed;
    for (const SiteResult& x : l.sites())
      if (x.reached_mm) probed.insert({x.site.fdi, x.site.site});
    chart_->SetProbed(probed);
  }
  if (const auto angle = l.tip_angle_deg()) {
    const QString colour = *angle <= 5 ? "#2a8a3a" : *angle <= 10 ? "#c88a00" : "#c02020";
    const int bars = std::min(20, static_cast<int>(*angle));
    tilt_label_->setText(
        QString(
            "Tilt from the long axis: <span style='color:%1'><b>%2&deg;</b> %3</span>")
            .arg(colour)
            .arg(*angle, 0, 'f', 0)
            .arg(QString(bars, QChar(0x2588))));
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

QString MainWindow::HelpHtml(std::optional<HelpTopic> topic) const {
  if (!topic)
    topic = lesson_spec_ && lesson_spec_->inspection() ? HelpTopic::kInspection
                                                       : HelpTopic::kProbing;
  const QString moving =
      "<b>Moving the instrument</b> (mouse and keyboard), as seen on the screen: D/A "
      "right and left, W/S up and down, Q/E into and out of the screen, 0.1 mm a press "
      "(hold Alt for 0.02 mm); with Shift they turn it about its tip. "
      "<b>N</b> places the probe over the next site, along the tooth (practice). "
      "<b>The press</b>: R pushes the probe down its own axis with 0.02 N more each "
      "press, F with 0.02 N less, X lets go: the tip goes down until the tissue answers "
      "with that force, so 0.24 N holds it at the pocket floor (the white mark on the "
      "gauge). <b>Walking</b>: with the tip in a sulcus, comma and period move it along "
      "the sulcus 0.3 mm (left and right on the screen) while the press keeps it down. "
      "Reset tool lifts it 6 mm above the site. Ctrl + drag moves it with the mouse, "
      "Ctrl + wheel pushes it. Drag without Ctrl turns the camera, the wheel zooms; "
      "the View buttons and Look at tooth place it.";
  if (*topic == HelpTopic::kInspection)
    return moving +
           "<br><br><b>The examination</b>: follow the steps in their order (lips, "
           "cheeks, gingiva, tongue, floor of "
           "the mouth, palate, then tooth by tooth). A region or surface counts as "
           "examined when the tip rests on it "
           "for a moment; a tooth surface counts as seen when the camera has shown it (a "
           "neighbouring tooth can hide "
           "it: turn the camera round). Touch gently: soft tissue pressed above its "
           "limit, or a carious lesion "
           "pressed above 0.5 N, is scored as damage.<br><br><b>Recording findings</b> "
           "on the odontogram: click a tooth to select it, then a "
           "surface of the selected tooth for caries, <i>Ca</i> for calculus, <i>G</i> "
           "for inflamed "
           "gingiva; right-click a tooth "
           "for its WHO status; click a soft-tissue region to record a lesion there. "
           "Keys: arrows choose the tooth, "
           "M D B L O mark caries on a surface, C calculus, G inflamed gingiva, 0-9 the "
           "WHO status. Press a key "
           "again to take the finding back.<br><br><b>Finishing</b>: Submit the findings "
           "ends the examination (you "
           "may still correct a finding); Lesson &gt; Finish shows your report.";
  return moving +
         "<br><br><b>Probing</b>: walk the probe around each tooth in short up-and-down "
         "strokes with the tip on the "
         "tooth, parallel to the long axis; at the contacts tilt it into the col. Press "
         "the pocket floor lightly: the "
         "gauge's green band is the force the lesson gives full credit "
         "for.<br><br><b>Charting</b>: click the chart (or "
         "press Tab to it), type the "
         "depth you read at each site in whole millimetres; it moves to the next site "
         "along the path. B or Space "
         "marks bleeding on the site you just entered; Backspace goes "
         "back. Depths of 10 mm and more: + then the second digit (+ 2 is 12 mm); a "
         "depth over 12 mm asks you to confirm it with Enter. You may chart a site with "
         "the probe still at its floor: that is its reading. Rows: PD, GM (the gingival "
         "margin, positive for recession), CAL = PD + GM, all in mm; in practice the "
         "true PD of each site you probed."
         "<br><br><b>Diagnosis</b>: at the end, "
         "Lesson &gt; Declare the diagnosis; then Lesson &gt; Finish shows your report.";
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

int MainWindow::RecoverUnfinishedAttempts(const std::filesystem::path& results_dir) {
  const std::filesystem::path results =
      results_dir.empty() ? DefaultResultsDir() : results_dir;
  const std::vector<std::filesystem::path> dirs = UnfinishedAttempts(results);
  if (dirs.empty()) return 0;
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
      const RecoveredAttempt a = RecoverAttempt(d, results, DefaultCacheDir());
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
  extent->addItems({"localized", "generalized"});
  form->addRow("Stage", stage);
  form->addRow("Extent", extent);
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
  }
  DeclareDiagnosis(d);
}

bool MainWindow::FinishLesson(bool show_report) {
  if (!lesson_ || !lesson_spec_) return false;
  StopSession();  // the recording is written out
  const LessonResult r = lesson_->Finish();
  QString problems;
  try {
    KeepAttempt(r, attempt_, attempt_.dir, lesson_start_.results_dir / "results.db");
  } catch (const std::exception& e) {
    problems = Q(e.what());
  }
  last_result_ = r;
  last_report_ = attempt_.dir / "report.html";
  last_recording_ = attempt_.recording();
  lesson_.reset();
  lesson_spec_.reset();
  scripted_student_.reset();
  recording_file_.clear();
  SetAidsLocked(false);
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
  auto* d = new ProgressDialog(dir / "results.db", student, this);
  d->setAttribute(Qt::WA_DeleteOnClose);
  d->show();
  return d;
}

QDialog* MainWindow::OpenInstructor(const std::string& passphrase,
                                    const std::filesystem::path& results_dir) {
  const std::filesystem::path dir =
      results_dir.empty() ? DefaultResultsDir() : results_dir;
  try {
    InstructorLock lock(dir / "instructor.pwhash");
    if (!lock.is_set()) lock.Set(passphrase);
    if (!lock.Check(passphrase)) {
      ShowErrors("Instructor", "Wrong passphrase.",
                 "The instructor's view stays closed.");
      return nullptr;
    }
    auto* d = new InstructorDialog(dir / "results.db", lesson_dirs_, this);
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
