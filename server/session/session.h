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
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "lbsolid/v1/simulation.pb.h"
#include "scene/simulation.h"
#include "io/api/scenario_translation.h"
#include "server/session/event_channel.h"
#include "server/session/frame_channel.h"
#include "server/session/output_recorder.h"
#include "io/storage/checkpoint_file.h"

namespace lbsolid::server {

namespace v1 = ::lbsolid::v1;

struct SessionSetup {
  std::string id;
  std::string request_id;
  v1::Scenario scenario;
  TranslatedScenario translated;  // must be ok()
  long long created_unix_ms = 0;
  std::string owner;  // the identity it belongs to (server/auth/identity.h)
  // Where scenario.outputs are recorded (output_recorder.h), and the writer named in them.
  std::string outputs_dir;
  std::string writer_version;
};

struct FieldData {
  long step = 0;
  long generation = -1;  // the Session::fields_generation_ the values were computed at
  scene::FluidFields fields;
  std::array<double, 3> spacing{1, 1, 1};
};

struct StepResult {
  long steps_taken = 0;
  bool deadline_reached = false;
  bool interrupted = false;  // the call was abandoned, or the session paused, cancelled or deleted
};

bool is_final(v1::SessionState state);  // FAILED or CANCELLED

class Session {
 public:
  using Clock = std::chrono::steady_clock;

  // Builds the simulation (throws std::invalid_argument if the scene cannot be built). Its fluid
  // steps run on `fluid_pool`, shared with the daemon's other sessions; without one, on threads
  // of its own.
  explicit Session(SessionSetup setup, std::shared_ptr<parallel::ThreadPool> fluid_pool = nullptr);
  ~Session();

  const std::string& id() const { return id_; }
  const std::string& request_id() const { return request_id_; }
  const std::string& owner() const { return owner_; }
  const v1::Scenario& scenario() const { return scenario_; }
  long cells() const;
  // What GetSession answers; without the scenario (ListSessions) when with_scenario is false.
  v1::Session describe(bool with_scenario = true) const;
  v1::SessionState state() const;

  // State changes, each refused with FAILED_PRECONDITION (naming the state) where it does not apply.
  // Run and Resume are also refused while a synchronous Step holds the session. Pause and Cancel
  // return once the step in flight has ended: nothing moves after they answer.
  absl::Status run(long steps);
  absl::Status pause();
  absl::Status resume();
  absl::Status cancel();
  // Up to `steps` steps on the calling thread, stopping before `deadline`, or at the next step
  // boundary once `abandoned()` is true or the session is paused, cancelled or deleted.
  absl::StatusOr<StepResult> step_now(long steps, std::chrono::system_clock::time_point deadline,
                                      const std::function<bool()>& abandoned);

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

  // The fluid's fields at the current step, shared by every reader of that step: at most
  // kFieldSnapshots copies per session are alive at once (slow readers hold theirs), so readers
  // cannot multiply the session's memory; past that, RESOURCE_EXHAUSTED.
  static constexpr int kFieldSnapshots = 2;
  absl::StatusOr<std::shared_ptr<const FieldData>> fields() const;
  storage::CheckpointContents checkpoint_contents() const;
  // Right after construction: continue from a checkpoint, in `state` with the given target.
  void restore(const scene::SimulationState& state, long target_step, v1::SessionState session_state);
  // The session is deleted or the daemon stops: every stream ends, the worker leaves it.
  void close();

  // Recording (scenario.outputs): opens the session's frame log, keeping what it holds through the
  // current step (call once, after restore() for a session that continues). Throws
  // std::runtime_error naming the path. Without outputs in the scenario it does nothing.
  void open_outputs();
  // Every frame recorded so far is durable (a save is about to claim the step it copied).
  void sync_outputs() const;
  // What ListOutputs shows: the recorded files, made as of now, then the checkpoints in checkpoint_dir.
  absl::StatusOr<std::vector<OutputFile>> outputs(const std::string& checkpoint_dir);
  // scenario.outputs.checkpoint_every: a worker's slice ends at each multiple, and the worker then
  // takes the checkpoint and says so.
  bool auto_checkpoint_due() const;
  void auto_checkpoint_taken(long step) { last_auto_checkpoint_ = step; }

  // Writes of this session's files (checkpoints, saves) happen one at a time under this lock.
  std::unique_lock<std::mutex> lock_saves() const { return std::unique_lock(saves_mutex_); }
  std::mutex& saves_mutex() const { return saves_mutex_; }
  // After recovery from a save: steps its worker had reached past the save (lost in a crash).
  void set_steps_lost(long steps) { steps_lost_ = steps; }
  // For the workers: true every kProgressNoteInterval while it runs (then its step is worth
  // recording, SessionStore::note_progress), to one caller only.
  static constexpr auto kProgressNoteInterval = std::chrono::milliseconds(250);
  bool progress_note_due();

 private:
  struct ParticleWatch {
    std::shared_ptr<FrameChannel<v1::ParticleFrame>> channel;
    std::vector<int> bodies;
  };

