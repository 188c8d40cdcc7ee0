// sulcus: the window. Opens on the start page (who, which lesson, which mode)
// over the last scene; or on a scene given on the command line (the workbench),
// or straight into a lesson (--lesson).

#include <QVTKOpenGLNativeWidget.h>

#include <QApplication>
#include <QCommandLineParser>
#include <QSettings>
#include <QSurfaceFormat>
#include <QTimer>
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
  cli.addPositionalArgument(
      "scene", "Scene file (default: the last one, or scenes/periodontal_probing.yaml)");
  QCommandLineOption device("device", "mouse, scripted:NAME or replay:FILE", "device");
  QCommandLineOption quit_after("quit-after",
                                "Quit after this many seconds (demos, tests)", "seconds");
  QCommandLineOption screenshot("screenshot",
                                "Save a screenshot here just before quitting", "png");
  QCommandLineOption lesson("lesson", "Start this lesson at once (no start page)",
                            "file");
  QCommandLineOption student("student", "Who takes the lesson", "name");
  QCommandLineOption workbench("workbench",
                               "Open the scene without a lesson (no start page)");
  cli.addOptions({device, quit_after, screenshot, lesson, student, workbench});
  cli.process(app);

  std::filesystem::path scene;
  const bool scene_given = !cli.positionalArguments().isEmpty();
  if (scene_given) {
    scene = cli.positionalArguments().front().toStdString();
  } else if (const QString last = QSettings().value("scene/last").toString();
             !last.isEmpty() && std::filesystem::exists(last.toStdString())) {
    scene = last.toStdString();
  } else {
    scene =
        std::filesystem::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml";
  }
  sulcus::ui::MainWindow window;
  window.SetLessonFolders({std::filesystem::path(SULCUS_SOURCE_DIR) / "lessons"});
  window.show();
  // A new student starts with the mouse, never with the last run's script.
  window.SetDevice(cli.isSet(device) ? cli.value(device).toStdString() : "mouse");
  QTimer::singleShot(0, &window, [&] {
    if (cli.isSet(lesson)) {
      sulcus::ui::MainWindow::LessonStart s;
      s.lesson = cli.value(lesson).toStdString();
      if (cli.isSet(student)) s.student = cli.value(student).toStdString();
      if (cli.isSet(device)) s.device = cli.value(device).toStdString();
      if (!window.StartLesson(s)) window.OpenScene(scene);
      return;
    }
    // The start page, unless a scene was asked for: who, which lesson, which
    // mode. Nothing is built in front of it: the lesson picked is prepared in
    // the background while the student types, and the workbench's scene only
    // when the workbench is chosen.
    if (!scene_given && !cli.isSet(workbench) && !cli.isSet(quit_after)) {
      if (!window.ShowStartPage()) window.OpenScene(scene);
      return;
    }
    window.OpenScene(scene);
  });
  if (cli.isSet(quit_after)) {
    QTimer::singleShot(static_cast<int>(cli.value(quit_after).toDouble() * 1000), &window,
                       [&] {
                         if (cli.isSet(screenshot))
                           window.SaveScreenshot(cli.value(screenshot).toStdString());
                         std::printf("%s\n", window.status_text().toStdString().c_str());
                         window.close();
                       });
  }
  return app.exec();
}
