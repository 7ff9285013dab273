#include "server/session/thread_priority.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>

namespace lbsolid::server {

namespace {
// PRIO_PROCESS with a thread id addresses that one thread (Linux).
id_t this_thread_id() { return static_cast<id_t>(syscall(SYS_gettid)); }
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

}  // namespace lbsolid::server
