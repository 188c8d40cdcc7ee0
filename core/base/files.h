#pragma once
// Files a command writes: never over one it reads or a store it keeps, and
// whole or not at all (a full disk is an error naming the file, and the old
// file survives).

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace sulcus {

/// A file that cannot be written where asked, in the user's words.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Whether `a` and `b` name the same existing file (device and inode, after
/// resolving links, so a hard link or a symlink to it counts). False when
/// either does not exist.
bool SameFile(const std::filesystem::path& a, const std::filesystem::path& b);

/// A file a command reads or keeps, with what it is ("the recording being
/// exported", "the results database").
struct KeptFile {
  std::filesystem::path path;
  std::string role;
};

/// Throws FileError when `out` is one of `kept` (SameFile), naming both and
/// what to do instead.
void RefuseOverwrite(const std::filesystem::path& out, const std::vector<KeptFile>& kept);

/// Why `file` cannot be read as a file, in the user's words ("" when it can):
/// no such file, a folder, or not a regular file (a FIFO would block, a
/// device such as /dev/zero never ends), checked before it is opened.
std::string UnreadableReason(const std::filesystem::path& file);

/// Whether `file`, with every link in it resolved, lies inside `folder` (also
/// resolved): compared component by component, so "/a/bc" is not inside "/a/b"
/// and "m.stl" inside "." is. A file that does not exist yet is resolved as far
/// as it exists.
bool IsInsideFolder(const std::filesystem::path& file,
                    const std::filesystem::path& folder);

/// A results database's own files (the database and SQLite's -wal and -shm).
std::vector<KeptFile> StoreFiles(const std::filesystem::path& db);

/// Flushes a folder's entries to the disk (a file created, renamed or removed
/// in it survives a crash). Best effort: errors are ignored.
void SyncFolder(const std::filesystem::path& dir);

/// Writes `path` through a temporary file in the same folder, flushed, checked
/// and renamed onto it by Commit(). A path that exists and is not a regular
/// file (a device such as /dev/stdout, a FIFO) is written directly, with its
/// errors checked. Destroyed without Commit(), it removes its temporary file
/// and leaves `path` as it was.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path, bool binary = false);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  std::ostream& stream() { return out_; }
  /// Throws FileError naming the path when anything written was lost.
  void Commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_, temp_;
  std::ofstream out_;
  bool direct_ = false, committed_ = false;
};

}  // namespace sulcus
