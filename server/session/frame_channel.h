#pragma once
// One client's stream of frames from a session (velocity profiles, particle positions), with the
// delivery mode it asked for:
//   every frame  lossless; publish() always queues, and the session's worker does not take its
//                next step while the client is `capacity` frames behind (wait_for_room(), called
//                outside the simulation lock, so other calls on the session go on meanwhile),
//   latest frame the worker never waits; an unread frame is replaced by the newer one and counted,
//                and each delivered frame carries the count of frames this client missed so far.
// "Delivered" means handed to gRPC: frames already in the transport's flow-control window count as
// read (a client wanting a tight bound keeps that window small; see the README).
// The worker publishes; the stream handler takes frames until the channel is closed (the session
// ended) or the client goes away (detach: the worker stops waiting for it).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

namespace lbsolid::server {

enum class Delivery { kEveryFrame, kLatestFrame };

template <class Frame>
class FrameChannel {
 public:
  FrameChannel(Delivery delivery, long every, std::size_t capacity = 8)
      : delivery_(delivery), every_(every), capacity_(capacity) {}

  long every() const { return every_; }
  bool due(long step) const { return first_frame_wanted_ || step % every_ == 0; }

  // A client that joins a running session gets its first frame from the worker, at the next step
  // boundary (or when the session pauses), instead of stopping the run to read the state.
  void want_first_frame() { first_frame_wanted_ = true; }
  bool first_frame_wanted() const { return first_frame_wanted_; }
  // True once the first frame is published (or the stream has ended) within `timeout`.
  bool wait_for_first_frame(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return ready_.wait_for(lock, timeout, [&] { return !first_frame_wanted_ || closed_ || detached_; });
  }

  // Worker side: queues the frame (latest mode: in place of an unread one). Never waits.
  void publish(Frame frame) {
    std::lock_guard lock(mutex_);
    first_frame_wanted_ = false;
    if (detached_ || closed_) return;
    if (delivery_ == Delivery::kLatestFrame && !queue_.empty()) {
      queue_.clear();
      ++skipped_;
    }
    queue_.push_back(std::move(frame));
    ready_.notify_all();
  }

  // Worker side: true while a lossless client is `capacity` frames behind.
  bool full() const {
    std::lock_guard lock(mutex_);
    return full_locked();
  }

  // Worker side: waits until the client has room, goes away, or `timeout` passes; true if room.
  bool wait_for_room(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    return room_.wait_for(lock, timeout, [&] { return !full_locked(); });
  }

  // Worker side: no more frames will come; the client gets those queued, then the end.
  void close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    ready_.notify_all();
    room_.notify_all();
  }

  // Client side: the next frame, or nothing after `timeout` (to let the handler notice a cancelled
  // call) or at the end (*finished is then true).
  std::optional<Frame> next(std::chrono::milliseconds timeout, bool* finished) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [&] { return !queue_.empty() || closed_; });
    *finished = queue_.empty() && closed_;
    if (queue_.empty()) return std::nullopt;
    Frame frame = std::move(queue_.front());
    queue_.pop_front();
    frame.set_skipped_frames(skipped_);
    room_.notify_all();
    return frame;
  }

  // Client side: the client has gone; never wait for it again.
  void detach() {
    std::lock_guard lock(mutex_);
    detached_ = true;
    queue_.clear();
    room_.notify_all();
  }

  bool lossless() const { return delivery_ == Delivery::kEveryFrame; }

  bool detached() const {
    std::lock_guard lock(mutex_);
    return detached_;
  }

 private:
  bool full_locked() const {
    return delivery_ == Delivery::kEveryFrame && !detached_ && !closed_ && queue_.size() >= capacity_;
  }

  const Delivery delivery_;
  const long every_;
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::deque<Frame> queue_;
  long skipped_ = 0;
  std::atomic<bool> first_frame_wanted_{false};
  bool closed_ = false;
  bool detached_ = false;
};

}  // namespace lbsolid::server
