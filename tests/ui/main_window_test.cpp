// The real window on the probing scene with a scripted device, under Xvfb.
// Screenshots go to the build tree (test-output/ui); the assertions are on the
// window's state.
#include "ui/main_window.h"

#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkRenderer.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QKeyEvent>
#include <QMessageBox>
#include <QMouseEvent>
#include <QScrollArea>
#include <QScrollBar>
#include <QSurfaceFormat>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/anatomy/soft_tissue.h"
#include "core/haptics/recording.h"
#include "tests/common/output.h"
#include "ui/chart_widget.h"
#include "ui/mouse_device.h"
#include "ui/scene_view.h"

namespace sulcus::ui {
namespace {

namespace fs = std::filesystem;

fs::path Out(const std::string& name) { return test::OutputPath("ui", name); }

void RunFor(int ms) {
  QElapsedTimer t;
  t.start();
  while (t.elapsed() < ms) QApplication::processEvents(QEventLoop::AllEvents, 10);
}

TEST(MainWindow, ProbingSceneWithAScriptedDevice) {
  MainWindow w;
  w.resize(1280, 800);
  w.show();
  w.SetDevice("scripted:poke");
  ASSERT_TRUE(w.OpenScene(
      fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml", true));
  ASSERT_NE(w.scene(), nullptr);
  RunFor(300);
  ASSERT_TRUE(w.SaveScreenshot(Out("start_view.png")));
  const Vector3 start = w.last_snapshot().X_WH.translation();
  // The poke presses on the crown once a second: the tool travels 4.5 mm. Wait
  // for it (and for a second of ticks), up to a generous bound: on a loaded
  // machine the window's frames come late, and wall time says nothing here.
  double travel = 0;
  QElapsedTimer t;
  t.start();
  while (t.elapsed() < 8000 && (travel <= 2.0 || w.last_snapshot().tick <= 1000)) {
    QApplication::processEvents(QEventLoop::AllEvents, 5);
    travel = std::max(travel, (w.last_snapshot().X_WH.translation() - start).norm());
  }
  const HapticSnapshot& s = w.last_snapshot();
  EXPECT_TRUE(w.running());
  EXPECT_GT(travel, 2.0) << "the device tool moved";
  EXPECT_GT(s.tick, 1000u);
  EXPECT_DOUBLE_EQ(w.gauge_force(),
                   std::max(0.0, s.force_W.dot(s.X_WG.rotation().col(2))))
      << "the gauge shows the engine's force along the probe";
  EXPECT_TRUE(w.status_text().contains("Haptic rate 1000 Hz"))
      << w.status_text().toStdString();
  EXPECT_TRUE(w.device_help().contains("scripted:poke, not your hand"))
      << w.device_help().toStdString();
  EXPECT_FALSE(w.device_help().contains("Ctrl+drag"))
      << "the footer describes the device that runs";
  EXPECT_LE(w.minimumSizeHint().height(), 740)
      << "fits a 1366 x 768 laptop screen with its panel";
  EXPECT_TRUE(w.LookAtTooth(44));
  EXPECT_FALSE(w.LookAtTooth(11));
  ASSERT_TRUE(w.SaveScreenshot(Out("probe_on_tooth.png")));

  // The probe in the buccal sulcus of 46: the scripted insert rests at the pocket
  // floor from 1.5 s to 2.5 s of loop time, with the clinical probing force.
  w.SetDevice("scripted:insert");
  EXPECT_TRUE(w.LookAtTooth(46));
  w.SetGingivaTranslucent(true);  // to see the probe in the sulcus
  // Wait for the dwell at the floor (1.5 to 2.5 s of every 4 s) with the output
  // fully ramped in (a late tick on a loaded machine restarts the 0.5 s ramp).
  auto at_floor = [&] {
    const HapticSnapshot& s = w.last_snapshot();
    const double phase = std::fmod(s.time_s, 4.0);
    return phase > 2.0 && phase < 2.4 && s.output_scale == 1.0;
  };
  QElapsedTimer waited;
  waited.start();
  while (!at_floor() && waited.elapsed() < 30000)
    QApplication::processEvents(QEventLoop::AllEvents, 5);
  ASSERT_TRUE(at_floor()) << "t = " << w.last_snapshot().time_s;
  // The floor pushes back along the probe with the clinical probing force,
  // which the gauge shows; the whole force the hand feels also holds the
  // sulcus' soft wall pushing sideways on the tilted shank.
  {
    const HapticSnapshot& s = w.last_snapshot();
    const double along = s.force_W.dot(s.X_WG.rotation().col(2));
    EXPECT_GE(w.gauge_force(), 0.20) << "inside the clinical probing band";
    EXPECT_LE(w.gauge_force(), 0.25) << "inside the clinical probing band";
    EXPECT_NEAR(w.gauge_force(), along, 1e-12);
    EXPECT_LE(s.force_W.norm(), 0.5) << "the wall's push on the shank is gentle";
  }
  {
    // The plot fills as display frames come: wait for it, not for a time (a loaded
    // machine draws fewer frames).
    QElapsedTimer plot_wait;
    plot_wait.start();
    while (w.plot_rows() < 5 && plot_wait.elapsed() < 60000)
      QApplication::processEvents(QEventLoop::AllEvents, 5);
  }
  EXPECT_GE(w.plot_rows(), 5) << "the VTK chart holds the last seconds";
  ASSERT_TRUE(w.SaveScreenshot(Out("probe_in_sulcus.png")));
  RunFor(1500);  // out again: the reading
  ASSERT_TRUE(w.last_reading().startsWith("reading ")) << w.last_reading().toStdString();
  EXPECT_NEAR(w.last_reading().section(' ', 1, 1).toDouble(), 4.0, 0.3)
      << "the scene's 4 mm pocket at 46 B";
  EXPECT_TRUE(w.last_reading().contains("at 46 B (")) << w.last_reading().toStdString();

  // The mouse and keyboard device: Ctrl + drag moves the tool, W moves it +y.
  w.SetDevice("mouse");
  ASSERT_NE(w.mouse(), nullptr);
  EXPECT_TRUE(w.device_help().contains("Ctrl+drag moves the tool"))
      << w.device_help().toStdString();
  const Vector3 tool_before = w.mouse()->pose().translation();
  QWidget* view = w.view_widget();
  const QPoint c = view->rect().center();
  QMouseEvent press(QEvent::MouseButtonPress, c, Qt::LeftButton, Qt::LeftButton,
                    Qt::ControlModifier);
  QMouseEvent move(QEvent::MouseMove, c + QPoint(60, 0), Qt::NoButton, Qt::LeftButton,
                   Qt::ControlModifier);
  QMouseEvent release(QEvent::MouseButtonRelease, c + QPoint(60, 0), Qt::LeftButton,
                      Qt::NoButton, Qt::ControlModifier);
  QApplication::sendEvent(view, &press);
  QApplication::sendEvent(view, &move);
  QApplication::sendEvent(view, &release);
  const Vector3 dragged = w.mouse()->pose().translation();
  EXPECT_GT((dragged - tool_before).norm(), 1.0)
      << "60 pixels of Ctrl + drag move the tool millimetres";
  // W moves the tool up the screen, whatever the camera: 0.1 mm a press.
  const Vector3 up = w.CameraAxes().up;
  QKeyEvent key(QEvent::KeyPress, Qt::Key_W, Qt::NoModifier);
  QApplication::sendEvent(view, &key);
  EXPECT_NEAR((w.mouse()->pose().translation() - dragged - 0.1 * up).norm(), 0, 1e-9)
      << "0.1 mm a press, up on the screen";
  QKeyEvent fine(QEvent::KeyPress, Qt::Key_W, Qt::AltModifier);
  QApplication::sendEvent(view, &fine);
  EXPECT_NEAR((w.mouse()->pose().translation() - dragged - 0.12 * up).norm(), 0, 1e-9)
      << "with Alt, 0.02 mm";
  // Q moves it into the screen.
  const Vector3 before_q = w.mouse()->pose().translation();
  QKeyEvent into(QEvent::KeyPress, Qt::Key_Q, Qt::NoModifier);
  QApplication::sendEvent(view, &into);
  EXPECT_NEAR(
      (w.mouse()->pose().translation() - before_q - 0.1 * w.CameraAxes().into).norm(), 0,
      1e-9);
  RunFor(100);
  EXPECT_LT(
      (w.last_snapshot().X_WH.translation() - w.mouse()->pose().translation()).norm(),
      kPositionStepMm)
      << "the haptic thread reads what the window set (on the recording grid)";

  // Recording on and off: the file holds the session's ticks.
  const fs::path rec = Out("window_session.rec");
  ASSERT_TRUE(w.StartRecording(rec));
  RunFor(400);
  w.StopRecording();
  EXPECT_TRUE(w.running()) << "the session goes on after the recording";
  const Recording recorded = ReadRecording(rec);
  EXPECT_GT(recorded.frames.size(), 100u);
  EXPECT_EQ(recorded.header.device_name, "mouse");

  w.ShowSpheres(3);
  EXPECT_EQ(w.view()->spheres_shown(), 3);
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("sphere_tree_view.png")));
  w.ShowSpheres(-1);

  // A scene with errors: a dialog lists them; the loaded scene stays.
  const fs::path bad = Out("bad_scene.yaml");
  std::ofstream(bad) << "objects:\n  - tooth: 19\n  - tooth: 46\n    pockets_mm: [2, 2, "
                        "2, 2, 2]\n  - box: [1, 1]\n";
  const CompiledScene* before = w.scene();
  EXPECT_FALSE(w.OpenScene(bad, true));
  EXPECT_EQ(w.scene(), before);
  ASSERT_NE(w.error_dialog(), nullptr);
  EXPECT_TRUE(w.error_dialog()->isVisible());
  const QString listed = w.error_dialog()->informativeText();
  EXPECT_TRUE(listed.contains(QString::fromStdString(bad.string() + ":2:")))
      << listed.toStdString();
  EXPECT_TRUE(listed.contains("FDI 19 does not exist")) << listed.toStdString();
  EXPECT_TRUE(listed.contains("found 5")) << listed.toStdString();
  EXPECT_TRUE(listed.contains("needs a 'tissue'")) << listed.toStdString();
  EXPECT_EQ(listed.count('\n'), 4) << listed.toStdString();
  RunFor(100);
  w.error_dialog()->grab().save(QString::fromStdString(Out("error_dialog.png").string()));
  EXPECT_TRUE(w.running()) << "the previous scene keeps running";
}

TEST(MainWindow, TheFullMouthIsSeenFromWhereADentistLooks) {
  MainWindow w;
  w.resize(1280, 760);
  w.show();
  w.SetDevice("mouse");
  ASSERT_TRUE(
      w.OpenScene(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml", true));
  RunFor(200);
  // Looking at a lower molar from the buccal side passes through the cheek: it turns
  // see-through.
  ASSERT_TRUE(w.LookAtTooth(36));
  EXPECT_GE(w.view()->see_through(), 1) << "the cheek in front of 36";
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("full_mouth_36.png")));
  // The occlusal view looks down on the lower arch, the incisors at the top of the
  // picture.
  w.view()->View(SceneView::Side::kOcclusal);
  double up[3], from[3], to[3];
  w.renderer()->GetActiveCamera()->GetViewUp(up);
  w.renderer()->GetActiveCamera()->GetPosition(from);
  w.renderer()->GetActiveCamera()->GetFocalPoint(to);
  EXPECT_GT(from[2] - to[2], 0) << "from above (the lower arch's occlusal side)";
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("full_mouth_occlusal.png")));
}

