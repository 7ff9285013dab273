// lbsolidd: the lbsolid simulation daemon. Serves lbsolid.v1.Simulation, the standard gRPC health
// service and server reflection on --listen; keeps sessions on --workers threads and saves them
// under --data_dir every --autosave_interval. SIGTERM (or SIGINT) stops taking calls, pauses and
// saves every session, then exits 0 (1 if a session could not be saved); the next start brings
// them back under their old ids (those that were running PAUSED).
#include <grpc/grpc.h>
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/impl/server_builder_option.h>
#include <spdlog/spdlog.h>

#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <system_error>
#include <thread>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "absl/flags/usage_config.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "fluid/kernel_isa.h"
#include "server/auth/transport.h"
#include "server/service/simulation_service.h"
#include "server/session/session_manager.h"
#include "server/session/thread_priority.h"
#include "io/storage/file_replace.h"
#include "io/version.h"

namespace {

// Leaves gRPC's reflection plugin out of a server. libgrpc++_reflection registers it for every
// ServerBuilder when the library loads, so not calling InitProtoReflectionServerBuilderPlugin
// does not turn it off (--reflection=false served it); a builder option may drop plugins.
class WithoutReflection final : public grpc::ServerBuilderOption {
 public:
  void UpdateArguments(grpc::ChannelArguments*) override {}
  void UpdatePlugins(std::vector<std::unique_ptr<grpc::ServerBuilderPlugin>>* plugins) override {
    std::erase_if(*plugins, [](const auto& plugin) { return plugin->name().find("reflection") != std::string::npos; });
  }
};

}  // namespace

ABSL_FLAG(std::string, listen, "127.0.0.1:50051", "address to serve on; port 0 picks a free port");
ABSL_FLAG(std::string, data_dir, "./lbsolid-data", "where checkpoints and saved sessions live");
ABSL_FLAG(int, workers, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
          "worker threads that advance running sessions");
ABSL_FLAG(int, max_sessions, 64, "sessions held at most");
ABSL_FLAG(int64_t, max_cells, int64_t{1} << 26, "fluid nodes per session at most");
ABSL_FLAG(int64_t, max_sync_steps, 10000, "largest Step request");
ABSL_FLAG(int64_t, max_memory, 0,
          "bytes all sessions together may take, by the estimate made before each is built; 0: 3/4 of physical memory");
ABSL_FLAG(int64_t, max_particles, int64_t{1} << 24, "solid particles of all sessions together");
ABSL_FLAG(int, max_fluid_threads, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
          "threads of the one pool that every session's fluid steps share, beyond the thread stepping each "
          "session (a session's scenario.fluid.threads cuts its steps into that many parts)");
ABSL_FLAG(int, owner_max_sessions, 0, "sessions one owner may hold at once; 0: --max_sessions");
ABSL_FLAG(int64_t, owner_max_memory, 0, "bytes one owner's sessions may take, as --max_memory; 0: --max_memory");
ABSL_FLAG(int, owner_max_running, 0, "sessions one owner may run at once; 0: --max_sessions");
ABSL_FLAG(double, owner_call_rate, 0,
          "calls per second one owner may make (token bucket; streams count once); past it RESOURCE_EXHAUSTED "
          "with the wait; 0: no limit");
ABSL_FLAG(double, owner_call_burst, 0, "calls an idle owner may make at once past --owner_call_rate; 0: one second's");
ABSL_FLAG(absl::Duration, autosave_interval, absl::Minutes(2),
          "wall time between automatic saves of every session that changed (a crash loses at most this); 0 "
          "turns them off");
ABSL_FLAG(int, max_call_threads, 256, "threads serving calls at once; further calls get RESOURCE_EXHAUSTED");
ABSL_FLAG(int, call_nice, 10,
          "nice levels below the simulation workers at which calls are answered (0-19; 0: the same priority), "
          "so that a crowd of clients slows the calls rather than the runs");
