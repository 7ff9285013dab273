#include "server/auth/call_rate_limiter.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace lbsolid::server::auth {

namespace {

// Past this many owners with a bucket, the full ones are dropped before another is added.
constexpr std::size_t kPruneAbove = 1024;

}  // namespace

CallRateLimiter::CallRateLimiter(CallRateLimits limits)
    : rate_(std::max(0.0, limits.calls_per_second)),
      burst_(limits.burst > 0 ? std::max(1.0, limits.burst) : std::max(1.0, rate_)) {}

void CallRateLimiter::forget_idle(Clock::time_point now) {
  for (auto it = buckets_.begin(); it != buckets_.end();) {
    const double idle_s = std::chrono::duration<double>(now - it->second.updated).count();
    if (it->second.tokens + idle_s * rate_ >= burst_)
      it = buckets_.erase(it);
    else
      ++it;
  }
}

absl::Status CallRateLimiter::charge(const std::string& owner, Clock::time_point now,
                                     std::chrono::milliseconds* retry_after) {
  if (rate_ <= 0) return absl::OkStatus();
  std::lock_guard lock(mutex_);
  auto it = buckets_.find(owner);
  if (it == buckets_.end()) {
    if (buckets_.size() >= kPruneAbove) forget_idle(now);
    it = buckets_.emplace(owner, Bucket{burst_, now}).first;
  }
  Bucket& bucket = it->second;
  const double elapsed_s = std::max(0.0, std::chrono::duration<double>(now - bucket.updated).count());
  bucket.tokens = std::min(burst_, bucket.tokens + elapsed_s * rate_);
  bucket.updated = std::max(bucket.updated, now);
  if (bucket.tokens >= 1) {
    bucket.tokens -= 1;
    return absl::OkStatus();
  }
  const auto wait = std::chrono::milliseconds(static_cast<long>(std::ceil((1 - bucket.tokens) / rate_ * 1000)));
  if (retry_after) *retry_after = wait;
  return absl::ResourceExhaustedError(absl::StrFormat(
      "owner %s: over the call rate limit of %g calls per second, %g at once (--owner_call_rate, "
      "--owner_call_burst); retry in %d ms",
      owner, rate_, burst_, wait.count()));
}

}  // namespace lbsolid::server::auth
