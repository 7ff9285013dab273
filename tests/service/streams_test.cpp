// The daemon's server streams as clients see them: WatchSession's state changes and progress,
// WatchProfiles and WatchParticles in both delivery modes (every frame: lossless, the session waits
// for the slowest such client; latest frame: the run never waits, missed frames are counted), a
// client going away midway, several clients at once, a session deleted under its streams, and two
// sessions running side by side.
//
// Slow clients are checked twice: through a connection with default settings (no frame lost in
// lossless mode, exact accounting of missed frames in latest mode) and through one with a tight
// HTTP/2 window (tight_window_stub), which takes gRPC's own buffering out of the picture and so
// checks the daemon's bounds themselves (lossless lag within the 8-frame queue, latest frame only).
//
// No assertion depends on how fast the machine is: clients wait for conditions with deadlines, and
// the latest-frame checks count frames rather than time them.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "service/daemon_process.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

using std::chrono::milliseconds;

constexpr long kChannelCapacity = 8;  // FrameChannel's default: frames a lossless client may lag

class Streams : public ::testing::Test {
 protected:
  Streams() : data_dir_("lbsolid-streams"), daemon_(data_dir_.path), stub_(daemon_.stub()) {}

  std::string create(const v1::Scenario& scenario = small_channel_with_disk()) {
    v1::Session session;
    const auto status = create_session(*stub_, scenario, &session);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return session.id();
  }

  v1::Session session(const std::string& id) {
    v1::Session out;
    const auto status = get_session(*stub_, id, &out);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return out;
  }

  std::unique_ptr<grpc::ClientReader<v1::ProfileFrame>> watch_profiles(grpc::ClientContext* context,
                                                                      const std::string& id, long every,
                                                                      v1::DeliveryMode delivery) {
    v1::WatchProfilesRequest request;
    request.set_session_id(id);
    request.set_every(every);
    request.set_delivery(delivery);
    return stub_->WatchProfiles(context, request);
  }

  ScopedDirectory data_dir_;
  DaemonProcess daemon_;
  std::unique_ptr<v1::Simulation::Stub> stub_;
};

// WatchSession: the first event is the current state (CREATED, from UNSPECIFIED); then the Run's
// CREATED -> RUNNING, progress events with steps that grow up to the target, and RUNNING -> DONE as
// the last event, after which the stream ends OK.
TEST_F(Streams, WatchSessionSeesStateChangesAndProgress) {
  const std::string id = create();
  v1::WatchSessionRequest request;
  request.set_session_id(id);
  request.set_progress_interval_s(0.05);
  auto context = deadline_context(30);
  auto reader = stub_->WatchSession(context.get(), request);
  v1::SessionEvent event;
  ASSERT_TRUE(reader->Read(&event));  // subscribed: nothing of the run can be missed now
  ASSERT_TRUE(event.has_state_changed());
  EXPECT_EQ(event.session_id(), id);
  EXPECT_EQ(event.state_changed().from(), v1::SESSION_STATE_UNSPECIFIED);
  EXPECT_EQ(event.state_changed().to(), v1::SESSION_STATE_CREATED);
  EXPECT_GT(event.unix_ms(), 0);

  constexpr long kTarget = 600;
  ASSERT_TRUE(run_session(*stub_, id, kTarget).ok());
  std::vector<std::pair<v1::SessionState, v1::SessionState>> changes;
  std::vector<v1::Progress> progress;
  v1::SessionEvent last;
  while (reader->Read(&event)) {
    EXPECT_EQ(event.session_id(), id);
    EXPECT_FALSE(event.has_error());
    if (event.has_state_changed()) changes.emplace_back(event.state_changed().from(), event.state_changed().to());
    if (event.has_progress()) progress.push_back(event.progress());
    last = event;
  }
  const auto status = reader->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();
  const std::vector<std::pair<v1::SessionState, v1::SessionState>> expected = {
      {v1::SESSION_STATE_CREATED, v1::SESSION_STATE_RUNNING}, {v1::SESSION_STATE_RUNNING, v1::SESSION_STATE_DONE}};
  EXPECT_EQ(changes, expected);
  ASSERT_TRUE(last.has_state_changed());
  EXPECT_EQ(last.state_changed().to(), v1::SESSION_STATE_DONE);
  ASSERT_FALSE(progress.empty());
  long previous = 0;
  for (const auto& p : progress) {
    EXPECT_GE(p.step(), previous);
    EXPECT_LE(p.step(), kTarget);
    EXPECT_EQ(p.target_step(), kTarget);
    EXPECT_GE(p.steps_per_second(), 0);
    previous = p.step();
  }
  EXPECT_GT(progress.back().step(), 0);
  EXPECT_EQ(session(id).step(), kTarget);
}

