#pragma once
// One session: a scenario, the Simulation built from it, its state (DESIGN.md: CREATED, RUNNING,
// PAUSED, DONE, FAILED, CANCELLED) and the clients watching it. A worker of the SessionManager
// advances it slice by slice; every slice ends between two steps, so Pause, Cancel, field reads and
// checkpoints never see half a step. Divergence (non-finite values, Mach number over the limit)
// ends the session FAILED with "step N: cause"; nothing here can take the daemon down.
//
// Locks: sim_mutex_ is held while the simulation steps or is read; mutex_ guards the state and the
// subscriber lists. Where both are taken, sim_mutex_ comes first.
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "lbsolid/v1/simulation.pb.h"
#include "scene/simulation.h"
#include "server/api/scenario_translation.h"
#include "server/session/event_channel.h"
#include "server/session/frame_channel.h"
#include "server/storage/checkpoint_file.h"

namespace lbsolid::server {

namespace v1 = ::lbsolid::v1;

struct SessionSetup {
  std::string id;
  std::string request_id;
  v1::Scenario scenario;
  TranslatedScenario translated;  // must be ok()
  long long created_unix_ms = 0;
};

struct FieldData {
  long step = 0;
  scene::FluidFields fields;
  std::array<double, 3> spacing{1, 1, 1};
};

struct StepResult {
  long steps_taken = 0;
  bool deadline_reached = false;
};

bool is_final(v1::SessionState state);  // FAILED or CANCELLED

class Session {
 public:
  using Clock = std::chrono::steady_clock;

  // Builds the simulation (throws std::invalid_argument if the scene cannot be built).
  explicit Session(SessionSetup setup);
  ~Session();

  const std::string& id() const { return id_; }
  const std::string& request_id() const { return request_id_; }
  const v1::Scenario& scenario() const { return scenario_; }
  long cells() const;
  v1::Session describe() const;
  v1::SessionState state() const;

  // State changes, each refused with FAILED_PRECONDITION (naming the state) where it does not apply.
  absl::Status run(long steps);
  absl::Status pause();
  absl::Status resume();
  absl::Status cancel();
  // Up to `steps` steps on the calling thread, stopping before `deadline`.
  absl::StatusOr<StepResult> step_now(long steps, std::chrono::system_clock::time_point deadline);

  // Worker pool: claim_schedule() is true when the caller must queue the session (it wants work
  // and is not queued yet); advance() runs one slice; finish_slice() is true when it must be queued
  // again (it still wants work), false when it leaves the queue.
  bool claim_schedule();
  void advance(std::chrono::milliseconds slice);
  bool finish_slice();

  // Streams. Each sends a first frame (or a state event) with the current state at once, so a
  // client can subscribe, wait for that frame, then Run without missing a frame.
  std::shared_ptr<EventChannel> watch_events(std::chrono::milliseconds progress_interval);
  absl::StatusOr<std::shared_ptr<FrameChannel<v1::ProfileFrame>>> watch_profiles(long every, Delivery delivery);
  absl::StatusOr<std::shared_ptr<FrameChannel<v1::ParticleFrame>>> watch_particles(
      long every, Delivery delivery, const std::vector<std::string>& bodies);

  absl::StatusOr<FieldData> fields() const;
  storage::CheckpointContents checkpoint_contents() const;
  // Right after construction: continue from a checkpoint, in `state` with the given target.
  void restore(const scene::SimulationState& state, long target_step, v1::SessionState session_state);
  // Pauses a running session and returns once no worker is stepping it.
  void pause_and_settle();
  // The session is deleted or the daemon stops: every stream ends, the worker leaves it.
  void close();

 private:
  struct ParticleWatch {
    std::shared_ptr<FrameChannel<v1::ParticleFrame>> channel;
    std::vector<int> bodies;
  };

  bool wants_work_locked() const;
  void set_state_locked(v1::SessionState next, const std::string& message = {});
  void emit_locked(v1::SessionEvent event);
  void close_streams_locked();
  // One step with what follows it: frames to due watchers, the stability check. False if the
  // session failed.
  bool step_once();
  void publish_frames(long step);
  // True while a lossless watcher is `capacity` frames behind.
  bool lossless_watcher_behind() const;
  // Waits until every lossless watcher has room, or `timeout`; true if all have room.
  bool wait_for_lossless_clients(std::chrono::milliseconds timeout);
  v1::ProfileFrame profile_frame() const;
  v1::ParticleFrame particle_frame(const std::vector<int>& bodies) const;
  void fail(long step, const std::string& cause);
  void record_rate(long steps, Clock::duration elapsed);
  void emit_progress();

  const std::string id_;
  const std::string request_id_;
  const v1::Scenario scenario_;
  const long long created_unix_ms_;
  const std::vector<std::string> warnings_;

  // Readers (streams subscribing, fields, checkpoints, Step) announce themselves, and the worker
  // ends its slice for them: std::mutex is not fair, and a worker that re-locks at once after each
  // slice would otherwise keep them waiting for many slices.
  std::unique_lock<std::mutex> lock_simulation() const;
  mutable std::atomic<int> readers_waiting_{0};
  mutable std::mutex sim_mutex_;
  std::unique_ptr<scene::Simulation> sim_;

  mutable std::mutex mutex_;
  v1::SessionState state_ = v1::SESSION_STATE_CREATED;
  std::string message_;
  std::atomic<long> step_{0};
  long target_ = 0;
  bool scheduled_ = false;
  bool closed_ = false;
  double steps_per_second_ = 0;
  std::vector<std::shared_ptr<EventChannel>> event_watchers_;
  std::vector<std::shared_ptr<FrameChannel<v1::ProfileFrame>>> profile_watchers_;
  std::vector<ParticleWatch> particle_watchers_;
  std::atomic<bool> has_frame_watchers_{false};
};

}  // namespace lbsolid::server
