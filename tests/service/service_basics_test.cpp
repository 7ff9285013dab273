// The daemon on its normal path: server info, the standard health service, server reflection
// (what grpcurl uses), and a session created, run to DONE and read back, with the fields it
// returns equal bit for bit to the same scenario run in process by the core.
#include <gtest/gtest.h>

#include <cstring>

#include "google/protobuf/descriptor.pb.h"
#include "reflection.grpc.pb.h"
#include "scene/simulation.h"
#include "io/api/scenario_translation.h"
#include "service/daemon_process.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

class ServiceBasics : public ::testing::Test {
 protected:
  ServiceBasics() : data_dir_("lbsolid-basics"), daemon_(data_dir_.path), stub_(daemon_.stub()) {}
  ScopedDirectory data_dir_;
  DaemonProcess daemon_;
  std::unique_ptr<v1::Simulation::Stub> stub_;
};

TEST_F(ServiceBasics, ServerInfoNamesVersionApiAndLimits) {
  v1::ServerInfo info;
  auto context = deadline_context();
  ASSERT_TRUE(stub_->GetServerInfo(context.get(), {}, &info).ok());
  EXPECT_EQ(info.api_version(), "lbsolid.v1");
  EXPECT_FALSE(info.version().empty());
  EXPECT_FALSE(info.git_revision().empty());
  EXPECT_EQ(info.workers(), 2);
  EXPECT_GT(info.max_cells(), 0);
  EXPECT_NE(std::find(info.capabilities().begin(), info.capabilities().end(), "lattice:D2Q7"), info.capabilities().end());
}

TEST_F(ServiceBasics, HealthServiceSaysServing) {
  std::string bytes;
  const grpc::Status status = health_check(daemon_.channel(), &bytes);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(bytes, std::string("\x08\x01", 2));  // HealthCheckResponse{status: SERVING}
  // By the service's name too, as Kubernetes' gRPC probes ask; a name the daemon does not serve is
  // NOT_FOUND, so the answer is not the same whatever is asked.
  bytes.clear();
  const grpc::Status named = health_check(daemon_.channel(), &bytes, "lbsolid.v1.Simulation");
  ASSERT_TRUE(named.ok()) << named.error_message();
  EXPECT_EQ(bytes, std::string("\x08\x01", 2));
  EXPECT_EQ(health_check(daemon_.channel(), &bytes, "lbsolid.v1.Nothing").error_code(), grpc::StatusCode::NOT_FOUND);
}

// lbsolidd --help lists its flags (it said "No flags matched"), --version names the build.
TEST(DaemonCommandLine, HelpListsTheFlagsAndVersionNamesTheBuild) {
  const auto output_of = [](const std::string& args) {
    FILE* pipe = popen((std::string(LBSOLIDD_PATH) + " " + args + " 2>&1").c_str(), "r");
    std::string out;
    char buffer[4096];
    while (std::size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
    pclose(pipe);
    return out;
  };
  const std::string help = output_of("--help");
  for (const char* flag : {"--listen", "--data_dir", "--tokens_file", "--owner_call_rate", "--max_memory"})
    EXPECT_NE(help.find(flag), std::string::npos) << flag << " missing from --help:\n" << help;
  EXPECT_EQ(help.find("No flags matched"), std::string::npos) << help;
  const std::string version = output_of("--version");
  EXPECT_EQ(version.rfind("lbsolidd 0.", 0), 0u) << version;
  EXPECT_NE(version.find("("), std::string::npos) << version;  // the git revision
}

TEST_F(ServiceBasics, ReflectionListsAndDescribesTheService) {
  using namespace grpc::reflection::v1alpha;
  auto reflection = ServerReflection::NewStub(daemon_.channel());
  auto context = deadline_context();
  auto stream = reflection->ServerReflectionInfo(context.get());
  ServerReflectionRequest list;
  list.set_list_services("");
  ASSERT_TRUE(stream->Write(list));
  ServerReflectionResponse listed;
  ASSERT_TRUE(stream->Read(&listed));
  std::vector<std::string> services;
  for (const auto& s : listed.list_services_response().service()) services.push_back(s.name());
  EXPECT_NE(std::find(services.begin(), services.end(), "lbsolid.v1.Simulation"), services.end());
  EXPECT_NE(std::find(services.begin(), services.end(), "grpc.health.v1.Health"), services.end());

  // What grpcurl does next: the file that defines the service, with its methods.
  ServerReflectionRequest symbol;
  symbol.set_file_containing_symbol("lbsolid.v1.Simulation");
  ASSERT_TRUE(stream->Write(symbol));
  ServerReflectionResponse described;
  ASSERT_TRUE(stream->Read(&described));
  bool found_step = false;
  for (const auto& serialized : described.file_descriptor_response().file_descriptor_proto()) {
    google::protobuf::FileDescriptorProto file;
    ASSERT_TRUE(file.ParseFromString(serialized));
    for (const auto& service : file.service())
      for (const auto& method : service.method()) found_step = found_step || method.name() == "Step";
  }
  EXPECT_TRUE(found_step);
  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
}

// --reflection=false: reflection answers UNIMPLEMENTED (gRPC's reflection library registers its
// plugin for every server when it loads, so leaving it unregistered did not turn it off); the API
// and health are served as before.
TEST(Reflection, CanBeTurnedOff) {
  const ScopedDirectory dir("lbsolid-no-reflection");
  DaemonProcess daemon(dir.path, {"--reflection=false"});
  using namespace grpc::reflection::v1alpha;
  auto reflection = ServerReflection::NewStub(daemon.channel());
  auto context = deadline_context();
  auto stream = reflection->ServerReflectionInfo(context.get());
  ServerReflectionRequest list;
  list.set_list_services("");
  stream->Write(list);
  stream->WritesDone();
  ServerReflectionResponse ignored;
  while (stream->Read(&ignored)) {
  }
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::UNIMPLEMENTED);
  std::string bytes;
  EXPECT_TRUE(health_check(daemon.channel(), &bytes).ok());
  v1::ServerInfo info;
  auto info_context = deadline_context();
  EXPECT_TRUE(daemon.stub()->GetServerInfo(info_context.get(), {}, &info).ok());
}

