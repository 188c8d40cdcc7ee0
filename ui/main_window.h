#pragma once
// The workbench window on the live haptic thread: the 3D view, the force gauge,
// the status panel, devices, recording, sphere-trees, camera views. The UI thread
// reads snapshots and events and sends commands; it never touches the engine's
// data (docs/architecture.md). Scenes compile off the UI thread behind a cancellable
// progress dialog; a scene with errors opens a dialog listing them all and the
// previous scene stays loaded.

#include <QMainWindow>
#include <QPoint>
#include <QString>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/haptics/effects.h"
#include "core/haptics/haptic_thread.h"
#include "core/haptics/recording.h"
#include "core/lesson/attempt.h"
#include "core/lesson/lesson.h"
#include "core/lesson/scripted_student.h"
#include "core/scene/scene.h"
#include "core/session/session.h"
#include "ui/scene_preparer.h"

class QCheckBox;
class QDialog;
class QDockWidget;
class QPushButton;
class QSlider;
class QComboBox;
class QLabel;
class QListWidget;
class QMessageBox;
class QSpinBox;
class QTimer;
class QVTKOpenGLNativeWidget;
class vtkGenericOpenGLRenderWindow;
class vtkRenderer;

namespace sulcus {
class MouseKeyboardDevice;
}  // namespace sulcus

namespace sulcus::ui {

class ChartWidget;
class OdontogramWidget;
class ForceGauge;
class ForcePlot;
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
  vtkRenderer* renderer() const { return renderer_; }
  MouseKeyboardDevice* mouse() const { return mouse_; }
  QWidget* view_widget() const;
  void ShowSpheres(int level);
  bool LookAtTooth(int fdi, bool lingual = false);
  /// The camera's axes in the world: right, up and into the screen (the keys
  /// move the probe along them).
  struct ViewAxes {
    Vector3 right, up, into, eye;
  };
  ViewAxes CameraAxes() const;
  /// Mouse and keyboard: the probe along a site's line, its tip this far above
  /// the margin (the press let go). False without the mouse or the site.
  bool PlaceProbeAt(const SiteRef& site, double above_margin_mm);
  /// The site N goes to and the camera follows: the chart's selected cell when
  /// it is a site of the lesson not yet charted (the student chose it), else
  /// the lesson's next site.
  std::optional<SiteRef> ProbeTarget() const;
  /// The press's step (R and F), N.
  static constexpr double kPressStepN = 0.02;
  void SetGingivaTranslucent(bool on);
  /// As the "hide lips and cheeks" box does.
  void SetLipsAndCheeksHidden(bool hidden);
  /// Saves the window (3D view included) as a PNG.
  bool SaveScreenshot(const std::filesystem::path& png);
  bool StartRecording(const std::filesystem::path& file);
  void StopRecording();

