// The per-owner call rate (token bucket) on a clock the test sets: the burst passes at once, the
// next call waits exactly one token's time, owners do not share a bucket, an idle owner's bucket
// refills only up to the burst, and a rate of 0 limits nothing.
#include "server/auth/call_rate_limiter.h"

#include <gtest/gtest.h>

#include <string>

namespace lbsolid::server::auth {
namespace {

using namespace std::chrono_literals;
using Clock = CallRateLimiter::Clock;

int passing(CallRateLimiter& limiter, const std::string& owner, Clock::time_point at, int tries) {
  int passed = 0;
  for (int i = 0; i < tries; ++i) passed += limiter.charge(owner, at).ok();
  return passed;
}

TEST(CallRateLimiter, TheBurstPassesThenOneCallPerToken) {
  CallRateLimiter limiter({/*calls_per_second=*/10, /*burst=*/5});
  const Clock::time_point t0{};
  EXPECT_EQ(passing(limiter, "alice", t0, 5), 5);
  std::chrono::milliseconds wait{0};
  const absl::Status refused = limiter.charge("alice", t0, &wait);
  EXPECT_EQ(refused.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(wait, 100ms);  // one token at 10 a second
  for (const char* fragment : {"owner alice", "10 calls per second", "5 at once", "--owner_call_rate", "retry in 100 ms"})
    EXPECT_NE(refused.message().find(fragment), std::string::npos) << fragment << ": " << refused.message();
  EXPECT_FALSE(limiter.charge("alice", t0 + 99ms).ok());
  EXPECT_TRUE(limiter.charge("alice", t0 + 100ms).ok());  // the refused calls took nothing
  EXPECT_EQ(passing(limiter, "bob", t0, 6), 5);           // his own bucket
}

TEST(CallRateLimiter, AnIdleOwnerRefillsOnlyToTheBurst) {
  CallRateLimiter limiter({4, 2});
  const Clock::time_point t0{};
  EXPECT_EQ(passing(limiter, "alice", t0, 2), 2);
  EXPECT_EQ(passing(limiter, "alice", t0 + 1h, 10), 2);
  // 1.5 s at 4 a second: 6 tokens, capped at 2.
  EXPECT_EQ(passing(limiter, "alice", t0 + 1h + 1500ms, 10), 2);
}

TEST(CallRateLimiter, DefaultBurstIsOneSecondsWorthAndZeroRateLimitsNothing) {
  CallRateLimiter per_second({3, 0});
  EXPECT_EQ(passing(per_second, "alice", Clock::time_point{}, 10), 3);
  CallRateLimiter slow({0.5, 0});  // under one a second: still one call at once
  EXPECT_EQ(passing(slow, "alice", Clock::time_point{}, 10), 1);
  CallRateLimiter unlimited({0, 0});
  EXPECT_FALSE(unlimited.limits_calls());
  EXPECT_EQ(passing(unlimited, "alice", Clock::time_point{}, 10000), 10000);
}

// Buckets of owners that went idle are dropped when many owners have called; an owner still
// limited keeps its state through that.
TEST(CallRateLimiter, ManyOwnersDoNotResetAnActiveOnesBucket) {
  CallRateLimiter limiter({1, 1});
  const Clock::time_point t0{};
  EXPECT_TRUE(limiter.charge("busy", t0).ok());
  for (int i = 0; i < 3000; ++i) EXPECT_TRUE(limiter.charge("owner-" + std::to_string(i), t0 + 10ms).ok());
  EXPECT_FALSE(limiter.charge("busy", t0 + 20ms).ok());
}

}  // namespace
}  // namespace lbsolid::server::auth