// The anatomy as a dentist looks at it: saved pictures to look at, with the
// view's state checked.
TEST(MainWindow, TheMouthFromTheFrontEachArchAndTheFindingsUpClose) {
  MainWindow w;
  w.resize(1280, 760);
  w.show();
  w.SetDevice("mouse");
  ASSERT_TRUE(
      w.OpenScene(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml", true));
  RunFor(200);
  SceneView* v = w.view();
  // From the front with the lips and cheeks held back.
  w.SetLipsAndCheeksHidden(true);
  EXPECT_TRUE(v->lips_and_cheeks_hidden()) << "the box hides them in the view";
  v->View(SceneView::Side::kFront);
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("mouth_front_retracted.png")));
  // And with them: the lips in front of the teeth.
  w.SetLipsAndCheeksHidden(false);
  EXPECT_FALSE(v->lips_and_cheeks_hidden());
  v->View(SceneView::Side::kFront);
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("mouth_front.png")));
  // Each arch occlusally: the upper from below, the lower arch and tongue faded.
  w.SetLipsAndCheeksHidden(true);
  v->View(SceneView::Side::kUpperOcclusal);
  double from[3], to[3];
  w.renderer()->GetActiveCamera()->GetPosition(from);
  w.renderer()->GetActiveCamera()->GetFocalPoint(to);
  EXPECT_LT(from[2] - to[2], 0) << "from below (the upper arch's occlusal side)";
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("upper_arch_occlusal.png")));
  v->View(SceneView::Side::kOcclusal);
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("lower_arch_occlusal.png")));
  // Caries up close: 36's occlusal and buccal lesions, 26's mesial one.
  const auto tooth_at = [&](int fdi) {
    for (const ObjectSpec& o : w.scene()->spec.objects)
      if (o.kind == ObjectSpec::Kind::kTooth && o.fdi == fdi) return o.X_WO;
    return RigidTransform();
  };
  const RigidTransform X36 = tooth_at(36);
  v->LookAt(X36 * Vector3(0, 1.5, 6), X36.rotation() * Vector3(0, 0.8, 1), 22,
            X36.rotation() * Vector3(1, 0, 0));
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("caries_36.png")));
  // Calculus on the lingual surfaces of the lower incisors, seen from behind them.
  const RigidTransform X31 = tooth_at(31);
  v->LookAt(X31 * Vector3(-2.5, -2, 1.5), X31.rotation() * Vector3(0, -1, 0.9), 26,
            X31.rotation() * Vector3(0, 0, 1));
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("calculus_31_41.png")));
  // The ulcer on the tongue's left lateral border, from above its left side.
  const TriangleMesh* tongue = nullptr;
  for (std::size_t i = 0; i < w.scene()->spec.objects.size(); ++i)
    if (w.scene()->spec.objects[i].anatomy == "tongue") tongue = &w.scene()->meshes[i];
  ASSERT_NE(tongue, nullptr);
  const Vector3 ulcer = LesionCentre("tongue", "lateral_border_left", *tongue);
  v->LookAt(ulcer, Vector3(0.55, 0.1, 1), 40, Vector3::UnitY());
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("ulcer_tongue.png")));
  // The probing sextant: recession and deep pockets at 46, its furcation above the
  // bone (7 mm pockets and 1 mm recession), seen through translucent gingiva.
  ASSERT_TRUE(w.OpenScene(
      fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml", true));
  RunFor(200);
  ASSERT_TRUE(w.LookAtTooth(46));
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("sextant_46.png")));
  w.SetGingivaTranslucent(true);
  const RigidTransform X46 = tooth_at(46);
  w.view()->LookAt(X46 * Vector3(0, 0, -2.5), X46.rotation() * Vector3(0, 1, 0.15), 40,
                   X46.rotation() * Vector3(0, 0, 1));
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("furcation_46.png")));
}

}  // namespace
}  // namespace sulcus::ui

