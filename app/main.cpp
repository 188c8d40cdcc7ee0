// sulcus: the window. Opens a scene (the command line's, the last one, or the
// periodontal probing scene) with the mouse and keyboard or a scripted device.

#include <QApplication>
#include <QCommandLineParser>
#include <QSettings>
#include <QSurfaceFormat>
#include <QTimer>
#include <QVTKOpenGLNativeWidget.h>

#include <cstdio>
#include <filesystem>

#include "ui/main_window.h"

#ifndef SULCUS_SOURCE_DIR
#define SULCUS_SOURCE_DIR "."
#endif

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("Sulcus");
  QApplication::setApplicationName("Sulcus");
  QCommandLineParser cli;
  cli.setApplicationDescription("Sulcus: haptic dental training simulator");
  cli.addHelpOption();
  cli.addPositionalArgument("scene", "Scene file (default: the last one, or scenes/periodontal_probing.yaml)");
  QCommandLineOption device("device", "mouse, scripted:NAME or replay:FILE", "device");
  QCommandLineOption quit_after("quit-after", "Quit after this many seconds (demos, tests)", "seconds");
  QCommandLineOption screenshot("screenshot", "Save a screenshot here just before quitting", "png");
  cli.addOptions({device, quit_after, screenshot});
  cli.process(app);

  std::filesystem::path scene;
  if (!cli.positionalArguments().isEmpty()) {
    scene = cli.positionalArguments().front().toStdString();
  } else if (const QString last = QSettings().value("scene/last").toString(); !last.isEmpty() &&
                                                                              std::filesystem::exists(last.toStdString())) {
    scene = last.toStdString();
  } else {
    scene = std::filesystem::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml";
  }
  sulcus::ui::MainWindow window;
  window.show();
  window.SetDevice(cli.isSet(device) ? cli.value(device).toStdString()
                                     : QSettings().value("device/last", "mouse").toString().toStdString());
  QTimer::singleShot(0, &window, [&] { window.OpenScene(scene); });
  if (cli.isSet(quit_after)) {
    QTimer::singleShot(static_cast<int>(cli.value(quit_after).toDouble() * 1000), &window, [&] {
      if (cli.isSet(screenshot)) window.SaveScreenshot(cli.value(screenshot).toStdString());
      std::printf("%s\n", window.status_text().toStdString().c_str());
      window.close();
    });
  }
  return app.exec();
}
