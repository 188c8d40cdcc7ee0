#pragma once
// A scene prepared off the UI thread: its meshes and sphere-trees (through the
// cache) and the gingiva as drawn. The window starts one as soon as it knows
// which scene comes next (the lesson picked on the start page), so the student
// goes on typing while it builds, and takes the result when the lesson starts.

#include <QString>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/scene/scene.h"

namespace sulcus::ui {

class ScenePreparer {
 public:
  /// One preparation; its worker thread shares it, so it outlives whoever drops it.
  struct Job {
    std::string key;  // what was asked for: a scene file, or a lesson and its seed
    std::mutex mutex;
    std::string stage;
    double fraction = 0;
    std::atomic<bool> cancel{false}, done{false};
    std::unique_ptr<CompiledScene> result;
    SeenGingiva seen;   // the gingiva as drawn (the engine's is the felt one)
    std::string error;  // "cancelled" when cancelled
    double seconds = 0;
  };

  ScenePreparer() = default;
  /// Cancels what is running and waits for it (a build stops at its next
  /// progress report), so no worker outlives the window and the statics it uses.
  ~ScenePreparer();
  ScenePreparer(const ScenePreparer&) = delete;
  ScenePreparer& operator=(const ScenePreparer&) = delete;

  /// The job preparing `spec` under `key`: the running (or finished, not yet
  /// taken) one when the key is the same, else a new one (the other is
  /// cancelled: one build at a time on a two-core machine).
  std::shared_ptr<Job> Prepare(const SceneSpec& spec, const std::string& key);
  /// The current job, if any.
  std::shared_ptr<Job> current() const { return job_; }
  /// Forgets the current job (after its result was taken).
  void Drop() { job_.reset(); }
  /// "Preparing the scene: trees of tooth 46 (43 %)", "The scene is ready
  /// (12.3 s)" or "" when nothing is prepared.
  QString Status() const;
  /// How many preparations were started (a taken-over one is not started again).
  int started() const { return started_; }

 private:
  std::shared_ptr<Job> job_;
  int started_ = 0;
  // Every worker started and not yet joined, with its job.
  std::vector<std::pair<std::shared_ptr<Job>, std::thread>> workers_;
};

}  // namespace sulcus::ui
