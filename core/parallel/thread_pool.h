#pragma once
// A fixed set of worker threads that split a loop over rows; the calling thread takes a share,
// so a pool of size 1 runs everything inline with no synchronisation.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace lbsolid::parallel {

class ThreadPool {
 public:
  // Throws std::system_error if a thread cannot start (the ones started are stopped first).
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }

  // Calls fn(begin, end) on contiguous, disjoint parts of [0, n) and returns when all are done.
  void parallel_for(long n, const std::function<void(long, long)>& fn);

 private:
  void worker_loop(int index);
  void stop_and_join();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::condition_variable done_;
  const std::function<void(long, long)>* job_ = nullptr;
  long job_size_ = 0;
  long generation_ = 0;
  int pending_ = 0;
  bool stopping_ = false;
};

}  // namespace lbsolid::parallel
