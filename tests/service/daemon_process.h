#pragma once
// A real lbsolidd for end-to-end tests: started as a child process on a free loopback port (the
// daemon writes the port it bound to --port_file), with its own data directory; stopped with a
// signal, and its exit status reported.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "lbsolid/v1/simulation.grpc.pb.h"

namespace lbsolid::testing {

namespace v1 = ::lbsolid::v1;

// Limits the daemon process starts under.
struct ProcessLimits {
  // RLIMIT_FSIZE: a write past this many bytes fails with EFBIG, as on a full disk (SIGXFSZ is
  // ignored so that the write fails instead of killing the daemon). Negative: no limit.
  long max_file_bytes = -1;
};

// How the test reaches the daemon: null credentials are plaintext; a --listen=unix:PATH among the
// daemon's flags is dialled as such. With a log_path, the daemon's log (its stdout and stderr) goes there.
// Without `connect`, the daemon is only started (a TLS daemon no client may reach).
struct Connection {
  std::shared_ptr<grpc::ChannelCredentials> credentials;
  std::string log_path;
  bool connect = true;
};

class DaemonProcess {
 public:
  // data_dir is created if needed and kept (a restart test starts a second daemon on it).
  explicit DaemonProcess(std::string data_dir, std::vector<std::string> extra_flags = {},
                         ProcessLimits limits = {}, Connection connection = {});
  ~DaemonProcess();  // kills the daemon if it still runs
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;

  // Sends `signal` and waits for the exit; returns the exit code (128 + signal if killed by one).
  int stop(int signal);
  bool running() const { return pid_ > 0; }
  int pid() const { return pid_; }
  const std::string& address() const { return address_; }
  std::unique_ptr<v1::Simulation::Stub> stub() const;
  std::shared_ptr<grpc::Channel> channel() const { return channel_; }

 private:
  std::string data_dir_;
  std::string address_;
  int pid_ = -1;
  std::shared_ptr<grpc::Channel> channel_;
};

// A fresh empty directory under the system temporary directory.
std::string fresh_directory(const std::string& stem);

// A fresh data directory, removed with everything in it at the end of its scope. Declare it before
// the DaemonProcess that uses it, so the daemon is gone first.
struct ScopedDirectory {
  explicit ScopedDirectory(const std::string& stem) : path(fresh_directory(stem)) {}
  ~ScopedDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  ScopedDirectory(const ScopedDirectory&) = delete;
  ScopedDirectory& operator=(const ScopedDirectory&) = delete;
  const std::string path;
};

// A context whose deadline is `seconds` away.
std::unique_ptr<grpc::ClientContext> deadline_context(double seconds = 10);

// Polls GetSession until the session is in `state` (true) or `seconds` pass (false).
bool wait_for_state(v1::Simulation::Stub& stub, const std::string& id, v1::SessionState state, double seconds = 30);

}  // namespace lbsolid::testing
