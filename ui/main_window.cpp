#include "ui/main_window.h"

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QEventLoop>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QLabel>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>
#include <QSettings>
#include <QSpinBox>
#include <QStatusBar>
#include <QTimer>
#include <QVBoxLayout>
#include <QMouseEvent>
#include <QStandardItemModel>
#include <QVTKOpenGLNativeWidget.h>
#include <QWheelEvent>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>

#include <chrono>
#include <cmath>

#include "core/haptics/devices/usb_discovery.h"
#include "core/haptics/scripted_device.h"
#include "core/spheretree/cache.h"
#include "ui/force_gauge.h"
#include "ui/force_plot.h"
#include "ui/mouse_device.h"
#include "ui/scene_view.h"

namespace sulcus::ui {
namespace {

QString Q(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  BuildUi();
  QSettings settings;
  restoreGeometry(settings.value("window/geometry").toByteArray());
  restoreState(settings.value("window/state").toByteArray());
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
  for (const UsbDeviceInfo& d : ScanUsb().known) {
    device_box_->addItem(Q(d.name + " (needs: " + d.backend + ")"));
    if (auto* model = qobject_cast<QStandardItemModel*>(device_box_->model()))
      model->item(device_box_->count() - 1)->setEnabled(false);
  }
  form->addRow("Device", device_box_);
  connect(device_box_, &QComboBox::textActivated, this, [this](const QString& d) { SetDevice(d.toStdString()); });
  sphere_level_ = new QSpinBox;
  sphere_level_->setRange(-1, 7);
  sphere_level_->setSpecialValueText("off");
  sphere_level_->setValue(-1);
  form->addRow("Sphere-tree level", sphere_level_);
  connect(sphere_level_, qOverload<int>(&QSpinBox::valueChanged), this, [this](int l) { ShowSpheres(l); });
  translucent_ = new QCheckBox("translucent gingiva");
  form->addRow("", translucent_);
  connect(translucent_, &QCheckBox::toggled, this, [this](bool on) {
    view_->SetGingivaTranslucent(on);
    vtk_widget_->renderWindow()->Render();
  });
  auto* look = new QSpinBox;
  look->setRange(11, 48);
  look->setValue(46);
  auto* look_button = new QPushButton("Look at tooth");
  connect(look_button, &QPushButton::clicked, this, [this, look] { LookAtTooth(look->value()); });
  auto* look_row = new QHBoxLayout;
  look_row->addWidget(look);
  look_row->addWidget(look_button);
  form->addRow("Camera", look_row);
  auto* views = new QHBoxLayout;
  for (auto [label, side] : {std::pair{"Buccal", SceneView::Side::kBuccal}, std::pair{"Lingual", SceneView::Side::kLingual},
                             std::pair{"Occlusal", SceneView::Side::kOcclusal}}) {
    auto* b = new QPushButton(label);
    connect(b, &QPushButton::clicked, this, [this, side = side] {
      view_->View(side);
      vtk_widget_->renderWindow()->Render();
    });
    views->addWidget(b);
  }
  form->addRow("View", views);
  auto* reset = new QPushButton("Reset tool");
  connect(reset, &QPushButton::clicked, this, [this] {
    if (session_) session_->loop().Send({HapticCommand::Kind::kResetTool});
  });
  auto* pause = new QPushButton("Pause");
  pause->setCheckable(true);
  connect(pause, &QPushButton::toggled, this, [this](bool on) {
    if (session_) session_->loop().Send({on ? HapticCommand::Kind::kPause : HapticCommand::Kind::kResume});
  });
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(reset);
  buttons->addWidget(pause);
  form->addRow("Tool", buttons);
  layout->addLayout(form);
  layout->addWidget(new QLabel("Events"));
  events_ = new QListWidget;
  layout->addWidget(events_, 1);
  auto* help = new QLabel("Mouse device: Ctrl+drag moves the tool, Ctrl+Shift+drag turns it, Ctrl+wheel pushes it; "
                          "keys W/S, A/D, Q/E move it (with Shift: turn). Drag without Ctrl moves the camera.");
  help->setWordWrap(true);
  layout->addWidget(help);
  auto* dock = new QDockWidget("Instrument", this);
  dock->setObjectName("instrument");
  dock->setWidget(panel);
  dock->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetFloatable);
  addDockWidget(Qt::RightDockWidgetArea, dock);

