#pragma once
// One client's stream of session events. State changes and errors are always delivered; progress
// events are thinned to the client's interval and an unread one is replaced by the newer one, so
// a slow client never makes the session wait and never sees stale progress.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

#include "lbsolid/v1/simulation.pb.h"

namespace lbsolid::server {

class EventChannel {
 public:
  using Clock = std::chrono::steady_clock;
  explicit EventChannel(std::chrono::milliseconds progress_interval) : interval_(progress_interval) {}

  void publish(const lbsolid::v1::SessionEvent& event) {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    if (event.has_progress()) {
      const auto now = Clock::now();
      if (now - last_progress_ < interval_) return;
      last_progress_ = now;
      if (!queue_.empty() && queue_.back().has_progress()) queue_.pop_back();
    }
    queue_.push_back(event);
    ready_.notify_all();
  }

  void close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    ready_.notify_all();
  }

  std::optional<lbsolid::v1::SessionEvent> next(std::chrono::milliseconds timeout, bool* finished) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [&] { return !queue_.empty() || closed_; });
    *finished = queue_.empty() && closed_;
    if (queue_.empty()) return std::nullopt;
    auto event = std::move(queue_.front());
    queue_.pop_front();
    return event;
  }

 private:
  const std::chrono::milliseconds interval_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<lbsolid::v1::SessionEvent> queue_;
  Clock::time_point last_progress_{};
  bool closed_ = false;
};

}  // namespace lbsolid::server
