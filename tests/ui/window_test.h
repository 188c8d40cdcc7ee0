#pragma once
// What the window tests share: where their pictures and lessons are, and a
// wait that runs the event loop.

#include <QApplication>
#include <QElapsedTimer>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "tests/common/output.h"

namespace sulcus::ui::window_test {

inline std::filesystem::path Out(const std::string& name) {
  return test::OutputPath("ui", name);
}
inline std::filesystem::path Lessons() {
  return std::filesystem::path(SULCUS_SOURCE_DIR) / "lessons";
}

// Runs the event loop until `done` holds (or a generous limit passes, which
// fails). Between rounds it sleeps a few milliseconds, as an idle event loop
// does: spinning would take a core from the workers a window test times.
template <class F>
bool WaitFor(F done, int limit_ms = 240000) {
  QElapsedTimer t;
  t.start();
  while (!done()) {
    if (t.elapsed() > limit_ms) return false;
    QApplication::processEvents(QEventLoop::AllEvents, 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(4));
  }
  return true;
}

}  // namespace sulcus::ui::window_test
