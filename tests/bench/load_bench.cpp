// lbsolid-load: the loopback load benchmark of the daemon (tests/service/load_driver.h). Starts a
// private lbsolidd, runs background sessions alone and then beside N clients, and prints the
// control calls' p50/p99 latency and the sessions' steps/s without and with the load.
//   lbsolid-load [--clients 64] [--seconds 10] [--sessions 2] [--think-ms 0] [--daemon-flag F]...
// --daemon-flag passes F (e.g. --call_nice=0) to the daemon; it may be repeated.
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "service/load_driver.h"
#include "service/test_scenarios.h"

int main(int argc, char** argv) {
  using namespace lbsolid::testing;
  // The clients stand in for remote ones: as in lbsolidd, no Abseil deadlock graph on gRPC's locks.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  LoadOptions options;
  options.seconds = 10;
  std::vector<std::string> daemon_flags = {"--max_sessions=1024", "--autosave_interval=0"};
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string flag = argv[k];
    if (flag == "--clients") options.clients = std::stoi(argv[k + 1]);
    else if (flag == "--seconds") options.seconds = std::stod(argv[k + 1]);
    else if (flag == "--sessions") options.background_sessions = std::stoi(argv[k + 1]);
    else if (flag == "--think-ms") options.think_ms = std::stod(argv[k + 1]);
    else if (flag == "--daemon-flag") daemon_flags.push_back(argv[k + 1]);
    else {
      std::cerr << "usage: lbsolid-load [--clients N] [--seconds S] [--sessions N] [--think-ms T] [--daemon-flag F]...\n";
      return 2;
    }
  }
  const ScopedDirectory dir("lbsolid-load-bench");
  DaemonProcess daemon(dir.path, daemon_flags);
  const auto report = run_load(daemon, options);
  std::cout << describe(report, options);
  return report.errors == 0 ? 0 : 1;
}
