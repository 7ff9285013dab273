// A diverging session must fail alone: it ends FAILED with "step N: <cause>" (the stability monitor
// names the quantity, here the Mach number), its watchers get an Error event and the state change,
// and a session running beside it on the same daemon reaches DONE untouched. The daemon answers on
// afterwards. (session.h: "nothing here can take the daemon down".)
#include <gtest/gtest.h>

#include <thread>

#include "service/daemon_process.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

class FailureIsolation : public ::testing::Test {
 protected:
  FailureIsolation() : data_dir_("lbsolid-failure"), daemon_(data_dir_.path), stub_(daemon_.stub()) {}

  std::string create(const v1::Scenario& scenario) {
    v1::Session session;
    const auto status = create_session(*stub_, scenario, &session);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return session.id();
  }

  ScopedDirectory data_dir_;
  DaemonProcess daemon_;
  std::unique_ptr<v1::Simulation::Stub> stub_;
};

TEST_F(FailureIsolation, DivergingSessionFailsAloneWithAnErrorEvent) {
  // The healthy session first, with a run long enough to still be going when the other fails
  // (the diverging one fails within some 20 steps).
  constexpr long kHealthyTarget = 3000;
  const std::string healthy = create(small_channel_with_disk());
  const std::string diverging = create(diverging_box());

  v1::WatchSessionRequest watch;
  watch.set_session_id(diverging);
  watch.set_progress_interval_s(0.05);
  auto context = deadline_context(30);
  auto reader = stub_->WatchSession(context.get(), watch);
  v1::SessionEvent event;
  ASSERT_TRUE(reader->Read(&event));  // the current state: subscribed before anything happens

  ASSERT_TRUE(run_session(*stub_, healthy, kHealthyTarget).ok());
  ASSERT_TRUE(run_session(*stub_, diverging, 100'000).ok());

  std::vector<v1::Error> errors;
  std::vector<v1::SessionState> states;
  while (reader->Read(&event)) {
    if (event.has_error()) errors.push_back(event.error());
    if (event.has_state_changed()) states.push_back(event.state_changed().to());
  }
  const auto status = reader->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();

  v1::Session failed;
  ASSERT_TRUE(get_session(*stub_, diverging, &failed).ok());
  EXPECT_EQ(failed.state(), v1::SESSION_STATE_FAILED);
  EXPECT_EQ(failed.message().rfind("step ", 0), 0u) << failed.message();
  EXPECT_NE(failed.message().find("Mach number"), std::string::npos) << failed.message();
  EXPECT_EQ(failed.message().rfind("step " + std::to_string(failed.step()) + ": ", 0), 0u) << failed.message();
  EXPECT_GT(failed.step(), 0);
  EXPECT_LT(failed.step(), 100);  // caught at a check, long before the target
  EXPECT_EQ(failed.step() % 10, 0);  // the scenario's check_interval

  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].step(), failed.step());
  EXPECT_NE(errors[0].message().find("Mach number"), std::string::npos) << errors[0].message();
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states.back(), v1::SESSION_STATE_FAILED);  // the stream ends after that change

  // The healthy session was running the whole time and completes normally.
  EXPECT_TRUE(wait_for_state(*stub_, healthy, v1::SESSION_STATE_DONE));
  v1::Session done;
  ASSERT_TRUE(get_session(*stub_, healthy, &done).ok());
  EXPECT_EQ(done.step(), kHealthyTarget);
  EXPECT_TRUE(done.message().empty()) << done.message();

  // FAILED is final, but the state stays readable.
  EXPECT_TRUE(has_status(run_session(*stub_, diverging, 10), grpc::StatusCode::FAILED_PRECONDITION, "FAILED"));
  FieldBytes fields;
  ASSERT_TRUE(read_fields(*stub_, diverging, &fields).ok());
  EXPECT_EQ(fields.step, failed.step());

  // And the daemon still answers, and still takes new work.
  v1::ServerInfo info;
  auto info_context = deadline_context();
  ASSERT_TRUE(stub_->GetServerInfo(info_context.get(), {}, &info).ok());
  EXPECT_EQ(info.sessions(), 2);
  const std::string after = create(small_channel_with_disk());
  ASSERT_TRUE(run_session(*stub_, after, 100).ok());
  EXPECT_TRUE(wait_for_state(*stub_, after, v1::SESSION_STATE_DONE));
}

// A watcher that subscribes after the failure gets the final state at once and its stream ends:
// nobody waits forever on a session that will not move again.
TEST_F(FailureIsolation, WatchingAFailedSessionEndsAtOnce) {
  const std::string diverging = create(diverging_box());
  ASSERT_TRUE(run_session(*stub_, diverging, 100'000).ok());
  ASSERT_TRUE(wait_for_state(*stub_, diverging, v1::SESSION_STATE_FAILED));
  v1::WatchSessionRequest watch;
  watch.set_session_id(diverging);
  auto context = deadline_context(10);
  auto reader = stub_->WatchSession(context.get(), watch);
  v1::SessionEvent event;
  ASSERT_TRUE(reader->Read(&event));
  ASSERT_TRUE(event.has_state_changed());
  EXPECT_EQ(event.state_changed().to(), v1::SESSION_STATE_FAILED);
  EXPECT_FALSE(reader->Read(&event));
  EXPECT_TRUE(reader->Finish().ok());

  v1::WatchProfilesRequest profiles;
  profiles.set_session_id(diverging);
  profiles.set_every(1);
  auto profiles_context = deadline_context(10);
  auto frames = stub_->WatchProfiles(profiles_context.get(), profiles);
  v1::ProfileFrame frame;
  ASSERT_TRUE(frames->Read(&frame));  // the state it failed in
  EXPECT_FALSE(frames->Read(&frame));
  EXPECT_TRUE(frames->Finish().ok());
}

}  // namespace
}  // namespace lbsolid::testing
