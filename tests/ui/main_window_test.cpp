// The real window on the probing scene with a scripted device, under Xvfb.
// Screenshots go to the build tree (test-output/ui); the assertions are on the
// window's state.
#include "ui/main_window.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QMessageBox>
#include <QSurfaceFormat>
#include <QVTKOpenGLNativeWidget.h>

#include <filesystem>
#include <fstream>

#include "ui/scene_view.h"

namespace sulcus::ui {
namespace {

namespace fs = std::filesystem;

fs::path Out(const std::string& name) {
  const fs::path dir = fs::path(SULCUS_TEST_OUTPUT) / "ui";
  fs::create_directories(dir);
  return dir / name;
}

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
  ASSERT_TRUE(w.OpenScene(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml", true));
  ASSERT_NE(w.scene(), nullptr);
  RunFor(300);
  ASSERT_TRUE(w.SaveScreenshot(Out("start_view.png")));
  const RigidTransform start = w.last_snapshot().X_WG;
  // The poke presses on the crown about one second in.
  RunFor(1200);
  const HapticSnapshot& s = w.last_snapshot();
  EXPECT_TRUE(w.running());
  EXPECT_GT((s.X_WH.translation() - start.translation()).norm(), 0.5) << "the device tool moved";
  EXPECT_GT(s.tick, 1000u);
  EXPECT_DOUBLE_EQ(w.gauge_force(), s.force_W.norm()) << "the gauge shows the engine's force";
  EXPECT_TRUE(w.status_text().contains("Haptic rate 1000 Hz")) << w.status_text().toStdString();
  EXPECT_TRUE(w.LookAtTooth(44));
  EXPECT_FALSE(w.LookAtTooth(11));
  ASSERT_TRUE(w.SaveScreenshot(Out("probe_on_tooth.png")));

  w.ShowSpheres(3);
  EXPECT_EQ(w.view()->spheres_shown(), 3);
  RunFor(100);
  ASSERT_TRUE(w.SaveScreenshot(Out("sphere_tree_view.png")));
  w.ShowSpheres(-1);

  // A scene with errors: a dialog lists them; the loaded scene stays.
  const fs::path bad = Out("bad_scene.yaml");
  std::ofstream(bad) << "objects:\n  - tooth: 19\n  - tooth: 46\n    pockets_mm: [2, 2, 2, 2, 2]\n  - box: [1, 1]\n";
  const CompiledScene* before = w.scene();
  EXPECT_FALSE(w.OpenScene(bad, true));
  EXPECT_EQ(w.scene(), before);
  ASSERT_NE(w.error_dialog(), nullptr);
  EXPECT_TRUE(w.error_dialog()->isVisible());
  const QString listed = w.error_dialog()->informativeText();
  EXPECT_TRUE(listed.contains(QString::fromStdString(bad.string() + ":2:"))) << listed.toStdString();
  EXPECT_TRUE(listed.contains("FDI 19 does not exist")) << listed.toStdString();
  EXPECT_TRUE(listed.contains("found 5")) << listed.toStdString();
  EXPECT_TRUE(listed.contains("needs a 'tissue'")) << listed.toStdString();
  EXPECT_EQ(listed.count('\n'), 4) << listed.toStdString();
  RunFor(100);
  w.error_dialog()->grab().save(QString::fromStdString(Out("error_dialog.png").string()));
  EXPECT_TRUE(w.running()) << "the previous scene keeps running";
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
