// Bad configurations are refused with a message naming the field and the reason.
#include <gtest/gtest.h>

#include <stdexcept>

#include "fluid/fluid_test_support.h"

namespace lbsolid::testing {
namespace {

std::string first_error(const FluidConfig& c, int dimension = 2, bool hexagonal = false) {
  const auto errors = fluid::validate_fluid_config(c, dimension, hexagonal);
  return errors.empty() ? "" : errors.front();
}

TEST(FluidConfigTest, DefaultPeriodicBoxIsValid) {
  FluidConfig c;
  c.nx = 8;
  c.ny = 8;
  EXPECT_TRUE(fluid::validate_fluid_config(c, 2, false).empty());
}

TEST(FluidConfigTest, EachBadFieldIsNamed) {
  FluidConfig c;
  c.nx = 0;
  EXPECT_EQ(first_error(c).rfind("nx: must be at least 1", 0), 0u) << first_error(c);

  c = FluidConfig{};
  c.omega = 2.0;
  EXPECT_EQ(first_error(c).rfind("omega: must lie in (0, 2)", 0), 0u) << first_error(c);
  c.omega = 0.0;
  EXPECT_EQ(first_error(c).rfind("omega:", 0), 0u);

  c = FluidConfig{};
  c.rho0 = -1;
  EXPECT_EQ(first_error(c).rfind("rho0:", 0), 0u);

  c = FluidConfig{};
  c.sides[fluid::kYLow].kind = WallKind::kBounceBack;
  EXPECT_EQ(first_error(c), "sides.y_low: periodic must be set on both y_low and y_high");

  c = FluidConfig{};
  c.nz = 3;
  EXPECT_EQ(first_error(c).rfind("nz: must be 1 on a 2D lattice", 0), 0u);

  c = FluidConfig{};
  c.ny = 3;
  EXPECT_EQ(first_error(c, 2, true).rfind("ny: a hexagonal (D2Q7) lattice periodic in y needs an even ny", 0), 0u);

  c = channel_config<D2Q9>(8, WallKind::kMovingWall, WallKind::kBounceBack);
  c.sides[fluid::kYLow].wall_velocity = {0, 0.1, 0};
  EXPECT_EQ(first_error(c), "sides.y_low.wall_velocity: must be tangential to the wall (zero along its normal)");

  c = channel_config<D2Q9>(8, WallKind::kBounceBack, WallKind::kBounceBack);
  c.sides[fluid::kYLow].traction = {0.1, 0, 0};
  EXPECT_EQ(first_error(c), "sides.y_low.traction: is only used by a free-slip wall, not a bounce-back side");

  c = FluidConfig{};
  c.sides[fluid::kXLow].kind = WallKind::kFreeSlip;
  c.sides[fluid::kXHigh].kind = WallKind::kFreeSlip;
  EXPECT_EQ(first_error(c), "sides.x_low: free-slip walls are supported on y and z sides only");

  c = FluidConfig{};
  c.body_force = {std::nan(""), 0, 0};
  EXPECT_EQ(first_error(c), "body_force: must be finite");

  c = FluidConfig{};
  c.streaming = static_cast<fluid::StreamingScheme>(9);
  EXPECT_EQ(first_error(c), "streaming: unknown scheme 9; use in-place or two-buffer");

  c = FluidConfig{};
  c.sides[fluid::kXLow].kind = static_cast<WallKind>(7);
  EXPECT_EQ(first_error(c), "sides.x_low: unknown wall kind 7");
}

TEST(FluidConfigTest, ConstructorRefusesWithEveryReason) {
  FluidConfig c;
  c.nx = -2;
  c.omega = 3;
  try {
    FluidLattice<D2Q9, double> fluid(c);
    FAIL() << "an invalid configuration was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("invalid D2Q9 fluid"), std::string::npos) << message;
    EXPECT_NE(message.find("nx: must be at least 1, got -2"), std::string::npos) << message;
    EXPECT_NE(message.find("omega: must lie in (0, 2)"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace lbsolid::testing
