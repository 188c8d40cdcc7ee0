#include "ui/scene_preparer.h"

#include <chrono>
#include <thread>

#include "core/spheretree/builder.h"
#include "core/spheretree/cache.h"

namespace sulcus::ui {

ScenePreparer::~ScenePreparer() {
  for (auto& [job, worker] : workers_) job->cancel = true;
  for (auto& [job, worker] : workers_) worker.join();
}

std::shared_ptr<ScenePreparer::Job> ScenePreparer::Prepare(const SceneSpec& spec,
                                                           const std::string& key) {
  if (job_ && job_->key == key && job_->error.empty() && !job_->cancel) return job_;
  if (job_ && !job_->done) job_->cancel = true;
  // Workers that finished are joined here; a cancelled one stops at its next
  // progress report and is joined at the next call or at the end.
  std::erase_if(workers_, [](auto& w) {
    if (!w.first->done) return false;
    w.second.join();
    return true;
  });
  auto job = std::make_shared<Job>();
  job->key = key;
  ++started_;
  job_ = job;
  workers_.emplace_back(job, [job, spec] {
    const auto t0 = std::chrono::steady_clock::now();
    try {
      // The gingiva as drawn is built with the trees, in the same workers.
      std::unique_ptr<CompiledScene> scene =
          CompileScene(spec, DefaultCacheDir(),
                       [job](std::string_view stage, double f) {
                         std::lock_guard lock(job->mutex);
                         job->stage = stage;
                         job->fraction = f;
                         return !job->cancel.load();
                       },
                       {.seen_gingiva = true});
      SeenGingiva seen = std::move(scene->seen);
      std::lock_guard lock(job->mutex);
      job->seen = std::move(seen);
      job->result = std::move(scene);
      job->fraction = 1;
    } catch (const BuildCancelled&) {
      std::lock_guard lock(job->mutex);
      job->error = "cancelled";
    } catch (const std::exception& e) {
      std::lock_guard lock(job->mutex);
      job->error = e.what();
    }
    job->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    job->done = true;
  });
  return job;
}

QString ScenePreparer::Status() const {
  if (!job_) return {};
  std::lock_guard lock(job_->mutex);
  if (job_->done) {
    if (job_->result)
      return QString("The scene is ready (prepared in %1 s).")
          .arg(job_->seconds, 0, 'f', 1);
    if (job_->error == "cancelled") return {};
    return QString("The scene could not be prepared: %1")
        .arg(QString::fromStdString(job_->error));
  }
  return QString(
             "Preparing the scene (the first time only: its collision spheres and its "
             "drawing): %1 (%2 %)")
      .arg(QString::fromStdString(job_->stage))
      .arg(static_cast<int>(job_->fraction * 100));
}

}  // namespace sulcus::ui
