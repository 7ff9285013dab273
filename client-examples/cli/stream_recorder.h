#pragma once
// One server stream read to the end on its own thread, each frame handed to a sink (submit --out
// records particles and profiles this way, lossless). In EVERY_FRAME mode the run waits for this
// reader, so the thread never blocks on anything but the stream and the sink, and a sink that
// fails cancels the stream at once rather than stall the session.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace lbsolid::cli {

template <class Frame>
class StreamRecorder {
 public:
  using Open = std::function<std::unique_ptr<grpc::ClientReader<Frame>>(grpc::ClientContext*)>;
  using Sink = std::function<void(const Frame&)>;  // may throw: the message becomes error()

  StreamRecorder(Open open, Sink sink) : sink_(std::move(sink)) {
    last_activity_ = std::chrono::steady_clock::now();
    thread_ = std::thread([this, open = std::move(open)] { read_all(open); });
  }
  ~StreamRecorder() { stop(); }
  StreamRecorder(const StreamRecorder&) = delete;
  StreamRecorder& operator=(const StreamRecorder&) = delete;

  // Waits until the first frame arrived or the stream ended, at most `wait`.
  void wait_first_frame(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, wait, [this] { return frames_ > 0 || ended_; });
  }

  // Lets the stream end by itself (it does when the session is final) while frames keep
  // arriving; cancels it once `idle` passes without one.
  void finish(std::chrono::milliseconds idle) {
    std::unique_lock lock(mutex_);
    while (!ended_) {
      const auto deadline = last_activity_ + idle;
      if (changed_.wait_until(lock, deadline, [this] { return ended_; })) break;
      if (std::chrono::steady_clock::now() >= last_activity_ + idle) {
        idle_cancelled_ = true;
        context_.TryCancel();
        break;
      }
    }
    lock.unlock();
    stop();
  }

  void stop() {  // cancels the stream if it is still open and waits for the thread
    context_.TryCancel();
    if (thread_.joinable()) thread_.join();
  }

  // Valid after finish()/stop().
  long frames() const { return frames_; }
  const std::string& error() const { return error_; }    // the sink's failure, if any
  const grpc::Status& status() const { return status_; }  // CANCELLED when cancelled here
  bool idle_cancelled() const { return idle_cancelled_; }

 private:
  void read_all(const Open& open) {
    auto reader = open(&context_);
    Frame frame;
    bool failed = false;
    while (reader->Read(&frame)) {
      try {
        if (!failed) sink_(frame);
      } catch (const std::exception& e) {
        failed = true;
        std::lock_guard lock(mutex_);
        error_ = e.what();
        context_.TryCancel();
      }
      std::lock_guard lock(mutex_);
      ++frames_;
      last_activity_ = std::chrono::steady_clock::now();
      changed_.notify_all();
    }
    const grpc::Status status = reader->Finish();
    std::lock_guard lock(mutex_);
    status_ = status;
    ended_ = true;
    changed_.notify_all();
  }

  Sink sink_;
  grpc::ClientContext context_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::chrono::steady_clock::time_point last_activity_;
  long frames_ = 0;
  bool ended_ = false;
  bool idle_cancelled_ = false;
  std::string error_;
  grpc::Status status_;
  std::thread thread_;  // last: started once everything above exists
};

}  // namespace lbsolid::cli