  // Menus.
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("&Open scene...", this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Open scene", Q(scene_file_.parent_path().string()),
                                                   "Scenes (*.yaml *.yml)");
    if (!f.isEmpty()) OpenScene(f.toStdString());
  }, QKeySequence::Open);
  QAction* record = file->addAction("&Record session");
  record->setCheckable(true);
  connect(record, &QAction::toggled, this, [this, record](bool on) {
    if (!on) {
      StopRecording();
      return;
    }
    const QString f = QFileDialog::getSaveFileName(this, "Record to", "session.rec", "Recordings (*.rec)");
    if (f.isEmpty() || !StartRecording(f.toStdString())) record->setChecked(false);
  });
  file->addAction("Replay a recording...", this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Replay", "", "Recordings (*.rec)");
    if (!f.isEmpty()) SetDevice("replay:" + f.toStdString());
  });
  file->addAction("Save &screenshot...", this, [this] {
    const QString f = QFileDialog::getSaveFileName(this, "Screenshot", "sulcus.png", "PNG (*.png)");
    if (!f.isEmpty()) SaveScreenshot(f.toStdString());
  });
  file->addSeparator();
  file->addAction("&Quit", this, &QWidget::close, QKeySequence::Quit);
  statusBar()->showMessage("Open a scene (File > Open scene).");
}