namespace sulcus::ui {
namespace {

void Press(QWidget* w, int key, const QString& text,
           Qt::KeyboardModifiers mods = Qt::NoModifier) {
  QKeyEvent press(QEvent::KeyPress, key, mods, text);
  QApplication::sendEvent(w, &press);
}

// Two-digit depths without ambiguity: "1" then "5" are two sites; "+" then "5"
// is 15 mm, which waits for Enter (over 12 mm); Esc cancels it. The CAL row is
// never truncated (the widget paints PD + GM).
TEST(ChartWidget, TwoDigitDepthsByAPrefixAndAConfirmationAbove12) {
  ChartWidget chart;
  const std::vector<SiteRef> path = {{46, 2}, {46, 1}, {46, 0}, {47, 2}};
  chart.SetLesson({46, 47}, path, {{{46, 2}, -0.5}});
  std::vector<ChartEntry> got;
  chart.on_entry = [&](const ChartEntry& e) { got.push_back(e); };
  Press(&chart, Qt::Key_1, "1");
  Press(&chart, Qt::Key_5, "5");
  ASSERT_EQ(got.size(), 2u) << "two keys, two sites";
  EXPECT_EQ(*got[0].pd_mm, 1);
  EXPECT_EQ(*got[1].pd_mm, 5);
  Press(&chart, Qt::Key_Plus, "+");
  Press(&chart, Qt::Key_2, "2");
  ASSERT_EQ(got.size(), 3u) << "12 mm needs no confirmation";
  EXPECT_EQ(*got[2].pd_mm, 12);
  Press(&chart, Qt::Key_Plus, "+");
  Press(&chart, Qt::Key_5, "5");
  EXPECT_EQ(got.size(), 3u) << "15 mm waits";
  ASSERT_TRUE(chart.pending());
  EXPECT_EQ(*chart.pending(), 15);
  Press(&chart, Qt::Key_Escape, "");
  EXPECT_FALSE(chart.pending());
  EXPECT_EQ(got.size(), 3u) << "cancelled";
  Press(&chart, Qt::Key_5, "%", Qt::ShiftModifier);  // Shift+5: 15 as well
  ASSERT_TRUE(chart.pending());
  Press(&chart, Qt::Key_Return, "\r");
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(*got[3].pd_mm, 15);
  EXPECT_EQ(got[3].site, (SiteRef{47, 2}));
}

// The whole mouth's chart is taller than its panel: as the cursor goes on to
// the lower arch the panel scrolls down to it, and back up with the upper.
TEST(ChartWidget, ThePanelFollowsTheCursorThroughTheWholeMouth) {
  std::vector<int> teeth;
  for (int q = 1; q <= 4; ++q)
    for (int p = 1; p <= 7; ++p) teeth.push_back(q * 10 + p);
  QScrollArea area;
  area.setWidgetResizable(true);
  auto* chart = new ChartWidget;
  area.setWidget(chart);
  area.resize(380, 300);
  area.show();
  chart->SetLesson(teeth, StandardPath(teeth), {});
  QApplication::processEvents();
  ASSERT_GT(chart->height(), area.viewport()->height()) << "the chart must be taller";
  EXPECT_TRUE(chart->wrapped()) << "a whole arch in 380 px is split at the midline";
  EXPECT_EQ(area.verticalScrollBar()->value(), 0);
  // The upper arch: 14 teeth, 84 sites; then the lower's first.
  for (int i = 0; i < 85; ++i) Press(chart, Qt::Key_2, "2");
  QApplication::processEvents();
  ASSERT_TRUE(chart->cursor());
  EXPECT_GE(chart->cursor()->fdi / 10, 3) << "on the lower arch";
  EXPECT_GT(area.verticalScrollBar()->value(), 0) << "scrolled down to the lower arch";
  const int down = area.verticalScrollBar()->value();
  chart->SetProbing(SiteRef{17, 2});
  QApplication::processEvents();
  EXPECT_LT(area.verticalScrollBar()->value(), down) << "back up to 17 being probed";
}

// No pocket reads 0 mm: "0" alone enters nothing and says why; "+ 0" is 10 mm.
TEST(ChartWidget, ZeroAloneIsNotADepth) {
  ChartWidget chart;
  chart.SetLesson({46}, {{46, 2}, {46, 1}}, {});
  std::vector<ChartEntry> got;
  chart.on_entry = [&](const ChartEntry& e) { got.push_back(e); };
  Press(&chart, Qt::Key_0, "0");
  EXPECT_TRUE(got.empty());
  EXPECT_TRUE(chart.zero_refused());
  Press(&chart, Qt::Key_3, "3");
  ASSERT_EQ(got.size(), 1u);
  EXPECT_FALSE(chart.zero_refused());
  EXPECT_EQ(got[0].site, (SiteRef{46, 2})) << "the cursor did not move on 0";
  Press(&chart, Qt::Key_Plus, "+");
  Press(&chart, Qt::Key_0, "0");
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(*got[1].pd_mm, 10);
}

}  // namespace
}  // namespace sulcus::ui

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("SulcusTest");
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
