#include "server/session/session.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "scene/instability_error.h"
#include "io/api/log_text.h"

namespace lbsolid::server {

namespace {

// How long a client joining a running session waits for the worker to publish its first frame
// before reading it itself (which stops the run for a moment): many slices' worth of steps of a
// session of ordinary size.
constexpr auto kFirstFrameWait = std::chrono::milliseconds(50);

long long unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

v1::Vector3 to_proto(const fluid::Vec3& v) {
  v1::Vector3 out;
  out.set_x(v[0]);
  out.set_y(v[1]);
  out.set_z(v[2]);
  return out;
}

// Body b's broken links that broke after step `since`, and how many it has in all. The log is in
// the order of breaking, so in step order.
void add_broken_links(const solid::SolidSystem& solid, int b, long since, v1::BodyFrame& out) {
  const auto& broken = solid.broken_links();
  const auto& body = solid.body(b);
  long count = 0;
  for (const auto& link : broken) count += solid.body_of(link.particle) == b;
  out.set_broken_link_count(count);
  const auto first = std::partition_point(broken.begin(), broken.end(),
                                          [since](const solid::BrokenLink& link) { return link.step <= since; });
  for (auto it = first; it != broken.end(); ++it) {
    if (solid.body_of(it->particle) != b) continue;
    auto* link = out.add_broken_links();
    link->set_step(it->step);
    link->set_particle(it->particle - body.first);
    const solid::Label l = solid.label(it->particle);
    link->mutable_label()->set_i(l[0]);
    link->mutable_label()->set_j(l[1]);
    link->mutable_label()->set_k(l[2]);
    link->set_link(it->link);
    *link->mutable_position() = to_proto(it->position);
  }
}

absl::Status wrong_state(const std::string& what, v1::SessionState state) {
  return absl::FailedPreconditionError(
      absl::StrCat(what, ": not allowed while the session is ", v1::SessionState_Name(state)));
}

absl::Status step_in_progress(const std::string& what) {
  return absl::FailedPreconditionError(
      absl::StrCat(what, ": a Step call is advancing the session; wait for it to return, or Cancel"));
}

}  // namespace

bool is_final(v1::SessionState state) {
  return state == v1::SESSION_STATE_FAILED || state == v1::SESSION_STATE_CANCELLED;
}

Session::Session(SessionSetup setup, std::shared_ptr<parallel::ThreadPool> fluid_pool)
    : id_(std::move(setup.id)),
      request_id_(std::move(setup.request_id)),
      owner_(std::move(setup.owner)),
      scenario_(std::move(setup.scenario)),
      output_plan_(setup.translated.outputs),
      outputs_dir_(std::move(setup.outputs_dir)),
      writer_version_(std::move(setup.writer_version)),
      created_unix_ms_(setup.created_unix_ms),
      warnings_(setup.translated.warnings),
      sim_(scene::build_simulation(setup.translated.scene, std::move(fluid_pool))) {
  refresh_sizes();
}

Session::~Session() = default;

void Session::refresh_sizes() {
  particles_ = sim_->solid() ? sim_->solid()->particle_count() : 0;
  fluid_bytes_ = static_cast<long long>(sim_->fluid_bytes());
  solid_bytes_ = static_cast<long long>(sim_->solid_bytes());
}

long Session::cells() const {
  const auto& f = sim_->scene().fluid;
  return sim_->has_fluid() ? static_cast<long>(f.nx) * f.ny * f.nz : 0;
}

v1::SessionState Session::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

v1::Session Session::describe(bool with_scenario) const {
  v1::Session s;
  s.set_id(id_);
  s.set_name(scenario_.name());
  s.set_request_id(request_id_);
  s.set_owner(owner_);
  if (with_scenario) *s.mutable_scenario() = scenario_;
  for (const auto& stage : sim_->stages()) s.add_stages(stage);  // fixed at build: no lock needed
  s.set_cells(cells());
  s.set_particles(particles_);
  s.set_fluid_bytes(fluid_bytes_);
  s.set_solid_bytes(solid_bytes_);
  s.set_created_unix_ms(created_unix_ms_);
  s.set_steps_lost(steps_lost_);
  for (const auto& warning : warnings_) s.add_warnings(warning);
  std::lock_guard lock(mutex_);
  s.set_state(state_);
  s.set_step(step_);
  s.set_target_step(target_);
  s.set_message(message_);
  if (state_ == v1::SESSION_STATE_RUNNING) {
    s.set_steps_per_second(steps_per_second_);
    s.set_mlups(steps_per_second_ * static_cast<double>(cells()) * 1e-6);
  }
  return s;
}

// ---- state changes -------------------------------------------------------------------------

absl::Status Session::run(long steps) {
  std::lock_guard lock(mutex_);
  if (closed_) return absl::NotFoundError(absl::StrCat("session_id: session ", id_, " was deleted"));
  if (state_ == v1::SESSION_STATE_RUNNING || is_final(state_)) return wrong_state("Run", state_);
  if (stepping_) return step_in_progress("Run");
  if (steps > std::numeric_limits<long>::max() - step_)
    return absl::InvalidArgumentError(absl::StrCat("steps: ", steps, " more steps from step ", step_.load(),
                                                   " would pass the largest step number"));
  target_ = step_ + steps;
  set_state_locked(v1::SESSION_STATE_RUNNING);
  return absl::OkStatus();
}

absl::Status Session::pause() {
  return stop_at_step_boundary("Pause", v1::SESSION_STATE_PAUSED,
                               [](v1::SessionState s) { return s == v1::SESSION_STATE_RUNNING; });
}

absl::Status Session::resume() {
  std::lock_guard lock(mutex_);
  if (state_ != v1::SESSION_STATE_PAUSED) return wrong_state("Resume", state_);
  if (stepping_) return step_in_progress("Resume");
  set_state_locked(step_ >= target_ ? v1::SESSION_STATE_DONE : v1::SESSION_STATE_RUNNING);
  return absl::OkStatus();
}

absl::Status Session::cancel() {
  return stop_at_step_boundary("Cancel", v1::SESSION_STATE_CANCELLED,
                               [](v1::SessionState s) { return !is_final(s); });
}

absl::Status Session::stop_at_step_boundary(const char* what, v1::SessionState next,
                                            bool (*allowed)(v1::SessionState)) {
  {
    std::lock_guard lock(mutex_);  // refuse at once, without waiting for the step in flight
    if (!allowed(state_)) return wrong_state(what, state_);
  }
  ++stop_requests_;  // a Step call lets go at its next step boundary; a worker ends its slice
  const auto sim_lock = lock_simulation();
  --stop_requests_;
  {
    std::lock_guard lock(mutex_);
    if (!allowed(state_)) return wrong_state(what, state_);  // it changed meanwhile (DONE, FAILED)
    set_state_locked(next);
  }
  // Clients that joined the run since its last step still wait for their first frame: the state
  // where it stopped (a cancelled session has closed its streams).
  if (has_frame_watchers_) publish_first_frames();
  return absl::OkStatus();
}

void Session::set_state_locked(v1::SessionState next, const std::string& message) {
  const auto previous = state_;
  state_ = next;
  runnable_ = !closed_ && next == v1::SESSION_STATE_RUNNING;
  message_ = message;
  spdlog::info("session {}: {} -> {} at step {}{}{}", id_, v1::SessionState_Name(previous), v1::SessionState_Name(next),
               step_.load(), message.empty() ? "" : ": ", message.empty() ? "" : log_text(message, 500));
  v1::SessionEvent event;
  event.mutable_state_changed()->set_from(previous);
  event.mutable_state_changed()->set_to(next);
  emit_locked(event);
  // Streams follow a session until it stops for good or reaches its target.
  if (is_final(next) || next == v1::SESSION_STATE_DONE) close_streams_locked();
}

void Session::emit_locked(v1::SessionEvent event) {
  event.set_session_id(id_);
  event.set_unix_ms(unix_ms_now());
  for (const auto& watcher : event_watchers_) watcher->publish(event);
}

void Session::close_streams_locked() {
  for (const auto& w : event_watchers_) w->close();
  for (const auto& w : profile_watchers_) w->close();
  for (const auto& w : particle_watchers_) w.channel->close();
  event_watchers_.clear();
  profile_watchers_.clear();
  particle_watchers_.clear();
  refresh_watch_flags_locked();
}

void Session::refresh_watch_flags_locked() {
  has_frame_watchers_ = !profile_watchers_.empty() || !particle_watchers_.empty();
  bool lossless = false;
  long next = std::numeric_limits<long>::max();
  const long step = step_;
  const auto consider = [&](const auto& w) {
    lossless = lossless || w.lossless();
    // Due at the next multiple of `every` after this step, or now for a first frame.
    next = std::min(next, w.first_frame_wanted() ? 0 : (step / w.every() + 1) * w.every());
  };
  for (const auto& w : profile_watchers_) consider(*w);
  for (const auto& w : particle_watchers_) consider(*w.channel);
  has_lossless_watchers_ = lossless;
  next_frame_step_ = next;
}

void Session::close() {
  std::lock_guard lock(mutex_);  // a Step call sees closed_ at its next step boundary
  closed_ = true;
  runnable_ = false;
  if (state_ == v1::SESSION_STATE_RUNNING) set_state_locked(v1::SESSION_STATE_CANCELLED);
  close_streams_locked();
}

void Session::emit_error_locked(long step, const std::string& message) {
  v1::SessionEvent event;
  event.mutable_error()->set_step(step);
  event.mutable_error()->set_message(message);
  emit_locked(event);
}

void Session::fail(long step, const std::string& cause) {
  std::lock_guard lock(mutex_);
  const std::string message = absl::StrCat("step ", step, ": ", cause);
  emit_error_locked(step, message);
  set_state_locked(v1::SESSION_STATE_FAILED, message);
}

// ---- stepping ------------------------------------------------------------------------------

bool Session::wants_work_locked() const {
  return !closed_ && state_ == v1::SESSION_STATE_RUNNING && step_ < target_;
}

bool Session::claim_schedule() {
  std::lock_guard lock(mutex_);
  if (scheduled_ || !wants_work_locked()) return false;
  scheduled_ = true;
  return true;
}

bool Session::finish_slice() {
  std::lock_guard lock(mutex_);
  if (state_ == v1::SESSION_STATE_RUNNING && !closed_ && step_ >= target_) set_state_locked(v1::SESSION_STATE_DONE);
  scheduled_ = wants_work_locked();
  return scheduled_;
}

bool Session::step_once() {
  const long step = sim_->step_count() + 1;
  ++fields_generation_;  // before: a step that throws halfway has changed the state too
  try {
    sim_->step();  // the scene's monitor checks the run every stability.check_interval steps
  } catch (const scene::InstabilityError& e) {
    step_ = sim_->step_count();
    fail(e.step(), e.message());
    return false;
  } catch (const std::exception& e) {
    fail(step, absl::StrCat("the simulation stopped: ", e.what()));
    return false;
  }
  step_ = sim_->step_count();
  refresh_sizes();
  if (has_frame_watchers_ && step_ >= next_frame_step_) publish_frames(step_);
  return record_outputs();
}

bool Session::record_outputs() {
  if (!recorder_) return true;
  const long step = sim_->step_count();
  const bool target_reached = step == target_;
  if (!recorder_->anything_due(step, target_reached)) return true;
  try {
    if (recorder_->particles_due(step))
      recorder_->record_particles(particle_frame(recorded_bodies_, recorder_->last_particles_step()));
    if (recorder_->profile_due(step)) recorder_->record_profile(profile_frame());
    if (recorder_->fields_due(step, target_reached))
      recorder_->record_fields(step, sim_->fluid_fields(), {1.0, scene::lattice_row_spacing(sim_->scene().lattice), 1.0});
  } catch (const std::exception& e) {
    stop_for_outputs(step, e.what());
    return false;
  }
  return true;
}

void Session::stop_for_outputs(long step, const std::string& cause) {
  std::lock_guard lock(mutex_);
  const std::string message = absl::StrCat("step ", step, ": outputs: cannot record (Resume tries again): ", cause);
  emit_error_locked(step, message);
  if (state_ == v1::SESSION_STATE_RUNNING) set_state_locked(v1::SESSION_STATE_PAUSED, message);
}

void Session::open_outputs() {
  if (!output_plan_.records_frames() || outputs_dir_.empty()) return;
  const auto sim_lock = lock_simulation();
  if (const auto* solid = sim_->solid()) {
    for (int b = 0; b < solid->body_count(); ++b) {
      const auto& name = solid->body(b).name;
      const auto& wanted = output_plan_.particle_bodies;
      if (wanted.empty() || std::find(wanted.begin(), wanted.end(), name) != wanted.end()) recorded_bodies_.push_back(b);
    }
  }
  recorder_ = std::make_unique<OutputRecorder>(outputs_dir_, output_plan_, scenario_, writer_version_,
                                               sim_->step_count());
}

void Session::sync_outputs() const {
  // The log's own lock orders this against the appends; fsync needs no simulation lock.
  if (recorder_) recorder_->sync();
}

absl::StatusOr<std::vector<OutputFile>> Session::outputs(const std::string& checkpoint_dir) {
  std::vector<OutputFile> files;
  if (recorder_) {
    auto made = recorder_->files();
    if (!made.ok()) return made.status();
    files = *std::move(made);
  }
  std::lock_guard lock(checkpoint_files_mutex_);
  try {
    for (auto& checkpoint : list_checkpoints(checkpoint_dir, checkpoint_files_)) files.push_back(std::move(checkpoint));
  } catch (const std::exception& e) {
    return absl::UnavailableError(absl::StrCat("outputs: cannot list the checkpoints: ", e.what()));
  }
  return files;
}

bool Session::auto_checkpoint_due() const {
  const long every = output_plan_.checkpoint_every;
  const long step = step_;
  return every > 0 && step > 0 && step % every == 0 && step > last_auto_checkpoint_;
}

std::unique_lock<std::mutex> Session::lock_simulation() const {
  ++readers_waiting_;
  std::unique_lock lock(sim_mutex_);
  --readers_waiting_;
  reader_entered_.notify_all();
  return lock;
}

void Session::advance(std::chrono::milliseconds slice) {
  if (readers_waiting_ > 0) {  // let them in first; the session is queued again
    std::unique_lock lock(handoff_mutex_);
    reader_entered_.wait_for(lock, std::chrono::milliseconds(5), [&] { return readers_waiting_ == 0; });
    return;
  }
  // A lossless client that is behind holds the run back; the wait happens here, outside the
  // simulation lock, so field reads, checkpoints, pauses and other streams go on meanwhile.
  if (has_frame_watchers_ && !wait_for_lossless_clients(slice)) return;
  std::lock_guard sim_lock(sim_mutex_);
  if (!record_outputs()) return;  // what is due at the current step: first frames, or a failed write
  const auto start = Clock::now();
  long taken = 0;
  // The checks between steps read atomics only: the session's mutex is shared with the calls,
  // whose threads run at a lower priority, and one preempted while holding it would stall the run.
  while (runnable_ && step_ < target_) {
    if (!step_once()) return;
    ++taken;
    if (Clock::now() - start >= slice || readers_waiting_ > 0) break;
    if (lossless_watcher_behind()) break;
    if (auto_checkpoint_due()) break;  // the worker takes it now, at this step
  }
  record_rate(taken, Clock::now() - start);
  emit_progress();
}

absl::StatusOr<StepResult> Session::step_now(long steps, std::chrono::system_clock::time_point deadline,
                                             const std::function<bool()>& abandoned) {
  const auto refused = [&]() -> absl::Status {
    if (closed_) return absl::NotFoundError(absl::StrCat("session_id: session ", id_, " was deleted"));
    if (state_ == v1::SESSION_STATE_RUNNING || is_final(state_)) return wrong_state("Step", state_);
    return absl::OkStatus();
  };
  {
    std::lock_guard lock(mutex_);  // refuse at once, without waiting for the worker's slice
    if (auto status = refused(); !status.ok()) return status;
  }
  const auto sim_lock = lock_simulation();
  {
    std::lock_guard lock(mutex_);
    if (auto status = refused(); !status.ok()) return status;
    stepping_ = true;  // Run and Resume are refused until this call returns
  }
  StepResult result;
  record_outputs();  // what is due at the current step (a failure is in the session's events)
  auto longest_step = std::chrono::system_clock::duration::zero();
  // Room for the answer to reach the client before its deadline, on a loaded machine too.
  const auto margin = std::chrono::milliseconds(50);
  while (result.steps_taken < steps) {
    if (step_call_must_stop(abandoned)) {
      result.interrupted = true;
      break;
    }
    const auto before = std::chrono::system_clock::now();
    if (before + 2 * longest_step + margin > deadline) {
      result.deadline_reached = true;
      break;
    }
    if (!step_once()) break;
    ++result.steps_taken;
    longest_step = std::max(longest_step, std::chrono::system_clock::now() - before);
  }
  std::lock_guard lock(mutex_);
  stepping_ = false;
  if (!is_final(state_) && result.steps_taken > 0) {
    target_ = std::max(target_.load(), step_.load());
    if (state_ != v1::SESSION_STATE_PAUSED) set_state_locked(v1::SESSION_STATE_PAUSED);
  }
  return result;
}

bool Session::step_call_must_stop(const std::function<bool()>& abandoned) const {
  if (stop_requests_ > 0 || abandoned()) return true;
  std::lock_guard lock(mutex_);
  return closed_ || is_final(state_);
}

bool Session::progress_note_due() {
  const auto now = Clock::now().time_since_epoch().count();
  auto last = progress_noted_.load();
  const auto interval = std::chrono::duration_cast<Clock::duration>(kProgressNoteInterval).count();
  return now - last >= interval && progress_noted_.compare_exchange_strong(last, now);
}

void Session::record_rate(long steps, Clock::duration elapsed) {
  const double seconds = std::chrono::duration<double>(elapsed).count();
  if (steps == 0 || seconds <= 0) return;
  const double rate = steps / seconds;
  std::lock_guard lock(mutex_);
  steps_per_second_ = steps_per_second_ == 0 ? rate : 0.7 * steps_per_second_ + 0.3 * rate;
}

void Session::emit_progress() {
  std::lock_guard lock(mutex_);
  if (event_watchers_.empty()) return;
  v1::SessionEvent event;
  auto* p = event.mutable_progress();
  p->set_step(step_);
  p->set_target_step(target_);
  p->set_steps_per_second(steps_per_second_);
  p->set_mlups(steps_per_second_ * static_cast<double>(cells()) * 1e-6);
  if (steps_per_second_ > 0) p->set_estimated_seconds_left(static_cast<double>(target_ - step_) / steps_per_second_);
  emit_locked(event);
}

// ---- observers -----------------------------------------------------------------------------

v1::ProfileFrame Session::profile_frame() const {
  v1::ProfileFrame frame;
  frame.set_step(sim_->step_count());
  const auto u = sim_->velocity_profile();
  const double dy = scene::lattice_row_spacing(sim_->scene().lattice);
  for (std::size_t y = 0; y < u.size(); ++y) {
    frame.add_y(static_cast<double>(y) * dy);
    frame.add_u_x(u[y]);
  }
  return frame;
}

v1::ParticleFrame Session::particle_frame(const std::vector<int>& bodies, long since) const {
  v1::ParticleFrame frame;
  frame.set_step(sim_->step_count());
  const auto& solid = *sim_->solid();
  for (int b : bodies) {
    const auto& body = solid.body(b);
    auto* out = frame.add_bodies();
    out->set_name(body.name);
    double energy = 0;
    for (int p = body.first; p < body.first + body.count; ++p) {
      energy += solid.energy(p);
      const auto& r = solid.position(p);
      const auto u = sim_->particle_velocity(p);
      for (int a = 0; a < 3; ++a) {
        out->add_position(r[a]);
        out->add_velocity(u[a]);
      }
    }
    const auto state = sim_->body_state(b);
    *out->mutable_centre_of_mass() = to_proto(state.centre_of_mass);
    *out->mutable_mean_velocity() = to_proto(state.velocity);
    out->set_mass(state.mass);
    out->set_energy(energy);
    *out->mutable_angular_momentum() = to_proto(state.angular_momentum);
    *out->mutable_angular_velocity() = to_proto(state.angular_velocity);
    out->set_orientation(state.orientation);
    const auto& q = state.orientation_quaternion;
    auto* quaternion = out->mutable_orientation_quaternion();
    quaternion->set_w(q[0]);
    quaternion->set_x(q[1]);
    quaternion->set_y(q[2]);
    quaternion->set_z(q[3]);
    *out->mutable_torque() = to_proto(state.torque);
    *out->mutable_anchor_force() = to_proto(state.anchor_force);
    add_broken_links(solid, b, since, *out);
  }
  return frame;
}

void Session::publish_frames(long step) { publish_frames_if([step](const auto& w) { return w.due(step); }); }

void Session::publish_first_frames() {
  publish_frames_if([](const auto& w) { return w.first_frame_wanted(); });
}

template <class Wanted>
void Session::publish_frames_if(const Wanted& wanted) {
  std::vector<std::shared_ptr<FrameChannel<v1::ProfileFrame>>> profiles;
  std::vector<ParticleWatch> particles;
  {
    std::lock_guard lock(mutex_);
    std::erase_if(profile_watchers_, [](const auto& w) { return w->detached(); });
    std::erase_if(particle_watchers_, [](const auto& w) { return w.channel->detached(); });
    for (const auto& w : profile_watchers_)
      if (wanted(*w)) profiles.push_back(w);
    for (const auto& w : particle_watchers_)
      if (wanted(*w.channel)) particles.push_back(w);
  }
  if (!profiles.empty()) {
    const auto frame = profile_frame();  // computed once for every due client
    for (const auto& w : profiles) w->publish(frame);
  }
  // A stream's first frame lists every break so far; the others those since the stream's last.
  for (const auto& w : particles)
    w.channel->publish(particle_frame(w.bodies, w.channel->first_frame_wanted() ? -1 : sim_->step_count() - w.channel->every()));
  std::lock_guard lock(mutex_);
  refresh_watch_flags_locked();
}

bool Session::lossless_watcher_behind() const {
  if (!has_lossless_watchers_) return false;
  std::lock_guard lock(mutex_);
  for (const auto& w : profile_watchers_)
    if (w->full()) return true;
  for (const auto& w : particle_watchers_)
    if (w.channel->full()) return true;
  return false;
}

bool Session::wait_for_lossless_clients(std::chrono::milliseconds timeout) {
  std::vector<std::shared_ptr<FrameChannel<v1::ProfileFrame>>> profiles;
  std::vector<std::shared_ptr<FrameChannel<v1::ParticleFrame>>> particles;
  {
    std::lock_guard lock(mutex_);
    for (const auto& w : profile_watchers_)
      if (w->full()) profiles.push_back(w);
    for (const auto& w : particle_watchers_)
      if (w.channel->full()) particles.push_back(w.channel);
  }
  const auto give_up = Clock::now() + timeout;
  const auto left = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::max(Clock::duration::zero(), give_up - Clock::now()));
  };
  for (const auto& w : profiles)
    if (!w->wait_for_room(left())) return false;
  for (const auto& w : particles)
    if (!w->wait_for_room(left())) return false;
  return true;
}