void MainWindow::ShowErrors(const QString& title, const QString& text, const QString& details) {
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
               QString("%1 has %2 error(s); the current scene stays loaded.").arg(Q(file.string())).arg(e.errors().size()),
               details);
    return false;
  }
  // Compile off the UI thread; the dialog shows progress and can cancel.
  struct Job {
    std::mutex mutex;
    std::string stage;
    double fraction = 0;
    std::atomic<bool> cancel{false}, done{false};
    std::unique_ptr<CompiledScene> result;
    std::string error;
  };
  auto job = std::make_shared<Job>();
  std::thread worker([job, spec] {
    try {
      job->result = CompileScene(spec, DefaultCacheDir(), [job](std::string_view stage, double f) {
        std::lock_guard lock(job->mutex);
        job->stage = stage;
        job->fraction = f;
        return !job->cancel.load();
      });
    } catch (const BuildCancelled&) {
      job->error = "cancelled";
    } catch (const std::exception& e) {
      job->error = e.what();
    }
    job->done = true;
  });
  worker.detach();  // it only touches `job`, which it shares
  auto* progress = new QProgressDialog(QString("Building %1 ...").arg(Q(spec.name)), "Cancel", 0, 1000, this);
  progress->setWindowModality(Qt::WindowModal);
  progress->setMinimumDuration(300);
  auto* poll = new QTimer(progress);
  QEventLoop* waiter = wait ? new QEventLoop(this) : nullptr;
  connect(progress, &QProgressDialog::canceled, this, [job] { job->cancel = true; });
  connect(poll, &QTimer::timeout, this, [this, job, progress, poll, file, waiter] {
    {
      std::lock_guard lock(job->mutex);
      progress->setValue(static_cast<int>(job->fraction * 1000));
      progress->setLabelText(QString("Building sphere-trees: %1").arg(Q(job->stage)));
    }
    if (!job->done) return;
    poll->stop();  // once: deleteLater may wait for an event loop that never comes back
    progress->hide();
    progress->deleteLater();
    if (job->result) {
      StopSession();
      scene_ = std::move(job->result);
      scene_file_ = file;
      view_->Load(*scene_);
      sphere_level_->setValue(-1);
      QSettings().setValue("scene/last", Q(file.string()));
      StartSession();
      setWindowTitle(QString("Sulcus - %1").arg(Q(scene_->spec.name)));
    } else if (job->error != "cancelled") {
      ShowErrors("Scene could not be built", QString("%1 could not be built; the current scene stays loaded.").arg(Q(file.string())),
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
  if (const int i = device_box_->findText(Q(device)); i >= 0) device_box_->setCurrentIndex(i);
  QSettings().setValue("device/last", Q(device));
  if (!scene_) return true;
  StartSession();
  return device_error_.empty();
}

void MainWindow::StopSession() {
  if (session_) {
    const bool recorded = session_->recorder() != nullptr;
    try {
      session_->Stop();  // a session's end ends its recording: everything recorded is written
      if (recorded) statusBar()->showMessage(QString("Recorded %1 ticks").arg(session_->recorder()->written()));
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
    // The tool starts above the first tooth's crown, working end along its axis.
    const ScriptTarget top = FindScriptTarget(*scene_, "poke");
    auto mouse = std::make_unique<MouseKeyboardDevice>(
        RigidTransform(Quaternion::FromTwoVectors(Vector3::UnitZ(), top.n_W), top.p_W + 4.0 * top.n_W));
    mouse_ = mouse.get();
    DeviceSpec d;
    d.device = std::move(mouse);
    d.name = "mouse";
    return d;
  };
  DeviceSpec device;
  if (device_name_.rfind("scripted:", 0) == 0 || device_name_.rfind("replay:", 0) == 0) {
    try {
      device = MakeDevice(device_name_, *scene_, 600.0);
    } catch (const std::exception& e) {
      device_error_ = e.what();
      ShowErrors("Device", QString("The device %1 cannot be used.").arg(Q(device_name_)), Q(device_error_));
    }
  }
  if (!device.device) device = use_mouse();
  session_device_ = device.device->caps().name;
  snapshot_ = HapticSnapshot{};  // nothing from the previous session is shown as this one's
  gauge_->Clear();
  plot_->Clear();
  events_->clear();
  last_reading_.clear();
  SessionOptions so;
  so.record = recording_file_;
  so.device_name = device_name_;
  so.stop_when_device_finished = false;
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
  try {
    session_->Start();
  } catch (const std::exception& e) {
    device_error_ = e.what();
    ShowErrors("Device", QString("The device %1 cannot be started.").arg(Q(device_name_)), Q(device_error_));
    session_.reset();
    session_ = std::make_unique<Session>(*scene_, use_mouse(), so);
    session_->AddConsumer(&tap_);
    session_->Start();
  }
  statusBar()->showMessage(QString("%1 on %2%3")
                               .arg(Q(session_device_), Q(scene_file_.string()),
                                    session_->recorder() ? QString(", recording") : QString()));
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
  if (!session_) return;
  HapticLoop& loop = session_->loop();
  if (loop.snapshots().Acquire()) snapshot_ = loop.snapshots().front();
  view_->Update(snapshot_);
  gauge_->SetForce(snapshot_.force_W.norm());
  plot_->Push(snapshot_.time_s, snapshot_.force_W.norm(), snapshot_.torque_W.norm());
  session_->Pump();
  for (const HapticEvent& e : tap_.events) {
    const QString what = Q(DescribeEvent(scene_->spec, e));
    if (e.kind == EventKind::kProbeReading) last_reading_ = what;
    events_->insertItem(0, QString("%1 s  %2").arg(e.tick / scene_->spec.rate_hz, 0, 'f', 2).arg(what));
    while (events_->count() > 200) delete events_->takeItem(events_->count() - 1);
  }
  tap_.events.clear();
  status_->setText(status_text());
  vtk_widget_->renderWindow()->Render();
}

QString MainWindow::status_text() const {
  if (!session_ || !session_->thread()) return "No scene loaded.";
  const HapticThread& thread = *session_->thread();
  const TimingStats& st = thread.stats();
  const HapticSnapshot& s = snapshot_;
  QString text;
  text += QString("Device: %1%2\n").arg(Q(session_device_),
                                         s.device_ok ? "" : " (NOT ANSWERING)");
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
  if (sphere_level_->value() != level) sphere_level_->setValue(level);  // re-enters through the signal
  if (view_->spheres_shown() != level) {
    view_->ShowSpheres(level);
    vtk_widget_->renderWindow()->Render();
  }
}

QWidget* MainWindow::view_widget() const { return vtk_widget_; }

void MainWindow::SetGingivaTranslucent(bool on) { translucent_->setChecked(on); }

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

void MainWindow::keyPressEvent(QKeyEvent* e) {
  if (!mouse_) {
    QMainWindow::keyPressEvent(e);
    return;
  }
  const double step = 0.25, turn = 0.05;  // mm, rad per key press
  Vector3 d = Vector3::Zero();
  switch (e->key()) {
    case Qt::Key_D: d.x() = 1; break;
    case Qt::Key_A: d.x() = -1; break;
    case Qt::Key_W: d.y() = 1; break;
    case Qt::Key_S: d.y() = -1; break;
    case Qt::Key_E: d.z() = 1; break;
    case Qt::Key_Q: d.z() = -1; break;
    default: QMainWindow::keyPressEvent(e); return;
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
    double pos[3], focal[3], up[3];
    cam->GetPosition(pos);
    cam->GetFocalPoint(focal);
    cam->GetViewUp(up);
    const Vector3 eye(pos[0], pos[1], pos[2]), at(focal[0], focal[1], focal[2]);
    const Vector3 view = (at - eye).normalized();
    const Vector3 v_up = (Vector3(up[0], up[1], up[2]) - Vector3(up[0], up[1], up[2]).dot(view) * view).normalized();
    const Vector3 right = view.cross(v_up);
    // Millimetres per pixel at the tool's distance from the camera.
    const double depth = std::max(1.0, (mouse_->pose().translation() - eye).dot(view));
    const double mm_per_px = 2 * depth * std::tan(cam->GetViewAngle() * 0.5 * M_PI / 180) / std::max(1, vtk_widget_->height());
    if (e->type() == QEvent::Wheel) {
      auto* w = static_cast<QWheelEvent*>(e);
      if (!(w->modifiers() & Qt::ControlModifier)) return QMainWindow::eventFilter(watched, e);
      mouse_->Nudge(-0.5 * (w->angleDelta().y() / 120.0) * view, Vector3::Zero());
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
      case Qt::Key_W: case Qt::Key_A: case Qt::Key_S: case Qt::Key_D: case Qt::Key_Q: case Qt::Key_E:
        keyPressEvent(k);
        return true;
      default: break;
    }
  }
  return QMainWindow::eventFilter(watched, e);
}

void MainWindow::closeEvent(QCloseEvent* e) {
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState());
  StopSession();
  QMainWindow::closeEvent(e);
}

}  // namespace sulcus::ui