// Every-frame delivery is lossless: the frames are exactly steps 0 (the state at subscription),
// every, 2 every, ..., target, in order, none skipped, each a full profile (one u_x per row).
TEST_F(Streams, EveryFrameModeDeliversEveryFrameInOrder) {
  const std::string id = create();
  constexpr long kEvery = 10, kTarget = 300;
  auto context = deadline_context(30);
  auto reader = watch_profiles(context.get(), id, kEvery, v1::DELIVERY_MODE_EVERY_FRAME);
  v1::ProfileFrame frame;
  ASSERT_TRUE(reader->Read(&frame));
  EXPECT_EQ(frame.step(), 0);
  ASSERT_TRUE(run_session(*stub_, id, kTarget).ok());
  std::vector<long> steps = {frame.step()};
  while (reader->Read(&frame)) {
    steps.push_back(frame.step());
    EXPECT_EQ(frame.skipped_frames(), 0);
    EXPECT_EQ(frame.y_size(), 16);
    EXPECT_EQ(frame.u_x_size(), 16);
    for (double u : frame.u_x()) EXPECT_TRUE(std::isfinite(u));
  }
  const auto status = reader->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();
  std::vector<long> expected;
  for (long s = 0; s <= kTarget; s += kEvery) expected.push_back(s);
  EXPECT_EQ(steps, expected);
  // The flow is driven along +x: away from the walls it moves forward by the end.
  EXPECT_GT(frame.u_x(8), 0);
  EXPECT_TRUE(wait_for_state(*stub_, id, v1::SESSION_STATE_DONE));
}

// A client that cancels its stream midway gets CANCELLED, and the daemon lets go of it: it was a
// lossless client on a tight transport window, which the session would wait for within some ten
// frames if the daemon kept it; yet the session runs on to DONE.
TEST_F(Streams, ClientCancellingMidwayDoesNotStopTheSession) {
  const std::string id = create();
  constexpr long kTarget = 2000;
  auto tight = tight_window_stub(daemon_);
  auto context = deadline_context(30);
  v1::WatchProfilesRequest request;
  request.set_session_id(id);
  request.set_every(1);
  request.set_delivery(v1::DELIVERY_MODE_EVERY_FRAME);
  auto reader = tight->WatchProfiles(context.get(), request);
  v1::ProfileFrame frame;
  ASSERT_TRUE(reader->Read(&frame));
  ASSERT_TRUE(run_session(*stub_, id, kTarget).ok());
  for (int k = 0; k < 3; ++k) ASSERT_TRUE(reader->Read(&frame));
  EXPECT_EQ(frame.step(), 3);
  context->TryCancel();
  while (reader->Read(&frame)) {
  }
  EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
  EXPECT_TRUE(wait_for_state(*stub_, id, v1::SESSION_STATE_DONE));
  EXPECT_EQ(session(id).step(), kTarget);
}

// Reads a latest-frame profile stream whose first frame (step 0) was read before a Run of
// `target` steps with every = 1, and whose client then slept until the session was DONE.
struct AfterSleep {
  long received = 1;                        // frames read in all, the first one included
  std::vector<v1::ProfileFrame> frames;     // those read after the sleep
};

AfterSleep read_after_sleep(grpc::ClientReader<v1::ProfileFrame>& reader) {
  AfterSleep out;
  v1::ProfileFrame frame;
  while (reader.Read(&frame)) {
    out.frames.push_back(frame);
    ++out.received;
  }
  return out;
}

