#pragma once
// CPU priority between the daemon's own threads. On Linux the nice value belongs to each thread,
// and a thread starts with the nice value of the thread that started it. Raising it needs no
// privilege; lowering it back does (RLIMIT_NICE, CAP_SYS_NICE), so a thread that must run at the
// daemon's base priority is started before the demotion, or by one started before it.
namespace lbsolid::server {

// Lowers the calling thread's priority by `increment` nice levels (0: nothing). Returns 0, or
// the errno of the refusal.
int lower_this_thread_priority(int increment);

// The calling thread's nice value.
int this_thread_nice();

}  // namespace lbsolid::server
