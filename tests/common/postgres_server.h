#pragma once
// A real PostgreSQL server for the results store's tests, as CI runs one: Debian's
// postgresql-15 binaries, a cluster made by initdb in a fresh folder under /tmp,
// listening on 127.0.0.1 on a free port, password authentication (scram-sha-256),
// stopped and removed with the object. As root (CI, the set-up scripts), the
// server runs as the `postgres` system user, which initdb requires.

#include <filesystem>
#include <functional>
#include <string>

namespace sulcus::test {

class PostgresServer {
 public:
  static constexpr const char* kUser = "sulcus";
  static constexpr const char* kPassword = "lab-secret-17";

  /// Makes the cluster and starts the server; throws std::runtime_error with the
  /// command and its log when something fails.
  PostgresServer();
  ~PostgresServer();
  PostgresServer(const PostgresServer&) = delete;
  PostgresServer& operator=(const PostgresServer&) = delete;

  void Start();
  /// `immediate`: as a crash would (no checkpoint, connections cut at once).
  void Stop(bool immediate = false);
  int port() const { return port_; }
  /// postgresql://sulcus:PASSWORD@127.0.0.1:PORT/DATABASE
  std::string url(const std::string& password = kPassword,
                  const std::string& database = "postgres") const;
  /// One SQL statement run by psql in `database`; its output, unaligned.
  std::string Sql(const std::string& database, const std::string& sql) const;
  /// One SQL statement run by psql as the user of `url`: its exit status (0: done)
  /// and, in *out, what psql said (errors included).
  int Try(const std::string& url, const std::string& sql, std::string* out) const;
  /// TLS as a school sets it up: a CA and a server certificate for 127.0.0.1
  /// made here (openssl), `ssl = on`, and every TCP connection required to use
  /// it (hostssl); restarts the server. Returns the CA's certificate file.
  std::filesystem::path EnableTls();
  /// A CA of its own that signed nothing this server shows (a wrong one).
  std::filesystem::path OtherCa();
  /// A new, empty database (dropped first if it exists); returns its URL.
  std::string FreshDatabase(const std::string& name);

 private:
  void Run(const std::string& command) const;
  std::filesystem::path dir_, bin_;
  int port_ = 0;
  bool running_ = false;
};

/// `n` stations at once: each a child process running `work(station)`; a
/// station that throws says why on standard error. Returns how many failed.
int RunStationsAtOnce(int n, const std::function<void(int station)>& work);

/// A TCP port nothing listens on now (bound and released).
int FreePort();

}  // namespace sulcus::test
