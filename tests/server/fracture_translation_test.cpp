// Point loads and fracture in the API's Scenario: they map to the core with their values, and
// every misuse comes back on its proto path with the reason.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "server/translation_test_support.h"

namespace lbsolid::server {
namespace {

namespace v1 = lbsolid::v1;

using testing::expect_one_error_starting;
using testing::listed;
using testing::translated;

// A free chain of 8 in a solid-only box, with `more` inside its body.
std::string chain(const std::string& more) {
  return "domain { nx: 64 ny: 64 } fluid { enabled: false } bodies { shape: BODY_SHAPE_CHAIN length: 8 "
         "centre { x: 32 y: 32 } " + more + " }";
}

TEST(FractureTranslation, PointLoadsAndThresholdsMapWithTheirValues) {
  const auto t = translated(chain("point_loads { label { i: 0 } force { x: -0.001 } } "
                                  "point_loads { label { i: 7 } force { x: 0.001 y: 0.0005 } } "
                                  "fracture { max_force: 0.002 }"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  const auto& body = t.scene.bodies.at(0);
  ASSERT_EQ(body.point_loads.size(), 2u);
  EXPECT_EQ(body.point_loads[0].label, (solid::Label{0, 0, 0}));
  EXPECT_EQ(body.point_loads[0].force, (solid::Vec3{-0.001, 0, 0}));
  EXPECT_EQ(body.point_loads[1].label, (solid::Label{7, 0, 0}));
  EXPECT_EQ(body.point_loads[1].force, (solid::Vec3{0.001, 0.0005, 0}));
  EXPECT_EQ(body.fracture.max_force, 0.002);
  EXPECT_EQ(body.fracture.max_stretch, 0.0);  // unset: off
  const auto stretch = translated(chain("fracture { max_stretch: 0.05 }"));
  ASSERT_TRUE(stretch.ok()) << listed(stretch.errors);
  EXPECT_EQ(stretch.scene.bodies.at(0).fracture.max_stretch, 0.05);
  EXPECT_FALSE(translated(chain("")).scene.bodies.at(0).fracture.enabled());
}

TEST(FractureTranslation, MisusesAreReportedOnTheirPaths) {
  struct Case {
    std::string scenario, error;
  };
  const Case cases[] = {
      {chain("fracture { }"), "scenario.bodies[0].fracture: give max_force, max_stretch or both"},
      {chain("fracture { max_force: 0 }"), "scenario.bodies[0].fracture.max_force: must be a positive number, got 0"},
      {chain("fracture { max_stretch: -0.1 }"), "scenario.bodies[0].fracture.max_stretch: must be a positive number"},
      {chain("fracture { max_force: inf }"), "scenario.bodies[0].fracture.max_force: must be a positive number"},
      {chain("fracture { max_force: 0.01 } rotation: true"),
       "scenario.bodies[0].rotation: a body that can break cannot rotate"},
      {chain("point_loads { force { x: 1 } }"), "scenario.bodies[0].point_loads[0].label: required"},
      {chain("point_loads { label { i: 8 } force { x: 1 } }"),
       "scenario.bodies[0].point_loads.label: label (8, 0, 0) is not a particle of this body"},
      {chain("point_loads { label { i: 1 } } point_loads { label { i: 1 } }"),
       "scenario.bodies[0].point_loads.label: label (1, 0, 0) appears twice"},
      {chain("point_loads { label { i: 1 } force { y: nan } }"),
       "scenario.bodies[0].point_loads.force: must be finite"},
  };
  for (const Case& c : cases) expect_one_error_starting(c.scenario, c.error);
  // With a fluid, the pairwise exchange cannot step a shed particle.
  expect_one_error_starting(
      "domain { nx: 64 ny: 64 } exchange: EXCHANGE_RULE_PAIRWISE bodies { shape: BODY_SHAPE_CHAIN length: 8 "
      "centre { x: 32 y: 32 } fracture { max_force: 0.01 } }",
      "scenario.bodies[0].fracture: breaking bodies need the common-velocity exchange rule");
}

}  // namespace
}  // namespace lbsolid::server
