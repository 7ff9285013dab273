// Bad input to lbsolidd: every refusal must carry the right gRPC status code (simulation.proto:
// INVALID_ARGUMENT, NOT_FOUND, RESOURCE_EXHAUSTED, FAILED_PRECONDITION, ALREADY_EXISTS) and a
// message that names the offending field, so a client can point its user at it. After each test the
// daemon must still answer GetServerInfo: no bad request may take it down.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <limits>

#include "io/api/scenario_translation.h"
#include "service/daemon_process.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

using grpc::StatusCode;

// Reads a server stream to its end and returns how it ended.
template <class Message, class Reader>
grpc::Status drain(Reader& reader) {
  Message message;
  while (reader->Read(&message)) {
  }
  return reader->Finish();
}

class BadInput : public ::testing::Test {
 protected:
  explicit BadInput(std::vector<std::string> flags = {"--max_sync_steps=50"})
      : data_dir_("lbsolid-bad-input"), daemon_(data_dir_.path, std::move(flags)), stub_(daemon_.stub()) {}

  // Whatever a test sent, the daemon is still there and answers.
  void TearDown() override {
    v1::ServerInfo info;
    auto context = deadline_context();
    const auto status = stub_->GetServerInfo(context.get(), {}, &info);
    EXPECT_TRUE(status.ok()) << "the daemon no longer answers: " << status.error_message();
    EXPECT_EQ(info.api_version(), "lbsolid.v1");
  }

  grpc::Status create(const v1::Scenario& scenario, v1::Session* session = nullptr, const std::string& request_id = {}) {
    v1::Session ignored;
    return create_session(*stub_, scenario, session ? session : &ignored, request_id);
  }

  // A valid session in state CREATED.
  std::string created_session() {
    v1::Session session;
    const auto status = create(small_channel_with_disk(), &session);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return session.id();
  }

  ScopedDirectory data_dir_;
  DaemonProcess daemon_;
  std::unique_ptr<v1::Simulation::Stub> stub_;
};

// The wire carries only well-formed messages, so malformed scenario text can only come from a file;
// the parser the CLI and the daemon's checkpoints share must say where the text breaks, as
// "line L column C", for text format and for JSON alike.
TEST(ScenarioText, MalformedTextNamesLineAndColumn) {
  v1::Scenario scenario;
  std::string error;
  EXPECT_FALSE(server::parse_scenario_text("name: \"broken\"\ndomain { nx: 32 ny: }\n", &scenario, &error));
  EXPECT_NE(error.find("line 2 column "), std::string::npos) << error;

  error.clear();
  EXPECT_FALSE(server::parse_scenario_text("name: \"typo\"\nfluid { omgea: 1.2 }\n", &scenario, &error));
  EXPECT_NE(error.find("line 2 column "), std::string::npos) << error;
  EXPECT_NE(error.find("omgea"), std::string::npos) << error;

  error.clear();
  EXPECT_FALSE(server::parse_scenario_text("{\n  \"name\": \"json\",\n  \"domain\": {\"nx\": 32,, \"ny\": 16}\n}\n",
                                           &scenario, &error));
  EXPECT_NE(error.find("line 3 column "), std::string::npos) << error;

  // And a good text still parses, so the errors above are about the breakage.
  error.clear();
  EXPECT_TRUE(server::parse_scenario_text("name: \"fine\"\ndomain { nx: 32 ny: 16 }\n", &scenario, &error)) << error;
  EXPECT_EQ(scenario.domain().nx(), 32);
}