ABSL_FLAG(absl::Duration, call_slice, absl::Microseconds(100),
          "time slice the kernel gives the call threads (0.1-100 ms; 0: the kernel's default; Linux 6.12+, ignored "
          "before): a short one lets a call that wakes preempt the simulation sooner, without changing its share");
ABSL_FLAG(absl::Duration, max_connection_idle, absl::Minutes(5), "a connection without calls this long is closed");
ABSL_FLAG(std::string, tls_cert, "", "PEM certificate chain: serve TLS (with --tls_key)");
ABSL_FLAG(std::string, tls_key, "", "PEM private key of --tls_cert");
ABSL_FLAG(std::string, tls_client_ca, "",
          "PEM CA certificates: require client certificates signed by them (mutual TLS); the certificate's common "
          "name is the caller's owner name unless a bearer token is sent");
ABSL_FLAG(std::string, tokens_file, "",
          "lines `<sha256 hex of a token> <owner> <user|admin>`: calls must send `authorization: Bearer <token>`; "
          "reloaded on SIGHUP");
ABSL_FLAG(absl::Duration, tls_reload_interval, absl::Minutes(1),
          "how often the --tls_* files are read again: a renewed certificate or CA is served without a restart");
ABSL_FLAG(bool, allow_insecure, false,
          "serve an address that is not loopback or a Unix socket without TLS or without authenticating callers");
ABSL_FLAG(bool, reflection, true, "serve gRPC reflection (grpcurl, grpc_cli)");
ABSL_FLAG(std::string, health_listen, "",
          "a second address serving only the gRPC health service, in plaintext, for probes that speak no TLS "
          "(Kubernetes' gRPC probes); it answers SERVING or NOT_SERVING and nothing else; empty: none");
ABSL_FLAG(std::string, advertise_address, "",
          "HOST:PORT where clients reach this daemon (told in every Session's endpoint, and in ServerInfo), so a "
          "client that knows several daemons follows each session to its own; empty: none");
ABSL_FLAG(std::string, port_file, "", "if set, the port actually bound is written there (for tests and scripts)");
ABSL_FLAG(std::string, log_level, "info", "trace, debug, info, warn or error");

namespace {

constexpr int kMaxMessageBytes = 4 << 20;
// Calls in flight at SIGTERM get this long to finish before they are cancelled.
constexpr auto kShutdownGrace = std::chrono::seconds(2);
constexpr int kMaxStreamsPerConnection = 100;

// What one client can hold of the daemon: streams per connection, threads for calls in flight
// (the synchronous server runs each call on a thread; past the cap calls get RESOURCE_EXHAUSTED),
// connections that sit idle (closed after --max_connection_idle), dead peers (keepalive pings).
void apply_connection_limits(grpc::ServerBuilder& builder) {
  builder.AddChannelArgument(GRPC_ARG_MAX_CONCURRENT_STREAMS, kMaxStreamsPerConnection);
  builder.AddChannelArgument(GRPC_ARG_MAX_CONNECTION_IDLE_MS,
                             static_cast<int>(absl::ToInt64Milliseconds(absl::GetFlag(FLAGS_max_connection_idle))));
  // A connection takes no new calls after an hour; the streams on it may go on (an infinite grace).
  builder.AddChannelArgument(GRPC_ARG_MAX_CONNECTION_AGE_MS, 60 * 60 * 1000);
  builder.AddChannelArgument(GRPC_ARG_MAX_CONNECTION_AGE_GRACE_MS, std::numeric_limits<int>::max());
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, 60 * 1000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 20 * 1000);
  grpc::ResourceQuota quota("lbsolidd");
  quota.SetMaxThreads(absl::GetFlag(FLAGS_max_call_threads));
  builder.SetResourceQuota(quota);
}

// Every connection and every file being written takes a descriptor; the soft limit (often 1024)
// is raised to the hard one so that the idle-connection timeout, not the limit, bounds them.
void raise_descriptor_limit() {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur >= limit.rlim_max) return;
  limit.rlim_cur = limit.rlim_max;
  if (setrlimit(RLIMIT_NOFILE, &limit) != 0) spdlog::warn("cannot raise the open-file limit: {}", std::strerror(errno));
}

