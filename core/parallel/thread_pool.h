#pragma once
// A fixed set of worker threads that split loops over rows. Several threads may call
// parallel_for at once (sessions of one daemon share one pool): each call is a job cut into its
// own number of parts; the caller works through its job's parts, idle pool threads take parts of
// the oldest unfinished job, and the call returns when all its parts are done. A pool of size 1
// runs every job on its caller with no synchronisation.
//
// Results do not depend on which thread ran a part: the parts are fixed by (n, parts) alone.
//
// A pool thread that finds no work stays awake for kStayAwake (yielding) before it sleeps: the
// jobs of one simulation step come microseconds apart, and a thread woken from sleep for each
// came too late for a short job, whose caller had meanwhile run every part itself. For the same
// reason a caller done with its parts watches for the others' end (kWatchForEnd) before sleeping.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace lbsolid::parallel {

class ThreadPool {
 public:
  // `threads` counts the caller: threads - 1 are started. Throws std::system_error if a thread
  // cannot start (the ones started are stopped first).
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  static constexpr std::chrono::microseconds kStayAwake{200};
  // A caller whose parts are done watches for the others' end this long before it sleeps.
  static constexpr std::chrono::microseconds kWatchForEnd{100};

  int size() const { return static_cast<int>(workers_.size()) + 1; }

  // Calls fn(begin, end) on `parts` contiguous, disjoint, near-equal parts of [0, n) (fewer when
  // n is smaller) and returns when all are done.
  void parallel_for(long n, int parts, const std::function<void(long, long)>& fn);
  // One part per thread of the pool.
  void parallel_for(long n, const std::function<void(long, long)>& fn) { parallel_for(n, size(), fn); }

 private:
  struct Job {
    const std::function<void(long, long)>* fn;
    long n;
    int parts;
    int next_part = 0;  // the first part nobody has taken
    std::atomic<int> unfinished;  // parts not yet done
  };
  // Takes the next part of `job` (the mutex held); removes the job from the queue with its last.
  int take_part_locked(Job& job);
  void run_part(Job& job, int part);  // runs it, then counts it done (takes the mutex)
  void worker_loop();
  // Returns once a job is queued or kStayAwake has passed.
  void stay_awake_for_work() const;
  void stop_and_join();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable work_;  // a job was queued, or the pool stops
  std::condition_variable done_;  // a job's last part finished
  std::deque<Job*> queue_;        // jobs with parts nobody has taken, oldest first
  std::atomic<int> queued_{0};    // queue_.size(), read without the mutex by threads staying awake
  bool stopping_ = false;
};

}  // namespace lbsolid::parallel