// A well-formed message whose content the daemon must refuse: no scenario at all, an enum value
// this version does not know (proto3 enums are open, so it arrives intact), a body without a shape.
TEST_F(BadInput, ScenarioTheDaemonCannotBuildIsRefusedNamingTheField) {
  v1::CreateSessionRequest empty;
  v1::Session session;
  auto context = deadline_context();
  EXPECT_TRUE(has_status(stub_->CreateSession(context.get(), empty, &session), StatusCode::INVALID_ARGUMENT, "scenario"));

  auto unknown_lattice = small_channel_with_disk();
  unknown_lattice.set_lattice(static_cast<v1::Lattice>(42));
  EXPECT_TRUE(has_status(create(unknown_lattice), StatusCode::INVALID_ARGUMENT, "scenario.lattice"));

  auto shapeless = small_channel_with_disk();
  shapeless.mutable_bodies(0)->set_shape(v1::BODY_SHAPE_UNSPECIFIED);
  const auto status = create(shapeless);
  EXPECT_TRUE(has_status(status, StatusCode::INVALID_ARGUMENT, "scenario.bodies[0]"));
  EXPECT_NE(status.error_message().find("shape"), std::string::npos) << status.error_message();

  // Nothing was created by the refused calls.
  v1::ListSessionsResponse list;
  auto list_context = deadline_context();
  ASSERT_TRUE(stub_->ListSessions(list_context.get(), {}, &list).ok());
  EXPECT_EQ(list.sessions_size(), 0);
}

// CreateSession's refusal names the first 20 problems in its status message (which must fit in a
// header); ValidateScenario answers with every one, in the same words, and creates nothing.
TEST_F(BadInput, ValidateScenarioListsEveryProblemCreateSessionSummarises) {
  auto scenario = small_channel_with_disk();
  constexpr int kBodies = 150;  // each one beyond a y wall of the 32 x 16 channel: one problem each
  for (int b = 1; b < kBodies; ++b) {
    auto* body = scenario.add_bodies();
    *body = scenario.bodies(0);
    body->set_name("b" + std::to_string(b));
    body->mutable_centre()->set_y(1000 + b);
  }
  scenario.mutable_bodies(0)->mutable_centre()->set_y(-1000);
  const auto refused = create(scenario);
  ASSERT_TRUE(has_status(refused, StatusCode::INVALID_ARGUMENT, "scenario.bodies[0]"));
  EXPECT_NE(refused.error_message().find(" more problems"), std::string::npos) << refused.error_message();

  v1::ValidateScenarioRequest request;
  *request.mutable_scenario() = scenario;
  v1::ValidateScenarioResponse checked;
  ASSERT_TRUE(stub_->ValidateScenario(deadline_context().get(), request, &checked).ok());
  EXPECT_EQ(checked.problems_total(), kBodies);
  ASSERT_EQ(checked.problems_size(), kBodies);
  for (int b = 0; b < kBodies; ++b)
    EXPECT_EQ(checked.problems(b).rfind("scenario.bodies[" + std::to_string(b) + "].centre: ", 0), 0u)
        << checked.problems(b);
  EXPECT_NE(refused.error_message().find(checked.problems(0)), std::string::npos) << "the same words";
  EXPECT_EQ(refused.error_message().find(checked.problems(kBodies - 1)), std::string::npos)
      << "the summary holds only the first problems";

  request.clear_scenario();
  *request.mutable_scenario() = small_channel_with_disk();
  request.mutable_scenario()->mutable_fluid()->set_omega(1.99);  // valid, near the stability limit
  ASSERT_TRUE(stub_->ValidateScenario(deadline_context().get(), request, &checked).ok());
  EXPECT_EQ(checked.problems_total(), 0);
  EXPECT_EQ(checked.problems_size(), 0);
  ASSERT_EQ(checked.warnings_total(), 1);
  EXPECT_NE(checked.warnings(0).find("scenario.fluid.omega"), std::string::npos) << checked.warnings(0);

  EXPECT_TRUE(has_status(stub_->ValidateScenario(deadline_context().get(), {}, &checked),
                         StatusCode::INVALID_ARGUMENT, "scenario"));
  v1::ListSessionsResponse list;
  ASSERT_TRUE(stub_->ListSessions(deadline_context().get(), {}, &list).ok());
  EXPECT_EQ(list.sessions_size(), 0) << "ValidateScenario created nothing";
}

