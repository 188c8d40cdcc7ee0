#pragma once
// A real Learning Record Store for the xAPI tests: Ralph (openfun's LRS, from
// PyPI, installed by scripts/test.sh into build/<preset>/lrs-venv) with its file
// system backend, HTTP basic authentication and one user, started on a free
// port of 127.0.0.1 in a fresh folder and stopped with the object.

#include <sys/types.h>

#include <filesystem>
#include <string>

namespace sulcus::test {

class LrsServer {
 public:
  static constexpr const char* kUser = "station";
  static constexpr const char* kPassword = "lrs-secret-23";

  /// Throws std::runtime_error naming what is missing (the venv: run
  /// scripts/test.sh) or what failed, with the server's log.
  explicit LrsServer(const std::filesystem::path& venv);
  ~LrsServer();
  LrsServer(const LrsServer&) = delete;
  LrsServer& operator=(const LrsServer&) = delete;

  /// http://127.0.0.1:PORT/xAPI
  std::string url() const;

 private:
  std::filesystem::path dir_;
  int port_ = 0;
  pid_t pid_ = -1;
};

}  // namespace sulcus::test
