#pragma once
// The kill sweep through KeepAttempt, for a results store of any kind: a
// station (a child process) keeping a finished attempt is stopped at each of
// KeepAttempt's steps (SIGKILL, SIGTERM and SIGINT in turn) and at timed
// instants within it, each time on a fresh copy of the attempt's folder; then
// a sync (RecoverAttempt over the attempts left waiting) runs. The caller
// checks that the store holds the attempt exactly once after each stop.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "core/lesson/attempt.h"

namespace sulcus::test {

struct SweepStop {
  std::string step;  // "": timed
  int signal = SIGKILL;
  int delay_us = 0;
  std::string What() const {
    return step.empty() ? "killed " + std::to_string(delay_us) + " us in"
                        : "stopped at '" + step + "' by signal " + std::to_string(signal);
  }
};

/// Each of KeepAttempt's steps by a signal in turn, then SIGKILL at `delays_us`.
inline std::vector<SweepStop> SweepStops(const std::vector<int>& delays_us) {
  std::vector<SweepStop> stops;
  const char* steps[] = {"start",  "marked",   "answers", "report",
                         "stored", "unmarked", "xapi",    "kept"};
  const int signals[] = {SIGKILL, SIGTERM, SIGINT};
  for (int i = 0; i < 8; ++i) stops.push_back({steps[i], signals[i % 3], 0});
  for (const int us : delays_us) stops.push_back({"", SIGKILL, us});
  return stops;
}

/// One stop: `made` (an attempt's folder, never kept) copied under `place`'s
/// folder, kept by a child stopped as `stop` says, then synced. Returns how many
/// attempts were left waiting (each stored by the sync).
inline int StopAndSync(const AttemptFolder& made, const LessonResult& result,
                       const ResultsPlace& place, const SweepStop& stop,
                       const std::filesystem::path& cache_dir) {
  namespace fs = std::filesystem;
  AttemptFolder folder{place.dir / "attempts" / made.dir.filename(), made.started};
  fs::create_directories(folder.dir.parent_path());
  fs::copy(made.dir, folder.dir, fs::copy_options::recursive);
  const pid_t child = fork();
  if (child < 0) {
    ADD_FAILURE() << "fork failed";
    return 0;
  }
  if (child == 0) {
    auto at = [&](const char* name) {
      if (!stop.step.empty() && stop.step == name) {
        kill(getpid(), stop.signal);
        _exit(9);  // (not reached: the signal's default action ends it)
      }
    };
    try {
      KeepAttempt(result, folder, folder.dir, place, at);
    } catch (...) {
      _exit(4);
    }
    _exit(0);
  }
  if (stop.step.empty()) {
    std::this_thread::sleep_for(std::chrono::microseconds(stop.delay_us));
    kill(child, SIGKILL);
  }
  int status = 0;
  waitpid(child, &status, 0);
  if (!stop.step.empty()) {
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == stop.signal) << stop.What();
  }
  const std::vector<fs::path> waiting = UnfinishedAttempts(place.dir);
  std::printf("figure: %s, %s: %s\n", place.Describe().substr(0, 10).c_str(),
              stop.What().c_str(),
              waiting.empty() ? "stored" : "waiting, stored by the sync");
  for (const fs::path& dir : waiting)
    EXPECT_NO_THROW(RecoverAttempt(dir, place, cache_dir)) << stop.What();
  EXPECT_TRUE(UnfinishedAttempts(place.dir).empty()) << stop.What();
  return static_cast<int>(waiting.size());
}

}  // namespace sulcus::test
