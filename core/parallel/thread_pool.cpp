#include "parallel/thread_pool.h"

#include <algorithm>

namespace lbsolid::parallel {

ThreadPool::ThreadPool(int threads) {
  try {
    for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { worker_loop(); });
  } catch (...) {
    stop_and_join();  // threads that did start must not outlive the failed constructor
    throw;
  }
}

ThreadPool::~ThreadPool() { stop_and_join(); }

void ThreadPool::stop_and_join() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  work_.notify_all();
  for (auto& t : workers_) t.join();
  workers_.clear();
}

int ThreadPool::take_part_locked(Job& job) {
  const int part = job.next_part++;
  if (job.next_part == job.parts) {
    queue_.erase(std::find(queue_.begin(), queue_.end(), &job));
    queued_.store(static_cast<int>(queue_.size()), std::memory_order_relaxed);
  }
  return part;
}

void ThreadPool::run_part(Job& job, int part) {
  // Part k of `parts` near-equal shares of [0, n).
  (*job.fn)(job.n * part / job.parts, job.n * (part + 1) / job.parts);
  // The job is not touched after the count: its caller may see it reach zero and return at once.
  if (job.unfinished.fetch_sub(1, std::memory_order_acq_rel) == 1) {
    // Under the mutex: a caller that found parts unfinished under it is waiting by now, and woken.
    std::lock_guard lock(mutex_);
    done_.notify_all();
  }
}

void ThreadPool::parallel_for(long n, int parts, const std::function<void(long, long)>& fn) {
  parts = static_cast<int>(std::clamp<long>(parts, 1, std::max(n, 1L)));
  if (workers_.empty() || parts == 1) {
    fn(0, n);  // the parts in sequence would compute the same
    return;
  }
  Job job{&fn, n, parts, 0, parts};
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(&job);
    queued_.store(static_cast<int>(queue_.size()), std::memory_order_relaxed);
  }
  for (int i = 1; i < parts; ++i) work_.notify_one();  // the caller takes a part itself
  // The caller works on its own job: it finishes even when every pool thread is busy elsewhere.
  for (;;) {
    int part;
    {
      std::lock_guard lock(mutex_);
      if (job.next_part == job.parts) break;
      part = take_part_locked(job);
    }
    run_part(job, part);
  }
  // Watched first, then slept on: a caller put to sleep and woken again took 13-16 us a job on
  // this project's VM against 2.5-7 watching (docs/performance.md), where a coupled step runs
  // about 7 jobs of 50-500 us.
  const auto until = std::chrono::steady_clock::now() + kWatchForEnd;
  while (job.unfinished.load(std::memory_order_acquire) != 0 && std::chrono::steady_clock::now() < until)
    std::this_thread::yield();  // (a thread with work on this core gets it)
  if (job.unfinished.load(std::memory_order_acquire) == 0) return;
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return job.unfinished.load(std::memory_order_acquire) == 0; });
}

void ThreadPool::stay_awake_for_work() const {
  const auto until = std::chrono::steady_clock::now() + kStayAwake;
  while (queued_.load(std::memory_order_relaxed) == 0 && std::chrono::steady_clock::now() < until)
    std::this_thread::yield();
}

void ThreadPool::worker_loop() {
  for (;;) {
    Job* job;
    int part;
    stay_awake_for_work();  // the queue itself is read under the mutex below
    {
      std::unique_lock lock(mutex_);
      work_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      job = queue_.front();
      part = take_part_locked(*job);
    }
    run_part(*job, part);
  }
}

}  // namespace lbsolid::parallel
