#pragma once
// One client's stream of frames from a session (velocity profiles, particle positions), with the
// delivery mode it asked for:
//   every frame  lossless; when the client is `capacity` frames behind, the session's worker waits
//                for it (the slowest lossless client sets the pace),
//   latest frame the worker never waits; an unread frame is replaced by the newer one and counted,
//                and each delivered frame carries the count of frames this client missed so far.
// The worker publishes; the stream handler takes frames until the channel is closed (the session
// ended) or the client goes away (detach: the worker stops waiting for it).
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
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
  bool due(long step) const { return step % every_ == 0; }

  // Worker side. In lossless mode waits while the client is `capacity` frames behind, unless it
  // detaches or `abandon()` turns true (the session is pausing or going away): then the frame is
  // queued anyway, so nothing is lost, and the worker goes on.
  void publish(Frame frame, const std::function<bool()>& abandon) {
    std::unique_lock lock(mutex_);
    if (detached_ || closed_) return;
    if (delivery_ == Delivery::kLatestFrame) {
      if (!queue_.empty()) {
        queue_.clear();
        ++skipped_;
      }
    } else {
      while (queue_.size() >= capacity_ && !detached_ && !abandon())
        room_.wait_for(lock, std::chrono::milliseconds(20));
      if (detached_) return;
    }
    queue_.push_back(std::move(frame));
    ready_.notify_all();
  }

  // Worker side: no more frames will come; the client gets those queued, then the end.
  void close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    ready_.notify_all();
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

  bool detached() const {
    std::lock_guard lock(mutex_);
    return detached_;
  }

 private:
  const Delivery delivery_;
  const long every_;
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::deque<Frame> queue_;
  long skipped_ = 0;
  bool closed_ = false;
  bool detached_ = false;
};

}  // namespace lbsolid::server