// A slow latest-frame client never holds the run back: it reads the first frame, then does not read
// again until the session is DONE (which it can only become if the run ignores the client). What
// it reads then: increasing steps, the final frame last, frames replaced and counted
// (skipped_frames > 0 at the end), and frames read + frames skipped = frames published.
TEST_F(Streams, SlowLatestFrameClientDoesNotSlowTheRun) {
  const std::string id = create();
  constexpr long kTarget = 4000;
  auto context = deadline_context(30);
  auto reader = watch_profiles(context.get(), id, 1, v1::DELIVERY_MODE_LATEST_FRAME);
  v1::ProfileFrame frame;
  ASSERT_TRUE(reader->Read(&frame));
  EXPECT_EQ(frame.step(), 0);
  ASSERT_TRUE(run_session(*stub_, id, kTarget).ok());
  ASSERT_TRUE(wait_for_state(*stub_, id, v1::SESSION_STATE_DONE));  // while the client "sleeps"

  const auto after = read_after_sleep(*reader);
  const auto status = reader->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();
  ASSERT_FALSE(after.frames.empty());
  for (std::size_t k = 1; k < after.frames.size(); ++k)
    EXPECT_GT(after.frames[k].step(), after.frames[k - 1].step());
  const auto& last = after.frames.back();
  EXPECT_EQ(last.step(), kTarget);  // the newest frame is never the one replaced
  EXPECT_GT(last.skipped_frames(), 0);
  EXPECT_EQ(after.received + last.skipped_frames(), kTarget + 1);  // frames at steps 0, 1, ..., kTarget
}

// The daemon's own latest-frame mechanism, seen through a tight transport window (see
// tight_window_stub): after the sleep the client reads at most the one frame that was in flight
// and then the final frame, which counts every frame it missed.
TEST_F(Streams, LatestFrameThroughATightWindowSkipsToTheNewestFrame) {
  const std::string id = create();
  constexpr long kTarget = 4000;
  auto tight = tight_window_stub(daemon_);
  auto context = deadline_context(30);
  v1::WatchProfilesRequest request;
  request.set_session_id(id);
  request.set_every(1);
  request.set_delivery(v1::DELIVERY_MODE_LATEST_FRAME);
  auto reader = tight->WatchProfiles(context.get(), request);
  v1::ProfileFrame frame;
  ASSERT_TRUE(reader->Read(&frame));
  ASSERT_TRUE(run_session(*stub_, id, kTarget).ok());
  ASSERT_TRUE(wait_for_state(*stub_, id, v1::SESSION_STATE_DONE));
  const auto after = read_after_sleep(*reader);
  EXPECT_TRUE(reader->Finish().ok());
  ASSERT_FALSE(after.frames.empty());
  EXPECT_LE(after.frames.size(), 2u);
  EXPECT_EQ(after.frames.back().step(), kTarget);
  EXPECT_EQ(after.received + after.frames.back().skipped_frames(), kTarget + 1);
}

// Lets a lossless client sleep after it has read up to `last_read`: polls until the session's step
// has stood still over several polls (the poll interval paces the wait; a deadline bounds it; it
// decides nothing) and returns the session as it then is.
v1::Session session_once_held(v1::Simulation::Stub& stub, const std::string& id) {
  v1::Session s;
  long held = -1;
  int unchanged = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (unchanged < 10 && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(milliseconds(30));
    EXPECT_TRUE(get_session(stub, id, &s).ok());
    if (s.state() != v1::SESSION_STATE_RUNNING) break;
    unchanged = s.step() == held ? unchanged + 1 : 0;
    held = s.step();
  }
  return s;
}