// omega outside (0, 2) gives no positive viscosity: INVALID_ARGUMENT naming scenario.fluid.omega.
TEST_F(BadInput, OmegaOutsideTheOpenIntervalIsRefused) {
  for (double omega : {0.0, 2.5, 2.0, -1.0}) {
    auto scenario = small_channel_with_disk();
    scenario.mutable_fluid()->set_omega(omega);
    EXPECT_TRUE(has_status(create(scenario), StatusCode::INVALID_ARGUMENT, "scenario.fluid.omega")) << "omega " << omega;
  }
  auto scenario = small_channel_with_disk();
  scenario.mutable_fluid()->set_omega(2.5);
  EXPECT_TRUE(has_status(create(scenario), StatusCode::INVALID_ARGUMENT, "2.5"));  // says what it got
}

// A grid needs at least one node per axis.
TEST_F(BadInput, EmptyGridIsRefused) {
  auto scenario = small_channel_with_disk();
  scenario.mutable_domain()->set_nx(0);
  EXPECT_TRUE(has_status(create(scenario), StatusCode::INVALID_ARGUMENT, "scenario.domain.nx"));
  scenario.mutable_domain()->set_nx(-3);
  EXPECT_TRUE(has_status(create(scenario), StatusCode::INVALID_ARGUMENT, "scenario.domain.nx"));
}

// A body placed beyond a wall cannot start: the message names the body.
TEST_F(BadInput, BodyOutsideTheDomainIsRefused) {
  auto scenario = small_channel_with_disk();
  scenario.mutable_bodies(0)->mutable_centre()->set_y(30);  // walls at y = -0.5 and 15.5
  EXPECT_TRUE(has_status(create(scenario), StatusCode::INVALID_ARGUMENT, "scenario.bodies[0]"));
}

// Run and Step take at least one step; zero and negative counts are refused before anything moves.
TEST_F(BadInput, NonPositiveStepsAreRefused) {
  const std::string id = created_session();
  for (long steps : {-5L, 0L}) {
    EXPECT_TRUE(has_status(run_session(*stub_, id, steps), StatusCode::INVALID_ARGUMENT, "steps")) << steps;
    v1::StepRequest step;
    step.set_session_id(id);
    step.set_steps(steps);
    v1::StepResponse response;
    auto context = deadline_context();
    EXPECT_TRUE(has_status(stub_->Step(context.get(), step, &response), StatusCode::INVALID_ARGUMENT, "steps")) << steps;
  }
  v1::Session session;
  ASSERT_TRUE(get_session(*stub_, id, &session).ok());
  EXPECT_EQ(session.state(), v1::SESSION_STATE_CREATED);
  EXPECT_EQ(session.step(), 0);
}

// Step is synchronous and bounded by --max_sync_steps (50 here): one more is refused, the bound
// itself is taken in full.
TEST_F(BadInput, StepAboveMaxSyncStepsIsRefused) {
  const std::string id = created_session();
  v1::StepRequest step;
  step.set_session_id(id);
  step.set_steps(51);
  v1::StepResponse response;
  {
    auto context = deadline_context();
    const auto status = stub_->Step(context.get(), step, &response);
    EXPECT_TRUE(has_status(status, StatusCode::INVALID_ARGUMENT, "steps"));
    EXPECT_NE(status.error_message().find("50"), std::string::npos) << status.error_message();
  }
  step.set_steps(50);
  auto context = deadline_context();
  ASSERT_TRUE(stub_->Step(context.get(), step, &response).ok());
  EXPECT_EQ(response.steps_taken(), 50);
  EXPECT_EQ(response.session().step(), 50);
}

