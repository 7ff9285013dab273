#pragma once
// CPU priority between the daemon's own threads. On Linux the nice value belongs to each thread,
// and a thread starts with the nice value of the thread that started it. Raising it needs no
// privilege; lowering it back does (RLIMIT_NICE, CAP_SYS_NICE), so a thread that must run at the
// daemon's base priority is started before the demotion, or by one started before it.
#include <chrono>
#include <optional>

namespace lbsolid::server {

// Lowers the calling thread's priority by `increment` nice levels (0: nothing). Returns 0, or
// the errno of the refusal.
int lower_this_thread_priority(int increment);

// The calling thread's nice value.
int this_thread_nice();

// Asks the scheduler for time slices of `slice` for the calling thread and the threads it starts
// from now on (Linux 6.12 and later: sched_setattr's sched_runtime for a normal thread; the kernel
// allows 0.1 to 100 ms and needs no privilege). Under EEVDF a thread with a shorter slice has an
// earlier deadline, so when it wakes it preempts a running thread of the same or higher weight
// sooner; its share of the CPU, which the nice value sets, does not change. Returns 0; EOPNOTSUPP
// when the kernel kept its default (an older kernel ignores the request); or the errno of the
// refusal.
int shorten_this_thread_time_slice(std::chrono::microseconds slice);

// The time slice of thread `tid` (0: the calling thread) if the kernel reports one: the kernel's
// default, or what shorten_this_thread_time_slice set.
std::optional<std::chrono::nanoseconds> thread_time_slice(int tid = 0);

}  // namespace lbsolid::server