long long physical_memory_bytes() {
  return static_cast<long long>(sysconf(_SC_PHYS_PAGES)) * static_cast<long long>(sysconf(_SC_PAGE_SIZE));
}

int fail_start(const std::string& message) {
  spdlog::critical("{}", message);
  return 2;
}

// gRPC starts threads of its own when it is first used (its executors, the resolver's, the timer
// manager, which starts more timer threads later), at the nice value and time slice of the thread
// that uses it. Holds gRPC open from a thread lowered to the calls' priority before anything else
// uses it, so that none of gRPC's threads competes with the simulation's. (A refusal to lower is
// reported once, when the main thread lowers itself.)
class GrpcStartedBelowTheSimulation {
 public:
  GrpcStartedBelowTheSimulation(int call_nice, absl::Duration call_slice) {
    std::thread([&] {
      lbsolid::server::lower_this_thread_priority(call_nice);
      if (call_slice != absl::ZeroDuration())
        lbsolid::server::shorten_this_thread_time_slice(absl::ToChronoMicroseconds(call_slice));
      grpc_init();
    }).join();
  }
  ~GrpcStartedBelowTheSimulation() { grpc_shutdown(); }
  GrpcStartedBelowTheSimulation(const GrpcStartedBelowTheSimulation&) = delete;
  GrpcStartedBelowTheSimulation& operator=(const GrpcStartedBelowTheSimulation&) = delete;
};

}  // namespace

