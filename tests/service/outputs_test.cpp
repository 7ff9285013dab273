// Results that live with the job (issue 13): what scenario.outputs declares is recorded by the
// daemon itself, listed by ListOutputs and sent by DownloadOutput (resumable, with the whole file's
// SHA-256), whatever happens to the client, and a daemon killed mid-run records every frame once.
// The values are held against the same scenario run in process by the core, bit for bit.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <fstream>
#include <thread>

#include "scene/simulation.h"
#include "io/api/scenario_translation.h"
#include "io/storage/h5md_file.h"
#include "service/coreutils_sha256.h"
#include "service/daemon_process.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

using namespace std::chrono_literals;
namespace storage = server::storage;

v1::Scenario recorded_channel(long profile_every, long particles_every, long checkpoint_every) {
  auto scenario = small_channel_with_disk(24, 12);
  auto* outputs = scenario.mutable_outputs();
  outputs->set_profile_every(profile_every);
  outputs->set_particles_every(particles_every);
  outputs->set_final_fields(true);
  outputs->set_checkpoint_every(checkpoint_every);
  return scenario;
}

std::string run_to_done(v1::Simulation::Stub& stub, const v1::Scenario& scenario, long steps) {
  v1::Session session;
  EXPECT_TRUE(create_session(stub, scenario, &session).ok());
  EXPECT_TRUE(run_session(stub, session.id(), steps).ok());
  EXPECT_TRUE(wait_for_state(stub, session.id(), v1::SESSION_STATE_DONE));
  return session.id();
}

