#pragma once
// All sessions of the daemon: creation (idempotent on a request id), lookup, deletion, the
// bounded worker pool that advances running sessions slice by slice (round robin between owners,
// then between each owner's sessions, so neither one long run nor one owner's many runs can starve
// the others), checkpoints, periodic saves, and the shutdown that saves every session so the next
// start brings them back under their old ids (session_store.h: the files).
//
// Every session belongs to the identity that created it (auth/identity.h). Each call names its
// caller: a user reaches only its own sessions and checkpoints (another's answer NOT_FOUND, exactly
// as if they did not exist), an admin reaches all. Request ids are per owner. Per-owner quotas
// (OwnerLimits) bound what one owner may hold and run.
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
#include "server/auth/identity.h"
#include "server/session/footprint.h"
#include "server/session/serial_executor.h"
#include "server/session/session.h"
#include "server/session/session_store.h"

namespace lbsolid::server {

// What one owner may hold at once; each defaults to the daemon's own limit (no quota).
struct OwnerLimits {
  int sessions = 64;
  long long memory_bytes = 8LL << 30;  // by the footprint estimate, as --max_memory
  int running = 64;                    // sessions RUNNING at once (Run and Resume are refused past it)
};

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
  OwnerLimits per_owner;
};

class SessionManager {
 public:
  // Throws std::filesystem::filesystem_error if data_dir cannot be used, std::system_error if a
  // thread (worker, autosave, builder, fluid pool) cannot start.
  SessionManager(std::string data_dir, ManagerLimits limits, storage::WriterInfo writer);
  ~SessionManager();  // stops the workers and the autosave (sessions are not saved: see shutdown())

  const ManagerLimits& limits() const { return limits_; }
  const storage::WriterInfo& writer() const { return store_.writer(); }

  // The new session belongs to `caller`; a request id already used by the same owner answers
  // with that owner's earlier session.
  absl::StatusOr<std::shared_ptr<Session>> create(const v1::Scenario& scenario, const std::string& request_id,
                                                  const auth::Identity& caller);
  // Every problem create() would find in the scenario itself (its size, its translation and
  // validation; not the daemon's limits), and its warnings. Builds nothing.
  TranslatedScenario validate(const v1::Scenario& scenario) const;
  // NOT_FOUND unless the session exists and the caller may act on it.
  absl::StatusOr<std::shared_ptr<Session>> find(const std::string& id, const auth::Identity& caller) const;
  // The caller's sessions; an admin's: every owner's.
  std::vector<std::shared_ptr<Session>> list(const auth::Identity& caller) const;
  int count() const;
  int running_count() const;  // sessions RUNNING now, every owner's
  absl::Status remove(const std::string& id, const auth::Identity& caller);

  // Run and Resume are refused (RESOURCE_EXHAUSTED) past the owner's quota of running sessions.
  absl::Status run(const std::string& id, long steps, const auth::Identity& caller);
  absl::Status resume(const std::string& id, const auth::Identity& caller);
  absl::Status cancel(const std::string& id, const auth::Identity& caller);
  // After a state change made outside the manager (a Step call): a session that ended FAILED or
  // CANCELLED loses its saved state at once, so that a crash cannot bring it back runnable.
  void settle(const Session& session);

  absl::StatusOr<CheckpointInfo> checkpoint(const std::string& id, const auth::Identity& caller);
  // What the session recorded (scenario.outputs) and its checkpoints, made as of now.
  absl::StatusOr<std::vector<OutputFile>> outputs(const std::string& id, const auth::Identity& caller);
  // A checkpoint of a session the caller may act on; the new session belongs to the checkpoint's owner.
  absl::StatusOr<std::shared_ptr<Session>> restore(const std::string& checkpoint_id, const std::string& request_id,
                                                   const auth::Identity& caller);
  // A checkpoint file from elsewhere (UploadCheckpoint), already on this disk: read, verified and
  // restored as Restore does, into a session of the caller's.
  absl::StatusOr<std::shared_ptr<Session>> restore_upload(const std::string& path, const std::string& request_id,
                                                          const auth::Identity& caller);
  // Where uploads are written before they are read (removed at start).
  std::string upload_dir() const { return store_.upload_dir(); }

  // Brings back the sessions an earlier daemon saved. Returns how many.
  int recover();
  // Pauses every running session; each has ended its step in flight when this returns.
  void pause_all();
  // Refuses new sessions, pauses every session, waits for the workers to leave them, saves each,
  // stops the pool. Returns the ids of the sessions that could not be saved (each logged, why).
  std::vector<std::string> shutdown();

 private:
  using Prepare = std::function<absl::Status(Session&)>;
  using RequestKey = std::pair<std::string, std::string>;  // owner, request id
  // Admits (request id, limits, the owner's quotas), builds and prepares (e.g. restores a state) a
  // session of `owner` outside the lock, then registers it.
  absl::StatusOr<std::shared_ptr<Session>> add(const v1::Scenario& scenario, const std::string& request_id,
                                               const std::string& owner, const Prepare& prepare);
  // Under mutex_: an earlier session of this request id (returned), or a reservation of a place
  // and of the footprint's memory, particles and threads.
  absl::StatusOr<std::shared_ptr<Session>> reserve_locked(std::unique_lock<std::mutex>& lock,
                                                          const v1::Scenario& scenario, const RequestKey& request,
                                                          const Footprint& footprint);
  absl::Status admit_footprint_locked(const Footprint& footprint, const std::string& owner) const;
  // A new session of `owner` continuing `contents`; errors name `field`, the log `source`.
  absl::StatusOr<std::shared_ptr<Session>> restore_contents(const storage::CheckpointContents& contents,
                                                            const std::string& field, const std::string& source,
                                                            const std::string& request_id, const std::string& owner);
  // Registers a built session with its footprint (under mutex_).
  void register_locked(const std::shared_ptr<Session>& session, const Footprint& footprint);
  // Every session, whoever owns it: for the autosave, the shutdown and the destructor.
  std::vector<std::shared_ptr<Session>> all_sessions() const;
  // Starts a session's run (Run or Resume) within its owner's quota of running sessions.
  absl::Status start_within_quota(Session& session, const std::function<absl::Status()>& start);
  absl::StatusOr<std::shared_ptr<Session>> build(SessionSetup setup) const;
  void schedule(const std::shared_ptr<Session>& session);
  // Under queue_mutex_: to the back of its owner's queue; the next session of the owner whose turn it is.
  void enqueue_locked(const std::shared_ptr<Session>& session);
  std::shared_ptr<Session> dequeue_locked();
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
  std::map<RequestKey, std::string> by_request_id_;
  std::set<RequestKey> requests_in_progress_;
  int creations_in_progress_ = 0;
  std::map<std::string, Footprint> footprints_;  // of registered sessions
  Footprint committed_;  // of registered sessions and creations in progress
  // By owner: sessions registered or being created, and their footprints.
  std::map<std::string, int> held_by_owner_;
  std::map<std::string, Footprint> committed_by_owner_;
  bool accepting_ = true;
  // Held while a Run or Resume counts its owner's running sessions and starts: two cannot both
  // take the last place.
  std::mutex start_mutex_;

  // Sessions waiting for a worker, by owner; owners take turns (owner_turns_ holds each owner with
  // a waiting session once).
  std::mutex queue_mutex_;
  std::condition_variable queue_ready_;
  std::map<std::string, std::deque<std::shared_ptr<Session>>> queues_;
  std::deque<std::string> owner_turns_;
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
