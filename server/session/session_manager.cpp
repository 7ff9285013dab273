#include "server/session/session_manager.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace lbsolid::server {

namespace fs = std::filesystem;

namespace {

constexpr auto kSlice = std::chrono::milliseconds(50);

long long unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// "s-000012" -> 12; 0 if the name is not a session id.
long session_number(const std::string& name) {
  if (name.size() < 3 || name.rfind("s-", 0) != 0) return 0;
  long n = 0;
  for (std::size_t k = 2; k < name.size(); ++k) {
    if (name[k] < '0' || name[k] > '9') return 0;
    n = n * 10 + (name[k] - '0');
  }
  return n;
}

// A checkpoint id is "<session id>/step-<digits>": nothing else may reach the file system.
bool valid_checkpoint_id(const std::string& id) {
  const auto slash = id.find('/');
  if (slash == std::string::npos || session_number(id.substr(0, slash)) == 0) return false;
  const std::string step = id.substr(slash + 1);
  if (step.size() <= 5 || step.rfind("step-", 0) != 0) return false;
  return step.find_first_not_of("0123456789", 5) == std::string::npos;
}

}  // namespace

SessionManager::SessionManager(std::string data_dir, ManagerLimits limits, storage::WriterInfo writer)
    : data_dir_(std::move(data_dir)), limits_(limits), writer_(std::move(writer)) {
  fs::create_directories(fs::path(data_dir_) / "sessions");
  fs::create_directories(fs::path(data_dir_) / "checkpoints");
  remove_partial_writes();
  // New ids never reuse one that has files on disk.
  for (const char* sub : {"sessions", "checkpoints"})
    for (const auto& entry : fs::directory_iterator(fs::path(data_dir_) / sub))
      next_number_ = std::max(next_number_, session_number(entry.path().filename().string()) + 1);
  for (int w = 0; w < limits_.workers; ++w) workers_.emplace_back([this] { work(); });
}

SessionManager::~SessionManager() {
  for (const auto& session : list()) session->close();
  stop_workers();
}

// A checkpoint is written as <file>.tmp-<pid> and renamed; a daemon killed mid-write leaves the
// temporary file behind (the old checkpoint is intact). Nothing else writes there: remove them.
void SessionManager::remove_partial_writes() {
  for (const auto& entry : fs::recursive_directory_iterator(data_dir_)) {
    if (!entry.is_regular_file() || entry.path().filename().string().find(".tmp-") == std::string::npos) continue;
    std::error_code ignored;
    fs::remove(entry.path(), ignored);
    spdlog::warn("removed {}: a checkpoint write interrupted by an earlier daemon", entry.path().string());
  }
}

std::string SessionManager::next_id() { return absl::StrFormat("s-%06d", next_number_++); }

// ---- creation ------------------------------------------------------------------------------