std::vector<v1::OutputFile> list_outputs(v1::Simulation::Stub& stub, const std::string& id) {
  v1::ListOutputsRequest request;
  request.set_session_id(id);
  v1::ListOutputsResponse response;
  const auto status = stub.ListOutputs(deadline_context().get(), request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return {response.files().begin(), response.files().end()};
}


// The whole file, checked against the SHA-256 the daemon named.
std::string download_whole(v1::Simulation::Stub& stub, const std::string& id, const std::string& name,
                           const std::string& local_path) {
  std::string bytes;
  v1::OutputFile file;
  EXPECT_TRUE(download_output(stub, id, name, 0, "", &bytes, &file).ok()) << name;
  EXPECT_EQ(file.name(), name);
  EXPECT_EQ(file.bytes(), static_cast<long>(bytes.size())) << name;
  EXPECT_EQ(coreutils_sha256(bytes), file.sha256()) << name;
  std::ofstream(local_path, std::ios::binary) << bytes;
  return bytes;
}

// u_x(y) of the same scenario run in process, at every multiple of `every` through `steps`.
std::vector<std::vector<double>> reference_profiles(const v1::Scenario& scenario, long every, long steps) {
  auto simulation = scene::build_simulation(server::translate_scenario(scenario).scene);
  std::vector<std::vector<double>> profiles{simulation->velocity_profile()};
  for (long step = 1; step <= steps; ++step) {
    simulation->step();
    if (step % every == 0) profiles.push_back(simulation->velocity_profile());
  }
  return profiles;
}

void expect_profiles(const std::string& h5md_path, const std::vector<std::vector<double>>& expected, long every) {
  const auto series = storage::read_h5md_series(h5md_path, "/observables/velocity_profile");
  ASSERT_EQ(series.step.size(), expected.size());
  const std::size_t rows = expected.front().size();
  for (std::size_t frame = 0; frame < expected.size(); ++frame) {
    EXPECT_EQ(series.step[frame], static_cast<long>(frame) * every) << "frame " << frame;
    for (std::size_t y = 0; y < rows; ++y)
      ASSERT_EQ(series.value[frame * rows + y], expected[frame][y]) << "frame " << frame << " row " << y;
  }
}

TEST(Outputs, TheDaemonRecordsWhatTheScenarioDeclares) {
  const ScopedDirectory dir("lbsolid-outputs");
  DaemonProcess daemon(dir.path + "/data");
  auto stub = daemon.stub();
  const auto scenario = recorded_channel(5, 10, 50);
  const std::string id = run_to_done(*stub, scenario, 100);

  std::vector<std::string> names;
  for (const auto& file : list_outputs(*stub, id)) names.push_back(file.name());
  EXPECT_EQ(names, (std::vector<std::string>{"particles.h5", "particles.xdmf", "fields.h5", "fields.xdmf",
                                             "checkpoints/step-000000050.h5", "checkpoints/step-000000100.h5"}));

  const std::string particles = dir.path + "/particles.h5";
  download_whole(*stub, id, "particles.h5", particles);
  expect_profiles(particles, reference_profiles(scenario, 5, 100), 5);
  const auto positions = storage::read_h5md_series(particles, "/particles/disk/position");
  EXPECT_EQ(positions.step, (std::vector<long>{0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100}));

  // The final fields are those GetField gives at the end, bit for bit.
  download_whole(*stub, id, "fields.h5", dir.path + "/fields.h5");
  download_whole(*stub, id, "fields.xdmf", dir.path + "/fields.xdmf");
  FieldBytes live;
  ASSERT_TRUE(read_fields(*stub, id, &live).ok());
  auto simulation = scene::build_simulation(server::translate_scenario(scenario).scene);
  for (int k = 0; k < 100; ++k) simulation->step();
  const auto fields = simulation->fluid_fields();
  EXPECT_EQ(live.bytes["density"], std::string(reinterpret_cast<const char*>(fields.density.data()),
                                               fields.density.size() * sizeof(double)));
  // The automatic checkpoint restores.
  v1::Session restored;
  ASSERT_TRUE(restore(*stub, id + "/step-000000050", &restored).ok());
  EXPECT_EQ(restored.step(), 50);
}

// A chain pulled apart by +-0.51 T at its ends (tests/physics/fracture_test.cpp): its middle
// link breaks in step 11. The recorded particles.h5 lists that break as the core does, bit for
// bit, and counts the body's broken links in every frame.
TEST(Outputs, ABreakingBodysBrokenLinksAreRecorded) {
  const ScopedDirectory dir("lbsolid-outputs");
  DaemonProcess daemon(dir.path + "/data");
  auto stub = daemon.stub();
  v1::Scenario scenario;
  std::string error;
  ASSERT_TRUE(server::parse_scenario_text(
      "domain { nx: 160 ny: 160 } fluid { enabled: false } contact { enabled: false } "
      "outputs { particles_every: 1 } "
      "bodies { name: \"chain\" shape: BODY_SHAPE_CHAIN length: 20 centre { x: 80 y: 80 } "
      "  point_loads { label { i: 0 } force { x: -0.00051 } } point_loads { label { i: 19 } force { x: 0.00051 } } "
      "  fracture { max_force: 0.001 } }",
      &scenario, &error))
      << error;
  const std::string id = run_to_done(*stub, scenario, 20);
  const std::string particles = dir.path + "/particles.h5";
  download_whole(*stub, id, "particles.h5", particles);

  auto simulation = scene::build_simulation(server::translate_scenario(scenario).scene);
  simulation->run(20);
  const auto& expected = simulation->solid()->broken_links();
  ASSERT_EQ(expected.size(), 1u);
  const auto broken = storage::read_h5md_series(particles, "/observables/chain/broken_links");
  ASSERT_EQ(broken.step, (std::vector<long>{expected[0].step}));
  EXPECT_EQ(broken.value, (std::vector<double>{static_cast<double>(expected[0].particle), 0, expected[0].position[0],
                                                expected[0].position[1], expected[0].position[2]}));
  const auto count = storage::read_h5md_series(particles, "/observables/chain/broken_link_count");
  ASSERT_EQ(count.value.size(), 21u);  // steps 0 to 20
  for (long step = 0; step <= 20; ++step)
    EXPECT_EQ(count.value[step], step >= expected[0].step ? 1 : 0) << "step " << step;
}

TEST(Outputs, ADownloadResumesFromAnOffsetAndRefusesAnotherVersion) {
  const ScopedDirectory dir("lbsolid-outputs");
  DaemonProcess daemon(dir.path + "/data");
  auto stub = daemon.stub();
  const std::string id = run_to_done(*stub, recorded_channel(1, 1, 0), 60);
  std::string whole;
  v1::OutputFile file;
  ASSERT_TRUE(download_output(*stub, id, "particles.h5", 0, "", &whole, &file, 1024).ok());
  ASSERT_GT(whole.size(), 3 * 1024u);  // several chunks

  // Interrupted after two chunks, twice, then resumed from what arrived.
  std::string parts;
  v1::OutputFile first;
  ASSERT_TRUE(download_output(*stub, id, "particles.h5", 0, "", &parts, &first, 1024, 2).ok());
  ASSERT_EQ(parts.size(), 2048u);
  v1::OutputFile again;
  ASSERT_TRUE(download_output(*stub, id, "particles.h5", static_cast<long>(parts.size()), first.sha256(), &parts,
                              &again, 1024, 1).ok());
  ASSERT_TRUE(download_output(*stub, id, "particles.h5", static_cast<long>(parts.size()), first.sha256(), &parts,
                              &again, 1024).ok());
  EXPECT_TRUE(parts == whole);
  EXPECT_EQ(coreutils_sha256(parts), file.sha256());

  std::string ignored;
  v1::OutputFile none;
  EXPECT_TRUE(has_status(download_output(*stub, id, "particles.h5", 10, std::string(64, '0'), &ignored, &none),
                         grpc::StatusCode::FAILED_PRECONDITION, "changed since"));
  EXPECT_TRUE(has_status(download_output(*stub, id, "particles.h5", file.bytes() + 1, "", &ignored, &none),
                         grpc::StatusCode::OUT_OF_RANGE, "offset"));
  EXPECT_TRUE(has_status(download_output(*stub, id, "../session.h5", 0, "", &ignored, &none),
                         grpc::StatusCode::NOT_FOUND, "has no output"));
  EXPECT_TRUE(has_status(download_output(*stub, id, "particles.h5", 0, "", &ignored, &none, 10),
                         grpc::StatusCode::INVALID_ARGUMENT, "chunk_bytes"));
}

// SIGKILL while a long run goes on, with autosaves every 100 ms: the next daemon brings the
// session back at its last save, and Resume goes on; paused a little later, its profile series has
// every multiple of 50 from 0 to the step it reached exactly once, with the values of an
// uninterrupted run.
TEST(Outputs, ARunKilledMidwayRecordsEveryFrameOnce) {
  const ScopedDirectory dir("lbsolid-outputs");
  auto scenario = recorded_channel(50, 0, 0);
  scenario.mutable_outputs()->set_final_fields(false);
  std::string id;
  long killed_near = 0;
  {
    DaemonProcess daemon(dir.path + "/data", {"--autosave_interval=100ms", "--workers=1"});
    auto stub = daemon.stub();
    v1::Session session;
    ASSERT_TRUE(create_session(*stub, scenario, &session).ok());
    id = session.id();
    ASSERT_TRUE(run_session(*stub, id, 1L << 40).ok());
    for (v1::Session now; get_session(*stub, id, &now).ok() && now.step() < 5000;) std::this_thread::sleep_for(5ms);
    std::this_thread::sleep_for(250ms);  // past an autosave
    v1::Session now;
    ASSERT_TRUE(get_session(*stub, id, &now).ok());
    killed_near = now.step();
    daemon.stop(SIGKILL);
  }
  DaemonProcess daemon(dir.path + "/data");
  auto stub = daemon.stub();
  v1::Session back;
  ASSERT_TRUE(get_session(*stub, id, &back).ok());
  ASSERT_EQ(back.state(), v1::SESSION_STATE_PAUSED);
  ASSERT_GE(back.step(), 5000);
  ASSERT_LE(back.step(), killed_near + 50000);  // the save is from before the kill
  ASSERT_TRUE(resume(*stub, id, &back).ok());
  std::this_thread::sleep_for(100ms);
  v1::PauseRequest pause;
  pause.set_session_id(id);
  v1::Session paused;
  ASSERT_TRUE(stub->Pause(deadline_context().get(), pause, &paused).ok());
  ASSERT_GT(paused.step(), back.step());
  const std::string particles = dir.path + "/particles.h5";
  download_whole(*stub, id, "particles.h5", particles);
  expect_profiles(particles, reference_profiles(scenario, 50, paused.step()), 50);
}

// UploadCheckpoint of `bytes` in 1 KiB chunks, the first message naming `named_bytes` and `sha256`.
grpc::Status upload(v1::Simulation::Stub& stub, const std::string& bytes, long named_bytes, const std::string& sha256,
                    v1::Session* session) {
  auto context = deadline_context(30);
  auto writer = stub.UploadCheckpoint(context.get(), session);
  v1::UploadCheckpointChunk first;
  first.set_bytes(named_bytes);
  first.set_sha256(sha256);
  bool open = writer->Write(first);
  for (std::size_t at = 0; open && at < bytes.size(); at += 1024) {
    v1::UploadCheckpointChunk chunk;
    chunk.set_data(bytes.substr(at, 1024));
    open = writer->Write(chunk);
  }
  writer->WritesDone();
  return writer->Finish();
}

// A checkpoint taken on one daemon (outputs.checkpoint_every), downloaded and uploaded to
// another, continues there bit for bit; damaged, mislabelled or cut-short uploads are refused.
TEST(Outputs, ACheckpointDownloadedFromOneDaemonContinuesOnAnother) {
  const ScopedDirectory dir("lbsolid-outputs");
  DaemonProcess first(dir.path + "/first");
  DaemonProcess second(dir.path + "/second");
  auto from = first.stub();
  auto to = second.stub();
  const std::string id = run_to_done(*from, recorded_channel(0, 0, 50), 100);
  std::string checkpoint;
  v1::OutputFile file;
  ASSERT_TRUE(download_output(*from, id, "checkpoints/step-000000050.h5", 0, "", &checkpoint, &file).ok());
  const long size = static_cast<long>(checkpoint.size());

  v1::Session uploaded;
  ASSERT_TRUE(upload(*to, checkpoint, size, file.sha256(), &uploaded).ok());
  EXPECT_EQ(uploaded.step(), 50);
  EXPECT_EQ(uploaded.state(), v1::SESSION_STATE_PAUSED);
  ASSERT_TRUE(run_session(*to, uploaded.id(), 50).ok());
  ASSERT_TRUE(wait_for_state(*to, uploaded.id(), v1::SESSION_STATE_DONE));
  FieldBytes there, here;
  ASSERT_TRUE(read_fields(*from, id, &there).ok());
  ASSERT_TRUE(read_fields(*to, uploaded.id(), &here).ok());
  EXPECT_EQ(here.step, 100);
  for (const char* name : {"density", "velocity"}) EXPECT_TRUE(here.bytes[name] == there.bytes[name]) << name;

  std::string damaged = checkpoint;
  damaged[damaged.size() / 2] ^= 0x10;  // inside the populations: HDF5 reads it, the checksum does not match
  v1::Session refused;
  EXPECT_TRUE(has_status(upload(*to, damaged, size, coreutils_sha256(damaged), &refused), grpc::StatusCode::DATA_LOSS,
                         "data: the uploaded checkpoint"));
  EXPECT_TRUE(has_status(upload(*to, damaged, size, file.sha256(), &refused), grpc::StatusCode::DATA_LOSS,
                         "have SHA-256"));
  EXPECT_TRUE(has_status(upload(*to, checkpoint.substr(0, 2048), size, file.sha256(), &refused),
                         grpc::StatusCode::INVALID_ARGUMENT, "cut short"));
  EXPECT_TRUE(has_status(upload(*to, "", 1L << 60, file.sha256(), &refused), grpc::StatusCode::RESOURCE_EXHAUSTED,
                         "--max_memory"));
  EXPECT_TRUE(has_status(upload(*to, checkpoint, size, "x", &refused), grpc::StatusCode::INVALID_ARGUMENT, "sha256"));
  v1::ListSessionsResponse listed;
  ASSERT_TRUE(to->ListSessions(deadline_context().get(), {}, &listed).ok());
  EXPECT_EQ(listed.sessions_size(), 1);  // none of the refused uploads left a session
}

}  // namespace
}  // namespace lbsolid::testing
