#pragma once
// The workbench window on the live haptic thread: the 3D view, the force gauge,
// the status panel, devices, recording, sphere-trees, camera views. The UI thread
// reads snapshots and events and sends commands; it never touches the engine's
// data (DESIGN.md). Scenes compile off the UI thread behind a cancellable
// progress dialog; a scene with errors opens a dialog listing them all and the
// previous scene stays loaded.

#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <QMainWindow>
#include <QPoint>
#include <QString>

#include "core/haptics/effects.h"
#include "core/haptics/haptic_thread.h"
#include "core/haptics/recording.h"
#include "core/scene/scene.h"
#include "core/session/session.h"

class QCheckBox;
class QComboBox;
class QLabel;
class QListWidget;
class QMessageBox;
class QSpinBox;
class QTimer;
class QVTKOpenGLNativeWidget;
class vtkGenericOpenGLRenderWindow;
class vtkRenderer;

namespace sulcus::ui {

class ForceGauge;
class ForcePlot;
class MouseKeyboardDevice;
class SceneView;

class MainWindow : public QMainWindow {
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Validates the scene now and compiles it off the UI thread; returns false
  /// (after showing the errors) when the file has errors. `wait` blocks (with the
  /// event loop running) until the compile ends (tests, the command line).
  bool OpenScene(const std::filesystem::path& file, bool wait = false);
  /// "mouse", "scripted:NAME" or "replay:FILE"; applies to the current scene.
  bool SetDevice(const std::string& device);

  // State, for tests and the status bar.
  const CompiledScene* scene() const { return scene_.get(); }
  const HapticSnapshot& last_snapshot() const { return snapshot_; }
  double gauge_force() const;
  int plot_rows() const;
  bool running() const { return session_ && session_->running(); }
  QMessageBox* error_dialog() const { return error_dialog_; }
  QString status_text() const;
  const QString& last_reading() const { return last_reading_; }
  SceneView* view() const { return view_.get(); }
  MouseKeyboardDevice* mouse() const { return mouse_; }
  QWidget* view_widget() const;
  void ShowSpheres(int level);
  bool LookAtTooth(int fdi);
  void SetGingivaTranslucent(bool on);
  /// Saves the window (3D view included) as a PNG.
  bool SaveScreenshot(const std::filesystem::path& png);
  bool StartRecording(const std::filesystem::path& file);
  void StopRecording();

 protected:
  void keyPressEvent(QKeyEvent* e) override;
  bool eventFilter(QObject* watched, QEvent* e) override;
  void closeEvent(QCloseEvent* e) override;

 private:
  void BuildUi();
  void StartSession();  // StopSession, then BeginSession
  void BeginSession();  // a loop and thread on the scene with the chosen device
  void StopSession();   // also ends a recording in progress
  void Tick();  // the display timer: snapshot -> view, gauge, status, events
  void ShowErrors(const QString& title, const QString& text, const QString& details);

  QVTKOpenGLNativeWidget* vtk_widget_ = nullptr;
  vtkRenderer* renderer_ = nullptr;
  std::unique_ptr<SceneView> view_;
  ForceGauge* gauge_ = nullptr;
  ForcePlot* plot_ = nullptr;
  QLabel* status_ = nullptr;
  QListWidget* events_ = nullptr;
  QComboBox* device_box_ = nullptr;
  QSpinBox* sphere_level_ = nullptr;
  QCheckBox* translucent_ = nullptr;
  QTimer* timer_ = nullptr;
  QMessageBox* error_dialog_ = nullptr;

  std::unique_ptr<CompiledScene> scene_;
  std::filesystem::path scene_file_;
  std::string device_name_ = "mouse";
  MouseKeyboardDevice* mouse_ = nullptr;  // the session's device when it is the mouse
  std::string session_device_;            // what the session's device calls itself
  std::filesystem::path recording_file_;  // a recording in progress
  std::unique_ptr<Session> session_;
  // The window's consumer of the tick stream: the events of the ticks pumped.
  struct EventTap final : TickConsumer {
    void OnTick(const TickRecord& r) override { events.insert(events.end(), r.events.begin(), r.events.begin() + r.num_events); }
    std::vector<HapticEvent> events;
  } tap_;
  HapticSnapshot snapshot_;
  std::string device_error_;
  QString last_reading_;
  bool dragging_ = false;
  QPoint drag_from_;
};

}  // namespace sulcus::ui
