#include "server/session/session_manager.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include <system_error>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "io/api/error_summary.h"
#include "io/api/log_text.h"
#include "server/session/session_id.h"

namespace lbsolid::server {

namespace {

constexpr auto kSlice = std::chrono::milliseconds(50);
// GetSession and Step answer with the scenario: at half the 4 MiB message limit it always fits.
constexpr std::size_t kMaxScenarioBytes = 2 << 20;
constexpr std::size_t kMaxRequestIdBytes = 128;  // a UUID is 36

long long unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// The state a saved session comes back in: the one it was saved in, except that a run in progress
// comes back PAUSED (Resume goes on). FAILED and CANCELLED sessions are never saved.
v1::SessionState recovered_state(const storage::CheckpointContents& contents) {
  if (contents.done) return v1::SESSION_STATE_DONE;
  return contents.started ? v1::SESSION_STATE_PAUSED : v1::SESSION_STATE_CREATED;
}

// A scenario a session cannot hold: too big for GetSession's answer. Empty if it fits.
std::string oversize_problem(const v1::Scenario& scenario) {
  const auto bytes = scenario.ByteSizeLong();
  if (bytes <= kMaxScenarioBytes) return {};
  return absl::StrCat("scenario: ", bytes, " bytes encoded, more than the ", kMaxScenarioBytes, " a session may hold");
}

absl::Status no_session(const std::string& id) {
  return absl::NotFoundError(absl::StrCat("session_id: no session \"", id.substr(0, 100), "\""));
}

absl::Status no_checkpoint(const std::string& id) {
  return absl::NotFoundError(absl::StrCat("checkpoint_id: no checkpoint \"", id, "\""));
}

}  // namespace

SessionManager::SessionManager(std::string data_dir, ManagerLimits limits, storage::WriterInfo writer)
    : limits_(limits),
      store_(std::move(data_dir), std::move(writer)),
      fluid_pool_(std::make_shared<parallel::ThreadPool>(limits_.max_fluid_threads + 1)) {
  try {
    for (int w = 0; w < limits_.workers; ++w) workers_.emplace_back([this] { work(); });
    if (limits_.autosave_interval.count() > 0) autosaver_ = std::thread([this] { autosave_loop(); });
  } catch (...) {  // a thread could not start: the ones that did must not outlive the constructor
    stop_autosave();
    stop_workers();
    throw;
  }
}

SessionManager::~SessionManager() {
  stop_autosave();
  for (const auto& session : all_sessions()) session->close();
  stop_workers();
}

// ---- creation ------------------------------------------------------------------------------

absl::Status SessionManager::admit_footprint_locked(const Footprint& f, const std::string& owner) const {
  if (f.cells > limits_.max_cells)
    return absl::ResourceExhaustedError(absl::StrCat("scenario.domain: ", f.cells, " fluid nodes exceed this daemon's limit of ",
                                                     limits_.max_cells, " per session (--max_cells)"));
  if (committed_.bytes() + f.bytes() > limits_.max_memory_bytes)
    return absl::ResourceExhaustedError(absl::StrCat(
        "scenario: needs about ", f.bytes() >> 20, " MiB (", f.resident_bytes >> 20, " MiB for its life, ",
        f.transient_bytes >> 20, " MiB to save or read it); the daemon has ",
        std::max(0LL, limits_.max_memory_bytes - committed_.bytes()) >> 20, " MiB of its ",
        limits_.max_memory_bytes >> 20, " MiB left (--max_memory)"));
  if (committed_.particles + f.particles > limits_.max_particles)
    return absl::ResourceExhaustedError(absl::StrCat("scenario.bodies: ", f.particles, " particles; the daemon has ",
                                                     std::max(0LL, limits_.max_particles - committed_.particles),
                                                     " of its ", limits_.max_particles, " left (--max_particles)"));
  const auto held = committed_by_owner_.find(owner);
  const long long owner_bytes = held == committed_by_owner_.end() ? 0 : held->second.bytes();
  if (owner_bytes + f.bytes() > limits_.per_owner.memory_bytes)
    return absl::ResourceExhaustedError(absl::StrCat(
        "quota: scenario needs about ", f.bytes() >> 20, " MiB; owner ", owner, " holds ", owner_bytes >> 20,
        " MiB of its quota of ", limits_.per_owner.memory_bytes >> 20, " MiB (--owner_max_memory)"));
  return absl::OkStatus();
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::reserve_locked(std::unique_lock<std::mutex>& lock,
                                                                        const v1::Scenario& scenario,
                                                                        const RequestKey& request,
                                                                        const Footprint& footprint) {
  if (!accepting_) return absl::UnavailableError("the daemon is shutting down; retry on its next start");
  const auto& [owner, request_id] = request;
  if (!request_id.empty()) {
    // A retry of a creation still in progress waits for it, then finds its session.
    creation_done_.wait(lock, [&] { return !requests_in_progress_.contains(request); });
    const auto it = by_request_id_.find(request);
    if (it != by_request_id_.end()) {
      const auto& session = sessions_.at(it->second);
      if (session->scenario().SerializeAsString() != scenario.SerializeAsString())
        return absl::AlreadyExistsError(absl::StrCat("request_id: \"", request_id, "\" already created session ",
                                                     it->second, " from a different scenario"));
      return session;
    }
  }
  if (static_cast<int>(sessions_.size()) + creations_in_progress_ >= limits_.max_sessions)
    return absl::ResourceExhaustedError(absl::StrCat("sessions: the daemon holds its limit of ", limits_.max_sessions,
                                                     " sessions (--max_sessions); delete one or retry later"));
  if (held_by_owner_[owner] >= limits_.per_owner.sessions)
    return absl::ResourceExhaustedError(absl::StrCat("quota: owner ", owner, " holds its quota of ",
                                                     limits_.per_owner.sessions,
                                                     " sessions (--owner_max_sessions); delete one first"));
  if (auto admitted = admit_footprint_locked(footprint, owner); !admitted.ok()) return admitted;
  committed_ += footprint;
  committed_by_owner_[owner] += footprint;
  ++held_by_owner_[owner];
  ++creations_in_progress_;
  if (!request_id.empty()) requests_in_progress_.insert(request);
  return nullptr;
}

void SessionManager::register_locked(const std::shared_ptr<Session>& session, const Footprint& footprint) {
  sessions_[session->id()] = session;
  footprints_[session->id()] = footprint;
  if (!session->request_id().empty()) by_request_id_[{session->owner(), session->request_id()}] = session->id();
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::build(SessionSetup setup) const {
  if (!setup.translated.ok()) return absl::InvalidArgumentError(error_summary(setup.translated.errors));
  try {
    return std::make_shared<Session>(std::move(setup), fluid_pool_);
  } catch (const std::invalid_argument& e) {
    return absl::InvalidArgumentError(e.what());
  } catch (const std::bad_alloc&) {
    return absl::ResourceExhaustedError("scenario.domain: not enough memory on the daemon for this scenario");
  }
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::add(const v1::Scenario& scenario,
                                                             const std::string& request_id, const std::string& owner,
                                                             const Prepare& prepare) {
  if (auto problem = oversize_problem(scenario); !problem.empty()) return absl::InvalidArgumentError(problem);
  if (request_id.size() > kMaxRequestIdBytes)
    return absl::InvalidArgumentError(absl::StrCat("request_id: ", request_id.size(), " bytes, more than ",
                                                   kMaxRequestIdBytes));
  const Footprint footprint = estimate_footprint(scenario);
  const RequestKey request{owner, request_id};
  {
    std::unique_lock lock(mutex_);
    auto reserved = reserve_locked(lock, scenario, request, footprint);
    if (!reserved.ok() || *reserved) return reserved;
  }
  absl::StatusOr<std::shared_ptr<Session>> session = absl::InternalError("not built");
  try {
    // Translated and validated here, at the caller's priority; built (allocated, initialised)
    // on the builder.
    const std::string id = new_session_id();
    SessionSetup setup{id,     request_id, scenario, translate_scenario(scenario), unix_ms_now(), owner,
                       store_.outputs_dir(id), store_.writer().version};
    session = builder_.run([&] { return build(std::move(setup)); });
    if (session.ok())
      if (auto prepared = prepare(**session); !prepared.ok()) session = prepared;
    if (session.ok()) (*session)->open_outputs();
  } catch (const std::bad_alloc&) {
    session = absl::ResourceExhaustedError("scenario: not enough memory on the daemon for this scenario");
  } catch (const std::exception& e) {
    session = absl::InternalError(absl::StrCat("scenario: the session could not be built: ", e.what()));
  }
  {
    std::lock_guard lock(mutex_);
    --creations_in_progress_;
    requests_in_progress_.erase(request);
    if (session.ok()) {
      register_locked(*session, footprint);
    } else {
      committed_ -= footprint;
      committed_by_owner_[owner] -= footprint;
      --held_by_owner_[owner];
    }
  }
  creation_done_.notify_all();
  if (session.ok()) autosave_wake_.notify_one();  // the first save of a new session comes soon
  return session;
}

TranslatedScenario SessionManager::validate(const v1::Scenario& scenario) const {
  if (auto problem = oversize_problem(scenario); !problem.empty()) {
    TranslatedScenario refused;  // not translated: CreateSession refuses it before that too
    refused.errors.push_back(std::move(problem));
    return refused;
  }
  return translate_scenario(scenario);
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::create(const v1::Scenario& scenario,
                                                                const std::string& request_id,
                                                                const auth::Identity& caller) {
  auto session = add(scenario, request_id, caller.owner, [](Session&) { return absl::OkStatus(); });
  if (!session.ok()) return session;
  const auto described = (*session)->describe();
  spdlog::info("session {}: created {} for {} ({} fluid nodes, {} particles, stages {})", (*session)->id(),
               log_text(scenario.name()), caller.owner, (*session)->cells(), described.particles(), absl::StrJoin(described.stages(), ","));
  for (const auto& warning : described.warnings()) spdlog::warn("session {}: {}", (*session)->id(), log_text(warning, 500));
  return session;
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::find(const std::string& id,
                                                              const auth::Identity& caller) const {
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(id);
  if (it == sessions_.end() || !caller.may_act_on(it->second->owner())) return no_session(id);
  return it->second;
}

std::vector<std::shared_ptr<Session>> SessionManager::list(const auth::Identity& caller) const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<Session>> out;
  for (const auto& [id, session] : sessions_)
    if (caller.may_act_on(session->owner())) out.push_back(session);
  return out;
}

std::vector<std::shared_ptr<Session>> SessionManager::all_sessions() const { return list(auth::local_admin()); }

int SessionManager::count() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(sessions_.size());
}

int SessionManager::running_count() const {
  int running = 0;
  for (const auto& session : all_sessions()) running += session->state() == v1::SESSION_STATE_RUNNING;
  return running;
}

absl::Status SessionManager::remove(const std::string& id, const auth::Identity& caller) {
  std::shared_ptr<Session> session;
  {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(id);
    if (it == sessions_.end() || !caller.may_act_on(it->second->owner())) return no_session(id);
    session = it->second;
    sessions_.erase(it);
    if (!session->request_id().empty()) by_request_id_.erase({session->owner(), session->request_id()});
  }
  session->close();
  {
    // Its memory is free once the last call holding it lets go; close() ended the streams.
    std::lock_guard lock(mutex_);
    committed_ -= footprints_.at(id);
    committed_by_owner_[session->owner()] -= footprints_.at(id);
    --held_by_owner_[session->owner()];
    footprints_.erase(id);
  }
  store_.forget(*session);
  store_.forget_outputs(*session);
  spdlog::info("session {}: deleted", id);
  return absl::OkStatus();
}

// ---- running -------------------------------------------------------------------------------

absl::Status SessionManager::start_within_quota(Session& session, const std::function<absl::Status()>& start) {
  std::lock_guard lock(start_mutex_);
  int running = 0;
  for (const auto& other : list({session.owner(), auth::Role::kUser}))
    if (other.get() != &session && other->state() == v1::SESSION_STATE_RUNNING) ++running;
  if (running >= limits_.per_owner.running)
    return absl::ResourceExhaustedError(absl::StrCat("quota: owner ", session.owner(), " runs its quota of ",
                                                     limits_.per_owner.running,
                                                     " sessions at once (--owner_max_running); pause one or wait"));
  return start();
}

absl::Status SessionManager::run(const std::string& id, long steps, const auth::Identity& caller) {
  auto session = find(id, caller);
  if (!session.ok()) return session.status();
  if (auto status = start_within_quota(**session, [&] { return (*session)->run(steps); }); !status.ok()) return status;
  schedule(*session);
  return absl::OkStatus();
}

absl::Status SessionManager::resume(const std::string& id, const auth::Identity& caller) {
  auto session = find(id, caller);
  if (!session.ok()) return session.status();
  if (auto status = start_within_quota(**session, [&] { return (*session)->resume(); }); !status.ok()) return status;
  schedule(*session);
  return absl::OkStatus();
}

absl::Status SessionManager::cancel(const std::string& id, const auth::Identity& caller) {
  auto session = find(id, caller);
  if (!session.ok()) return session.status();
  if (auto status = (*session)->cancel(); !status.ok()) return status;
  settle(**session);
  return absl::OkStatus();
}

void SessionManager::settle(const Session& session) {
  if (is_final(session.state())) store_.forget(session);
}

void SessionManager::schedule(const std::shared_ptr<Session>& session) {
  if (!session->claim_schedule()) return;
  std::lock_guard lock(queue_mutex_);
  enqueue_locked(session);
  queue_ready_.notify_one();
}

void SessionManager::enqueue_locked(const std::shared_ptr<Session>& session) {
  auto& queue = queues_[session->owner()];
  if (queue.empty()) owner_turns_.push_back(session->owner());
  queue.push_back(session);
}

std::shared_ptr<Session> SessionManager::dequeue_locked() {
  const std::string owner = owner_turns_.front();
  owner_turns_.pop_front();
  auto& queue = queues_.at(owner);
  auto session = queue.front();
  queue.pop_front();
  if (queue.empty()) queues_.erase(owner);
  else owner_turns_.push_back(owner);  // its next session waits for the other owners' turns
  return session;
}

void SessionManager::work() {
  while (true) {
    std::shared_ptr<Session> session;
    {
      std::unique_lock lock(queue_mutex_);
      queue_ready_.wait(lock, [&] { return stopping_ || !owner_turns_.empty(); });
      if (stopping_) return;
      session = dequeue_locked();
    }
    session->advance(kSlice);
    if (session->auto_checkpoint_due()) {  // the slice ended at a multiple of outputs.checkpoint_every
      if (const auto taken = store_.checkpoint(*session); taken.ok()) session->auto_checkpoint_taken(taken->step);
    }
    const bool more = session->finish_slice();
    settle(*session);
    if (session->progress_note_due()) store_.note_progress(*session, session->describe().step());
    if (more) {
      std::lock_guard lock(queue_mutex_);
      enqueue_locked(session);  // to the back: round robin between owners, then their sessions
      queue_ready_.notify_one();
    }
  }
}

void SessionManager::stop_workers() {
  {
    std::lock_guard lock(queue_mutex_);
    stopping_ = true;
    queues_.clear();
    owner_turns_.clear();
    queue_ready_.notify_all();
  }
  for (auto& worker : workers_)
    if (worker.joinable()) worker.join();
  workers_.clear();
}

// ---- checkpoints and outputs ---------------------------------------------------------------

absl::StatusOr<std::vector<OutputFile>> SessionManager::outputs(const std::string& id, const auth::Identity& caller) {
  auto session = find(id, caller);
  if (!session.ok()) return session.status();
  return (*session)->outputs(store_.checkpoint_dir(id));
}

absl::StatusOr<CheckpointInfo> SessionManager::checkpoint(const std::string& id, const auth::Identity& caller) {
  auto session = find(id, caller);
  if (!session.ok()) return session.status();
  return store_.checkpoint(**session);
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::restore(const std::string& checkpoint_id,
                                                                 const std::string& request_id,
                                                                 const auth::Identity& caller) {
  auto contents = store_.read_checkpoint(checkpoint_id);
  if (!contents.ok()) return contents.status();
  if (const auto problem = auth::owner_name_problem(contents->owner); !problem.empty())
    return absl::DataLossError(absl::StrCat("checkpoint_id: its owner ", problem));
  if (!caller.may_act_on(contents->owner)) return no_checkpoint(checkpoint_id);
  return restore_contents(*contents, "checkpoint_id", checkpoint_id, request_id, contents->owner);
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::restore_upload(const std::string& path,
                                                                        const std::string& request_id,
                                                                        const auth::Identity& caller) {
  auto contents = store_.read_checkpoint_file(path);
  if (!contents.ok()) return contents.status();
  return restore_contents(*contents, "data", "an uploaded checkpoint", request_id, caller.owner);
}

absl::StatusOr<std::shared_ptr<Session>> SessionManager::restore_contents(const storage::CheckpointContents& contents,
                                                                          const std::string& field,
                                                                          const std::string& source,
                                                                          const std::string& request_id,
                                                                          const std::string& owner) {
  v1::Scenario scenario;
  std::string error;
  if (!parse_scenario_text(contents.scenario_text, &scenario, &error))
    return absl::DataLossError(absl::StrCat(field, ": its scenario does not parse: ", error));
  auto session = add(scenario, request_id, owner, [&](Session& fresh) {
    try {
      fresh.restore(contents.state, contents.target_step, v1::SESSION_STATE_PAUSED);
      return absl::OkStatus();
    } catch (const std::invalid_argument& e) {
      return absl::DataLossError(absl::StrCat(field, ": ", e.what()));
    }
  });
  if (!session.ok()) return session;
  spdlog::info("session {}: restored from {} at step {} for {}", (*session)->id(), log_text(source),
               contents.state.step, owner);
  return session;
}

// ---- saves, shutdown and recovery ----------------------------------------------------------

void SessionManager::autosave(const std::shared_ptr<Session>& session) {
  const auto d = session->describe();
  const auto version = std::make_tuple(static_cast<long>(d.step()), static_cast<long>(d.target_step()),
                                       static_cast<int>(d.state()));
  const auto known = saved_.find(session->id());
  if (known != saved_.end() && known->second == version) return;  // nothing changed since
  if (is_final(d.state())) return;  // settle() removed its save
  const auto saved = store_.save(*session);
  if (!saved.ok()) {
    spdlog::error("session {}: autosave failed: {}", session->id(), log_text(std::string(saved.status().message()), 1000));
    return;
  }
  saved_[session->id()] = version;
  spdlog::debug("session {}: autosaved at step {}", session->id(), *saved);
}

void SessionManager::autosave_loop() {
  std::unique_lock lock(autosave_mutex_);
  auto next_pass = std::chrono::steady_clock::now() + limits_.autosave_interval;
  while (!autosave_stopping_) {
    // A new session wakes it early for its first save; the others wait for the interval.
    autosave_wake_.wait_until(lock, next_pass);
    if (autosave_stopping_) break;
    const bool full_pass = std::chrono::steady_clock::now() >= next_pass;
    if (full_pass) next_pass = std::chrono::steady_clock::now() + limits_.autosave_interval;
    lock.unlock();
    const auto sessions = all_sessions();
    std::erase_if(saved_, [&](const auto& entry) {
      return std::none_of(sessions.begin(), sessions.end(), [&](const auto& s) { return s->id() == entry.first; });
    });
    for (const auto& session : sessions)
      if (full_pass || !saved_.contains(session->id())) autosave(session);
    lock.lock();
  }
}

void SessionManager::stop_autosave() {
  {
    std::lock_guard lock(autosave_mutex_);
    autosave_stopping_ = true;
  }
  autosave_wake_.notify_all();
  if (autosaver_.joinable()) autosaver_.join();
}

void SessionManager::pause_all() {
  for (const auto& session : all_sessions())
    if (session->state() == v1::SESSION_STATE_RUNNING) (void)session->pause();  // it may have just ended
}

std::vector<std::string> SessionManager::shutdown() {
  {
    std::lock_guard lock(mutex_);
    accepting_ = false;
  }
  stop_autosave();
  pause_all();  // again: calls in flight at SIGTERM may have resumed some
  stop_workers();
  const auto sessions = all_sessions();
  std::vector<std::string> unsaved;
  for (const auto& session : sessions) {
    if (is_final(session->state())) {
      store_.forget(*session);  // a failed or cancelled run does not come back
    } else if (const auto saved = store_.save(*session); saved.ok()) {
      spdlog::info("session {}: saved for the next start at step {}", session->id(), *saved);
    } else {
      spdlog::error("session {}: NOT SAVED, its work since the last save is lost: {}", session->id(),
                    log_text(std::string(saved.status().message()), 1000));
      unsaved.push_back(session->id());
    }
    session->close();  // its streams end now
  }
  return unsaved;
}

int SessionManager::recover() {
  int recovered = 0;
  for (auto& saved : store_.saved_sessions()) {
    const auto& contents = saved.contents;
    v1::Scenario scenario;
    std::string error;
    if (!parse_scenario_text(contents.scenario_text, &scenario, &error)) {
      spdlog::error("session {}: not recovered: its scenario does not parse: {}", contents.session_id,
                    log_text(error, 500));
      continue;
    }
    if (const auto problem = auth::owner_name_problem(contents.owner); !problem.empty()) {
      spdlog::error("session {}: not recovered: its owner {}", contents.session_id, problem);
      continue;
    }
    auto session = build({contents.session_id, contents.request_id, scenario, translate_scenario(scenario),
                          unix_ms_now(), contents.owner, store_.outputs_dir(contents.session_id),
                          store_.writer().version});
    if (!session.ok()) {
      spdlog::error("session {}: not recovered: {}", contents.session_id, log_text(std::string(session.status().message()), 1000));
      continue;
    }
    try {
      (*session)->restore(contents.state, contents.target_step, recovered_state(contents));
    } catch (const std::invalid_argument& e) {
      spdlog::error("session {}: not recovered: {}", contents.session_id, log_text(e.what(), 1000));
      continue;
    }
    (*session)->set_steps_lost(saved.steps_lost);
    try {
      (*session)->open_outputs();  // the frames past the save are dropped: they are recorded again
    } catch (const std::exception& e) {
      spdlog::error("session {}: recovered, but its outputs are not recorded: {}", contents.session_id,
                    log_text(e.what(), 1000));
    }
    {
      std::lock_guard lock(mutex_);
      const Footprint footprint = estimate_footprint(scenario);  // counted even past the limits
      committed_ += footprint;
      committed_by_owner_[contents.owner] += footprint;
      ++held_by_owner_[contents.owner];
      register_locked(*session, footprint);
    }
    if (saved.steps_lost > 0)
      spdlog::warn("session {}: recovered at step {}; {} steps run after its last save were lost", contents.session_id,
                   contents.state.step, saved.steps_lost);
    else
      spdlog::info("session {}: recovered {} at step {}", contents.session_id,
                   v1::SessionState_Name(recovered_state(contents)), contents.state.step);
    ++recovered;
  }
  std::vector<std::string> kept;
  for (const auto& session : all_sessions()) kept.push_back(session->id());
  store_.remove_orphan_outputs(kept);
  return recovered;
}

}  // namespace lbsolid::server