// Checks a lossless client held the session, then lets it read on: every frame comes, in order,
// none skipped, and the session reaches DONE.
void expect_held_then_complete(v1::Simulation::Stub& stub, const std::string& id,
                               grpc::ClientReader<v1::ProfileFrame>& reader, long last_read, long every,
                               long target, long allowed_lag_frames) {
  const auto waiting = session_once_held(stub, id);
  EXPECT_EQ(waiting.state(), v1::SESSION_STATE_RUNNING) << "the session did not wait for its lossless client";
  EXPECT_LT(waiting.step(), target);
  EXPECT_LE(waiting.step() - last_read, allowed_lag_frames * every)
      << "while the lossless client slept after reading step " << last_read << ", the session ran on to step "
      << waiting.step() << " (" << waiting.state() << ")";
  long expected = last_read;
  v1::ProfileFrame frame;
  while (reader.Read(&frame)) {
    EXPECT_EQ(frame.step(), expected + every);
    EXPECT_EQ(frame.skipped_frames(), 0);
    expected = frame.step();
  }
  EXPECT_TRUE(reader.Finish().ok());
  EXPECT_EQ(expected, target);
  EXPECT_TRUE(wait_for_state(stub, id, v1::SESSION_STATE_DONE));
}

// A lossless client with default channel settings that stops reading loses nothing: every frame
// comes, in order, none skipped. (With default settings gRPC's HTTP/2 window, grown by BDP probing,
// holds thousands of small frames, and frames in the transport count as delivered: the session is
// held back only once that window and the daemon's 8-frame queue are full. How far it runs ahead
// is the client's choice of window; the hold-back itself is checked through a tight window below.)
TEST_F(Streams, SlowLosslessClientOnDefaultSettingsMissesNoFrame) {
  const std::string id = create();
  constexpr long kTarget = 3000;
  auto context = deadline_context(30);
  auto reader = watch_profiles(context.get(), id, 1, v1::DELIVERY_MODE_EVERY_FRAME);
  v1::ProfileFrame frame;
  ASSERT_TRUE(reader->Read(&frame));
  EXPECT_EQ(frame.step(), 0);
  ASSERT_TRUE(run_session(*stub_, id, kTarget).ok());
  std::this_thread::sleep_for(milliseconds(200));  // the client is slow; nothing is decided by this
  long expected = 0;
  while (reader->Read(&frame)) {
    EXPECT_EQ(frame.step(), expected + 1);
    EXPECT_EQ(frame.skipped_frames(), 0);
    expected = frame.step();
  }
  EXPECT_TRUE(reader->Finish().ok());
  EXPECT_EQ(expected, kTarget);
  EXPECT_TRUE(wait_for_state(*stub_, id, v1::SESSION_STATE_DONE));
}

// The daemon's own lossless mechanism, seen through a tight transport window: the session waits
// within the channel's capacity (plus the frame being written, the one waiting to be queued and at
// most one in the transport) of the client, for every = 1 and every = 10 alike.
TEST_F(Streams, LosslessThroughATightWindowLagsAtMostTheChannelCapacity) {
  auto tight = tight_window_stub(daemon_);
  for (long every : {1L, 10L}) {
    const std::string id = create();
    const long target = 400 * every;
    auto context = deadline_context(30);
    v1::WatchProfilesRequest request;
    request.set_session_id(id);
    request.set_every(every);
    request.set_delivery(v1::DELIVERY_MODE_EVERY_FRAME);
    auto reader = tight->WatchProfiles(context.get(), request);
    v1::ProfileFrame frame;
    ASSERT_TRUE(reader->Read(&frame));
    ASSERT_TRUE(run_session(*stub_, id, target).ok());
    ASSERT_TRUE(reader->Read(&frame));
    expect_held_then_complete(*stub_, id, *reader, frame.step(), every, target, kChannelCapacity + 3);
  }
}

