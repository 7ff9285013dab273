// Sessions under concurrent calls, in process (no RPC): a synchronous Step against Run, Pause,
// Cancel, deletion and a client that gives up; Pause and Cancel against a worker in the middle of
// a step. Each case was a defect: a Run answered OK and then dropped, a Step that kept going for
// nobody, a Pause answered with a step the session then moved past.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <future>
#include <thread>

#include "server/session/session.h"
#include "server/session/session_manager.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

const server::auth::Identity kLocal = server::auth::local_admin();  // the one caller of a daemon without authentication

using namespace std::chrono_literals;
using server::Session;

constexpr long kEndless = 1L << 40;  // more steps than any test lets run

// A grid large enough that one step takes a sizeable time (about a millisecond): a state change
// then nearly always lands while a step is in flight, which is the case under test.
v1::Scenario slow_scenario() { return small_channel_with_disk(192, 160); }

std::shared_ptr<Session> make_session(const v1::Scenario& scenario = slow_scenario()) {
  return std::make_shared<Session>(
      server::SessionSetup{"s-test", "", scenario, server::translate_scenario(scenario), 0, "local", "", ""});
}

// Waits until the session has taken at least one step since `from`.
void wait_for_progress(const Session& session, long from = 0) {
  const auto give_up = std::chrono::steady_clock::now() + 30s;
  while (session.describe().step() <= from) {
    ASSERT_LT(std::chrono::steady_clock::now(), give_up) << "the session never advanced";
    std::this_thread::sleep_for(1ms);
  }
}

std::future<absl::StatusOr<server::StepResult>> step_in_background(std::shared_ptr<Session> session,
                                                                    std::function<bool()> abandoned = [] {
                                                                      return false;
                                                                    }) {
  return std::async(std::launch::async, [session, abandoned] {
    return session->step_now(kEndless, std::chrono::system_clock::now() + 1h, abandoned);
  });
}

TEST(SessionConcurrency, RunAndResumeAreRefusedWhileAStepCallHoldsTheSession) {
  auto session = make_session();
  auto stepping = step_in_background(session);
  wait_for_progress(*session);
  const auto run = session->run(100);
  EXPECT_EQ(run.code(), absl::StatusCode::kFailedPrecondition) << run;
  EXPECT_NE(run.message().find("Step call"), std::string::npos) << run;
  ASSERT_TRUE(session->cancel().ok());
  const auto result = stepping.get();
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_TRUE(result->interrupted);
  EXPECT_EQ(session->state(), v1::SESSION_STATE_CANCELLED);
  // The Run was refused, so nothing may have set a target beyond what the Step reached.
  EXPECT_EQ(session->describe().target_step(), session->describe().step());
}

TEST(SessionConcurrency, AStepWhoseClientGaveUpStopsAtTheNextStepBoundary) {
  auto session = make_session();
  std::atomic<bool> gone{false};
  auto stepping = step_in_background(session, [&] { return gone.load(); });
  wait_for_progress(*session);
  gone = true;
  ASSERT_EQ(stepping.wait_for(20s), std::future_status::ready) << "the abandoned Step kept stepping";
  const auto result = stepping.get();
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result->interrupted);
  EXPECT_LT(result->steps_taken, kEndless);
  // It stops where it was: the step counter does not move afterwards.
  const long stopped = session->describe().step();
  EXPECT_EQ(stopped, result->steps_taken);
  std::this_thread::sleep_for(20ms);
  EXPECT_EQ(session->describe().step(), stopped);
}

TEST(SessionConcurrency, DeletingASessionStopsItsStepCall) {
  auto session = make_session();
  auto stepping = step_in_background(session);
  wait_for_progress(*session);
  session->close();
  ASSERT_EQ(stepping.wait_for(20s), std::future_status::ready) << "the Step went on after deletion";
  EXPECT_TRUE(stepping.get()->interrupted);
}

// A manager with one worker running the session; Pause and Cancel must answer with the step at
// which it really stopped.
class StateChangeWhileRunning : public ::testing::Test {
 protected:
  StateChangeWhileRunning()
      : data_dir_("lbsolid-session-concurrency"), manager_(data_dir_.path, server::ManagerLimits{}, {"test", "test"}) {}
  ScopedDirectory data_dir_;
  server::SessionManager manager_;
};

TEST_F(StateChangeWhileRunning, PauseAnswersWithTheStepAtWhichTheSessionStopped) {
  auto session = manager_.create(slow_scenario(), "", kLocal);
  ASSERT_TRUE(session.ok()) << session.status();
  const std::string id = (*session)->id();
  ASSERT_TRUE(manager_.run(id, kEndless, kLocal).ok());
  long previous = 0;
  for (int round = 0; round < 10; ++round) {
    wait_for_progress(**session, previous);
    ASSERT_TRUE((*session)->pause().ok());
    const long answered = (*session)->describe().step();
    std::this_thread::sleep_for(10ms);  // several steps' time: a step in flight would show now
    EXPECT_EQ((*session)->describe().step(), answered) << "round " << round;
    EXPECT_EQ((*session)->state(), v1::SESSION_STATE_PAUSED);
    previous = answered;
    ASSERT_TRUE(manager_.resume(id, kLocal).ok());
  }
  ASSERT_TRUE((*session)->cancel().ok());
  const long cancelled = (*session)->describe().step();
  std::this_thread::sleep_for(10ms);
  EXPECT_EQ((*session)->describe().step(), cancelled);
}

// describe() reads the sizes of the solid while a worker steps it (a data race the TSan build
// reports; here it must at least give the values of the built session).
TEST_F(StateChangeWhileRunning, DescribeWhileRunningReadsConsistentSizes) {
  auto session = manager_.create(slow_scenario(), "", kLocal);
  ASSERT_TRUE(session.ok());
  const auto before = (*session)->describe();
  ASSERT_TRUE(manager_.run((*session)->id(), kEndless, kLocal).ok());
  for (int k = 0; k < 200; ++k) {
    const auto now = (*session)->describe();
    EXPECT_EQ(now.particles(), before.particles());
    EXPECT_EQ(now.fluid_bytes(), before.fluid_bytes());
  }
  ASSERT_TRUE((*session)->cancel().ok());
}

}  // namespace
}  // namespace lbsolid::testing