std::shared_ptr<EventChannel> Session::watch_events(std::chrono::milliseconds progress_interval) {
  auto channel = std::make_shared<EventChannel>(progress_interval);
  std::lock_guard lock(mutex_);
  v1::SessionEvent first;  // the current state, from UNSPECIFIED
  first.set_session_id(id_);
  first.set_unix_ms(unix_ms_now());
  first.mutable_state_changed()->set_to(state_);
  channel->publish(first);
  if (closed_ || is_final(state_) || state_ == v1::SESSION_STATE_DONE)
    channel->close();
  else
    event_watchers_.push_back(channel);
  return channel;
}

template <class Frame, class Register>
bool Session::join_running(const std::shared_ptr<FrameChannel<Frame>>& channel, const Register& register_watcher) {
  {
    std::lock_guard lock(mutex_);
    if (closed_ || state_ != v1::SESSION_STATE_RUNNING) return false;
    channel->want_first_frame();
    register_watcher();
    refresh_watch_flags_locked();
  }
  // The worker publishes it after its next step. A run that does not move (held back by a
  // lossless client, or with steps longer than this wait) has it read here, between two steps.
  if (!channel->wait_for_first_frame(kFirstFrameWait)) {
    const auto sim_lock = lock_simulation();
    publish_first_frames();
  }
  return true;
}

