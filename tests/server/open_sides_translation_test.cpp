// Open sides in the API's Scenario: a velocity inlet and a pressure outlet map to the core with
// their fields, and every misuse comes back on its proto path with the reason.
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

// A D2Q9 channel between bounce-back y walls, with the given x sides.
std::string channel(const std::string& x_low, const std::string& x_high, const std::string& more = "") {
  return "domain { nx: 40 ny: 12 y_low { kind: WALL_KIND_BOUNCE_BACK } y_high { kind: WALL_KIND_BOUNCE_BACK } "
         "x_low { " + x_low + " } x_high { " + x_high + " } } " + more;
}

const std::string kInlet = "kind: WALL_KIND_VELOCITY_INLET inflow_speed: 0.02 inflow_profile: INFLOW_PROFILE_PARABOLIC";
const std::string kOutlet = "kind: WALL_KIND_PRESSURE_OUTLET outflow_density: 0.995";

TEST(OpenSidesTranslation, InletAndOutletMapWithTheirFields) {
  const auto t = translated(channel(kInlet, kOutlet));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  EXPECT_TRUE(t.warnings.empty()) << listed(t.warnings);
  const auto& inlet = t.scene.fluid.sides[fluid::kXLow];
  const auto& outlet = t.scene.fluid.sides[fluid::kXHigh];
  EXPECT_EQ(inlet.kind, fluid::WallKind::kVelocityInlet);
  EXPECT_EQ(inlet.inflow_speed, 0.02);
  EXPECT_EQ(inlet.inflow_profile, fluid::InflowProfile::kParabolic);
  EXPECT_EQ(outlet.kind, fluid::WallKind::kPressureOutlet);
  EXPECT_EQ(outlet.outflow_density, 0.995);
  // Unset: a uniform profile and the outlet at rho0 (0 in the core).
  const auto defaults = translated(channel("kind: WALL_KIND_VELOCITY_INLET inflow_speed: 0.01",
                                           "kind: WALL_KIND_PRESSURE_OUTLET"));
  ASSERT_TRUE(defaults.ok()) << listed(defaults.errors);
  EXPECT_EQ(defaults.scene.fluid.sides[fluid::kXLow].inflow_profile, fluid::InflowProfile::kUniform);
  EXPECT_EQ(defaults.scene.fluid.sides[fluid::kXHigh].outflow_density, 0.0);
}

TEST(OpenSidesTranslation, MisusesAreReportedOnTheirPaths) {
  struct Case {
    std::string scenario, error;
  };
  const Case cases[] = {
      {"domain { nx: 8 ny: 8 x_low { kind: WALL_KIND_BOUNCE_BACK } x_high { kind: WALL_KIND_BOUNCE_BACK } "
       "y_low { kind: WALL_KIND_VELOCITY_INLET inflow_speed: 0.01 } y_high { kind: WALL_KIND_BOUNCE_BACK } }",
       "scenario.domain.y_low.kind: velocity inlets are supported on x sides only"},
      {channel("kind: WALL_KIND_BOUNCE_BACK inflow_speed: 0.01", kOutlet),
       "scenario.domain.x_low.inflow_speed: is only used by a velocity inlet, not a bounce-back side"},
      {channel(kInlet, "kind: WALL_KIND_PRESSURE_OUTLET inflow_profile: INFLOW_PROFILE_PARABOLIC"),
       "scenario.domain.x_high.inflow_profile: is only used by a velocity inlet, not a pressure outlet side"},
      {channel(kInlet + " outflow_density: 1", kOutlet),
       "scenario.domain.x_low.outflow_density: is only used by a pressure outlet, not a velocity inlet side"},
      {channel(kInlet, "kind: WALL_KIND_PRESSURE_OUTLET outflow_density: 0"),
       "scenario.domain.x_high.outflow_density: must be a positive density (leave it unset for rho0)"},
      {channel(kInlet, "kind: WALL_KIND_PRESSURE_OUTLET outflow_density: -1"),
       "scenario.domain.x_high.outflow_density: must be a positive finite density"},
      {channel("kind: WALL_KIND_VELOCITY_INLET inflow_speed: nan", kOutlet),
       "scenario.domain.x_low.inflow_speed: must be finite"},
      // D2Q9: c_s = 0.577, so 0.6 is Mach 1.04 and 0.3 is Mach 0.52, above the monitor's default 0.5.
      {channel("kind: WALL_KIND_VELOCITY_INLET inflow_speed: 0.6", kOutlet),
       "scenario.domain.x_low.inflow_speed: Mach number 1.04 must stay below 1"},
      {channel("kind: WALL_KIND_VELOCITY_INLET inflow_speed: -0.3", kOutlet),
       "scenario.domain.x_low.inflow_speed: Mach number 0.52 reaches the monitor's max_mach 0.5"},
      {channel(kInlet, "kind: WALL_KIND_PRESSURE_OUTLET outflow_density: 2.5"),
       "scenario.domain.x_high.outflow_density: 2.5 lies outside the monitor's band (0.5, 2)"},
      {channel("kind: WALL_KIND_VELOCITY_INLET inflow_profile: 7", kOutlet),
       "scenario.domain.x_low.inflow_profile: unknown value 7; use INFLOW_PROFILE_UNIFORM or INFLOW_PROFILE_PARABOLIC"},
  };
  for (const Case& c : cases) expect_one_error_starting(c.scenario, c.error);
}

// The monitor's limits apply only when it runs: with a wider band the same outlet is fine, and a
// fast inlet is warned about, as a fast moving wall is.
TEST(OpenSidesTranslation, LimitsFollowTheMonitor) {
  const auto wide = translated(channel(kInlet, "kind: WALL_KIND_PRESSURE_OUTLET outflow_density: 2.5",
                                       "stability { max_density: 3 }"));
  EXPECT_TRUE(wide.ok()) << listed(wide.errors);
  const auto fast = translated(channel("kind: WALL_KIND_VELOCITY_INLET inflow_speed: 0.1", kOutlet));
  ASSERT_TRUE(fast.ok()) << listed(fast.errors);
  ASSERT_EQ(fast.warnings.size(), 1u) << listed(fast.warnings);
  EXPECT_EQ(fast.warnings[0].rfind("scenario.domain.x_low.inflow_speed: Mach number 0.173 is above 0.1", 0), 0u)
      << fast.warnings[0];
}

}  // namespace
}  // namespace lbsolid::server
