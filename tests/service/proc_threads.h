#pragma once
// The threads of a process as Linux shows them in /proc/<pid>/task/*/stat: each one's nice value
// (field 19) and the CPU time it has used (fields 14 and 15, user and system).
#include <vector>

namespace lbsolid::testing {

struct ThreadStat {
  int tid = 0;
  int nice = 0;
  double cpu_seconds = 0;
};

// Threads that end while they are read are left out.
std::vector<ThreadStat> thread_stats(int pid);

// CPU seconds the whole process has used, its ended threads included (/proc/<pid>/stat).
double process_cpu_seconds(int pid);

}  // namespace lbsolid::testing