  // Lessons (the lesson engine, core/lesson): a lesson runs as one session,
  // recorded into its attempt's folder; the lesson is a consumer of its ticks.
  struct LessonStart {
    std::filesystem::path lesson;
    std::string student = "student";
    std::optional<LessonSpec::Mode> mode;  // empty: the lesson's
    std::string device =
        "mouse";  // or student:NAME (a scripted student), scripted:..., replay:...
    bool free_run = false;  // the thread as fast as it can (scripted students in tests)
    std::optional<std::uint64_t> seed;  // a generated case's
    std::filesystem::path results_dir;  // empty: DefaultResultsDir()
    std::string sign_in;  // the student's sign-in (StartDialog), kept with the attempt
  };
  /// Loads the lesson (its errors shown, nothing changed when it has any), builds
  /// its scene (waiting) and starts it. False when it could not start.
  bool StartLesson(const LessonStart& start);
  /// The start page (who, which lesson, which mode); starts the chosen lesson.
  const ScenePreparer& preparer() const { return preparer_; }
  /// Whether the loupe is shown (the tip in a sulcus, the box checked).
  bool loupe_shown() const;
  /// The start page; true when it started a lesson.
  bool ShowStartPage();
  /// Starts preparing the scene of `lesson` (with `seed`, or the lesson's own:
  /// a new case is drawn now and kept for its start) off the UI thread.
  void PrepareLesson(const std::filesystem::path& lesson,
                     std::optional<std::uint64_t> seed);
  void SetLessonFolders(std::vector<std::filesystem::path> dirs) {
    lesson_dirs_ = std::move(dirs);
  }
  bool DeclareDiagnosis(const DeclaredDiagnosis& d);
  /// Ends the lesson: the recording written, the attempt scored, its entries and
  /// report saved, stored in the results database, and the report shown.
  bool FinishLesson(bool show_report = true);
  /// Ends the lesson in progress as the student leaves it (`why` kept in the
  /// result when a step is left undone), stored, no report shown.
  void LeaveLesson(const std::string& why);
  /// Keeps the attempts that were started and never kept (Sulcus stopped
  /// mid-lesson): each rebuilt from its recording and entries, stored as
  /// incomplete, and the student told. Returns how many were kept.
  int RecoverUnfinishedAttempts(const std::filesystem::path& results_dir = {});
  /// The footer's line on how the tool is moved (it names the device that runs).
  QString device_help() const;
  /// The footer's results store: which it is and how many attempts wait for it.
  QString results_footer() const;
  void UpdateResultsFooter();
  const LessonRun* lesson() const { return lesson_.get(); }
  ChartWidget* chart() const { return chart_; }
  OdontogramWidget* odontogram() const { return odontogram_; }
  /// Inspection lessons: the odontogram submitted as complete (the button does this).
  bool SubmitFindings();
  /// The help (F1): for the lesson being taken (probing and charting, or the
  /// oral examination and its odontogram), or the topic asked for.
  enum class HelpTopic { kProbing, kInspection };
  QString HelpHtml(std::optional<HelpTopic> topic = std::nullopt) const;
  const std::optional<LessonResult>& last_result() const { return last_result_; }
  const std::filesystem::path& last_report() const { return last_report_; }
  QString lesson_text() const;
  /// The banner over the lesson panel (the device stopped answering), empty when hidden.
  QString banner_text() const;
  /// Wraps the device of every session started from now on (tests: a device
  /// that can be unplugged and plugged back in). Empty: the device as it is.
  using DeviceWrapper = std::function<std::unique_ptr<Device>(std::unique_ptr<Device>)>;
  void SetDeviceWrapper(DeviceWrapper wrap) { device_wrapper_ = std::move(wrap); }
  std::uint64_t frames() const { return frames_; }  // display frames drawn
  bool aids_locked() const { return aids_locked_; }
  QDialog* report_dialog() const { return report_dialog_; }

  // Replay of a recorded attempt: the recorded device tool (blue, the ghost) and
  // rendered tool in the view, play, pause, step, scrub and speed; the live
  // session is stopped meanwhile. A rubric line of the report opens it at its tick.
  bool OpenReplay(const std::filesystem::path& recording, std::uint64_t tick = 0);
  void CloseReplay();
  bool replaying() const { return replay_ != nullptr; }
  std::uint64_t replay_tick() const;
  const TickRecord* replay_frame() const;
  void SetReplayPlaying(bool on);
  /// An instructor's recorded demonstration played as a ghost probe while the
  /// student probes live, tick for tick from the session's start; empty stops it.
  bool SetDemonstration(const std::filesystem::path& recording);
  const std::optional<RigidTransform>& ghost_pose() const;
  /// A student's attempts over time (the results database); returns the dialog.
  QDialog* ShowProgress(const std::string& student,
                        const std::filesystem::path& results_dir = {});
  /// The instructor's view for this passphrase (set on first use); nullptr,
  /// after saying so, for a wrong one.
  QDialog* OpenInstructor(const std::string& passphrase,
                          const std::filesystem::path& results_dir = {});

 protected:
  void keyPressEvent(QKeyEvent* e) override;

  bool eventFilter(QObject* watched, QEvent* e) override;
  void closeEvent(QCloseEvent* e) override;

 private:
  void BuildUi();
  void StartSession();  // StopSession, then BeginSession
  void BeginSession();  // a loop and thread on the scene with the chosen device
  void StopSession();   // also ends a recording in progress
  void Tick();          // the display timer: snapshot -> view, gauge, status, events
  void ShowErrors(const QString& title, const QString& text, const QString& details);
  // `key` names what `spec` was made from (a lesson and its seed), so that a
  // preparation started for it on the start page is taken over; empty: the file.
  bool OpenSpec(const SceneSpec& spec, const std::filesystem::path& file, bool wait,
                const std::string& key = {});
  static std::string LessonKey(const std::filesystem::path& lesson, std::uint64_t seed);
  std::uint64_t LessonSeed(const LessonSpec& spec, const std::filesystem::path& lesson,
                           std::optional<std::uint64_t> chosen);
  void BuildLessonDock();
  void UpdateLessonPanel();
  void SetAidsLocked(bool locked);
  void AskDiagnosis();
  void ShowReport(const LessonResult& r, const std::filesystem::path& html);
  const ProbingSite* SceneSite(const SiteRef& s) const;
  QString HeldBackText() const;
  // The keys' tip: where the press has taken the hand, and the hand put so
  // that its tip is at X_WT with the press kept.
  RigidTransform KeyTipPose() const;
  // Blood at the margins the lesson shows (3D view and loupe).
  void ShowBlood(const std::vector<BloodMark>& marks);
  void PlaceKeyTip(const RigidTransform& X_WT);
  void UpdateLoupe(const std::optional<SiteRef>& tip);
  static constexpr double kHeldBackMm = 2.0;
  static constexpr int kDockLayoutVersion = 2;