// Every call that names a session: an id the daemon never gave out is NOT_FOUND (naming
// session_id), an empty one INVALID_ARGUMENT.
TEST_F(BadInput, UnknownOrEmptySessionIdIsRefusedByEveryPerSessionCall) {
  created_session();  // the daemon holds a session, just not the one asked for
  const std::vector<std::pair<std::string, std::function<grpc::Status(const std::string&)>>> calls = {
      {"GetSession",
       [&](const std::string& id) {
         v1::GetSessionRequest r;
         r.set_session_id(id);
         v1::Session out;
         auto c = deadline_context();
         return stub_->GetSession(c.get(), r, &out);
       }},
      {"DeleteSession",
       [&](const std::string& id) {
         v1::DeleteSessionRequest r;
         r.set_session_id(id);
         v1::DeleteSessionResponse out;
         auto c = deadline_context();
         return stub_->DeleteSession(c.get(), r, &out);
       }},
      {"Run", [&](const std::string& id) { return run_session(*stub_, id, 10); }},
      {"Step",
       [&](const std::string& id) {
         v1::StepRequest r;
         r.set_session_id(id);
         r.set_steps(10);
         v1::StepResponse out;
         auto c = deadline_context();
         return stub_->Step(c.get(), r, &out);
       }},
      {"Pause",
       [&](const std::string& id) {
         v1::PauseRequest r;
         r.set_session_id(id);
         v1::Session out;
         auto c = deadline_context();
         return stub_->Pause(c.get(), r, &out);
       }},
      {"Resume",
       [&](const std::string& id) {
         v1::ResumeRequest r;
         r.set_session_id(id);
         v1::Session out;
         auto c = deadline_context();
         return stub_->Resume(c.get(), r, &out);
       }},
      {"Cancel",
       [&](const std::string& id) {
         v1::CancelRequest r;
         r.set_session_id(id);
         v1::Session out;
         auto c = deadline_context();
         return stub_->Cancel(c.get(), r, &out);
       }},
      {"Checkpoint",
       [&](const std::string& id) {
         v1::CheckpointRequest r;
         r.set_session_id(id);
         v1::CheckpointResponse out;
         auto c = deadline_context();
         return stub_->Checkpoint(c.get(), r, &out);
       }},
      {"WatchSession",
       [&](const std::string& id) {
         v1::WatchSessionRequest r;
         r.set_session_id(id);
         auto c = deadline_context();
         auto reader = stub_->WatchSession(c.get(), r);
         return drain<v1::SessionEvent>(reader);
       }},
      {"WatchProfiles",
       [&](const std::string& id) {
         v1::WatchProfilesRequest r;
         r.set_session_id(id);
         r.set_every(10);
         auto c = deadline_context();
         auto reader = stub_->WatchProfiles(c.get(), r);
         return drain<v1::ProfileFrame>(reader);
       }},
      {"WatchParticles",
       [&](const std::string& id) {
         v1::WatchParticlesRequest r;
         r.set_session_id(id);
         r.set_every(10);
         auto c = deadline_context();
         auto reader = stub_->WatchParticles(c.get(), r);
         return drain<v1::ParticleFrame>(reader);
       }},
      {"GetField",
       [&](const std::string& id) {
         v1::GetFieldRequest r;
         r.set_session_id(id);
         auto c = deadline_context();
         auto reader = stub_->GetField(c.get(), r);
         return drain<v1::FieldMessage>(reader);
       }},
  };
  for (const auto& [name, call] : calls) {
    EXPECT_TRUE(has_status(call("s-999999"), StatusCode::NOT_FOUND, "session_id")) << name;
    EXPECT_TRUE(has_status(call("no such session"), StatusCode::NOT_FOUND, "session_id")) << name;
    EXPECT_TRUE(has_status(call(""), StatusCode::INVALID_ARGUMENT, "session_id")) << name;
  }
}

