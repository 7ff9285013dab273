// lbsolid-call-cost: the CPU one call of each kind costs the daemon and its client, alone. Starts a
// private lbsolidd holding --sessions small paused sessions (the load benchmark's mix holds about
// as many), then makes --calls calls of one kind after another from one client and divides the
// CPU the daemon and this process used by the calls made.
//   lbsolid-call-cost [--calls 2000] [--sessions 66] [--only KIND] [--daemon-flag F]...
// --only measures the one kind whose name starts with KIND (e.g. Step), to profile it alone.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "service/proc_threads.h"
#include "service/test_scenarios.h"

namespace {

using namespace lbsolid;
using namespace lbsolid::testing;

double own_cpu_seconds() {
  rusage self{};
  getrusage(RUSAGE_SELF, &self);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(self.ru_utime) + seconds(self.ru_stime);
}

struct Kind {
  std::string name;
  std::function<grpc::Status(v1::Simulation::Stub&)> call;
};

}  // namespace

int main(int argc, char** argv) {
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);  // as lbsolid-load's clients
  int calls = 2000, sessions = 66;
  std::string only;
  std::vector<std::string> daemon_flags = {"--max_sessions=1024", "--autosave_interval=0"};
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string flag = argv[k];
    if (flag == "--calls") calls = std::stoi(argv[k + 1]);
    else if (flag == "--sessions") sessions = std::stoi(argv[k + 1]);
    else if (flag == "--only") only = argv[k + 1];
    else if (flag == "--daemon-flag") daemon_flags.push_back(argv[k + 1]);
    else {
      std::cerr << "usage: lbsolid-call-cost [--calls N] [--sessions N] [--only KIND] [--daemon-flag F]...\n";
      return 2;
    }
  }
  const ScopedDirectory dir("lbsolid-call-cost");
  DaemonProcess daemon(dir.path, daemon_flags);
  auto stub = daemon.stub();
  v1::Session first;
  for (int s = 0; s < sessions; ++s) {
    v1::Session session;
    if (!create_session(*stub, small_channel_with_disk(24, 12), &session).ok()) {
      std::cerr << "cannot create session " << s << "\n";
      return 1;
    }
    if (s == 0) first = session;
  }
  const std::string id = first.id();
  const std::vector<Kind> kinds = {
      {"GetSession", [&](v1::Simulation::Stub& st) { v1::Session s; return get_session(st, id, &s); }},
      {"ListSessions", [&](v1::Simulation::Stub& st) {
         v1::ListSessionsResponse r;
         return st.ListSessions(deadline_context().get(), {}, &r);
       }},
      {"Step (5 steps)", [&](v1::Simulation::Stub& st) {
         v1::StepRequest r;
         r.set_session_id(id);
         r.set_steps(5);
         v1::StepResponse s;
         return st.Step(deadline_context().get(), r, &s);
       }},
      {"GetField", [&](v1::Simulation::Stub& st) { FieldBytes f; return read_fields(st, id, &f); }},
      {"CreateSession + DeleteSession", [&](v1::Simulation::Stub& st) {
         v1::Session temporary;
         auto status = create_session(st, small_channel_with_disk(16, 8), &temporary);
         if (!status.ok()) return status;
         v1::DeleteSessionRequest r;
         r.set_session_id(temporary.id());
         v1::DeleteSessionResponse s;
         return st.DeleteSession(deadline_context().get(), r, &s);
       }},
  };
  std::printf("%d calls of each kind, one after another, beside %d paused 24 x 12 sessions\n", calls, sessions);
  std::printf("%-30s %14s %14s %12s\n", "call", "daemon ms/call", "client ms/call", "wall ms/call");
  for (const auto& kind : kinds) {
    if (kind.name.rfind(only, 0) != 0) continue;
    for (int k = 0; k < calls / 10; ++k) kind.call(*stub);  // warm: connections, arenas, threads
    const double daemon_before = process_cpu_seconds(daemon.pid()), client_before = own_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < calls; ++k) {
      const auto status = kind.call(*stub);
      if (!status.ok()) {
        std::cerr << kind.name << ": " << status.error_message() << "\n";
        return 1;
      }
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double daemon_cpu = process_cpu_seconds(daemon.pid()) - daemon_before;
    const double client_cpu = own_cpu_seconds() - client_before;
    std::printf("%-30s %14.3f %14.3f %12.3f\n", kind.name.c_str(), 1e3 * daemon_cpu / calls,
                1e3 * client_cpu / calls, 1e3 * wall / calls);
  }
  return 0;
}