TEST_F(ServiceBasics, SessionRunsToDoneAndItsFieldsEqualTheCoreRunInProcess) {
  const auto scenario = small_channel_with_disk();
  v1::CreateSessionRequest create;
  *create.mutable_scenario() = scenario;
  v1::Session session;
  {
    auto context = deadline_context();
    ASSERT_TRUE(stub_->CreateSession(context.get(), create, &session).ok());
  }
  EXPECT_EQ(session.state(), v1::SESSION_STATE_CREATED);
  EXPECT_EQ(session.warnings_size(), 0);
  EXPECT_EQ(session.cells(), 32 * 16);
  EXPECT_GT(session.particles(), 0);
  const std::vector<std::string> stages(session.stages().begin(), session.stages().end());
  EXPECT_EQ(stages, (std::vector<std::string>{"exchange", "fluid", "loads", "contact", "solid"}));

  v1::RunRequest run;
  run.set_session_id(session.id());
  run.set_steps(120);
  {
    auto context = deadline_context();
    ASSERT_TRUE(stub_->Run(context.get(), run, &session).ok());
  }
  ASSERT_TRUE(wait_for_state(*stub_, session.id(), v1::SESSION_STATE_DONE));

  v1::GetFieldRequest get;
  get.set_session_id(session.id());
  get.add_fields("velocity");
  get.set_chunk_bytes(1024);  // several chunks for this small grid
  auto context = deadline_context();
  auto reader = stub_->GetField(context.get(), get);
  v1::FieldMessage message;
  v1::FieldHeader header;
  std::string bytes;
  int chunks = 0;
  while (reader->Read(&message)) {
    if (message.has_header()) header = message.header();
    if (message.has_chunk()) {
      EXPECT_EQ(message.chunk().offset(), static_cast<long>(bytes.size()));
      bytes += message.chunk().data();
      ++chunks;
    }
  }
  ASSERT_TRUE(reader->Finish().ok());
  EXPECT_EQ(header.step(), 120);
  EXPECT_EQ(std::vector<long>(header.shape().begin(), header.shape().end()), (std::vector<long>{1, 16, 32, 3}));
  EXPECT_EQ(header.total_bytes(), static_cast<long>(bytes.size()));
  EXPECT_GT(chunks, 1);

  auto in_process = scene::build_simulation(server::translate_scenario(scenario).scene);
  in_process->run(120);
  const auto expected = in_process->fluid_fields().velocity;
  ASSERT_EQ(bytes.size(), expected.size() * sizeof(double));
  EXPECT_EQ(0, std::memcmp(bytes.data(), expected.data(), bytes.size()));
}

// A field read is computed once per state and sent again while nothing changes (Session keeps the
// last one): every read after a step must be the new state, and a read again the same.
// Each read is compared with the core run in process to the same step.
TEST_F(ServiceBasics, FieldsReadBetweenStepsAreEachTheCurrentState) {
  const auto scenario = small_channel_with_disk();
  v1::CreateSessionRequest create;
  *create.mutable_scenario() = scenario;
  v1::Session session;
  ASSERT_TRUE(stub_->CreateSession(deadline_context().get(), create, &session).ok());
  auto in_process = scene::build_simulation(server::translate_scenario(scenario).scene);
  const auto expect_current = [&](const char* when) {
    FieldBytes read;
    ASSERT_TRUE(read_fields(*stub_, session.id(), &read, 1024).ok()) << when;
    EXPECT_EQ(read.step, in_process->step_count()) << when;
    const auto expected = in_process->fluid_fields();
    for (const auto& [name, values] : {std::pair{"density", &expected.density}, {"velocity", &expected.velocity}}) {
      ASSERT_EQ(read.bytes[name].size(), values->size() * sizeof(double)) << when << " " << name;
      EXPECT_EQ(0, std::memcmp(read.bytes[name].data(), values->data(), read.bytes[name].size())) << when << " " << name;
    }
  };
  v1::StepRequest step;
  step.set_session_id(session.id());
  step.set_steps(10);
  v1::StepResponse stepped;
  expect_current("at the start");
  for (int round = 0; round < 3; ++round) {
    ASSERT_TRUE(stub_->Step(deadline_context().get(), step, &stepped).ok());
    in_process->run(10);
    expect_current("after a step");
    expect_current("read again at the same step");
  }
}

