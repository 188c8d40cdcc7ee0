#include "tests/common/lrs_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "tests/common/output.h"
#include "tests/common/postgres_server.h"

namespace sulcus::test {

namespace fs = std::filesystem;

namespace {

bool Listening(int port) {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  const bool ok = connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  close(s);
  return ok;
}

}  // namespace

LrsServer::LrsServer(const fs::path& venv) {
  const fs::path ralph = venv / "bin" / "ralph", uvicorn = venv / "bin" / "uvicorn";
  if (!fs::exists(ralph) || !fs::exists(uvicorn))
    throw std::runtime_error("no Ralph LRS in " + venv.string() +
                             " (scripts/test.sh installs it from PyPI: ralph-malph)");
  char tmpl[] = "/tmp/sulcus-lrs-XXXXXX";
  if (!mkdtemp(tmpl)) throw std::runtime_error("cannot make a folder under /tmp");
  dir_ = tmpl;
  fs::create_directories(dir_ / "app");
  fs::create_directories(dir_ / "data");
  // `ralph auth` loads the API too, which needs its backend named.
  const std::string env = "RALPH_APP_DIR=" + (dir_ / "app").string() +
                          " RALPH_AUTH_FILE=" + (dir_ / "auth.json").string() +
                          " RALPH_RUNSERVER_BACKEND=fs ";
  const std::string auth = env + ralph.string() + " auth -u " + kUser + " -p " +
                           kPassword +
                           " -s statements/write -s statements/read/mine"
                           " -M mailto:station@example.com -w >" +
                           (dir_ / "auth.log").string() + " 2>&1";
  if (std::system(auth.c_str()) != 0)
    throw std::runtime_error("failed: " + auth + "\n" + ReadText(dir_ / "auth.log"));
  port_ = FreePort();
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("cannot start the LRS (fork)");
  if (pid_ == 0) {
    setpgid(0, 0);
    setenv("RALPH_APP_DIR", (dir_ / "app").c_str(), 1);
    setenv("RALPH_AUTH_FILE", (dir_ / "auth.json").c_str(), 1);
    setenv("RALPH_RUNSERVER_BACKEND", "fs", 1);
    setenv("RALPH_RUNSERVER_AUTH_BACKENDS", "basic", 1);
    setenv("RALPH_BACKENDS__LRS__FS__DEFAULT_DIRECTORY_PATH", (dir_ / "data").c_str(), 1);
    const int log =
        open((dir_ / "server.log").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(log, 1);
    dup2(log, 2);
    const std::string port = std::to_string(port_);
    execl(uvicorn.c_str(), uvicorn.c_str(), "ralph.api:app", "--host", "127.0.0.1",
          "--port", port.c_str(), "--workers", "1", static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!Listening(port_)) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("the LRS stopped at once:\n" +
                               ReadText(dir_ / "server.log"));
    }
    if (std::chrono::steady_clock::now() > until)
      throw std::runtime_error("the LRS did not listen within 60 s:\n" +
                               ReadText(dir_ / "server.log"));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

LrsServer::~LrsServer() {
  if (pid_ > 0) {
    kill(-pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

std::string LrsServer::url() const {
  return "http://127.0.0.1:" + std::to_string(port_) + "/xAPI";
}

}  // namespace sulcus::test
