#pragma once
// Per-owner call rates (--owner_call_rate, --owner_call_burst): a token bucket per owner, so that
// one owner's crowd of clients cannot take the daemon's CPU from the simulations and from other
// owners. A call over the rate is refused at once, before it does any work, with
// RESOURCE_EXHAUSTED naming the limit and how long until a call is allowed again (a code the
// clients retry). Streams are charged one call when they open.
#include <chrono>
#include <map>
#include <mutex>
#include <string>

#include "absl/status/status.h"

namespace lbsolid::server::auth {

struct CallRateLimits {
  double calls_per_second = 0;  // per owner; 0: no limit
  double burst = 0;             // calls an idle owner may make at once; 0: one second's worth
};

class CallRateLimiter {
 public:
  using Clock = std::chrono::steady_clock;

  explicit CallRateLimiter(CallRateLimits limits);
  bool limits_calls() const { return rate_ > 0; }

  // Takes one call from `owner`'s bucket at `now`. When it is empty: RESOURCE_EXHAUSTED, and
  // *retry_after (if given) the wait until the next call would pass.
  absl::Status charge(const std::string& owner, Clock::time_point now,
                      std::chrono::milliseconds* retry_after = nullptr);

 private:
  struct Bucket {
    double tokens;
    Clock::time_point updated;
  };
  // Drops the buckets that have refilled (their owners idle): the map holds active owners only.
  void forget_idle(Clock::time_point now);

  const double rate_, burst_;
  std::mutex mutex_;
  std::map<std::string, Bucket> buckets_;
};

}  // namespace lbsolid::server::auth