// A lossless client holding a session back must hold back only the session's steps: other clients
// still read it. GetField, Checkpoint and a new subscription answer, and Step (not allowed while
// RUNNING) is refused at once rather than waiting for the slow client. (The worker waits for the
// client outside the simulation lock, which all of these take.)
TEST_F(Streams, StalledLosslessClientDoesNotBlockOtherCalls) {
  const std::string id = create();
  auto tight = tight_window_stub(daemon_);
  auto stalled_context = deadline_context(30);
  v1::WatchProfilesRequest request;
  request.set_session_id(id);
  request.set_every(1);
  request.set_delivery(v1::DELIVERY_MODE_EVERY_FRAME);
  auto stalled = tight->WatchProfiles(stalled_context.get(), request);
  v1::ProfileFrame frame;
  ASSERT_TRUE(stalled->Read(&frame));
  ASSERT_TRUE(run_session(*stub_, id, 100'000).ok());
  const auto held = session_once_held(*stub_, id);
  ASSERT_EQ(held.state(), v1::SESSION_STATE_RUNNING);
  ASSERT_LT(held.step(), 100'000);

  {
    v1::GetFieldRequest get;
    get.set_session_id(id);
    get.add_fields("density");
    auto context = deadline_context(1);
    auto reader = stub_->GetField(context.get(), get);
    v1::FieldMessage message;
    while (reader->Read(&message)) {
    }
    const auto status = reader->Finish();
    EXPECT_TRUE(status.ok()) << "GetField: " << status.error_code() << " " << status.error_message();
  }
  {
    v1::CheckpointRequest checkpoint;
    checkpoint.set_session_id(id);
    v1::CheckpointResponse saved;
    auto context = deadline_context(1);
    const auto status = stub_->Checkpoint(context.get(), checkpoint, &saved);
    EXPECT_TRUE(status.ok()) << "Checkpoint: " << status.error_code() << " " << status.error_message();
  }
  {
    v1::StepRequest step;
    step.set_session_id(id);
    step.set_steps(1);
    v1::StepResponse stepped;
    auto context = deadline_context(1);
    EXPECT_TRUE(has_status(stub_->Step(context.get(), step, &stepped), grpc::StatusCode::FAILED_PRECONDITION,
                           "RUNNING"));
  }
  {
    auto context = deadline_context(1);
    auto second = watch_profiles(context.get(), id, 1, v1::DELIVERY_MODE_LATEST_FRAME);
    EXPECT_TRUE(second->Read(&frame)) << "a second watcher got no first frame";
    context->TryCancel();
    while (second->Read(&frame)) {
    }
    second->Finish();
  }
  // The slow client goes away; the session is free again.
  stalled_context->TryCancel();
  while (stalled->Read(&frame)) {
  }
  stalled->Finish();
  v1::PauseRequest pause;
  pause.set_session_id(id);
  v1::Session paused;
  auto context = deadline_context();
  EXPECT_TRUE(stub_->Pause(context.get(), pause, &paused).ok());
}

// Several clients on one session at once, each with its own pace and mode: two lossless profile
// clients (every 5 and every 25), a latest-frame particle client and an event client, read in
// parallel threads; each gets what its own request asked for.
TEST_F(Streams, SeveralClientsWatchOneSession) {
  const std::string id = create();
  constexpr long kTarget = 300;
  std::atomic<int> subscribed{0};
  auto lossless = [&](long every, std::vector<long>* steps) {
    auto context = deadline_context(30);
    auto reader = watch_profiles(context.get(), id, every, v1::DELIVERY_MODE_EVERY_FRAME);
    v1::ProfileFrame frame;
    if (reader->Read(&frame)) steps->push_back(frame.step());
    ++subscribed;
    while (reader->Read(&frame)) steps->push_back(frame.step());
    EXPECT_TRUE(reader->Finish().ok());
  };
  std::vector<long> every5, every25, particle_steps;
  long particle_skipped = 0;
  std::vector<v1::SessionState> states;
  std::vector<std::thread> clients;
  clients.emplace_back(lossless, 5, &every5);
  clients.emplace_back(lossless, 25, &every25);
  clients.emplace_back([&] {
    v1::WatchParticlesRequest request;
    request.set_session_id(id);
    request.set_every(1);
    auto context = deadline_context(30);
    auto reader = stub_->WatchParticles(context.get(), request);
    v1::ParticleFrame frame;
    if (reader->Read(&frame)) particle_steps.push_back(frame.step());
    ++subscribed;
    while (reader->Read(&frame)) {
      particle_steps.push_back(frame.step());
      particle_skipped = frame.skipped_frames();
    }
    EXPECT_TRUE(reader->Finish().ok());
  });
  clients.emplace_back([&] {
    v1::WatchSessionRequest request;
    request.set_session_id(id);
    auto context = deadline_context(30);
    auto reader = stub_->WatchSession(context.get(), request);
    v1::SessionEvent event;
    bool first = true;
    while (reader->Read(&event)) {
      if (event.has_state_changed()) states.push_back(event.state_changed().to());
      if (first) ++subscribed;
      first = false;
    }
    EXPECT_TRUE(reader->Finish().ok());
  });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (subscribed < 4 && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(milliseconds(5));
  EXPECT_EQ(subscribed, 4);
  EXPECT_TRUE(run_session(*stub_, id, kTarget).ok());  // no ASSERT before the threads are joined
  for (auto& t : clients) t.join();

  std::vector<long> expected5, expected25;
  for (long s = 0; s <= kTarget; s += 5) expected5.push_back(s);
  for (long s = 0; s <= kTarget; s += 25) expected25.push_back(s);
  EXPECT_EQ(every5, expected5);
  EXPECT_EQ(every25, expected25);
  ASSERT_FALSE(particle_steps.empty());
  EXPECT_EQ(particle_steps.front(), 0);
  EXPECT_EQ(particle_steps.back(), kTarget);
  EXPECT_TRUE(std::is_sorted(particle_steps.begin(), particle_steps.end()));
  EXPECT_EQ(static_cast<long>(particle_steps.size()) + particle_skipped, kTarget + 1);
  EXPECT_EQ(states, (std::vector<v1::SessionState>{v1::SESSION_STATE_CREATED, v1::SESSION_STATE_RUNNING,
                                                   v1::SESSION_STATE_DONE}));
}

// WatchParticles: one body frame for the disk, with 3 values (x, y, z) per particle for position and
// velocity, the centre of mass where the scenario put the disk at step 0, and a mean velocity; under
// its load along +x the disk moves along +x.
TEST_F(Streams, WatchParticlesReturnsTheDisksParticles) {
  const std::string id = create();
  const long particles = session(id).particles();
  ASSERT_GT(particles, 0);
  v1::WatchParticlesRequest request;
  request.set_session_id(id);
  request.set_every(50);
  request.set_delivery(v1::DELIVERY_MODE_EVERY_FRAME);
  request.add_bodies("disk");
  auto context = deadline_context(30);
  auto reader = stub_->WatchParticles(context.get(), request);
  v1::ParticleFrame first;
  ASSERT_TRUE(reader->Read(&first));
  ASSERT_TRUE(run_session(*stub_, id, 400).ok());
  EXPECT_EQ(first.step(), 0);
  ASSERT_EQ(first.bodies_size(), 1);
  const auto& disk = first.bodies(0);
  EXPECT_EQ(disk.name(), "disk");
  EXPECT_EQ(disk.position_size(), 3 * particles);
  EXPECT_EQ(disk.velocity_size(), 3 * particles);
  EXPECT_NEAR(disk.centre_of_mass().x(), 32 / 3.0, 1e-9);
  EXPECT_NEAR(disk.centre_of_mass().y(), 8.0, 1e-9);
  EXPECT_EQ(disk.mean_velocity().x(), 0);
  EXPECT_GT(disk.mass(), 0);
  double mean_x = 0;
  for (long p = 0; p < particles; ++p) mean_x += disk.position(static_cast<int>(3 * p)) / static_cast<double>(particles);
  EXPECT_NEAR(mean_x, disk.centre_of_mass().x(), 1e-9);  // equal masses: the centroid

  v1::ParticleFrame frame;
  long frames = 1;
  while (reader->Read(&frame)) {
    ++frames;
    ASSERT_EQ(frame.bodies_size(), 1);
    EXPECT_EQ(frame.bodies(0).position_size(), 3 * particles);
    EXPECT_EQ(frame.bodies(0).velocity_size(), 3 * particles);
  }
  EXPECT_TRUE(reader->Finish().ok());
  EXPECT_EQ(frames, 400 / 50 + 1);
  EXPECT_EQ(frame.step(), 400);
  EXPECT_GT(frame.bodies(0).mean_velocity().x(), 0);
  EXPECT_GT(frame.bodies(0).centre_of_mass().x(), disk.centre_of_mass().x());
}

// Deleting a running session ends all its streams (including a lossless one whose client does not
// read, which the worker is waiting on), and the session is gone: NOT_FOUND, not listed.
TEST_F(Streams, DeletingARunningSessionEndsItsStreams) {
  const std::string id = create();
  auto events_context = deadline_context(30);
  v1::WatchSessionRequest events_request;
  events_request.set_session_id(id);
  auto events = stub_->WatchSession(events_context.get(), events_request);
  auto latest_context = deadline_context(30);
  auto latest = watch_profiles(latest_context.get(), id, 1, v1::DELIVERY_MODE_LATEST_FRAME);
  auto tight = tight_window_stub(daemon_);
  auto lossless_context = deadline_context(30);
  v1::WatchProfilesRequest lossless_request;
  lossless_request.set_session_id(id);
  lossless_request.set_every(1);
  lossless_request.set_delivery(v1::DELIVERY_MODE_EVERY_FRAME);
  auto lossless = tight->WatchProfiles(lossless_context.get(), lossless_request);
  v1::SessionEvent event;
  v1::ProfileFrame frame;
  ASSERT_TRUE(events->Read(&event));
  ASSERT_TRUE(latest->Read(&frame));
  ASSERT_TRUE(lossless->Read(&frame));

  ASSERT_TRUE(run_session(*stub_, id, 1'000'000'000).ok());
  // The lossless client reads nothing more: the worker ends up waiting for it.
  const auto held = session_once_held(*stub_, id);
  EXPECT_EQ(held.state(), v1::SESSION_STATE_RUNNING);
  EXPECT_GT(held.step(), 0);
  v1::DeleteSessionRequest remove;
  remove.set_session_id(id);
  v1::DeleteSessionResponse removed;
  {
    auto context = deadline_context();
    ASSERT_TRUE(stub_->DeleteSession(context.get(), remove, &removed).ok());
  }
  // Each stream ends by itself, well before its 30 s deadline.
  while (events->Read(&event)) {
  }
  auto status = events->Finish();
  EXPECT_TRUE(status.ok()) << "WatchSession: " << status.error_code() << " " << status.error_message();
  while (latest->Read(&frame)) {
  }
  status = latest->Finish();
  EXPECT_TRUE(status.ok()) << "WatchProfiles (latest): " << status.error_code() << " " << status.error_message();
  while (lossless->Read(&frame)) {
  }
  status = lossless->Finish();
  EXPECT_TRUE(status.ok()) << "WatchProfiles (lossless): " << status.error_code() << " " << status.error_message();

  v1::Session gone;
  EXPECT_TRUE(has_status(get_session(*stub_, id, &gone), grpc::StatusCode::NOT_FOUND, "session_id"));
  v1::ListSessionsResponse list;
  auto context = deadline_context();
  ASSERT_TRUE(stub_->ListSessions(context.get(), {}, &list).ok());
  EXPECT_EQ(list.sessions_size(), 0);
}

// Two sessions of the same scenario running at once on the two workers both reach DONE, and neither
// disturbs the other: their final fields are equal bit for bit.
TEST_F(Streams, TwoSessionsRunAtOnce) {
  const std::string a = create(), b = create();
  ASSERT_NE(a, b);
  ASSERT_TRUE(run_session(*stub_, a, 800).ok());
  ASSERT_TRUE(run_session(*stub_, b, 800).ok());
  EXPECT_TRUE(wait_for_state(*stub_, a, v1::SESSION_STATE_DONE));
  EXPECT_TRUE(wait_for_state(*stub_, b, v1::SESSION_STATE_DONE));
  FieldBytes fa, fb;
  ASSERT_TRUE(read_fields(*stub_, a, &fa).ok());
  ASSERT_TRUE(read_fields(*stub_, b, &fb).ok());
  EXPECT_EQ(fa.step, 800);
  EXPECT_EQ(fb.step, 800);
  ASSERT_EQ(fa.bytes.size(), 2u);
  EXPECT_TRUE(fa.bytes == fb.bytes);
}

}  // namespace
}  // namespace lbsolid::testing
