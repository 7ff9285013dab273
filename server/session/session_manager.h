#pragma once
// All sessions of the daemon: creation (idempotent on a request id), lookup, deletion, the
// bounded worker pool that advances running sessions slice by slice (round robin, so one long run
// cannot starve the others), checkpoints, periodic saves, and the shutdown that saves every
// session so the next start brings them back under their old ids (session_store.h: the files).
//
// No request holds the manager-wide lock while it does real work: scenarios are translated,
// validated and built outside it (a request id being created is reserved meanwhile).
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "absl/status/statusor.h"
#include "server/session/footprint.h"
#include "server/session/serial_executor.h"
#include "server/session/session.h"
#include "server/session/session_store.h"

namespace lbsolid::server {

struct ManagerLimits {
  int workers = 1;
  int max_sessions = 64;
  long max_cells = 1L << 26;  // fluid nodes per session
  long max_sync_steps = 10000;
  // Admission over all sessions together (footprint.h estimates each before it is built).
  long long max_memory_bytes = 8LL << 30;
  long long max_particles = 1LL << 24;
  // Threads of the one pool every session's fluid steps share, beyond the thread stepping each
  // session (a session of scenario.fluid.threads N cuts each step into N parts for it).
  int max_fluid_threads = 2;
  // Wall time between automatic saves of every session that changed; zero turns them off.
  std::chrono::milliseconds autosave_interval = std::chrono::minutes(2);
};

class SessionManager {
 public:
  // Throws std::filesystem::filesystem_error if data_dir cannot be used, std::system_error if a
  // thread (worker, autosave, builder, fluid pool) cannot start.
  SessionManager(std::string data_dir, ManagerLimits limits, storage::WriterInfo writer);
  ~SessionManager();  // stops the workers and the autosave (sessions are not saved: see shutdown())

  const ManagerLimits& limits() const { return limits_; }
  const storage::WriterInfo& writer() const { return store_.writer(); }

  absl::StatusOr<std::shared_ptr<Session>> create(const v1::Scenario& scenario, const std::string& request_id);
  // Every problem create() would find in the scenario itself (its size, its translation and
  // validation; not the daemon's limits), and its warnings. Builds nothing.
  TranslatedScenario validate(const v1::Scenario& scenario) const;
  absl::StatusOr<std::shared_ptr<Session>> find(const std::string& id) const;
  std::vector<std::shared_ptr<Session>> list() const;
  int count() const;
  absl::Status remove(const std::string& id);

  absl::Status run(const std::string& id, long steps);
  absl::Status resume(const std::string& id);
  absl::Status cancel(const std::string& id);
  // After a state change made outside the manager (a Step call): a session that ended FAILED or
  // CANCELLED loses its saved state at once, so that a crash cannot bring it back runnable.
  void settle(const Session& session);

  absl::StatusOr<CheckpointInfo> checkpoint(const std::string& id);
  absl::StatusOr<std::shared_ptr<Session>> restore(const std::string& checkpoint_id, const std::string& request_id);

  // Brings back the sessions an earlier daemon saved. Returns how many.
  int recover();
  // Pauses every running session; each has ended its step in flight when this returns.
  void pause_all();
  // Refuses new sessions, pauses every session, waits for the workers to leave them, saves each,
  // stops the pool. Returns the ids of the sessions that could not be saved (each logged, why).
  std::vector<std::string> shutdown();

 private:
  using Prepare = std::function<absl::Status(Session&)>;
  // Admits (request id, limits), builds and prepares (e.g. restores a state) a session outside
  // the lock, then registers it.
  absl::StatusOr<std::shared_ptr<Session>> add(const v1::Scenario& scenario, const std::string& request_id,
                                               const Prepare& prepare);
  // Under mutex_: an earlier session of this request id (returned), or a reservation of a place
  // and of the footprint's memory, particles and threads.
  absl::StatusOr<std::shared_ptr<Session>> reserve_locked(std::unique_lock<std::mutex>& lock,
                                                          const v1::Scenario& scenario, const std::string& request_id,
                                                          const Footprint& footprint);
  absl::Status admit_footprint_locked(const Footprint& footprint) const;
  absl::StatusOr<std::shared_ptr<Session>> build(SessionSetup setup) const;
  void schedule(const std::shared_ptr<Session>& session);
  void work();
  void stop_workers();
  void autosave_loop();
  void autosave(const std::shared_ptr<Session>& session);
  void stop_autosave();

  const ManagerLimits limits_;
  const SessionStore store_;
  // Started before the workers, at the daemon's base priority; sessions keep it alive.
  const std::shared_ptr<parallel::ThreadPool> fluid_pool_;

  mutable std::mutex mutex_;
  std::condition_variable creation_done_;
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::map<std::string, std::string> by_request_id_;
  std::set<std::string> requests_in_progress_;
  int creations_in_progress_ = 0;
  std::map<std::string, Footprint> footprints_;  // of registered sessions
  Footprint committed_;  // of registered sessions and creations in progress
  bool accepting_ = true;

  std::mutex queue_mutex_;
  std::condition_variable queue_ready_;
  std::deque<std::shared_ptr<Session>> queue_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;

  std::mutex autosave_mutex_;
  std::condition_variable autosave_wake_;
  bool autosave_stopping_ = false;
  // What each session's last save held (step, target, state): unchanged sessions are not saved again.
  std::map<std::string, std::tuple<long, long, int>> saved_;
  std::thread autosaver_;

  // Started with the manager, so at the daemon's base priority: see SerialExecutor.
  SerialExecutor builder_;
};

}  // namespace lbsolid::server