  bool wants_work_locked() const;
  // Pause and Cancel: refused unless allowed(state); otherwise waits for the step in flight (on a
  // worker or in a Step call) to end, then moves to `next` at that step.
  absl::Status stop_at_step_boundary(const char* what, v1::SessionState next,
                                     bool (*allowed)(v1::SessionState));
  // A Step call must stop: its client gave up, or a state change or deletion waits for it.
  bool step_call_must_stop(const std::function<bool()>& abandoned) const;
  // Sizes shown by describe(), read here under the simulation lock (a restore resizes the solid).
  void refresh_sizes();
  void set_state_locked(v1::SessionState next, const std::string& message = {});
  void emit_locked(v1::SessionEvent event);
  void emit_error_locked(long step, const std::string& message);
  void close_streams_locked();
  void refresh_watch_flags_locked();
  // One step with what follows it: frames to due watchers, the stability check. False if the
  // session failed.
  bool step_once();
  void publish_frames(long step);  // to the watchers due at `step`; under the simulation lock
  void publish_first_frames();     // to the watchers still waiting for their first frame; idem
  template <class Wanted>
  void publish_frames_if(const Wanted& wanted);
  // Registers a watcher of a running session, whose first frame the worker will publish; false
  // (nothing done) if the session is not running.
  template <class Frame, class Register>
  bool join_running(const std::shared_ptr<FrameChannel<Frame>>& channel, const Register& register_watcher);
  // True while a lossless watcher is `capacity` frames behind.
  bool lossless_watcher_behind() const;
  // Waits until every lossless watcher has room, or `timeout`; true if all have room.
  bool wait_for_lossless_clients(std::chrono::milliseconds timeout);
  v1::ProfileFrame profile_frame() const;
  // The bodies' frame; each body's broken links listed are those that broke after step `since`.
  v1::ParticleFrame particle_frame(const std::vector<int>& bodies, long since) const;
  void fail(long step, const std::string& cause);
  // Under the simulation lock: records what scenario.outputs wants at the current step. False if a
  // write failed: the session is then PAUSED with the cause (Resume records it again).
  bool record_outputs();
  void stop_for_outputs(long step, const std::string& cause);
  void record_rate(long steps, Clock::duration elapsed);
  void emit_progress();

  const std::string id_;
  const std::string request_id_;
  const std::string owner_;
  const v1::Scenario scenario_;
  const OutputPlan output_plan_;
  const std::string outputs_dir_;
  const std::string writer_version_;
  const long long created_unix_ms_;
  const std::vector<std::string> warnings_;

  // Readers (streams subscribing, fields, checkpoints, Step) announce themselves, and the worker
  // ends its slice for them: std::mutex is not fair, and a worker that re-locks at once after each
  // slice would otherwise keep them waiting for many slices.
  std::unique_lock<std::mutex> lock_simulation() const;
  mutable std::atomic<int> readers_waiting_{0};
  // A worker that gave way to readers sleeps here until they have the lock, instead of spinning
  // through the queue (which took a third of the workers' time under 64 clients).
  mutable std::mutex handoff_mutex_;
  mutable std::condition_variable reader_entered_;
  mutable std::mutex sim_mutex_;
  std::unique_ptr<scene::Simulation> sim_;
  std::unique_ptr<OutputRecorder> recorder_;  // used under sim_mutex_, set once by open_outputs()
  std::vector<int> recorded_bodies_;
  std::atomic<long> last_auto_checkpoint_{0};
  std::mutex checkpoint_files_mutex_;
  std::map<std::string, OutputFile> checkpoint_files_;  // their SHA-256, computed once

  mutable std::mutex saves_mutex_;
  mutable std::mutex snapshots_mutex_;  // taken before sim_mutex_, never inside it
  mutable std::vector<std::weak_ptr<const FieldData>> snapshots_;
  struct SpareSnapshot {
    std::mutex mutex;
    std::unique_ptr<FieldData> data;
  };
  const std::shared_ptr<SpareSnapshot> spare_snapshot_ = std::make_shared<SpareSnapshot>();
  // Counts the changes of the simulation's state (a step begun, a state loaded), under sim_mutex_:
  // a spare snapshot of the current generation is still the fields, and is sent again as it is.
  long fields_generation_ = 0;
  std::atomic<Clock::rep> progress_noted_{0};  // Clock ticks of the last note
  std::atomic<long> steps_lost_{0};

  // Pause, Cancel and close() waiting for a Step call to let go of the simulation.
  std::atomic<int> stop_requests_{0};
  std::atomic<long> particles_{0};
  std::atomic<long long> fluid_bytes_{0};
  std::atomic<long long> solid_bytes_{0};

  mutable std::mutex mutex_;
  v1::SessionState state_ = v1::SESSION_STATE_CREATED;
  bool stepping_ = false;  // a Step call holds the simulation
  std::string message_;
  std::atomic<long> step_{0};
  std::atomic<long> target_{0};  // written under mutex_ while the session does not run
  bool scheduled_ = false;
  bool closed_ = false;
  double steps_per_second_ = 0;
  std::vector<std::shared_ptr<EventChannel>> event_watchers_;
  std::vector<std::shared_ptr<FrameChannel<v1::ProfileFrame>>> profile_watchers_;
  std::vector<ParticleWatch> particle_watchers_;
  // Read by the worker between steps without mutex_ (refresh_watch_flags_locked() keeps them):
  std::atomic<bool> runnable_{false};  // RUNNING and not closed
  std::atomic<bool> has_frame_watchers_{false};
  std::atomic<bool> has_lossless_watchers_{false};
  std::atomic<long> next_frame_step_{0};  // no frame is due before this step
};

}  // namespace lbsolid::server