// The lifecycle calls on their normal path: Step (synchronous), Run, Pause, Resume, Cancel,
// ListSessions and DeleteSession, each leaving the state DESIGN.md gives it.
TEST_F(ServiceBasics, LifecycleCallsMoveTheSessionThroughItsStates) {
  v1::CreateSessionRequest create;
  *create.mutable_scenario() = small_channel_with_disk();
  v1::Session session;
  ASSERT_TRUE(stub_->CreateSession(deadline_context().get(), create, &session).ok());
  const std::string id = session.id();

  v1::StepRequest step;
  step.set_session_id(id);
  step.set_steps(7);
  v1::StepResponse stepped;
  ASSERT_TRUE(stub_->Step(deadline_context().get(), step, &stepped).ok());
  EXPECT_EQ(stepped.steps_taken(), 7);
  EXPECT_FALSE(stepped.deadline_reached());
  EXPECT_EQ(stepped.session().step(), 7);
  EXPECT_EQ(stepped.session().state(), v1::SESSION_STATE_PAUSED);

  v1::RunRequest run;
  run.set_session_id(id);
  run.set_steps(1000000);  // long enough to pause it midway
  ASSERT_TRUE(stub_->Run(deadline_context().get(), run, &session).ok());
  EXPECT_EQ(session.target_step(), 1000007);
  v1::PauseRequest pause;
  pause.set_session_id(id);
  ASSERT_TRUE(stub_->Pause(deadline_context().get(), pause, &session).ok());
  EXPECT_EQ(session.state(), v1::SESSION_STATE_PAUSED);
  v1::GetSessionRequest get;
  get.set_session_id(id);
  v1::Session first, second;
  ASSERT_TRUE(stub_->GetSession(deadline_context().get(), get, &first).ok());
  ASSERT_TRUE(stub_->GetSession(deadline_context().get(), get, &second).ok());
  EXPECT_EQ(first.step(), second.step());  // paused: it does not move
  EXPECT_LT(first.step(), 1000007);

  v1::ResumeRequest resume;
  resume.set_session_id(id);
  ASSERT_TRUE(stub_->Resume(deadline_context().get(), resume, &session).ok());
  EXPECT_EQ(session.state(), v1::SESSION_STATE_RUNNING);
  v1::CancelRequest cancel;
  cancel.set_session_id(id);
  ASSERT_TRUE(stub_->Cancel(deadline_context().get(), cancel, &session).ok());
  EXPECT_EQ(session.state(), v1::SESSION_STATE_CANCELLED);

  v1::ListSessionsResponse list;
  ASSERT_TRUE(stub_->ListSessions(deadline_context().get(), {}, &list).ok());
  ASSERT_EQ(list.sessions_size(), 1);
  EXPECT_EQ(list.sessions(0).id(), id);
  v1::DeleteSessionRequest remove;
  remove.set_session_id(id);
  v1::DeleteSessionResponse removed;
  ASSERT_TRUE(stub_->DeleteSession(deadline_context().get(), remove, &removed).ok());
  EXPECT_EQ(stub_->GetSession(deadline_context().get(), get, &session).error_code(), grpc::StatusCode::NOT_FOUND);
}

// Step honours the call's deadline: asked for more steps than fit, it stops before the deadline,
// answers in time, and the session holds exactly the steps it reports.
TEST_F(ServiceBasics, StepStopsBeforeTheDeadline) {
  v1::CreateSessionRequest create;
  *create.mutable_scenario() = small_channel_with_disk(256, 128);  // ~1 ms per step
  v1::Session session;
  ASSERT_TRUE(stub_->CreateSession(deadline_context().get(), create, &session).ok());
  v1::StepRequest step;
  step.set_session_id(session.id());
  step.set_steps(10000);
  v1::StepResponse stepped;
  const auto status = stub_->Step(deadline_context(0.5).get(), step, &stepped);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_TRUE(stepped.deadline_reached());
  EXPECT_GT(stepped.steps_taken(), 0);
  EXPECT_LT(stepped.steps_taken(), 10000);
  EXPECT_EQ(stepped.session().step(), stepped.steps_taken());
}

// A scenario near the edge of stability is accepted, with the quantity named in its warnings.
TEST_F(ServiceBasics, NearEdgeScenarioIsCreatedWithAWarning) {
  v1::CreateSessionRequest create;
  *create.mutable_scenario() = small_channel_with_disk();
  create.mutable_scenario()->mutable_fluid()->set_omega(1.97);
  v1::Session session;
  ASSERT_TRUE(stub_->CreateSession(deadline_context().get(), create, &session).ok());
  ASSERT_EQ(session.warnings_size(), 1);
  EXPECT_EQ(session.warnings(0).rfind("scenario.fluid.omega: 1.97 is above 1.95", 0), 0u) << session.warnings(0);
}

}  // namespace
}  // namespace lbsolid::testing