// Stream parameters: every >= 1, a known delivery mode, a progress interval of at least 0.05 s,
// body names the scenario has.
TEST_F(BadInput, BadStreamParametersAreRefused) {
  const std::string id = created_session();
  for (long every : {0L, -1L}) {
    v1::WatchProfilesRequest profiles;
    profiles.set_session_id(id);
    profiles.set_every(every);
    auto c1 = deadline_context();
    auto r1 = stub_->WatchProfiles(c1.get(), profiles);
    EXPECT_TRUE(has_status(drain<v1::ProfileFrame>(r1), StatusCode::INVALID_ARGUMENT, "every")) << every;

    v1::WatchParticlesRequest particles;
    particles.set_session_id(id);
    particles.set_every(every);
    auto c2 = deadline_context();
    auto r2 = stub_->WatchParticles(c2.get(), particles);
    EXPECT_TRUE(has_status(drain<v1::ParticleFrame>(r2), StatusCode::INVALID_ARGUMENT, "every")) << every;
  }
  {
    v1::WatchProfilesRequest profiles;
    profiles.set_session_id(id);
    profiles.set_every(1);
    profiles.set_delivery(static_cast<v1::DeliveryMode>(7));
    auto c = deadline_context();
    auto r = stub_->WatchProfiles(c.get(), profiles);
    EXPECT_TRUE(has_status(drain<v1::ProfileFrame>(r), StatusCode::INVALID_ARGUMENT, "delivery"));
  }
  {
    v1::WatchParticlesRequest particles;
    particles.set_session_id(id);
    particles.set_every(1);
    particles.add_bodies("no such body");
    auto c = deadline_context();
    auto r = stub_->WatchParticles(c.get(), particles);
    EXPECT_TRUE(has_status(drain<v1::ParticleFrame>(r), StatusCode::INVALID_ARGUMENT, "bodies"));
  }
  {
    v1::WatchSessionRequest events;
    events.set_session_id(id);
    events.set_progress_interval_s(0.01);
    auto c = deadline_context();
    auto r = stub_->WatchSession(c.get(), events);
    EXPECT_TRUE(has_status(drain<v1::SessionEvent>(r), StatusCode::INVALID_ARGUMENT, "progress_interval_s"));
  }
}

// GetField knows two fields and sends chunks of 1 KiB to 3 MiB.
TEST_F(BadInput, BadFieldRequestsAreRefused) {
  const std::string id = created_session();
  {
    v1::GetFieldRequest request;
    request.set_session_id(id);
    request.add_fields("density");
    request.add_fields("pressure");
    auto c = deadline_context();
    auto r = stub_->GetField(c.get(), request);
    const auto status = drain<v1::FieldMessage>(r);
    EXPECT_TRUE(has_status(status, StatusCode::INVALID_ARGUMENT, "fields[1]"));
    EXPECT_NE(status.error_message().find("pressure"), std::string::npos) << status.error_message();
  }
  for (long chunk : {-1L, 1L, 1023L, (3L << 20) + 1, 1L << 40}) {
    v1::GetFieldRequest request;
    request.set_session_id(id);
    request.set_chunk_bytes(chunk);
    auto c = deadline_context();
    auto r = stub_->GetField(c.get(), request);
    EXPECT_TRUE(has_status(drain<v1::FieldMessage>(r), StatusCode::INVALID_ARGUMENT, "chunk_bytes")) << chunk;
  }
}

// A checkpoint id must have the form "<session id>/step-<digits>" with a session id as the daemon
// makes them ("s-" and 32 lowercase hex digits) and at most 18 digits (nothing else may reach the
// file system: no "..", no absolute path); a well-formed id with no file is NOT_FOUND.
TEST_F(BadInput, MalformedOrUnknownCheckpointIdIsRefused) {
  for (const std::string id : {"", "nonsense", "../../etc/passwd", "/etc/passwd", "s-000001/../../../etc/passwd",
                               "s-000001/step-", "s-000001/step-12x", "s-000001/step-000000010.h5", "x-000001/step-10",
                               "s-000001", "s-000001/step-10/more", "s-000001/step-10",
                               "s-0123456789abcdef0123456789ABCDEF/step-10",
                               "s-0123456789abcdef0123456789abcdef/step-1234567890123456789"}) {
    v1::RestoreRequest request;
    request.set_checkpoint_id(id);
    v1::Session session;
    auto context = deadline_context();
    EXPECT_TRUE(has_status(stub_->Restore(context.get(), request, &session), StatusCode::INVALID_ARGUMENT,
                           "checkpoint_id"))
        << "\"" << id << "\"";
  }
  v1::RestoreRequest request;
  request.set_checkpoint_id("s-0123456789abcdef0123456789abcdef/step-000000100");
  v1::Session session;
  auto context = deadline_context();
  EXPECT_TRUE(has_status(stub_->Restore(context.get(), request, &session), StatusCode::NOT_FOUND, "checkpoint_id"));
}

