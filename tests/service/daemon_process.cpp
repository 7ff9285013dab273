#include "service/daemon_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <thread>

namespace lbsolid::testing {

namespace fs = std::filesystem;

std::string fresh_directory(const std::string& stem) {
  std::random_device random;
  const fs::path dir = fs::temp_directory_path() / (stem + "-" + std::to_string(getpid()) + "-" + std::to_string(random()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

DaemonProcess::DaemonProcess(std::string data_dir, std::vector<std::string> extra_flags, ProcessLimits limits,
                             Connection connection)
    : data_dir_(std::move(data_dir)) {
  fs::create_directories(data_dir_);
  const std::string port_file = data_dir_ + "/port";
  fs::remove(port_file);
  std::vector<std::string> args = {LBSOLIDD_PATH, "--listen=127.0.0.1:0", "--data_dir=" + data_dir_,
                                   "--port_file=" + port_file, "--workers=2", "--log_level=warn"};
  args.insert(args.end(), extra_flags.begin(), extra_flags.end());
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);  // a crashed test takes its daemon with it
    if (!connection.log_path.empty()) {
      const int log = open(connection.log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (log < 0 || dup2(log, STDOUT_FILENO) < 0 || dup2(log, STDERR_FILENO) < 0) _exit(126);
    }
    if (limits.max_file_bytes >= 0) {
      signal(SIGXFSZ, SIG_IGN);  // ignored dispositions survive execv
      const rlimit size{static_cast<rlim_t>(limits.max_file_bytes), static_cast<rlim_t>(limits.max_file_bytes)};
      if (setrlimit(RLIMIT_FSIZE, &size) != 0) _exit(126);
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  int port = 0;
  while (port == 0) {
    if (std::chrono::steady_clock::now() > give_up) throw std::runtime_error("lbsolidd did not write its port");
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("lbsolidd exited at start with status " + std::to_string(WEXITSTATUS(status)));
    }
    std::ifstream in(port_file);
    if (!(in >> port)) port = 0;
    if (port == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  address_ = "127.0.0.1:" + std::to_string(port);
  for (const auto& flag : extra_flags)  // the last --listen counts, as for the daemon's flags
    if (flag.starts_with("--listen=unix:")) address_ = flag.substr(std::string("--listen=").size());
    else if (flag.starts_with("--listen=")) address_ = "127.0.0.1:" + std::to_string(port);
  const auto credentials = connection.credentials ? connection.credentials : grpc::InsecureChannelCredentials();
  channel_ = grpc::CreateChannel(address_, credentials);
  if (connection.connect && !channel_->WaitForConnected(std::chrono::system_clock::now() + std::chrono::seconds(10)))
    throw std::runtime_error("lbsolidd at " + address_ + " did not accept a connection");
}

DaemonProcess::~DaemonProcess() {
  if (pid_ > 0) stop(SIGKILL);
}

int DaemonProcess::stop(int signal) {
  if (pid_ <= 0) return -1;
  kill(pid_, signal);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

std::unique_ptr<v1::Simulation::Stub> DaemonProcess::stub() const { return v1::Simulation::NewStub(channel_); }

std::unique_ptr<grpc::ClientContext> deadline_context(double seconds) {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<long>(seconds * 1000)));
  return context;
}

bool wait_for_state(v1::Simulation::Stub& stub, const std::string& id, v1::SessionState state, double seconds) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<long>(seconds * 1000));
  while (std::chrono::steady_clock::now() < give_up) {
    v1::GetSessionRequest request;
    request.set_session_id(id);
    v1::Session session;
    auto context = deadline_context();
    if (stub.GetSession(context.get(), request, &session).ok() && session.state() == state) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

}  // namespace lbsolid::testing
