// The daemon answers calls below the priority of its simulation threads (--call_nice), so that a
// crowd of clients slows the calls rather than the runs: the workers, the autosave, the session
// builder and the fluid pool every session's steps share keep the base priority; gRPC's threads, which
// answer the calls, run lower.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <map>

#include <thread>

#include "server/session/thread_priority.h"
#include "service/daemon_process.h"
#include "service/proc_threads.h"
#include "service/refused_start.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

#if defined(__SANITIZE_THREAD__)
constexpr int kSanitizerThreads = 1;
#else
constexpr int kSanitizerThreads = 0;
#endif

// Threads of `pid` by nice value.
std::map<int, int> threads_by_nice(int pid) {
  std::map<int, int> count;
  for (const auto& thread : thread_stats(pid)) ++count[thread.nice];
  return count;
}

TEST(CallPriority, CallsAreAnsweredBelowTheSimulationThreads) {
  ScopedDirectory dir("lbsolid-priority");
  const int base = getpriority(PRIO_PROCESS, 0);  // this thread's nice: the daemon starts from it
  ASSERT_LE(base + 7, 19) << "run the test at nice 12 or less: above, the demotion cannot show";
  DaemonProcess daemon(dir.path, {"--call_nice=7", "--workers=2", "--max_fluid_threads=3"});
  auto stub = daemon.stub();
  v1::Session session;
  ASSERT_TRUE(create_session(*stub, small_channel_with_disk(), &session).ok());  // calls were answered

  // Base priority: 2 workers, the autosave thread, the session builder and the 3 threads of the
  // fluid pool (started before the demotion), and ThreadSanitizer's background thread, which the
  // main thread starts with its first thread; everything gRPC started, below, its first threads
  // included (a base-priority gRPC thread would start more at the base priority while the daemon
  // runs: its timer manager does).
  auto before = threads_by_nice(daemon.pid());
  EXPECT_EQ(before[base], 7 + kSanitizerThreads) << "threads at the base nice " << base;
  EXPECT_GE(before[base + 7], 1) << "call threads at nice " << base + 7;
  EXPECT_EQ(before.size(), 2u) << "no thread at a third priority";

  // A session with 3 fluid threads starts none: its steps run on the pool, at the base priority,
  // not at the lowered one of the call that asked.
  auto threaded = small_channel_with_disk(64, 32);
  threaded.mutable_fluid()->set_threads(3);
  ASSERT_TRUE(create_session(*stub, threaded, &session).ok());
  auto after = threads_by_nice(daemon.pid());
  EXPECT_EQ(after[base], before[base]);
}

// Whether this kernel gives a normal thread the slice it asks for (Linux 6.12+), tried on a thread
// of this test, which is then gone.
bool kernel_honours_slices() {
  bool honoured = false;
  std::thread([&] { honoured = server::shorten_this_thread_time_slice(std::chrono::microseconds(250)) == 0; }).join();
  return honoured;
}

// The call threads ask for short time slices (--call_slice), so that a call that wakes preempts a
// step sooner; the simulation threads keep the kernel's default.
TEST(CallPriority, CallThreadsRunWithTheShortSliceAndTheSimulationThreadsWithout) {
  ScopedDirectory dir("lbsolid-slice");
  const int base = getpriority(PRIO_PROCESS, 0);
  ASSERT_LE(base + 7, 19) << "run the test at nice 12 or less: above, the demotion cannot show";
  const auto default_slice = server::thread_time_slice();
  DaemonProcess daemon(dir.path, {"--call_nice=7", "--call_slice=300us", "--workers=2"});
  auto stub = daemon.stub();
  v1::Session session;
  ASSERT_TRUE(create_session(*stub, small_channel_with_disk(), &session).ok());

  int calls = 0, base_threads = 0;
  for (const auto& thread : thread_stats(daemon.pid())) {
    const auto slice = server::thread_time_slice(thread.tid);
    if (!slice) continue;  // the thread ended meanwhile
    if (thread.nice == base + 7) {
      ++calls;
      if (kernel_honours_slices())
        EXPECT_EQ(slice->count(), 300'000) << "call thread " << thread.tid;
      else
        EXPECT_EQ(*slice, default_slice) << "call thread " << thread.tid << ": an older kernel keeps its default";
    } else {
      ++base_threads;
      ASSERT_TRUE(default_slice.has_value());
      EXPECT_EQ(*slice, *default_slice) << "simulation thread " << thread.tid;
    }
  }
  EXPECT_GE(calls, 1);
  EXPECT_GE(base_threads, 2);
}

TEST(CallPriority, ASliceOutsideTheKernelsRangeIsRefusedAtStart) {
  for (const char* flag : {"--call_slice=50us", "--call_slice=1s", "--call_slice=-1ms"})
    expect_refused_start({flag}, "--call_slice: must be 0 or lie in [100us, 100ms]");
}

}  // namespace
}  // namespace lbsolid::testing