// A request id makes CreateSession idempotent: the same id with the same scenario returns the first
// session (a retried call creates nothing new); with another scenario it is ALREADY_EXISTS.
TEST_F(BadInput, RequestIdReuse) {
  v1::Session first, again;
  ASSERT_TRUE(create(small_channel_with_disk(), &first, "request-7f3a").ok());
  ASSERT_TRUE(create(small_channel_with_disk(), &again, "request-7f3a").ok());
  EXPECT_EQ(again.id(), first.id());
  EXPECT_EQ(again.request_id(), "request-7f3a");

  auto other = small_channel_with_disk();
  other.set_name("another scenario");
  EXPECT_TRUE(has_status(create(other, nullptr, "request-7f3a"), StatusCode::ALREADY_EXISTS, "request_id"));

  v1::ListSessionsResponse list;
  auto context = deadline_context();
  ASSERT_TRUE(stub_->ListSessions(context.get(), {}, &list).ok());
  ASSERT_EQ(list.sessions_size(), 1);
  EXPECT_EQ(list.sessions(0).id(), first.id());
}

// Watching what a scenario does not have: profiles need a fluid, particles need bodies.
TEST_F(BadInput, WatchingWhatTheScenarioLacksIsFailedPrecondition) {
  v1::Session no_bodies;
  ASSERT_TRUE(create(diverging_box(), &no_bodies).ok());
  v1::WatchParticlesRequest particles;
  particles.set_session_id(no_bodies.id());
  particles.set_every(1);
  auto c1 = deadline_context();
  auto r1 = stub_->WatchParticles(c1.get(), particles);
  EXPECT_TRUE(has_status(drain<v1::ParticleFrame>(r1), StatusCode::FAILED_PRECONDITION, "bodies"));

  auto bodies_only = small_channel_with_disk();
  bodies_only.mutable_fluid()->set_enabled(false);
  bodies_only.mutable_fluid()->clear_body_force();
  v1::Session no_fluid;
  ASSERT_TRUE(create(bodies_only, &no_fluid).ok());
  v1::WatchProfilesRequest profiles;
  profiles.set_session_id(no_fluid.id());
  profiles.set_every(1);
  auto c2 = deadline_context();
  auto r2 = stub_->WatchProfiles(c2.get(), profiles);
  EXPECT_TRUE(has_status(drain<v1::ProfileFrame>(r2), StatusCode::FAILED_PRECONDITION, "fluid"));
  v1::GetFieldRequest field;
  field.set_session_id(no_fluid.id());
  auto c3 = deadline_context();
  auto r3 = stub_->GetField(c3.get(), field);
  EXPECT_TRUE(has_status(drain<v1::FieldMessage>(r3), StatusCode::FAILED_PRECONDITION, "fluid"));
}

// Run adds `steps` to the current step: a count so large that the target would overflow int64 must
// be refused (INVALID_ARGUMENT naming steps), never turned into a negative target that leaves the
// session RUNNING forever with no worker on it.
TEST_F(BadInput, RunWhoseTargetWouldOverflowIsRefused) {
  const std::string id = created_session();
  v1::StepRequest step;
  step.set_session_id(id);
  step.set_steps(5);
  v1::StepResponse stepped;
  {
    auto context = deadline_context();
    ASSERT_TRUE(stub_->Step(context.get(), step, &stepped).ok());
  }
  v1::Session session;
  const auto status = run_session(*stub_, id, std::numeric_limits<int64_t>::max(), &session);
  if (status.ok()) {
    ADD_FAILURE() << "Run(INT64_MAX) at step 5 was accepted: state " << v1::SessionState_Name(session.state())
                  << ", step " << session.step() << ", target_step " << session.target_step();
    EXPECT_GT(session.target_step(), session.step());
  } else {
    EXPECT_TRUE(has_status(status, StatusCode::INVALID_ARGUMENT, "steps"));
  }
  v1::CancelRequest cancel;
  cancel.set_session_id(id);
  auto context = deadline_context();
  stub_->Cancel(context.get(), cancel, &session);
}