absl::Status SessionManager::admit(const std::string& request_id, const v1::Scenario& scenario,
                                   std::shared_ptr<Session>* existing) {
  if (!request_id.empty()) {
    const auto it = by_request_id_.find(request_id);
    if (it != by_request_id_.end()) {
      const auto session = sessions_.find(it->second);
      if (session != sessions_.end()) {
        if (session->second->scenario().SerializeAsString() != scenario.SerializeAsString())
          return absl::AlreadyExistsError(absl::StrCat("request_id: \"", request_id, "\" already created session ",
                                                       it->second, " from a different scenario"));
        *existing = session->second;
        return absl::OkStatus();
      }
    }
  }
  if (static_cast<int>(sessions_.size()) >= limits_.max_sessions)
    return absl::ResourceExhaustedError(absl::StrCat("sessions: the daemon holds its limit of ", limits_.max_sessions,
                                                     " sessions (--max_sessions); delete one or retry later"));
  return absl::OkStatus();
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::build(SessionSetup setup) {
  if (!setup.translated.ok())
    return absl::InvalidArgumentError(absl::StrJoin(setup.translated.errors, "; "));
  const auto& f = setup.translated.scene.fluid;
  const long cells = setup.translated.scene.with_fluid ? static_cast<long>(f.nx) * f.ny * f.nz : 0;
  if (cells > limits_.max_cells)
    return absl::ResourceExhaustedError(absl::StrCat("scenario.domain: ", cells, " fluid nodes exceed this daemon's limit of ",
                                                     limits_.max_cells, " per session (--max_cells)"));
  try {
    return std::make_shared<Session>(std::move(setup));
  } catch (const std::invalid_argument& e) {
    return absl::InvalidArgumentError(e.what());
  } catch (const std::bad_alloc&) {
    return absl::ResourceExhaustedError("scenario.domain: not enough memory on the daemon for this scenario");
  }
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::create(const v1::Scenario& scenario,
                                                                const std::string& request_id) {
  std::lock_guard lock(mutex_);  // one creation at a time: ids and request ids stay consistent
  auto session = add_locked(scenario, request_id, [](Session&) { return absl::OkStatus(); });
  if (!session.ok()) return session;
  const auto described = (*session)->describe();
  spdlog::info("session {}: created \"{}\" ({} fluid nodes, {} particles, stages {})", (*session)->id(),
               scenario.name(), (*session)->cells(), described.particles(), absl::StrJoin(described.stages(), ","));
  for (const auto& warning : described.warnings()) spdlog::warn("session {}: {}", (*session)->id(), warning);
  return session;
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::add_locked(
    const v1::Scenario& scenario, const std::string& request_id,
    const std::function<absl::Status(Session&)>& prepare) {
  std::shared_ptr<Session> existing;
  if (auto admitted = admit(request_id, scenario, &existing); !admitted.ok()) return admitted;
  if (existing) return existing;
  SessionSetup setup{next_id(), request_id, scenario, translate_scenario(scenario), unix_ms_now()};
  auto session = build(std::move(setup));
  if (session.ok())
    if (auto prepared = prepare(**session); !prepared.ok()) session = prepared;
  if (!session.ok()) {
    --next_number_;  // the id was not used
    return session.status();
  }
  sessions_[(*session)->id()] = *session;
  if (!request_id.empty()) by_request_id_[request_id] = (*session)->id();
  return session;
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::find(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(id);
  if (it == sessions_.end()) return absl::NotFoundError(absl::StrCat("session_id: no session \"", id, "\""));
  return it->second;
}

std::vector<std::shared_ptr<Session>> SessionManager::list() const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<Session>> out;
  for (const auto& [id, session] : sessions_) out.push_back(session);
  return out;
}

int SessionManager::count() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(sessions_.size());
}

absl::Status SessionManager::remove(const std::string& id) {
  std::shared_ptr<Session> session;
  {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(id);
    if (it == sessions_.end()) return absl::NotFoundError(absl::StrCat("session_id: no session \"", id, "\""));
    session = it->second;
    sessions_.erase(it);
    if (!session->request_id().empty()) by_request_id_.erase(session->request_id());
  }
  session->close();
  std::error_code ignored;
  fs::remove_all(fs::path(data_dir_) / "sessions" / id, ignored);
  spdlog::info("session {}: deleted", id);
  return absl::OkStatus();
}

// ---- running -------------------------------------------------------------------------------

absl::Status SessionManager::run(const std::string& id, long steps) {
  auto session = find(id);
  if (!session.ok()) return session.status();
  if (auto status = (*session)->run(steps); !status.ok()) return status;
  schedule(*session);
  return absl::OkStatus();
}

absl::Status SessionManager::resume(const std::string& id) {
  auto session = find(id);
  if (!session.ok()) return session.status();
  if (auto status = (*session)->resume(); !status.ok()) return status;
  schedule(*session);
  return absl::OkStatus();
}

void SessionManager::schedule(const std::shared_ptr<Session>& session) {
  if (!session->claim_schedule()) return;
  std::lock_guard lock(queue_mutex_);
  queue_.push_back(session);
  queue_ready_.notify_one();
}

void SessionManager::work() {
  while (true) {
    std::shared_ptr<Session> session;
    {
      std::unique_lock lock(queue_mutex_);
      queue_ready_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      session = queue_.front();
      queue_.pop_front();
    }
    session->advance(kSlice);
    if (session->finish_slice()) {
      std::lock_guard lock(queue_mutex_);
      queue_.push_back(session);  // to the back: round robin between running sessions
      queue_ready_.notify_one();
    }
  }
}

void SessionManager::stop_workers() {
  {
    std::lock_guard lock(queue_mutex_);
    stopping_ = true;
    queue_.clear();
    queue_ready_.notify_all();
  }
  for (auto& worker : workers_)
    if (worker.joinable()) worker.join();
  workers_.clear();
}

// ---- checkpoints ---------------------------------------------------------------------------

absl::StatusOr<CheckpointInfo> SessionManager::checkpoint(const std::string& id) {
  auto session = find(id);
  if (!session.ok()) return session.status();
  const auto contents = (*session)->checkpoint_contents();
  CheckpointInfo info;
  info.step = contents.state.step;
  info.checkpoint_id = absl::StrFormat("%s/step-%09d", id, info.step);
  const fs::path path = fs::path(data_dir_) / "checkpoints" / (info.checkpoint_id + ".h5");
  try {
    fs::create_directories(path.parent_path());
    storage::write_checkpoint(path.string(), contents, writer_);
  } catch (const std::exception& e) {
    spdlog::error("session {}: checkpoint failed: {}", id, e.what());
    return absl::InternalError(absl::StrCat("checkpoint: ", e.what()));
  }
  info.path = path.string();
  info.bytes = static_cast<long>(fs::file_size(path));
  spdlog::info("session {}: checkpoint {} ({} bytes)", id, info.checkpoint_id, info.bytes);
  return info;
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::restore(const std::string& checkpoint_id,
                                                                 const std::string& request_id) {
  if (!valid_checkpoint_id(checkpoint_id))
    return absl::InvalidArgumentError(absl::StrCat("checkpoint_id: \"", checkpoint_id,
                                                   "\" is not of the form <session id>/step-<step>"));
  const fs::path path = fs::path(data_dir_) / "checkpoints" / (checkpoint_id + ".h5");
  if (!fs::exists(path)) return absl::NotFoundError(absl::StrCat("checkpoint_id: no checkpoint \"", checkpoint_id, "\""));
  storage::CheckpointContents contents;
  try {
    contents = storage::read_checkpoint(path.string());
  } catch (const std::exception& e) {
    return absl::DataLossError(absl::StrCat("checkpoint_id: ", e.what()));
  }
  v1::Scenario scenario;
  std::string error;
  if (!parse_scenario_text(contents.scenario_text, &scenario, &error))
    return absl::DataLossError(absl::StrCat("checkpoint_id: its scenario does not parse: ", error));

  std::lock_guard lock(mutex_);
  auto session = add_locked(scenario, request_id, [&](Session& fresh) {
    try {
      fresh.restore(contents.state, contents.target_step, v1::SESSION_STATE_PAUSED);
      return absl::OkStatus();
    } catch (const std::invalid_argument& e) {
      return absl::DataLossError(absl::StrCat("checkpoint_id: ", e.what()));
    }
  });
  if (!session.ok()) return session;
  spdlog::info("session {}: restored from {} at step {}", (*session)->id(), checkpoint_id, contents.state.step);
  return session;
}

// ---- shutdown and recovery -----------------------------------------------------------------

void SessionManager::shutdown() {
  const auto sessions = list();
  for (const auto& session : sessions) session->pause_and_settle();
  stop_workers();
  for (const auto& session : sessions) {
    const fs::path dir = fs::path(data_dir_) / "sessions" / session->id();
    std::error_code ignored;
    if (is_final(session->state())) {
      fs::remove_all(dir, ignored);  // a failed or cancelled run does not come back
      continue;
    }
    try {
      fs::create_directories(dir);
      storage::write_checkpoint((dir / "session.h5").string(), session->checkpoint_contents(), writer_);
      spdlog::info("session {}: saved for the next start at step {}", session->id(), session->describe().step());
    } catch (const std::exception& e) {
      spdlog::error("session {}: could not be saved: {}", session->id(), e.what());
    }
    session->close();  // its streams end now, so the server's shutdown need not wait for them
  }
}

int SessionManager::recover() {
  int recovered = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(data_dir_) / "sessions")) {
    const fs::path file = entry.path() / "session.h5";
    if (!fs::exists(file)) continue;
    try {
      const auto contents = storage::read_checkpoint(file.string());
      v1::Scenario scenario;
      std::string error;
      if (!parse_scenario_text(contents.scenario_text, &scenario, &error)) throw std::runtime_error(error);
      SessionSetup setup{contents.session_id, contents.request_id, scenario, translate_scenario(scenario),
                         unix_ms_now()};
      auto session = build(std::move(setup));
      if (!session.ok()) throw std::runtime_error(std::string(session.status().message()));
      // A run that had reached its target comes back DONE; every other one PAUSED (Resume goes on).
      (*session)->restore(contents.state, contents.target_step,
                          contents.done ? v1::SESSION_STATE_DONE : v1::SESSION_STATE_PAUSED);
      std::lock_guard lock(mutex_);
      sessions_[contents.session_id] = *session;
      if (!contents.request_id.empty()) by_request_id_[contents.request_id] = contents.session_id;
      next_number_ = std::max(next_number_, session_number(contents.session_id) + 1);
      spdlog::info("session {}: recovered {} at step {}", contents.session_id, contents.done ? "DONE" : "PAUSED",
                   contents.state.step);
      ++recovered;
    } catch (const std::exception& e) {
      spdlog::error("{}: not recovered: {}", file.string(), e.what());
    }
  }
  return recovered;
}

}  // namespace lbsolid::server
