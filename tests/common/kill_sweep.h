#pragma once
// The kill sweep through KeepAttempt, for a results store of any kind: a
// station (a child process) keeping a finished attempt is stopped at each of
// KeepAttempt's steps (SIGKILL, SIGTERM and SIGINT in turn) and at timed
// instants within it, each time on a fresh copy of the attempt's folder; then
// a sync (RecoverAttempt over the attempts left waiting) runs. The caller
// checks that the store holds the attempt exactly once after each stop. The
// same for a disk that fills while the attempt is kept (FullDiskAndSync).

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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

/// A short attempt to keep (the spot prober's, on the probing lesson), made into
/// its own folder under `base` (emptied first) and never kept: each case of a
/// sweep keeps a copy of its folder.
struct MadeAttempt {
  AttemptFolder folder;
  AttemptOutcome out;
};
inline MadeAttempt MakeSpotAttempt(const std::filesystem::path& base,
                                   const std::string& student,
                                   const std::filesystem::path& cache_dir) {
  std::filesystem::remove_all(base);
  MadeAttempt m{NewAttemptFolder(base, student), {}};
  AttemptOptions o;
  o.student = student;
  o.device = "student:spot";
  o.cache_dir = cache_dir;
  o.record = m.folder.recording();
  o.keep_in = &m.folder;
  m.out = RunAttempt(
      std::filesystem::path(SULCUS_SOURCE_DIR) / "lessons" / "periodontal_probing.yaml",
      o);
  return m;
}

/// Each of KeepAttempt's steps by a signal in turn, then SIGKILL at `delays_us`.
inline std::vector<SweepStop> SweepStops(const std::vector<int>& delays_us) {
  std::vector<SweepStop> stops;
  const char* steps[] = {"start",  "marked", "answers",  "report",
                         "stored", "xapi",   "unmarked", "kept"};
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

/// A disk of its own, small: a tmpfs mounted at `dir` while it lives (where the
/// test may mount, as root), which a filler file fills but a given number of
/// bytes. Where it may not mount, a file-size limit in the keeping child stands
/// in for it (every write past it fails as on a full disk).
class SmallDisk {
 public:
  SmallDisk(std::filesystem::path dir, int megabytes) : dir_(std::move(dir)) {
    umount2(dir_.c_str(), MNT_DETACH);  // left by a run that was killed
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    const std::string size = "size=" + std::to_string(megabytes) + "m";
    // SULCUS_TEST_NO_MOUNT=1 tries the stand-in where the test could mount.
    const char* no_mount = std::getenv("SULCUS_TEST_NO_MOUNT");
    mounted_ = !(no_mount && std::string(no_mount) == "1") &&
               mount("tmpfs", dir_.c_str(), "tmpfs", 0, size.c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_) umount2(dir_.c_str(), MNT_DETACH);
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;
  bool mounted() const { return mounted_; }
  const std::filesystem::path& dir() const { return dir_; }
  std::uintmax_t Free() const {
    struct statvfs v {};
    return statvfs(dir_.c_str(), &v) == 0 ? std::uintmax_t{v.f_bavail} * v.f_frsize : 0;
  }
  /// Fills the disk but `bytes` (to its block size); Empty() takes the filler away.
  void LeaveFree(std::uintmax_t bytes) {
    if (!mounted_) return;
    std::ofstream out(dir_ / "filler", std::ios::binary);
    const std::string block(4096, 'x');
    for (std::uintmax_t free = Free(); free > bytes; free = Free()) {
      const std::uintmax_t n = std::min<std::uintmax_t>(block.size(), free - bytes);
      if (!out.write(block.data(), static_cast<std::streamsize>(n)).flush()) break;
    }
  }
  void Empty() { std::filesystem::remove(dir_ / "filler"); }

 private:
  std::filesystem::path dir_;
  bool mounted_ = false;
};

/// One full-disk case: `made` copied into `place`'s folder on `disk`, the disk
/// filled but `free` bytes, the attempt kept by a child (which returns, throws,
/// or is ended by SIGXFSZ, all of which a full disk may cause); the disk emptied,
/// the attempt checked stored or waiting (`stored` counts it in the store), then
/// synced. Returns whether it was left waiting.
inline bool FullDiskAndSync(const AttemptFolder& made, const LessonResult& result,
                            SmallDisk& disk, const ResultsPlace& place,
                            std::uintmax_t free, const std::filesystem::path& cache_dir,
                            const std::function<int()>& stored) {
  namespace fs = std::filesystem;
  const AttemptFolder folder{place.dir / "attempts" / made.dir.filename(), made.started};
  fs::create_directories(folder.dir.parent_path());
  fs::copy(made.dir, folder.dir, fs::copy_options::recursive);
  disk.LeaveFree(free);
  const std::uintmax_t left = disk.mounted() ? disk.Free() : free;  // or the limit
  const pid_t child = fork();
  if (child < 0) {
    ADD_FAILURE() << "fork failed";
    return false;
  }
  if (child == 0) {
    if (!disk.mounted()) {
      const rlimit limit{static_cast<rlim_t>(free), static_cast<rlim_t>(free)};
      setrlimit(RLIMIT_FSIZE, &limit);
      signal(SIGXFSZ, SIG_IGN);  // a write past it fails with EFBIG instead
    }
    try {
      KeepAttempt(result, folder, folder.dir, place);
    } catch (...) {
      _exit(4);
    }
    _exit(0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  disk.Empty();
  const bool waiting = !UnfinishedAttempts(place.dir).empty();
  const int rows = stored();
  std::printf("figure: full disk (%s), %ju bytes free: keeping %s, %s\n",
              disk.mounted() ? "a tmpfs filled" : "a file-size limit per file", left,
              WIFEXITED(status) && WEXITSTATUS(status) == 0 ? "returned" : "failed",
              waiting ? "waiting, stored by the sync" : "stored");
  EXPECT_TRUE(waiting || rows == 1) << free << " bytes free: neither stored nor waiting";
  EXPECT_LE(rows, 1);
  for (const fs::path& dir : UnfinishedAttempts(place.dir))
    EXPECT_NO_THROW(RecoverAttempt(dir, place, cache_dir)) << free << " bytes free";
  EXPECT_TRUE(UnfinishedAttempts(place.dir).empty()) << free << " bytes free";
  return waiting;
}

}  // namespace sulcus::test