class BadInputSmallLimits : public BadInput {
 protected:
  BadInputSmallLimits() : BadInput({"--max_sessions=2", "--max_cells=1000"}) {}
};

// --max_cells=1000: a 64 x 32 grid (2048 nodes) is RESOURCE_EXHAUSTED naming scenario.domain, while
// 32 x 16 (512) fits.
TEST_F(BadInputSmallLimits, GridAboveMaxCellsIsRefused) {
  v1::ServerInfo info;
  auto context = deadline_context();
  ASSERT_TRUE(stub_->GetServerInfo(context.get(), {}, &info).ok());
  EXPECT_EQ(info.max_cells(), 1000);
  EXPECT_TRUE(has_status(create(small_channel_with_disk(64, 32)), StatusCode::RESOURCE_EXHAUSTED, "scenario.domain"));
  EXPECT_TRUE(create(small_channel_with_disk(32, 16)).ok());
}

// --max_sessions=2: a third session is RESOURCE_EXHAUSTED; a retried create (same request id) still
// gets its session; deleting one makes room again.
TEST_F(BadInputSmallLimits, ThirdSessionAboveMaxSessionsIsRefused) {
  v1::Session a, b, c;
  ASSERT_TRUE(create(small_channel_with_disk(), &a, "first").ok());
  ASSERT_TRUE(create(small_channel_with_disk(), &b).ok());
  EXPECT_TRUE(has_status(create(small_channel_with_disk(), &c), StatusCode::RESOURCE_EXHAUSTED, "sessions"));
  v1::Session retried;
  ASSERT_TRUE(create(small_channel_with_disk(), &retried, "first").ok());
  EXPECT_EQ(retried.id(), a.id());

  v1::DeleteSessionRequest remove;
  remove.set_session_id(b.id());
  v1::DeleteSessionResponse removed;
  auto context = deadline_context();
  ASSERT_TRUE(stub_->DeleteSession(context.get(), remove, &removed).ok());
  EXPECT_TRUE(create(small_channel_with_disk(), &c).ok());
}

// Step is not allowed while a worker runs the session (FAILED_PRECONDITION naming the state), nor
// Resume; after Cancel the session is final and Run is refused too.
TEST_F(BadInput, WrongStateIsFailedPrecondition) {
  const std::string id = created_session();
  ASSERT_TRUE(run_session(*stub_, id, 1'000'000'000).ok());  // runs for as long as the test needs
  v1::StepRequest step;
  step.set_session_id(id);
  step.set_steps(10);
  v1::StepResponse stepped;
  {
    auto context = deadline_context();
    EXPECT_TRUE(has_status(stub_->Step(context.get(), step, &stepped), StatusCode::FAILED_PRECONDITION, "RUNNING"));
  }
  {
    v1::ResumeRequest resume;
    resume.set_session_id(id);
    v1::Session session;
    auto context = deadline_context();
    EXPECT_TRUE(has_status(stub_->Resume(context.get(), resume, &session), StatusCode::FAILED_PRECONDITION));
  }
  EXPECT_TRUE(has_status(run_session(*stub_, id, 10), StatusCode::FAILED_PRECONDITION, "RUNNING"));
  {
    v1::CancelRequest cancel;
    cancel.set_session_id(id);
    v1::Session session;
    auto context = deadline_context();
    ASSERT_TRUE(stub_->Cancel(context.get(), cancel, &session).ok());
    EXPECT_EQ(session.state(), v1::SESSION_STATE_CANCELLED);
  }
  EXPECT_TRUE(has_status(run_session(*stub_, id, 10), StatusCode::FAILED_PRECONDITION, "CANCELLED"));
  auto context = deadline_context();
  EXPECT_TRUE(has_status(stub_->Step(context.get(), step, &stepped), StatusCode::FAILED_PRECONDITION, "CANCELLED"));
}

}  // namespace
}  // namespace lbsolid::testing