  QVTKOpenGLNativeWidget* vtk_widget_ = nullptr;
  vtkRenderer* renderer_ = nullptr;
  std::unique_ptr<SceneView> view_;
  ForceGauge* gauge_ = nullptr;
  ForceGauge* lesson_gauge_ = nullptr;  // the same figure on the lesson's tab
  QDockWidget* instrument_dock_ = nullptr;
  ForcePlot* plot_ = nullptr;
  QLabel* status_ = nullptr;
  QListWidget* events_ = nullptr;
  QComboBox* device_box_ = nullptr;
  QSpinBox* sphere_level_ = nullptr;
  QCheckBox* translucent_ = nullptr;
  QCheckBox* loupe_box_ = nullptr;
  QCheckBox* lips_hidden_ = nullptr;
  QTimer* timer_ = nullptr;
  QMessageBox* error_dialog_ = nullptr;

  std::unique_ptr<CompiledScene> scene_;
  std::filesystem::path scene_file_;
  ScenePreparer preparer_;
  std::optional<std::pair<std::string, std::uint64_t>> drawn_seed_;  // lesson key, seed
  std::string device_name_ = "mouse";
  MouseKeyboardDevice* mouse_ = nullptr;  // the session's device when it is the mouse
  std::string session_device_;            // what the session's device calls itself
  std::filesystem::path recording_file_;  // a recording in progress
  std::unique_ptr<Session> session_;
  // The window's consumer of the tick stream: the events of the ticks pumped.
  struct EventTap final : TickConsumer {
    void OnTick(const TickRecord& r) override {
      events.insert(events.end(), r.events.begin(), r.events.begin() + r.num_events);
    }
    std::vector<HapticEvent> events;
  } tap_;
  std::vector<std::filesystem::path> lesson_dirs_;
  // The lesson in progress.
  std::optional<LessonSpec> lesson_spec_;
  std::unique_ptr<LessonRun> lesson_;
  std::unique_ptr<ScriptedHand>
      scripted_student_;  // a scripted student or inspector playing the hand
  LessonStart lesson_start_;
  std::uint64_t lesson_seed_ = 0;
  AttemptFolder attempt_;
  QDockWidget* lesson_dock_ = nullptr;
  QLabel *step_label_ = nullptr, *next_label_ = nullptr, *tip_label_ = nullptr,
         *tilt_label_ = nullptr;
  QLabel* banner_ = nullptr;  // the device stopped answering, ...
  DeviceWrapper device_wrapper_;
  QLabel* device_help_ = nullptr;
  QLabel* results_footer_ = nullptr;
  void UpdateDeviceHelp(const std::string& device);
  bool device_was_lost_ = false;
  void SaveEntriesSoFar();
  QListWidget* feedback_ = nullptr;
  ChartWidget* chart_ = nullptr;
  OdontogramWidget* odontogram_ = nullptr;
  std::size_t shown_findings_ = 0, views_sent_ = 0;
  ViewSample last_view_;
  QPushButton *diagnose_button_ = nullptr, *finish_button_ = nullptr;
  std::size_t feedback_shown_ = 0;
  int looked_at_ = 0;
  bool looked_lingual_ = false;
  bool aids_locked_ = false;
  std::optional<LessonResult> last_result_;
  std::filesystem::path last_report_;
  QDialog* report_dialog_ = nullptr;
  std::filesystem::path last_recording_;
  // The replay.
  std::unique_ptr<Recording> replay_;
  std::unique_ptr<Recording> demonstration_;
  std::size_t replay_index_ = 0;
  double replay_position_ = 0;  // fractional frame index while playing
  bool replay_playing_ = false;
  double replay_speed_ = 1.0;
  std::chrono::steady_clock::time_point replay_clock_;
  QDockWidget* replay_dock_ = nullptr;
  QSlider* replay_slider_ = nullptr;
  QPushButton* replay_play_ = nullptr;
  QLabel* replay_label_ = nullptr;
  void BuildReplayDock();
  void ShowReplayFrame();
  std::uint64_t frames_ = 0;
  HapticSnapshot snapshot_;
  std::string device_error_;
  QString last_reading_;
  bool dragging_ = false;
  QPoint drag_from_;
};

}  // namespace sulcus::ui
