#pragma once
// One thread that runs the closures handed to it, one at a time, in order, while the caller
// waits. The session manager builds sessions on it: allocating and initialising a large session
// is simulation work, done at the daemon's base priority, which this thread keeps while the
// threads that answer calls run lower (thread_priority.h).
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>

namespace lbsolid::server {

class SerialExecutor {
 public:
  SerialExecutor();
  ~SerialExecutor();  // runs what is queued, then stops
  SerialExecutor(const SerialExecutor&) = delete;
  SerialExecutor& operator=(const SerialExecutor&) = delete;

  // Runs fn() on the executor's thread and returns its result (or rethrows its exception).
  template <class Fn>
  auto run(Fn fn) -> decltype(fn()) {
    std::packaged_task<decltype(fn())()> task(std::move(fn));
    auto result = task.get_future();
    post([&task] { task(); });
    return result.get();
  }

 private:
  void post(std::function<void()> job);
  void loop();

  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace lbsolid::server
