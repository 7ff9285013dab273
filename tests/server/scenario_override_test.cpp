// The CLI's --set PATH=VALUE (client-examples/cli/scenario_override.h): each field kind set by its
// path, and every way an assignment can be wrong refused with exit 2 and a message naming it.
#include <gtest/gtest.h>

#include <google/protobuf/text_format.h>

#include "cli_error.h"
#include "exit_codes.h"
#include "scenario_override.h"

namespace lbsolid::cli {
namespace {

lbsolid::v1::Scenario two_bodies() {
  lbsolid::v1::Scenario s;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(R"(
    name: "sweep" lattice: LATTICE_D2Q9
    domain { nx: 32 ny: 16 y_high { kind: WALL_KIND_MOVING_WALL wall_velocity { x: 0.01 } } }
    fluid { omega: 1.0 }
    bodies { name: "a" shape: BODY_SHAPE_DISK radius: 2 centre { x: 8 y: 8 } }
    bodies { name: "b" shape: BODY_SHAPE_DISK radius: 2 centre { x: 20 y: 8 } })",
                                                            &s));
  return s;
}

TEST(ScenarioOverride, SetsEachKindOfFieldByItsPath) {
  auto s = two_bodies();
  apply_override(s, "fluid.omega=1.2");                      // double
  apply_override(s, "bodies[1].load.x=2e-5");                // inside a repeated message
  apply_override(s, "domain.nx=48");                         // integer
  apply_override(s, "domain.y_high.wall_velocity.x=-0.02");  // nested messages
  apply_override(s, "lattice=LATTICE_D2Q7");                 // enum by name
  apply_override(s, "bodies[0].shape=3");                    // enum by number (BODY_SHAPE_CHAIN)
  apply_override(s, "bodies[0].rotation=true");              // bool
  apply_override(s, "name=a = b");                           // a string: everything after the first '='
  EXPECT_EQ(s.fluid().omega(), 1.2);
  EXPECT_EQ(s.bodies(1).load().x(), 2e-5);
  EXPECT_EQ(s.bodies(0).load().x(), 0);  // the other body untouched
  EXPECT_EQ(s.domain().nx(), 48);
  EXPECT_EQ(s.domain().y_high().wall_velocity().x(), -0.02);
  EXPECT_EQ(s.lattice(), lbsolid::v1::LATTICE_D2Q7);
  EXPECT_EQ(s.bodies(0).shape(), lbsolid::v1::BODY_SHAPE_CHAIN);
  EXPECT_TRUE(s.bodies(0).rotation());
  EXPECT_EQ(s.name(), "a = b");
  // A message not set in the file is created by the first field set in it.
  auto t = two_bodies();
  apply_override(t, "fluid.body_force.y=-1e-6");
  EXPECT_EQ(t.fluid().body_force().y(), -1e-6);
}

TEST(ScenarioOverride, RefusesWhatDoesNotFitNamingTheAssignment) {
  const std::pair<const char*, const char*> bad[] = {
      {"fluid.omega", "expected PATH=VALUE"},
      {"fluid.omgea=1", "has no field 'omgea'"},
      {"bodies.load.x=1", "is repeated: give an index"},
      {"bodies[2].load.x=1", "has 2 entries; index 2 is past its end"},
      {"fluid[0].omega=1", "is not repeated"},
      {"fluid=1", "is a message"},
      {"fluid.omega.x=1", "is a value, not a message"},
      {"fluid.omega=fast", "is not a finite number"},
      {"fluid.omega=1e999", "is not a finite number"},
      {"fluid.omega=nan", "is not a finite number"},
      {"domain.nx=1.5", "is not a int32"},
      {"domain.nx=99999999999", "is not a int32"},
      {"bodies[0].rotation=yes", "is not true or false"},
      {"lattice=LATTICE_D5Q1", "is not one of"},
      {"bodies[x].load.x=1", "is not a field name"},
      {"bodies[-1].load.x=1", "is not a field name"},
      {".omega=1", "is not a field name"},
  };
  for (const auto& [assignment, reason] : bad) {
    auto s = two_bodies();
    const auto before = s.SerializeAsString();
    try {
      apply_override(s, assignment);
      ADD_FAILURE() << assignment << " was accepted";
    } catch (const CliError& e) {
      EXPECT_EQ(e.exit_code, kExitBadInput) << assignment;
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(std::string("--set ") + assignment + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(reason), std::string::npos) << assignment << ": " << message;
    }
    EXPECT_EQ(s.SerializeAsString(), before) << assignment << " changed the scenario although refused";
  }
}

}  // namespace
}  // namespace lbsolid::cli
