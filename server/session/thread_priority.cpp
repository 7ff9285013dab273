#include "server/session/thread_priority.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

namespace lbsolid::server {

namespace {
// PRIO_PROCESS with a thread id addresses that one thread (Linux).
id_t this_thread_id() { return static_cast<id_t>(syscall(SYS_gettid)); }

// struct sched_attr of <linux/sched/types.h> as of its first version (48 bytes), which every
// kernel with sched_setattr accepts; glibc 2.36 has no wrapper for it.
struct SchedAttr {
  std::uint32_t size = sizeof(SchedAttr);
  std::uint32_t sched_policy = 0;
  std::uint64_t sched_flags = 0;
  std::int32_t sched_nice = 0;
  std::uint32_t sched_priority = 0;
  std::uint64_t sched_runtime = 0;  // a normal thread's slice, in ns (Linux 6.12+)
  std::uint64_t sched_deadline = 0;
  std::uint64_t sched_period = 0;
};

bool read_attr(int tid, SchedAttr* attr) {
  return syscall(SYS_sched_getattr, tid, attr, sizeof(SchedAttr), 0) == 0;
}
}  // namespace

int this_thread_nice() {
  errno = 0;  // -1 is a valid nice value: errno tells an error apart
  const int nice = getpriority(PRIO_PROCESS, this_thread_id());
  return errno == 0 ? nice : 0;
}

int lower_this_thread_priority(int increment) {
  if (increment <= 0) return 0;
  return setpriority(PRIO_PROCESS, this_thread_id(), this_thread_nice() + increment) == 0 ? 0 : errno;
}

int shorten_this_thread_time_slice(std::chrono::microseconds slice) {
  SchedAttr attr;
  if (!read_attr(0, &attr)) return errno;
  attr.size = sizeof(SchedAttr);
  attr.sched_flags = 0;
  // The same policy and nice value: only the slice changes.
  attr.sched_runtime = static_cast<std::uint64_t>(std::chrono::nanoseconds(slice).count());
  if (syscall(SYS_sched_setattr, 0, &attr, 0) != 0) return errno;
  const auto now = thread_time_slice();
  return now && *now == std::chrono::nanoseconds(slice) ? 0 : EOPNOTSUPP;
}

std::optional<std::chrono::nanoseconds> thread_time_slice(int tid) {
  SchedAttr attr;
  if (!read_attr(tid, &attr) || attr.sched_runtime == 0) return std::nullopt;
  return std::chrono::nanoseconds(attr.sched_runtime);
}

}  // namespace lbsolid::server