absl::StatusOr<std::shared_ptr<FrameChannel<v1::ProfileFrame>>> Session::watch_profiles(long every,
                                                                                        Delivery delivery) {
  if (!sim_->has_fluid()) return absl::FailedPreconditionError("WatchProfiles: the scenario has no fluid");
  auto channel = std::make_shared<FrameChannel<v1::ProfileFrame>>(delivery, every);
  if (join_running(channel, [&] { profile_watchers_.push_back(channel); })) return channel;
  const auto sim_lock = lock_simulation();  // between two steps: the first frame is the current state
  channel->publish(profile_frame());
  std::lock_guard lock(mutex_);
  if (closed_ || is_final(state_) || state_ == v1::SESSION_STATE_DONE) {
    channel->close();
  } else {
    profile_watchers_.push_back(channel);
    refresh_watch_flags_locked();
  }
  return channel;
}

absl::StatusOr<std::shared_ptr<FrameChannel<v1::ParticleFrame>>> Session::watch_particles(
    long every, Delivery delivery, const std::vector<std::string>& names) {
  const auto* solid = sim_->solid();
  if (!solid) return absl::FailedPreconditionError("WatchParticles: the scenario has no bodies");
  std::vector<int> bodies;
  std::vector<std::string> known;
  for (int b = 0; b < solid->body_count(); ++b) known.push_back(solid->body(b).name);
  if (names.empty())
    for (int b = 0; b < solid->body_count(); ++b) bodies.push_back(b);
  for (const auto& name : names) {
    const auto it = std::find(known.begin(), known.end(), name);
    if (it == known.end())
      return absl::InvalidArgumentError(
          absl::StrCat("bodies: no body named \"", name, "\"; the scenario has ", absl::StrJoin(known, ", ")));
    bodies.push_back(static_cast<int>(it - known.begin()));
  }
  auto channel = std::make_shared<FrameChannel<v1::ParticleFrame>>(delivery, every);
  if (join_running(channel, [&] { particle_watchers_.push_back({channel, bodies}); })) return channel;
  const auto sim_lock = lock_simulation();
  channel->publish(particle_frame(bodies, -1));
  std::lock_guard lock(mutex_);
  if (closed_ || is_final(state_) || state_ == v1::SESSION_STATE_DONE) {
    channel->close();
  } else {
    particle_watchers_.push_back({channel, bodies});
    refresh_watch_flags_locked();
  }
  return channel;
}