int main(int argc, char** argv) {
  absl::SetProgramUsageMessage("lbsolidd [--listen HOST:PORT] [--data_dir DIR] [--workers N] ...");
  // --help lists the flags of this file (Abseil's default matches files named like the binary,
  // and there is none: it said "No flags matched"); --version names the build.
  absl::FlagsUsageConfig usage;
  usage.contains_help_flags = [](absl::string_view file) { return absl::EndsWith(file, "daemon/main.cpp"); };
  usage.contains_helpshort_flags = usage.contains_help_flags;
  usage.version_string = [] { return std::string("lbsolidd ") + LBSOLID_VERSION + " (" + LBSOLID_GIT_REVISION + ")\n"; };
  absl::SetFlagsUsageConfig(usage);
  absl::ParseCommandLine(argc, argv);
  // Debian builds Abseil without NDEBUG, which leaves absl::Mutex's deadlock detection on: every
  // lock gRPC takes then updates a global lock graph (measured under the 64-client load: several
  // percent of all CPU, in daemon and clients alike). It is a debugging aid, never a release check.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  spdlog::set_level(spdlog::level::from_str(absl::GetFlag(FLAGS_log_level)));
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  if (const std::string error = lbsolid::fluid::kernel_isa_environment_error(); !error.empty()) return fail_start(error);

  lbsolid::server::ManagerLimits limits;
  limits.workers = absl::GetFlag(FLAGS_workers);
  limits.max_sessions = absl::GetFlag(FLAGS_max_sessions);
  limits.max_cells = absl::GetFlag(FLAGS_max_cells);
  limits.max_sync_steps = absl::GetFlag(FLAGS_max_sync_steps);
  limits.max_memory_bytes = absl::GetFlag(FLAGS_max_memory);
  if (limits.max_memory_bytes == 0) limits.max_memory_bytes = physical_memory_bytes() / 4 * 3;
  limits.max_particles = absl::GetFlag(FLAGS_max_particles);
  limits.max_fluid_threads = absl::GetFlag(FLAGS_max_fluid_threads);
  if (limits.max_memory_bytes < 0) return fail_start("--max_memory: must not be negative");
  if (limits.max_particles < 0) return fail_start("--max_particles: must not be negative");
  if (limits.max_fluid_threads < 0 || limits.max_fluid_threads > 1024)
    return fail_start("--max_fluid_threads: must lie in [0, 1024]");
  const absl::Duration autosave = absl::GetFlag(FLAGS_autosave_interval);
  if (autosave < absl::ZeroDuration()) return fail_start("--autosave_interval: must not be negative");
  limits.autosave_interval = absl::ToChronoMilliseconds(autosave);
  if (limits.workers < 1) return fail_start("--workers: must be at least 1");
  if (absl::GetFlag(FLAGS_max_call_threads) < 8) return fail_start("--max_call_threads: must be at least 8");
  if (absl::GetFlag(FLAGS_call_nice) < 0 || absl::GetFlag(FLAGS_call_nice) > 19)
    return fail_start("--call_nice: must lie in [0, 19]");
  const absl::Duration call_slice = absl::GetFlag(FLAGS_call_slice);
  if (call_slice != absl::ZeroDuration() && (call_slice < absl::Microseconds(100) || call_slice > absl::Milliseconds(100)))
    return fail_start("--call_slice: must be 0 or lie in [100us, 100ms], got " + absl::FormatDuration(call_slice));
  if (absl::GetFlag(FLAGS_max_connection_idle) < absl::Seconds(1))
    return fail_start("--max_connection_idle: must be at least 1s");
  if (limits.max_sessions < 1) return fail_start("--max_sessions: must be at least 1");
  if (limits.max_cells < 1) return fail_start("--max_cells: must be at least 1");
  const auto quota = [](auto flag, auto whole) { return flag == 0 ? whole : flag; };
  limits.per_owner.sessions = quota(absl::GetFlag(FLAGS_owner_max_sessions), limits.max_sessions);
  limits.per_owner.memory_bytes = quota(absl::GetFlag(FLAGS_owner_max_memory), limits.max_memory_bytes);
  limits.per_owner.running = quota(absl::GetFlag(FLAGS_owner_max_running), limits.max_sessions);
  if (limits.per_owner.sessions < 0) return fail_start("--owner_max_sessions: must not be negative");
  if (limits.per_owner.memory_bytes < 0) return fail_start("--owner_max_memory: must not be negative");
  if (limits.per_owner.running < 0) return fail_start("--owner_max_running: must not be negative");
  const lbsolid::server::auth::CallRateLimits call_limits{absl::GetFlag(FLAGS_owner_call_rate),
                                                          absl::GetFlag(FLAGS_owner_call_burst)};
  if (!(call_limits.calls_per_second >= 0) || !std::isfinite(call_limits.calls_per_second))
    return fail_start("--owner_call_rate: must be a finite number of calls per second, 0 or more");
  if (!(call_limits.burst >= 0) || !std::isfinite(call_limits.burst))
    return fail_start("--owner_call_burst: must be a finite number of calls, 0 or more");
  const std::string advertise_address = absl::GetFlag(FLAGS_advertise_address);
  if (const absl::Status ok = lbsolid::server::auth::check_advertise_address(advertise_address); !ok.ok())
    return fail_start(std::string(ok.message()));

  // Signals are taken by one thread with sigwait: block them before any other thread starts (the TLS
  // file watcher's included: a SIGHUP delivered to it would end the daemon).
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::optional<GrpcStartedBelowTheSimulation> grpc_started;
  try {
    grpc_started.emplace(absl::GetFlag(FLAGS_call_nice), call_slice);
  } catch (const std::system_error& e) {
    return fail_start(std::string("cannot start a thread: ") + e.what());
  }

  std::shared_ptr<lbsolid::server::auth::TokenTable> tokens;
  if (!absl::GetFlag(FLAGS_tokens_file).empty()) {
    try {
      tokens = std::make_shared<lbsolid::server::auth::TokenTable>(absl::GetFlag(FLAGS_tokens_file));
    } catch (const std::exception& e) {
      return fail_start(e.what());
    }
  }
  const auto authenticator = std::make_shared<const lbsolid::server::auth::Authenticator>(
      tokens, !absl::GetFlag(FLAGS_tls_client_ca).empty());
  const lbsolid::server::auth::TransportOptions transport{
      absl::GetFlag(FLAGS_listen), absl::GetFlag(FLAGS_tls_cert), absl::GetFlag(FLAGS_tls_key),
      absl::GetFlag(FLAGS_tls_client_ca), absl::GetFlag(FLAGS_allow_insecure),
      static_cast<unsigned>(std::clamp<int64_t>(absl::ToInt64Seconds(absl::GetFlag(FLAGS_tls_reload_interval)), 0,
                                                24 * 3600))};
  const auto credentials = lbsolid::server::auth::server_credentials(transport, authenticator);
  if (!credentials.ok()) return fail_start(std::string(credentials.status().message()));
  if (!lbsolid::server::auth::is_local_address(transport.listen)) {
    if (transport.tls_cert.empty())
      spdlog::warn("--allow_insecure: serving plaintext on {}: anyone on the network can read and forge calls",
                   transport.listen);
    if (!authenticator->authenticates())
      spdlog::warn("--allow_insecure: no --tokens_file or --tls_client_ca: anyone who reaches {} acts as admin",
                   transport.listen);
  }

  raise_descriptor_limit();

  std::unique_ptr<lbsolid::server::SessionManager> manager;
  try {
    manager = std::make_unique<lbsolid::server::SessionManager>(
        absl::GetFlag(FLAGS_data_dir), limits,
        lbsolid::server::storage::WriterInfo{LBSOLID_VERSION, LBSOLID_GIT_REVISION});
  } catch (const std::filesystem::filesystem_error& e) {
    return fail_start(std::string("--data_dir: ") + e.what());
  } catch (const std::system_error& e) {
    return fail_start(std::string("--workers, --max_fluid_threads: cannot start the threads: ") + e.what());
  } catch (const std::exception& e) {
    return fail_start(std::string("--data_dir: ") + e.what());
  }
  const int recovered = manager->recover();
  // The workers, the autosave and the session builder have started at the base priority; gRPC's
  // first threads below it; every thread from here on (the server's, and so every call) starts
  // from this one, below it too.
  if (const int error = lbsolid::server::lower_this_thread_priority(absl::GetFlag(FLAGS_call_nice)); error != 0)
    spdlog::warn("--call_nice: cannot lower the priority of the call threads: {}", std::strerror(error));
  if (call_slice != absl::ZeroDuration()) {
    const int error = lbsolid::server::shorten_this_thread_time_slice(absl::ToChronoMicroseconds(call_slice));
    if (error == EOPNOTSUPP)
      spdlog::info("--call_slice: this kernel keeps its own time slices (they need Linux 6.12 or later)");
    else if (error != 0)
      spdlog::warn("--call_slice: cannot set the call threads' time slice: {}", std::strerror(error));
  }

  lbsolid::server::SimulationService service(*manager, authenticator, call_limits, advertise_address);
  grpc::EnableDefaultHealthCheckService(true);
  if (absl::GetFlag(FLAGS_reflection)) grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  // The probes' server: health alone.
  lbsolid::v1::Simulation::Service unimplemented;
  grpc::ServerBuilder health_builder;
  int health_port = 0;
  const std::string health_listen = absl::GetFlag(FLAGS_health_listen);
  if (!health_listen.empty()) {
    health_builder.AddListeningPort(health_listen, grpc::InsecureServerCredentials(), &health_port);
    health_builder.SetOption(std::make_unique<WithoutReflection>());
    // A server needs a synchronous service for gRPC to poll its calls (and serve health with):
    // the generated base class, whose every method answers UNIMPLEMENTED. (A generic callback
    // service works too, but its reactor's hand-offs inside gRPC, which is not built for
    // ThreadSanitizer, read as races there.)
    health_builder.RegisterService(&unimplemented);
    apply_connection_limits(health_builder);
  }
  grpc::ServerBuilder builder;
  if (!absl::GetFlag(FLAGS_reflection)) builder.SetOption(std::make_unique<WithoutReflection>());
  int port = 0;
  builder.AddListeningPort(transport.listen, *credentials, &port);
  builder.SetMaxReceiveMessageSize(kMaxMessageBytes);
  builder.SetMaxSendMessageSize(kMaxMessageBytes);
  apply_connection_limits(builder);
  builder.RegisterService(&service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  // A Unix socket has no port: gRPC reports 1 for it.
  if (!server || port == 0) return fail_start("--listen: cannot serve on " + absl::GetFlag(FLAGS_listen));
  std::unique_ptr<grpc::Server> health_server;
  if (!health_listen.empty()) {
    health_server = health_builder.BuildAndStart();
    if (!health_server || health_port == 0) return fail_start("--health_listen: cannot serve on " + health_listen);
  }
  // Probes that name the service (Kubernetes' gRPC probes) get the same answer as those that do not.
  const auto set_serving = [&](bool serving) {
    for (grpc::Server* s : {server.get(), health_server.get()}) {
      if (!s) continue;
      s->GetHealthCheckService()->SetServingStatus(serving);
      s->GetHealthCheckService()->SetServingStatus("lbsolid.v1.Simulation", serving);
    }
  };
  set_serving(true);
  if (!absl::GetFlag(FLAGS_port_file).empty()) {
    try {  // readers never see a half-written number
      lbsolid::server::storage::write_text_file_replacing(absl::GetFlag(FLAGS_port_file), absl::StrCat(port, "\n"));
    } catch (const std::exception& e) {
      return fail_start(std::string("--port_file: ") + e.what());
    }
  }
  spdlog::info(
      "lbsolidd {} ({}) serving lbsolid.v1 on {} (port {}, {}, {}), {} workers, data in {}, {} sessions recovered; "
      "limits: {} MiB, {} particles, {} fluid threads; autosave every {}; fluid kernels for {}{}",
      LBSOLID_VERSION, LBSOLID_GIT_REVISION, transport.listen, port,
      transport.tls_cert.empty() ? "plaintext" : (transport.tls_client_ca.empty() ? "TLS" : "mutual TLS"),
      tokens ? absl::StrCat(tokens->size(), " tokens") : std::string(authenticator->authenticates() ? "certificates" : "no authentication"),
      limits.workers,
      absl::GetFlag(FLAGS_data_dir), recovered, limits.max_memory_bytes >> 20, limits.max_particles,
      limits.max_fluid_threads, absl::FormatDuration(autosave), lbsolid::fluid::kernel_isa_name(lbsolid::fluid::kernel_isa()),
      health_server ? absl::StrCat("; health alone on ", health_listen, " (plaintext)") : std::string());

  int signal = 0;
  while (sigwait(&signals, &signal) == 0 && signal == SIGHUP) {
    if (!tokens) {
      spdlog::info("SIGHUP: no --tokens_file to reload");
    } else if (const auto status = tokens->reload(); status.ok()) {
      spdlog::info("SIGHUP: {} tokens loaded from {}", tokens->size(), absl::GetFlag(FLAGS_tokens_file));
    } else {
      spdlog::error("SIGHUP: the tokens in force stay: {}", std::string(status.message()));
    }
  }
  spdlog::info("{}: no new calls; pausing and saving every session", signal == SIGTERM ? "SIGTERM" : "SIGINT");
  // Runs stop where SIGTERM found them; then no more calls (new ones get UNAVAILABLE; those in
  // flight finish, or are cancelled after the grace period), so that nothing is answered OK after
  // its session was saved; then the saves.
  set_serving(false);
  manager->pause_all();
  server->Shutdown(std::chrono::system_clock::now() + kShutdownGrace);
  if (health_server) health_server->Shutdown(std::chrono::system_clock::now());
  const auto unsaved = manager->shutdown();
  manager.reset();
  if (unsaved.empty())
    spdlog::info("lbsolidd stopped; every session saved");
  else
    spdlog::critical("lbsolidd stopped; {} session(s) NOT saved (see above): {}", unsaved.size(),
                     absl::StrJoin(unsaved, ", "));
  // Everything is on disk and logged: leave without the libraries' exit handlers, because HDF5
  // 1.10.8 crashes in them (H5F__close_cb) after a write failed for lack of space, which would
  // turn an honest exit code into a segfault.
  spdlog::shutdown();
  std::_Exit(unsaved.empty() ? 0 : 1);
}
