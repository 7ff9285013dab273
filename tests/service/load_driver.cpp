#include "service/load_driver.h"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "service/proc_threads.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {

namespace {

using Clock = std::chrono::steady_clock;

std::shared_ptr<grpc::Channel> own_connection(const std::string& address) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // one TCP connection per client
  return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args);
}

// The background sessions' steps together, read with GetSession.
long total_steps(v1::Simulation::Stub& stub, const std::vector<std::string>& ids) {
  long total = 0;
  for (const auto& id : ids) {
    v1::Session s;
    if (get_session(stub, id, &s).ok()) total += s.step();
  }
  return total;
}

double rate_over(v1::Simulation::Stub& stub, const std::vector<std::string>& ids, double seconds) {
  const long before = total_steps(stub, ids);
  const auto start = Clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const long after = total_steps(stub, ids);
  return static_cast<double>(after - before) / std::chrono::duration<double>(Clock::now() - start).count();
}

// The q-quantile of sorted, non-empty values (the lower neighbour, no interpolation).
double percentile(const std::vector<double>& sorted, double q) {
  return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
}

class Tally {
 public:
  void control(const std::string& rpc, double ms) {
    std::lock_guard lock(mutex_);
    latencies_.push_back(ms);
    by_rpc_[rpc].push_back(ms);
  }
  void call(const std::string& rpc, const grpc::Status& status) {
    std::lock_guard lock(mutex_);
    ++report_.calls;
    if (status.ok()) return;
    ++report_.errors;
    if (report_.error_samples.size() < 10)
      report_.error_samples.push_back(rpc + ": " + std::to_string(status.error_code()) + " " + status.error_message());
  }
  LoadReport finish() {
    std::lock_guard lock(mutex_);
    std::sort(latencies_.begin(), latencies_.end());
    report_.control_calls = static_cast<long>(latencies_.size());
    if (!latencies_.empty()) {
      report_.p50_ms = percentile(latencies_, 0.5);
      report_.p99_ms = percentile(latencies_, 0.99);
      report_.max_ms = latencies_.back();
    }
    for (auto& [rpc, ms] : by_rpc_) {
      std::sort(ms.begin(), ms.end());
      report_.by_rpc.push_back({rpc, static_cast<long>(ms.size()), percentile(ms, 0.5), percentile(ms, 0.99)});
    }
    return report_;
  }

 private:
  std::mutex mutex_;
  std::vector<double> latencies_;
  std::map<std::string, std::vector<double>> by_rpc_;
  LoadReport report_;
};

// A control call, timed. `call` makes the RPC with the context it is given.
template <class Call>
void timed(Tally& tally, const std::string& rpc, Call&& call) {
  auto context = deadline_context(30);
  const auto start = Clock::now();
  const grpc::Status status = call(context.get());
  tally.control(rpc, std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  tally.call(rpc, status);
}

// One client: its own session to step and read, a background session to watch; a fixed cycle of
// calls until `until`.
void client_loop(const std::string& address, const std::string& background, int index, Clock::time_point until,
                 double think_ms, Tally& tally) {
  // Connected before the first call: with 64 connections opened at once, a few connection attempts
  // fail on loopback now and then (errno ENOENT, seen with 0 errors on calls otherwise), and gRPC
  // retries them after a backoff; a call made meanwhile fails fast. A client that cannot connect
  // within 10 s counts as an error.
  const auto channel = own_connection(address);
  if (!channel->WaitForConnected(std::chrono::system_clock::now() + std::chrono::seconds(10))) {
    tally.call("connect", grpc::Status(grpc::StatusCode::UNAVAILABLE, "no connection within 10 s"));
    return;
  }
  auto stub = v1::Simulation::NewStub(channel);
  v1::Session own;
  tally.call("CreateSession", create_session(*stub, small_channel_with_disk(24, 12), &own));
  for (long round = 0; Clock::now() < until; ++round) {
    if (think_ms > 0) std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(think_ms));
    switch ((round + index) % 6) {
      case 0:
        timed(tally, "GetSession", [&](grpc::ClientContext* c) {
          v1::GetSessionRequest r;
          r.set_session_id(background);
          v1::Session s;
          return stub->GetSession(c, r, &s);
        });
        break;
      case 1:
        timed(tally, "ListSessions", [&](grpc::ClientContext* c) {
          v1::ListSessionsResponse s;
          return stub->ListSessions(c, {}, &s);
        });
        break;
      case 2:
        timed(tally, "Step", [&](grpc::ClientContext* c) {
          v1::StepRequest r;
          r.set_session_id(own.id());
          r.set_steps(5);
          v1::StepResponse s;
          return stub->Step(c, r, &s);
        });
        break;
      case 3: {
        FieldBytes fields;
        tally.call("GetField", read_fields(*stub, own.id(), &fields));
        break;
      }
      case 4: {  // a profile stream of the running session: two frames, then the client leaves
        grpc::ClientContext context;
        v1::WatchProfilesRequest r;
        r.set_session_id(background);
        r.set_every(10);
        auto reader = stub->WatchProfiles(&context, r);
        v1::ProfileFrame frame;
        const bool read = reader->Read(&frame) && reader->Read(&frame);
        context.TryCancel();
        const auto status = reader->Finish();
        tally.call("WatchProfiles", read || status.ok() ? grpc::Status::OK : status);
        break;
      }
      case 5: {
        v1::Session temporary;
        timed(tally, "CreateSession", [&](grpc::ClientContext* c) {
          v1::CreateSessionRequest r;
          *r.mutable_scenario() = small_channel_with_disk(16, 8);
          return stub->CreateSession(c, r, &temporary);
        });
        timed(tally, "DeleteSession", [&](grpc::ClientContext* c) {
          v1::DeleteSessionRequest r;
          r.set_session_id(temporary.id());
          v1::DeleteSessionResponse s;
          return stub->DeleteSession(c, r, &s);
        });
        break;
      }
    }
  }
  v1::DeleteSessionRequest r;
  r.set_session_id(own.id());
  v1::DeleteSessionResponse s;
  tally.call("DeleteSession", stub->DeleteSession(deadline_context().get(), r, &s));
}