absl::StatusOr<std::shared_ptr<const FieldData>> Session::fields() const {
  if (!sim_->has_fluid()) return absl::FailedPreconditionError("GetField: the scenario has no fluid");
  std::lock_guard snapshots_lock(snapshots_mutex_);
  std::erase_if(snapshots_, [](const auto& s) { return s.expired(); });
  for (const auto& weak : snapshots_)
    if (auto shared = weak.lock(); shared && shared->step == step_) return shared;
  if (static_cast<int>(snapshots_.size()) >= kFieldSnapshots)
    return absl::ResourceExhaustedError(absl::StrCat("GetField: ", kFieldSnapshots, " reads of session ", id_,
                                                     " at earlier steps are still in flight; retry when one ends"));
  std::unique_ptr<FieldData> filled;
  {
    std::lock_guard lock(spare_snapshot_->mutex);
    filled = std::move(spare_snapshot_->data);
  }
  if (!filled) filled = std::make_unique<FieldData>();
  {
    const auto sim_lock = lock_simulation();
    if (filled->generation != fields_generation_) {  // else nothing changed since the spare was filled
      filled->step = sim_->step_count();
      sim_->fill_fluid_fields(filled->fields);  // into the spare's memory, already faulted in
      filled->generation = fields_generation_;
    }
  }
  filled->spacing = {1.0, scene::lattice_row_spacing(sim_->scene().lattice), 1.0};
  // The last reader hands the snapshot back as the next one's buffer (one is kept: the footprint
  // counts one field read for the session's whole life), even if the session is gone by then.
  std::shared_ptr<const FieldData> data(filled.release(), [spare = spare_snapshot_](const FieldData* done) {
    std::unique_ptr<FieldData> owned(const_cast<FieldData*>(done));
    std::lock_guard lock(spare->mutex);
    if (!spare->data) spare->data = std::move(owned);
  });
  snapshots_.push_back(data);
  return data;
}

storage::CheckpointContents Session::checkpoint_contents() const {
  const auto sim_lock = lock_simulation();
  storage::CheckpointContents c;
  c.scenario_text = scenario_to_text(scenario_);
  c.session_id = id_;
  c.session_name = scenario_.name();
  c.request_id = request_id_;
  c.owner = owner_;
  c.state = sim_->save_state();
  std::lock_guard lock(mutex_);
  c.target_step = target_;
  c.done = state_ == v1::SESSION_STATE_DONE;
  c.started = state_ != v1::SESSION_STATE_CREATED;
  return c;
}

void Session::restore(const scene::SimulationState& state, long target_step, v1::SessionState session_state) {
  const auto sim_lock = lock_simulation();
  ++fields_generation_;
  sim_->load_state(state);
  refresh_sizes();
  std::lock_guard lock(mutex_);
  step_ = sim_->step_count();
  last_auto_checkpoint_ = step_.load();
  target_ = target_step;
  state_ = session_state;
  runnable_ = !closed_ && session_state == v1::SESSION_STATE_RUNNING;
}

}  // namespace lbsolid::server
