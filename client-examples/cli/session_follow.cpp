#include "session_follow.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "message_format.h"

namespace lbsolid::cli {
namespace {

using namespace std::chrono_literals;
using lbsolid::v1::Session;

// Transient poll failures tolerated in a row before the daemon counts as gone.
constexpr int kMaxFailedPolls = 3;

ProgressSample sample_of(const Session& s) {
  ProgressSample p;
  p.step = s.step();
  p.target_step = s.target_step();
  p.steps_per_second = s.steps_per_second();
  p.mlups = s.mlups();
  if (s.steps_per_second() > 0) p.seconds_left = double(s.target_step() - s.step()) / s.steps_per_second();
  return p;
}

// What was last heard of the session, from the stream's thread and the polls.
class LastSeen {
 public:
  explicit LastSeen(Session initial) : session_(std::move(initial)) {}
  void set(const Session& s) {
    std::lock_guard lock(mutex_);
    session_ = s;
  }
  void update(const lbsolid::v1::SessionEvent& event) {
    std::lock_guard lock(mutex_);
    if (event.has_progress()) {
      session_.set_step(event.progress().step());
      session_.set_target_step(event.progress().target_step());
    } else if (event.has_state_changed()) {
      session_.set_state(event.state_changed().to());
    }
  }
  Session get() {
    std::lock_guard lock(mutex_);
    return session_;
  }

 private:
  std::mutex mutex_;
  Session session_;
};

void report_event(const lbsolid::v1::SessionEvent& event, ProgressReporter& progress) {
  if (event.has_progress()) {
    const auto& e = event.progress();
    progress.progress({e.step(), e.target_step(), e.steps_per_second(), e.mlups(), e.estimated_seconds_left()});
  } else if (event.has_state_changed()) {
    // The first event of a stream tells the current state, coming from no state.
    const auto& change = event.state_changed();
    const bool initial = change.from() == lbsolid::v1::SESSION_STATE_UNSPECIFIED;
    progress.message(event.session_id() + ": " + (initial ? "" : state_name(change.from()) + " -> ") +
                     state_name(change.to()));
  } else if (event.has_error()) {
    progress.message(event.session_id() + ": error at step " + std::to_string(event.error().step()) + ": " +
                     event.error().message());
  }
}

// One WatchSession stream read on its own thread until it ends or is cancelled.
class EventStream {
 public:
  EventStream(Daemon& daemon, const std::string& session_id, ProgressReporter& progress, LastSeen& last_seen) {
    thread_ = std::thread([this, &daemon, session_id, &progress, &last_seen] {
      lbsolid::v1::WatchSessionRequest request;
      request.set_session_id(session_id);
      request.set_progress_interval_s(1.0);
      auto reader = daemon.stub().WatchSession(&context_, request);
      lbsolid::v1::SessionEvent event;
      while (reader->Read(&event)) {
        last_seen.update(event);
        report_event(event, progress);
      }
      const grpc::Status status = reader->Finish();
      std::lock_guard lock(mutex_);
      status_ = status;
      ended_ = true;
      ended_signal_.notify_all();
    });
  }
  ~EventStream() {
    context_.TryCancel();
    if (thread_.joinable()) thread_.join();
  }
  // True if the stream ended within `wait`.
  bool wait_end(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    return ended_signal_.wait_for(lock, wait, [this] { return ended_; });
  }
  grpc::Status finish() {  // cancels if still open, waits for the thread
    context_.TryCancel();
    thread_.join();
    return status_;
  }

 private:
  grpc::ClientContext context_;
  std::mutex mutex_;
  std::condition_variable ended_signal_;
  bool ended_ = false;
  grpc::Status status_;
  std::thread thread_;
};

Session follow(Daemon& daemon, const std::string& session_id, ProgressReporter& progress, LastSeen& last_seen) {
  lbsolid::v1::GetSessionRequest get;
  get.set_session_id(session_id);
  int failed_polls = 0;
  for (;;) {
    EventStream stream(daemon, session_id, progress, last_seen);
    std::optional<Session> final_session;
    // Poll soon at first (a short run may end before the stream is registered), then every 5 s.
    auto interval = 500ms;
    while (!final_session && !stream.wait_end(interval)) {
      interval = std::min(interval * 2, std::chrono::milliseconds(5s));
      try {
        const Session s = daemon.call("GetSession", &Stub::GetSession, get);
        last_seen.set(s);
        failed_polls = 0;
        if (is_final(s.state()))
          final_session = s;
        else if (s.state() == lbsolid::v1::SESSION_STATE_RUNNING)
          progress.progress(sample_of(s));
      } catch (const RpcError& e) {
        if (e.exit_code() != kExitTransient || ++failed_polls >= kMaxFailedPolls) throw;
      }
    }
    const grpc::Status stream_status = stream.finish();
    if (final_session) return *final_session;
    // The stream ended by itself: normally because the session reached a final state.
    if (!stream_status.ok() && exit_code_for(stream_status) != kExitTransient)
      throw RpcError("WatchSession", stream_status);
    try {
      const Session s = daemon.call("GetSession", &Stub::GetSession, get);
      last_seen.set(s);
      failed_polls = 0;
      if (is_final(s.state())) return s;
    } catch (const RpcError& e) {
      if (e.exit_code() != kExitTransient || ++failed_polls >= kMaxFailedPolls) throw;
    }
    std::this_thread::sleep_for(1s);  // not final yet: watch again, without spinning
  }
}

}  // namespace

Session follow_session(Daemon& daemon, const std::string& session_id, ProgressReporter& progress,
                       Session* last_seen) {
  Session initial = last_seen ? *last_seen : Session();
  initial.set_id(session_id);
  LastSeen seen(initial);
  try {
    return follow(daemon, session_id, progress, seen);
  } catch (...) {
    if (last_seen) *last_seen = seen.get();
    throw;
  }
}

}  // namespace lbsolid::cli