// CPU seconds used so far by the daemon's threads at its base priority (the lowest nice value
// among them: these threads live as long as the daemon or their session), by the rest of the
// daemon (the call threads, which gRPC starts and ends as calls come: counted from the process's
// total, which keeps the time of ended threads), and by this process.
struct CpuSplit {
  double daemon_base = 0, daemon_calls = 0, clients = 0;
  CpuSplit operator-(const CpuSplit& o) const {
    return {daemon_base - o.daemon_base, daemon_calls - o.daemon_calls, clients - o.clients};
  }
};

CpuSplit cpu_split(int daemon_pid) {
  const auto threads = thread_stats(daemon_pid);
  int base = 19;
  for (const auto& t : threads) base = std::min(base, t.nice);
  CpuSplit split;
  for (const auto& t : threads)
    if (t.nice == base) split.daemon_base += t.cpu_seconds;
  split.daemon_calls = process_cpu_seconds(daemon_pid) - split.daemon_base;
  rusage self{};
  getrusage(RUSAGE_SELF, &self);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  split.clients = seconds(self.ru_utime) + seconds(self.ru_stime);
  return split;
}

}  // namespace

LoadReport run_load(const DaemonProcess& daemon, const LoadOptions& options) {
  auto stub = daemon.stub();
  std::vector<std::string> background;
  for (int b = 0; b < options.background_sessions; ++b) {
    v1::Session session;
    if (!create_session(*stub, small_channel_with_disk(options.background_nx, options.background_ny), &session).ok())
      throw std::runtime_error("cannot create a background session");
    if (!run_session(*stub, session.id(), 1L << 40).ok()) throw std::runtime_error("cannot run a background session");
    background.push_back(session.id());
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // past the first slices
  const double alone = rate_over(*stub, background, options.seconds);

  Tally tally;
  const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.seconds));
  // jthreads: if anything below throws, the clients (which stop by themselves at `until`) are
  // joined and the exception reaches the test, instead of std::terminate from a joinable thread.
  std::vector<std::jthread> clients;
  for (int c = 0; c < options.clients; ++c)
    clients.emplace_back(client_loop, daemon.address(), background[c % background.size()], c, until, options.think_ms,
                         std::ref(tally));
  // The rate under load over the middle of the load, once every client is connected.
  std::this_thread::sleep_for(std::chrono::duration<double>(0.2 * options.seconds));
  const CpuSplit before = cpu_split(daemon.pid());
  const auto start = Clock::now();
  const double loaded = rate_over(*stub, background, 0.6 * options.seconds);
  const CpuSplit used = cpu_split(daemon.pid()) - before;
  const double window = std::chrono::duration<double>(Clock::now() - start).count();
  for (auto& t : clients) t.join();

  for (const auto& id : background) {
    v1::DeleteSessionRequest r;
    r.set_session_id(id);
    v1::DeleteSessionResponse s;
    tally.call("DeleteSession", stub->DeleteSession(deadline_context().get(), r, &s));
  }
  LoadReport report = tally.finish();
  report.steps_per_second_alone = alone;
  report.steps_per_second_loaded = loaded;
  report.daemon_base_cores = used.daemon_base / window;
  report.daemon_call_cores = used.daemon_calls / window;
  report.client_cores = used.clients / window;
  return report;
}

std::string describe(const LoadReport& r, const LoadOptions& o) {
  std::ostringstream out;
  out << o.clients << " clients (" << o.think_ms << " ms between calls) for " << o.seconds << " s beside "
      << o.background_sessions << " running "
      << o.background_nx << " x " << o.background_ny << " sessions\n"
      << "  calls " << r.calls << ", errors " << r.errors << "\n"
      << "  control calls " << r.control_calls << ": p50 " << r.p50_ms << " ms, p99 " << r.p99_ms << " ms, max "
      << r.max_ms << " ms\n"
      << "  background steps/s: alone " << r.steps_per_second_alone << ", under load " << r.steps_per_second_loaded
      << " (" << 100.0 * r.steps_per_second_loaded / std::max(1e-9, r.steps_per_second_alone) << "%)\n"
      << "  CPU under load (cores): daemon simulation threads " << r.daemon_base_cores << ", daemon call threads "
      << r.daemon_call_cores << ", clients " << r.client_cores << "\n";
  for (const auto& c : r.by_rpc)
    out << "    " << c.rpc << ": " << c.calls << " calls, p50 " << c.p50_ms << " ms, p99 " << c.p99_ms << " ms\n";
  for (const auto& e : r.error_samples) out << "  error: " << e << "\n";
  return out.str();
}

}  // namespace lbsolid::testing
