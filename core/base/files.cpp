#include "core/base/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace fs = std::filesystem;

namespace sulcus {

bool SameFile(const fs::path& a, const fs::path& b) {
  struct stat sa {
  }, sb{};
  if (::stat(a.c_str(), &sa) != 0 || ::stat(b.c_str(), &sb) != 0) return false;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

void RefuseOverwrite(const fs::path& out, const std::vector<KeptFile>& kept) {
  for (const KeptFile& k : kept)
    if (!k.path.empty() && SameFile(out, k.path))
      throw FileError("will not write " + out.string() + ": it is " + k.role + " (" +
                      k.path.string() +
                      "), which writing would destroy; choose another output path");
}

std::string UnreadableReason(const fs::path& file) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec || !fs::exists(st)) return "no such file";
  if (fs::is_directory(st)) return "is a folder, not a file";
  if (!fs::is_regular_file(st))
    return "is not a regular file (a FIFO or a device?); give a file";
  return {};
}

bool IsInsideFolder(const fs::path& file, const fs::path& folder) {
  std::error_code ec;
  const fs::path f = fs::weakly_canonical(fs::absolute(file, ec), ec);
  if (ec) return false;
  const fs::path d = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  if (ec) return false;
  const fs::path rel = f.lexically_relative(d);
  return !rel.empty() && *rel.begin() != "..";
}

std::vector<KeptFile> StoreFiles(const fs::path& db) {
  return {{db, "the results database"},
          {fs::path(db.string() + "-wal"), "the results database's journal"},
          {fs::path(db.string() + "-shm"), "the results database's shared memory"}};
}

AtomicFile::AtomicFile(fs::path path, bool binary) : path_(std::move(path)) {
  const auto mode = std::ios::out | std::ios::trunc |
                    (binary ? std::ios::binary : std::ios::openmode{});
  std::error_code ec;
  const fs::file_status st = fs::status(path_, ec);
  if (!ec && fs::exists(st) && !fs::is_regular_file(st)) {
    if (fs::is_directory(st))
      throw FileError("cannot write " + path_.string() +
                      ": it is a folder; give a file name");
    direct_ = true;
    out_.open(path_, mode);
  } else {
    const fs::path dir = path_.has_parent_path() ? path_.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec))
      throw FileError("cannot write " + path_.string() + ": the folder " + dir.string() +
                      " does not exist");
    temp_ = dir / ("." + path_.filename().string() + ".part-" +
                   std::to_string(static_cast<long>(::getpid())));
    out_.open(temp_, mode);
  }
  if (!out_)
    throw FileError("cannot write " + path_.string() + ": " + std::strerror(errno) +
                    " (check the folder exists and can be written)");
}

void SyncFolder(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

AtomicFile::~AtomicFile() {
  if (committed_ || direct_) return;
  out_.close();
  std::error_code ec;
  fs::remove(temp_, ec);
}

void AtomicFile::Commit() {
  out_.flush();
  bool ok = static_cast<bool>(out_);
  out_.close();
  ok = ok && !out_.fail();
  if (ok && !direct_) {
    // The data on the disk before the name moves (a crash leaves the old file).
    const int fd = ::open(temp_.c_str(), O_RDONLY);
    ok = fd >= 0 && ::fsync(fd) == 0;
    if (fd >= 0) ::close(fd);
  }
  if (!ok) {
    std::error_code ec;
    if (!direct_) fs::remove(temp_, ec);
    throw FileError("could not write " + path_.string() +
                    ": the disk may be full or the file system read-only" +
                    (direct_ ? "" : "; the file there before is unchanged"));
  }
  if (!direct_) {
    std::error_code ec;
    fs::rename(temp_, path_, ec);
    if (ec) {
      fs::remove(temp_, ec);
      throw FileError("could not write " + path_.string() + ": " + ec.message());
    }
  }
  committed_ = true;
}

}  // namespace sulcus
