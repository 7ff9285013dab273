// lbsolidd: the lbsolid simulation daemon. Serves lbsolid.v1.Simulation, the standard gRPC health
// service and server reflection on --listen; keeps sessions on --workers threads. SIGTERM (or
// SIGINT) pauses and checkpoints every session under --data_dir, then exits 0; the next start
// brings those sessions back PAUSED under their old ids.
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "server/service/simulation_service.h"
#include "server/session/session_manager.h"
#include "server/version.h"

ABSL_FLAG(std::string, listen, "127.0.0.1:50051", "address to serve on; port 0 picks a free port");
ABSL_FLAG(std::string, data_dir, "./lbsolid-data", "where checkpoints and saved sessions live");
ABSL_FLAG(int, workers, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
          "worker threads that advance running sessions");
ABSL_FLAG(int, max_sessions, 64, "sessions held at most");
ABSL_FLAG(int64_t, max_cells, int64_t{1} << 26, "fluid nodes per session at most");
ABSL_FLAG(int64_t, max_sync_steps, 10000, "largest Step request");
ABSL_FLAG(std::string, port_file, "", "if set, the port actually bound is written there (for tests and scripts)");
ABSL_FLAG(std::string, log_level, "info", "trace, debug, info, warn or error");

namespace {

constexpr int kMaxMessageBytes = 4 << 20;

void write_port_file(const std::string& path, int port) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary);
    out << port << "\n";
  }
  std::filesystem::rename(temporary, path);  // readers never see a half-written number
}

int fail_start(const std::string& message) {
  spdlog::critical("{}", message);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  absl::SetProgramUsageMessage("lbsolidd [--listen HOST:PORT] [--data_dir DIR] [--workers N] ...");
  absl::ParseCommandLine(argc, argv);
  spdlog::set_level(spdlog::level::from_str(absl::GetFlag(FLAGS_log_level)));
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");

  lbsolid::server::ManagerLimits limits;
  limits.workers = absl::GetFlag(FLAGS_workers);
  limits.max_sessions = absl::GetFlag(FLAGS_max_sessions);
  limits.max_cells = absl::GetFlag(FLAGS_max_cells);
  limits.max_sync_steps = absl::GetFlag(FLAGS_max_sync_steps);
  if (limits.workers < 1) return fail_start("--workers: must be at least 1");
  if (limits.max_sessions < 1) return fail_start("--max_sessions: must be at least 1");
  if (limits.max_cells < 1) return fail_start("--max_cells: must be at least 1");

  // Signals are taken by one thread with sigwait: block them before any other thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::unique_ptr<lbsolid::server::SessionManager> manager;
  try {
    manager = std::make_unique<lbsolid::server::SessionManager>(
        absl::GetFlag(FLAGS_data_dir), limits,
        lbsolid::server::storage::WriterInfo{LBSOLID_VERSION, LBSOLID_GIT_REVISION});
  } catch (const std::exception& e) {
    return fail_start(std::string("--data_dir: ") + e.what());
  }
  const int recovered = manager->recover();

  lbsolid::server::SimulationService service(*manager);
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(absl::GetFlag(FLAGS_listen), grpc::InsecureServerCredentials(), &port);
  builder.SetMaxReceiveMessageSize(kMaxMessageBytes);
  builder.SetMaxSendMessageSize(kMaxMessageBytes);
  builder.RegisterService(&service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) return fail_start("--listen: cannot serve on " + absl::GetFlag(FLAGS_listen));
  server->GetHealthCheckService()->SetServingStatus(true);
  if (!absl::GetFlag(FLAGS_port_file).empty()) write_port_file(absl::GetFlag(FLAGS_port_file), port);
  spdlog::info("lbsolidd {} ({}) serving lbsolid.v1 on {} (port {}), {} workers, data in {}, {} sessions recovered",
               LBSOLID_VERSION, LBSOLID_GIT_REVISION, absl::GetFlag(FLAGS_listen), port, limits.workers,
               absl::GetFlag(FLAGS_data_dir), recovered);

  int signal = 0;
  sigwait(&signals, &signal);
  spdlog::info("{}: pausing and checkpointing every session", signal == SIGTERM ? "SIGTERM" : "SIGINT");
  server->GetHealthCheckService()->SetServingStatus(false);
  manager->shutdown();
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  manager.reset();
  spdlog::info("lbsolidd stopped");
  return 0;
}
