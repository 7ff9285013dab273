// 64 clients on a real daemon for a few seconds beside two running sessions (load_driver.h):
// every call succeeds. The latency and steps/s figures are printed, not asserted: speed is
// measured by lbsolid-load (tests/bench/load_bench.cpp), never by a timed test.
#include <gtest/gtest.h>

#include <iostream>

#include "service/load_driver.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

TEST(Load, SixtyFourClientsMixingCallsGetNoErrors) {
  const ScopedDirectory dir("lbsolid-load");
  DaemonProcess daemon(dir.path, {"--max_sessions=256", "--autosave_interval=0"});
  LoadOptions options;
  options.seconds = 3;
  options.background_nx = 96;
  options.background_ny = 48;
  const auto report = run_load(daemon, options);
  std::cout << describe(report, options);
  EXPECT_EQ(report.errors, 0);
  EXPECT_GT(report.control_calls, options.clients);  // every client got through its cycle
  EXPECT_EQ(daemon.stop(SIGTERM), 0);
}

}  // namespace
}  // namespace lbsolid::testing
