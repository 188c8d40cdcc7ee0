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
#include "ui/main_window_parts.h"
#include "ui/mouse_device.h"
#include "ui/odontogram_widget.h"
#include "ui/progress_dialog.h"
#include "ui/scene_view.h"
#include "ui/start_dialog.h"

namespace sulcus::ui {

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
  // The loupe: a magnified inset in the view's lower right corner, and over it
  // (the window's upper layer) the probe's markings, seen through the gingiva.
  window->SetNumberOfLayers(2);
  auto loupe = vtkSmartPointer<vtkRenderer>::New();
  auto loupe_marks = vtkSmartPointer<vtkRenderer>::New();
  for (vtkRenderer* r : {loupe.Get(), loupe_marks.Get()}) {
    r->SetViewport(0.66, 0.02, 0.99, 0.45);
    r->InteractiveOff();  // the mouse moves the main view's camera
    window->AddRenderer(r);
  }
  loupe_marks->SetLayer(1);
  view_->AttachLoupe(loupe, loupe_marks);
  setCentralWidget(vtk_widget_);
  vtk_widget_->installEventFilter(this);  // the tool keys reach the mouse device, not VTK
  // And from the lesson's panel (the chart, the feedback list) too.
  qApp->installEventFilter(this);

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
  loupe_box_ = new QCheckBox("loupe");
  loupe_box_->setChecked(true);
  loupe_box_->setToolTip(
      "While the tip is in a sulcus: a magnified view of where the gingival margin "
      "crosses the probe's markings, the markings drawn through the gingiva");
  auto* see_row = new QHBoxLayout;
  see_row->addWidget(translucent_);
  see_row->addWidget(lips_hidden_);
  see_row->addWidget(loupe_box_);
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
  UpdateResultsFooter();
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
    bool first = false;
    try {
      first = !InstructorLock(ResultsPlaceFor(DefaultResultsDir())).is_set();
    } catch (const std::exception& e) {
      ShowErrors("Instructor", "The instructor's view cannot be opened.", Q(e.what()));
      return;
    }
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
  } catch (const LoadError& e) {
    QString details;
    for (const ErrorAt& err : e.errors()) details += Q(err.ToString()) + "\n";
    ShowErrors("Scene has errors",
               QString("The scene file %1 has %2 error(s); the current scene stays "
                       "loaded.")
                   .arg(Q(file.string()))
                   .arg(e.errors().size()),
               details);
    return false;
  }
  return OpenSpec(spec, file, wait);
}

bool MainWindow::OpenSpec(const SceneSpec& spec, const std::filesystem::path& file,
                          bool wait, const std::string& key) {
  // Prepared off the UI thread (perhaps already, while the start page was
  // open); the dialog shows what is left and can cancel.
  const auto job = preparer_.Prepare(spec, key.empty() ? "scene:" + file.string() : key);
  auto* progress = new QProgressDialog(QString("Building %1 ...").arg(Q(spec.name)),
                                       "Cancel", 0, 1000, this);
  progress->setWindowModality(Qt::WindowModal);
  progress->setMinimumDuration(job->done ? 100000 : 300);
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
    if (preparer_.current() == job) preparer_.Drop();
    if (job->result) {
      StopSession();
      statusBar()->showMessage(
          QString("Scene ready in %1 s").arg(job->seconds, 0, 'f', 1), 10000);
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
  try {
    // One factory for every device name (the mouse is this window's own).
    if (lesson_spec_) {
      LessonDevice made = MakeLessonDevice(device_name_, *lesson_spec_, *scene_, 600.0);
      scripted_student_ = std::move(made.student);
      device = std::move(made.device);
    } else if (ParseDeviceName(device_name_).kind != DeviceName::Kind::kMouse) {
      device = MakeDevice(device_name_, *scene_, 600.0);
    }
  } catch (const std::exception& e) {
    device_error_ = e.what();
    ShowErrors("Device", QString("The device %1 cannot be used.").arg(Q(device_name_)),
               Q(device_error_));
    device = {};
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
    std::vector<int> missing;
    for (const auto& [fdi, why] : scene_->spec.missing) missing.push_back(fdi);
    chart_->SetLesson(lesson_spec_->teeth, lesson_spec_->path, recession, missing);
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
    looked_lingual_ = false;
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
  std::optional<DeviceName> name;
  try {
    name = ParseDeviceName(device);
  } catch (const std::invalid_argument&) {
    // "replay of ...", a hardware device: described by what runs
  }
  if (name && name->kind == DeviceName::Kind::kMouse) {
    text =
        "Mouse and keyboard: W/S, A/D, Q/E move the probe as the screen shows it "
        "(Shift: turn); N to the next site; R/F press harder/lighter along the probe, X "
        "lets go; comma/period walk along the sulcus, T tilts into the col. Ctrl+drag "
        "moves the tool. F1 for "
        "more.";
  } else if (name && name->kind == DeviceName::Kind::kStudent) {
    text = QString(
               "A scripted student (%1) holds the probe: watch it work. Drag moves the "
               "camera.")
               .arg(Q(name->what));
  } else if (name || device.rfind("replay", 0) == 0) {
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
  if (lesson_)
    UpdateLessonPanel();
  else if (view_->loupe_shown())
    UpdateLoupe(std::nullopt);
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

bool MainWindow::LookAtTooth(int fdi, bool lingual) {
  const bool ok = view_->LookAtTooth(fdi, lingual);
  if (!ok) statusBar()->showMessage(QString("Tooth %1 is not in this scene").arg(fdi));
  vtk_widget_->renderWindow()->Render();
  return ok;
}

bool MainWindow::SaveScreenshot(const std::filesystem::path& png) {
  vtk_widget_->renderWindow()->Render();
  return grab().save(Q(png.string()), "PNG");
}

void MainWindow::closeEvent(QCloseEvent* e) {
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState(kDockLayoutVersion));
  // A lesson in progress is kept: scored as far as it went, stored, its report written.
  if (lesson_) LeaveLesson("the window was closed before the last step");
  StopSession();
  QMainWindow::closeEvent(e);
}

}  // namespace sulcus::ui
