#pragma once
// All sessions of the daemon: creation (idempotent on a request id), lookup, deletion, the
// bounded worker pool that advances running sessions slice by slice (round robin, so one long run
// cannot starve the others), checkpoints, and the shutdown that pauses and checkpoints every
// session so the next start brings them back PAUSED under their old ids.
//
// Files under data_dir:
//   checkpoints/<session id>/step-<step>.h5   taken by the Checkpoint call (kept after deletion)
//   sessions/<session id>/session.h5          written at shutdown, read at start
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/statusor.h"
#include "server/session/session.h"

namespace lbsolid::server {

struct ManagerLimits {
  int workers = 1;
  int max_sessions = 64;
  long max_cells = 1L << 26;  // fluid nodes per session
  long max_sync_steps = 10000;
};

struct CheckpointInfo {
  std::string checkpoint_id;  // "<session id>/step-<step>"
  std::string path;
  long step = 0;
  long bytes = 0;
};

class SessionManager {
 public:
  SessionManager(std::string data_dir, ManagerLimits limits, storage::WriterInfo writer);
  ~SessionManager();  // stops the workers (sessions are not checkpointed: see shutdown())

  const ManagerLimits& limits() const { return limits_; }
  const storage::WriterInfo& writer() const { return writer_; }

  absl::StatusOr<std::shared_ptr<Session>> create(const v1::Scenario& scenario, const std::string& request_id);
  absl::StatusOr<std::shared_ptr<Session>> find(const std::string& id) const;
  std::vector<std::shared_ptr<Session>> list() const;
  int count() const;
  absl::Status remove(const std::string& id);

  absl::Status run(const std::string& id, long steps);
  absl::Status resume(const std::string& id);

  absl::StatusOr<CheckpointInfo> checkpoint(const std::string& id);
  absl::StatusOr<std::shared_ptr<Session>> restore(const std::string& checkpoint_id, const std::string& request_id);

  // Brings back the sessions a previous shutdown() saved. Returns how many.
  int recover();
  // Pauses every session, waits for the workers to leave them, checkpoints each, stops the pool.
  void shutdown();

 private:
  absl::StatusOr<std::shared_ptr<Session>> build(SessionSetup setup);
  // Admits (request id, limits), builds, prepares (e.g. restores a state) and registers a session.
  absl::StatusOr<std::shared_ptr<Session>> add_locked(const v1::Scenario& scenario, const std::string& request_id,
                                                      const std::function<absl::Status(Session&)>& prepare);
  absl::Status admit(const std::string& request_id, const v1::Scenario& scenario, std::shared_ptr<Session>* existing);
  std::string next_id();
  void remove_partial_writes();
  void schedule(const std::shared_ptr<Session>& session);
  void work();
  void stop_workers();

  const std::string data_dir_;
  const ManagerLimits limits_;
  const storage::WriterInfo writer_;

  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::map<std::string, std::string> by_request_id_;
  long next_number_ = 1;

  std::mutex queue_mutex_;
  std::condition_variable queue_ready_;
  std::deque<std::shared_ptr<Session>> queue_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace lbsolid::server
