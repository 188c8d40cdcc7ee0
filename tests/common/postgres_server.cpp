#include "tests/common/postgres_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "tests/common/output.h"

namespace sulcus::test {

namespace fs = std::filesystem;

int FreePort() {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t n = sizeof a;
  if (s < 0 || bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      getsockname(s, reinterpret_cast<sockaddr*>(&a), &n) != 0)
    throw std::runtime_error("no free TCP port on 127.0.0.1");
  close(s);
  return ntohs(a.sin_port);
}

namespace {

fs::path PostgresBin() {
  std::error_code ec;
  for (const char* v : {"15", "16", "17", "14", "13"}) {
    const fs::path bin = fs::path("/usr/lib/postgresql") / v / "bin";
    if (fs::exists(bin / "initdb", ec) && fs::exists(bin / "pg_ctl", ec)) return bin;
  }
  throw std::runtime_error(
      "no PostgreSQL server binaries (/usr/lib/postgresql/N/bin/initdb); install "
      "postgresql-15 (scripts/install-deps.sh)");
}

}  // namespace

PostgresServer::PostgresServer() : bin_(PostgresBin()) {
  char tmpl[] = "/tmp/sulcus-pg-XXXXXX";
  if (!mkdtemp(tmpl)) throw std::runtime_error("cannot make a folder under /tmp");
  dir_ = tmpl;
  std::ofstream(dir_ / "pw") << kPassword << "\n";
  if (geteuid() == 0) Run("chown -R postgres:postgres " + dir_.string());
  Run((bin_ / "initdb").string() + " -D " + (dir_ / "data").string() + " -U " + kUser +
      " --auth=scram-sha-256 --pwfile=" + (dir_ / "pw").string() +
      " -E UTF8 --no-sync >" + (dir_ / "initdb.log").string() + " 2>&1");
  port_ = FreePort();
  Start();
}

PostgresServer::~PostgresServer() {
  try {
    Stop(true);
  } catch (const std::exception&) {
    // Removed below either way.
  }
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

void PostgresServer::Run(const std::string& command) const {
  const std::string as =
      geteuid() == 0 && command.rfind("chown", 0) != 0 ? "runuser -u postgres -- " : "";
  const std::string full = as + "sh -c '" + command + "'";
  if (std::system(full.c_str()) != 0)
    throw std::runtime_error("failed: " + full + "\n" + ReadText(dir_ / "initdb.log") +
                             ReadText(dir_ / "server.log"));
}

void PostgresServer::Start() {
  if (running_) return;
  Run((bin_ / "pg_ctl").string() + " -D " + (dir_ / "data").string() + " -l " +
      (dir_ / "server.log").string() + " -w -t 60 -o \"-p " + std::to_string(port_) +
      " -k " + dir_.string() +
      " -c listen_addresses=127.0.0.1 -c fsync=off -c max_connections=60\" start "
      ">/dev/null");
  running_ = true;
}

void PostgresServer::Stop(bool immediate) {
  if (!running_) return;
  running_ = false;
  Run((bin_ / "pg_ctl").string() + " -D " + (dir_ / "data").string() + " -m " +
      (immediate ? "immediate" : "fast") + " -w stop >/dev/null");
}

std::string PostgresServer::url(const std::string& password,
                                const std::string& database) const {
  return std::string("postgresql://") + kUser + ":" + password +
         "@127.0.0.1:" + std::to_string(port_) + "/" + database;
}

std::string PostgresServer::Sql(const std::string& database,
                                const std::string& sql) const {
  const std::string command = "PGPASSWORD=" + std::string(kPassword) + " " +
                              (bin_ / "psql").string() + " -At -h 127.0.0.1 -p " +
                              std::to_string(port_) + " -U " + kUser + " -d " + database +
                              " -c \"" + sql + "\"";
  FILE* p = popen(command.c_str(), "r");
  if (!p) throw std::runtime_error("failed: " + command);
  std::string out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  if (pclose(p) != 0) throw std::runtime_error("failed: " + command + "\n" + out);
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

namespace {

void Shell(const std::string& command) {
  if (std::system(command.c_str()) != 0) throw std::runtime_error("failed: " + command);
}

// A self-signed CA in `dir` (ca.crt, ca.key).
void MakeCa(const fs::path& dir, const std::string& name) {
  fs::create_directories(dir);
  Shell("openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj '/CN=" + name +
        "' -keyout " + (dir / "ca.key").string() + " -out " + (dir / "ca.crt").string() +
        " >/dev/null 2>&1");
}

}  // namespace

int RunStationsAtOnce(int n, const std::function<void(int station)>& work) {
  std::vector<pid_t> children;
  int failed = 0;
  for (int s = 0; s < n; ++s) {
    const pid_t child = fork();
    if (child < 0) {
      ++failed;
      continue;
    }
    if (child == 0) {
      try {
        work(s);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "station %d: %s\n", s, e.what());
        _exit(1);
      }
      _exit(0);
    }
    children.push_back(child);
  }
  for (const pid_t c : children) {
    int status = 0;
    waitpid(c, &status, 0);
    failed += !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  return failed;
}

fs::path PostgresServer::EnableTls() {
  const fs::path tls = dir_ / "tls";
  MakeCa(tls, "Sulcus test school CA");
  std::ofstream(tls / "ext.cnf")
      << "subjectAltName=DNS:localhost,IP:127.0.0.1\nbasicConstraints=CA:FALSE\n";
  Shell("openssl req -newkey rsa:2048 -nodes -subj '/CN=127.0.0.1' -keyout " +
        (tls / "server.key").string() + " -out " + (tls / "server.csr").string() +
        " >/dev/null 2>&1");
  Shell("openssl x509 -req -in " + (tls / "server.csr").string() + " -CA " +
        (tls / "ca.crt").string() + " -CAkey " + (tls / "ca.key").string() +
        " -CAcreateserial -days 2 -extfile " + (tls / "ext.cnf").string() + " -out " +
        (tls / "server.crt").string() + " >/dev/null 2>&1");
  Shell("chmod 600 " + (tls / "server.key").string());
  if (geteuid() == 0) Shell("chown -R postgres:postgres " + tls.string());
  std::ofstream(dir_ / "data" / "postgresql.conf", std::ios::app)
      << "ssl = on\nssl_cert_file = '" << (tls / "server.crt").string()
      << "'\nssl_key_file = '" << (tls / "server.key").string() << "'\n";
  // Every TCP connection over TLS: "host" lines become "hostssl".
  const fs::path hba = dir_ / "data" / "pg_hba.conf";
  std::string text = ReadText(hba), out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    out += (line.rfind("host ", 0) == 0 ? "hostssl " + line.substr(5) : line) + "\n";
  std::ofstream(hba) << out;
  Stop();
  Start();
  return tls / "ca.crt";
}

fs::path PostgresServer::OtherCa() {
  MakeCa(dir_ / "other-ca", "Another CA");
  return dir_ / "other-ca" / "ca.crt";
}

int PostgresServer::Try(const std::string& url, const std::string& sql,
                        std::string* out) const {
  const std::string command = (bin_ / "psql").string() + " -At -v ON_ERROR_STOP=1 '" +
                              url + "' -c \"" + sql + "\" 2>&1";
  FILE* p = popen(command.c_str(), "r");
  if (!p) throw std::runtime_error("failed: " + command);
  out->clear();
  char buf[256];
  while (std::fgets(buf, sizeof buf, p)) *out += buf;
  return pclose(p);
}

std::string PostgresServer::FreshDatabase(const std::string& name) {
  const std::string psql = "PGPASSWORD=" + std::string(kPassword) + " " +
                           (bin_ / "psql").string() + " -q -h 127.0.0.1 -p " +
                           std::to_string(port_) + " -U " + kUser + " -d postgres -c ";
  const std::string command = psql + "\"DROP DATABASE IF EXISTS " + name +
                              "\" 2>/dev/null && " + psql + "\"CREATE DATABASE " + name +
                              "\" >/dev/null";
  if (std::system(command.c_str()) != 0) throw std::runtime_error("failed: " + command);
  return url(kPassword, name);
}

}  // namespace sulcus::test
