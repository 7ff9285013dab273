#pragma once
// A bounded loopback load on a real lbsolidd: background sessions run while many clients, each on
// its own connection, mix control calls (GetSession, ListSessions, GetServerInfo, Step), field
// reads, profile streams and create/delete of sessions. It stops by itself after a set time and
// reports every call that failed, the latency of control calls and the background sessions'
// steps per second without and with the load.
#include <string>
#include <vector>

#include "service/daemon_process.h"

namespace lbsolid::testing {

struct LoadOptions {
  int clients = 64;
  double seconds = 5;           // of load (the same again is measured without it first)
  int background_sessions = 2;  // long runs whose rate is measured
  int background_nx = 192, background_ny = 96;
  // Each client's pause between two calls: 0 is a closed loop that takes all the CPU it can get
  // (the clients share this machine's cores with the daemon); more is a client that does
  // something else between calls, as an orchestrator does.
  double think_ms = 0;
};

struct LoadReport {
  long calls = 0;
  long errors = 0;
  std::vector<std::string> error_samples;  // the first few "<rpc>: <code> <message>"
  double p50_ms = 0, p99_ms = 0, max_ms = 0;  // control calls
  long control_calls = 0;
  struct PerRpc {
    std::string rpc;
    long calls = 0;
    double p50_ms = 0, p99_ms = 0;
  };
  std::vector<PerRpc> by_rpc;  // the control calls by method
  double steps_per_second_alone = 0;   // background sessions together, no clients
  double steps_per_second_loaded = 0;  // the same, under the load
  // Where the CPU went while the loaded rate was measured, in cores (CPU seconds per second):
  // the daemon's threads at its base priority (workers, kernel threads, autosave, builder), its
  // other threads (gRPC's, answering the calls: --call_nice lower), and this process's clients.
  double daemon_base_cores = 0, daemon_call_cores = 0, client_cores = 0;
};

// The daemon needs room for clients + background sessions (--max_sessions).
LoadReport run_load(const DaemonProcess& daemon, const LoadOptions& options);

// A few lines for a person: the figures of the report.
std::string describe(const LoadReport& report, const LoadOptions& options);

}  // namespace lbsolid::testing
