// Admission: what a session will cost is estimated from its scenario before anything is built, and
// the daemon refuses what would pass its memory or particle limits, naming the figure.
// The estimate is held against what build_simulation really allocates.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <iterator>
#include <thread>

#include "scene/simulation.h"
#include "io/api/scenario_translation.h"
#include "server/session/footprint.h"
#include "server/session/session_manager.h"
#include "service/test_scenarios.h"

namespace lbsolid::testing {
namespace {

const server::auth::Identity kLocal = server::auth::local_admin();  // the one caller of a daemon without authentication

v1::Scenario sheet_without_fluid(int side) {
  v1::Scenario s;
  s.set_name("sheet");
  s.mutable_domain()->set_nx(side + 8);
  s.mutable_domain()->set_ny(side + 8);
  s.mutable_fluid()->set_enabled(false);
  auto* body = s.add_bodies();
  body->set_shape(v1::BODY_SHAPE_RECTANGLE);
  body->add_size(side);
  body->add_size(side);
  body->mutable_centre()->set_x(side / 2.0 + 4);
  body->mutable_centre()->set_y(side / 2.0 + 4);
  return s;
}

v1::Scenario chains_in_d2q7() {
  auto s = small_channel_with_disk(48, 40);
  s.set_lattice(v1::LATTICE_D2Q7);
  s.mutable_bodies()->Clear();
  for (int c = 0; c < 12; ++c) {
    auto* chain = s.add_bodies();
    chain->set_shape(v1::BODY_SHAPE_CHAIN);
    chain->set_length(8);
    chain->mutable_centre()->set_x(4 + 3.5 * c);
    chain->mutable_centre()->set_y(10);
  }
  return s;
}

v1::Scenario ball_in_d3q19() {
  auto s = small_channel_with_disk(24, 24);
  s.set_lattice(v1::LATTICE_D3Q19);
  s.mutable_domain()->set_nz(24);
  s.mutable_bodies(0)->set_radius(4);
  s.mutable_bodies(0)->mutable_centre()->set_z(12);
  return s;
}

v1::Scenario float_two_buffer() {
  auto s = small_channel_with_disk(64, 32);
  s.set_precision(v1::PRECISION_FLOAT);
  s.mutable_fluid()->set_streaming(v1::STREAMING_TWO_BUFFER);
  return s;
}

// The estimate bounds the allocation from above (after a step, when the exchange has sized its
// node records), and not by more than the slack it allows on purpose: solid arrays counted at
// twice their size (push_back growth) and 64 KiB of rounding per population array.
TEST(Footprint, BoundsWhatTheBuiltSimulationAllocates) {
  for (const auto& scenario : {small_channel_with_disk(), chains_in_d2q7(), ball_in_d3q19(), float_two_buffer(),
                               sheet_without_fluid(40)}) {
    const auto translated = server::translate_scenario(scenario);
    ASSERT_TRUE(translated.ok()) << scenario.name();
    const auto sim = scene::build_simulation(translated.scene);
    sim->step();  // the exchange sizes its node records at its first step
    const long long actual = static_cast<long long>(sim->fluid_bytes() + sim->solid_bytes());
    const auto estimate = server::estimate_footprint(scenario);
    EXPECT_GE(estimate.resident_bytes, actual) << scenario.name();
    const long long rounding = 19 * 2 * ((64 << 10) + 17 * 64);
    EXPECT_LE(estimate.resident_bytes, 2 * actual + rounding) << scenario.name();
    const long long particles = sim->solid() ? sim->solid()->particle_count() : 0;
    EXPECT_GE(estimate.particles, particles) << scenario.name();
    EXPECT_EQ(estimate.cells, sim->has_fluid() ? static_cast<long long>(translated.scene.fluid.nx) *
                                                     translated.scene.fluid.ny * translated.scene.fluid.nz
                                               : 0);
  }
}

TEST(Footprint, HugeFieldsSaturateInsteadOfOverflowing) {
  auto s = sheet_without_fluid(8);
  s.mutable_bodies(0)->set_size(0, 1 << 30);
  s.mutable_bodies(0)->set_size(1, 1 << 30);
  s.mutable_bodies(0)->add_size(1 << 30);
  auto* disk = s.add_bodies();
  disk->set_shape(v1::BODY_SHAPE_DISK);
  disk->set_radius(1e300);
  const auto f = server::estimate_footprint(s);
  // Saturated at 2^60 each (no wrap to a negative or small figure that would pass admission).
  EXPECT_GE(f.particles, 1LL << 59);
  EXPECT_GE(f.bytes(), 1LL << 60);
  EXPECT_GT(f.resident_bytes, 0);
}

class Admission : public ::testing::Test {
 protected:
  server::ManagerLimits limits() const {
    server::ManagerLimits l;
    l.max_memory_bytes = 256LL << 20;
    l.max_particles = 100000;
    l.max_fluid_threads = 4;
    l.workers = 2;
    l.autosave_interval = {};
    return l;
  }
  ScopedDirectory dir_{"lbsolid-admission"};
  server::SessionManager manager_{dir_.path, limits(), {"test", "test"}};
};

// A 49-byte request for a 2048 x 2048 sheet built 1.27 GB: now refused before anything is built.
TEST_F(Admission, ASessionPastTheMemoryLimitIsRefusedNamingTheFigure) {
  auto big = sheet_without_fluid(2048);
  const auto created = manager_.create(big, "", kLocal);
  ASSERT_EQ(created.status().code(), absl::StatusCode::kResourceExhausted) << created.status();
  EXPECT_NE(created.status().message().find("--max_memory"), std::string::npos) << created.status();
  EXPECT_NE(created.status().message().find("MiB"), std::string::npos) << created.status();
  EXPECT_EQ(manager_.count(), 0);
}

TEST_F(Admission, ParticlesOfAllSessionsTogetherAreCapped) {
  // 200 x 200 = 40000 particles each (a few MiB): two fit under 100000, the third does not.
  ASSERT_TRUE(manager_.create(sheet_without_fluid(200), "", kLocal).ok());
  ASSERT_TRUE(manager_.create(sheet_without_fluid(200), "", kLocal).ok());
  const auto third = manager_.create(sheet_without_fluid(200), "", kLocal);
  ASSERT_EQ(third.status().code(), absl::StatusCode::kResourceExhausted) << third.status();
  EXPECT_NE(third.status().message().find("--max_particles"), std::string::npos) << third.status();
  // Deleting one gives its particles back.
  ASSERT_TRUE(manager_.remove(manager_.list(kLocal).front()->id(), kLocal).ok());
  EXPECT_TRUE(manager_.create(sheet_without_fluid(200), "", kLocal).ok());
}

int threads_of_this_process() {
  return static_cast<int>(std::distance(std::filesystem::directory_iterator("/proc/self/task"),
                                        std::filesystem::directory_iterator()));
}

// Every session's fluid steps run on the manager's one pool (max_fluid_threads = 4, started with
// the manager): sessions asking for several threads start none of their own, so any number of
// them fit, and the daemon's thread count never grows with its sessions. (Each session used to
// start threads - 1 of its own, and the third of these was refused.)
TEST_F(Admission, SessionsShareTheDaemonsFluidThreads) {
  const int before = threads_of_this_process();
  auto threaded = small_channel_with_disk();
  threaded.mutable_fluid()->set_threads(3);
  for (int k = 0; k < 5; ++k) ASSERT_TRUE(manager_.create(threaded, "", kLocal).ok()) << k;
  EXPECT_EQ(threads_of_this_process(), before);
  // They step on the shared pool, several at once.
  for (const auto& session : manager_.list(kLocal)) ASSERT_TRUE(manager_.run(session->id(), 200, kLocal).ok());
  for (const auto& session : manager_.list(kLocal)) {
    for (int wait = 0; wait < 2000 && session->state() != v1::SESSION_STATE_DONE; ++wait)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(session->state(), v1::SESSION_STATE_DONE) << session->id();
  }
  EXPECT_EQ(threads_of_this_process(), before);
}

}  // namespace
}  // namespace lbsolid::testing
