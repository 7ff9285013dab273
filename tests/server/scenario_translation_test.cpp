// The API's Scenario becomes a core::Scene: absent fields take the defaults scenario.proto
// documents, every enum value has its core counterpart, and every problem, found in the message
// or by the core, comes back together with the others and with the field's full proto path.
// Scenario files parse (text or JSON, errors with line and column), and every file shipped in
// client-examples/scenarios translates cleanly and runs.
#include "io/api/scenario_translation.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/simulation.h"
#include "io/api/core_field_paths.h"
#include "io/api/error_summary.h"
#include "io/api/log_text.h"

namespace lbsolid::server {
namespace {

namespace v1 = lbsolid::v1;
using google::protobuf::util::MessageDifferencer;

v1::Scenario parse(const std::string& text) {
  v1::Scenario scenario;
  std::string error;
  EXPECT_TRUE(parse_scenario_text(text, &scenario, &error)) << error << "\nin:\n" << text;
  return scenario;
}

std::vector<std::string> errors_of(const std::string& text) { return translate_scenario(parse(text)).errors; }

std::string listed(const std::vector<std::string>& errors) {
  std::string out;
  for (const auto& e : errors) out += "\n  " + e;
  return out.empty() ? " (none)" : out;
}

int count_starting(const std::vector<std::string>& errors, const std::string& start) {
  return static_cast<int>(
      std::count_if(errors.begin(), errors.end(), [&](const std::string& e) { return e.rfind(start, 0) == 0; }));
}

#define EXPECT_ERROR(errors, start)           \
  EXPECT_EQ(count_starting(errors, start), 1) \
      << "expected one error starting \"" << (start) << "\"; got" << listed(errors)

const char* const kChannel = R"(
  lattice: LATTICE_D2Q7
  domain { nx: 20 ny: 10 y_low { kind: WALL_KIND_BOUNCE_BACK } y_high { kind: WALL_KIND_BOUNCE_BACK } }
)";

std::string channel_with(const std::string& more) { return kChannel + more; }

// ---- Defaults.

// A binary request may carry fields this build does not know (a newer client): ignored, they would
// change nothing the client expects, and they cannot be written in the text form a checkpoint
// stores, so that checkpoint would never restore (found by fuzz_scenario_binary and fuzz_service).
TEST(ScenarioTranslation, UnknownFieldsAreRefusedByPath) {
  v1::Scenario scenario = parse(channel_with("bodies { shape: BODY_SHAPE_DISK radius: 2 centre { x: 8 y: 4 } }"));
  ASSERT_TRUE(translate_scenario(scenario).ok());
  scenario.GetReflection()->MutableUnknownFields(&scenario)->AddVarint(12, 7);
  auto* body = scenario.mutable_bodies(0);
  body->GetReflection()->MutableUnknownFields(body)->AddFixed64(40, 1);
  const auto errors = translate_scenario(scenario).errors;
  EXPECT_ERROR(errors, "scenario: field number 12 is not a field of lbsolid.v1.Scenario");
  EXPECT_ERROR(errors, "scenario.bodies[0]: field number 40 is not a field of lbsolid.v1.Body");
}

TEST(ScenarioTranslation, AbsentFieldsTakeTheDocumentedDefaults) {
  const TranslatedScenario t = translate_scenario(parse("domain { nx: 8 ny: 6 }"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  scene::Scene expected;  // the core's defaults are the proto's
  expected.fluid.nx = 8;
  expected.fluid.ny = 6;
  EXPECT_EQ(t.scene.lattice, scene::LatticeKind::kD2Q9);
  EXPECT_EQ(t.scene.precision, scene::Precision::kDouble);
  EXPECT_EQ(t.scene.fluid.nz, 1);
  EXPECT_EQ(t.scene.fluid.omega, 1.0);
  EXPECT_EQ(t.scene.fluid.rho0, 1.0);
  EXPECT_EQ(t.scene.fluid.threads, 1);
  EXPECT_EQ(t.scene.fluid.streaming, fluid::StreamingScheme::kInPlace);
  EXPECT_EQ(t.scene.fluid.collision, fluid::CollisionModel::kBgk);
  EXPECT_EQ(t.scene.fluid.trt_magic, 3.0 / 16.0);
  EXPECT_EQ(t.scene.fluid.body_force, expected.fluid.body_force);
  for (int side = 0; side < 6; ++side) {
    EXPECT_EQ(t.scene.fluid.sides[side].kind, fluid::WallKind::kPeriodic);
    EXPECT_EQ(t.scene.fluid.sides[side].wall_velocity, expected.fluid.sides[side].wall_velocity);
    EXPECT_EQ(t.scene.fluid.sides[side].traction, expected.fluid.sides[side].traction);
  }
  EXPECT_TRUE(t.scene.with_fluid);
  EXPECT_TRUE(t.scene.bodies.empty());
  EXPECT_TRUE(t.scene.contact.enabled);
  EXPECT_EQ(t.scene.contact.restitution, 1.0);
  EXPECT_EQ(t.scene.exchange, coupling::ExchangeRule::kCommonVelocity);
  EXPECT_EQ(t.scene.monitor.interval, 100);
  EXPECT_EQ(t.scene.monitor.limits.max_mach, 0.5);
  EXPECT_EQ(t.scene.monitor.limits.min_density, 0.5);
  EXPECT_EQ(t.scene.monitor.limits.max_density, 2.0);
}

TEST(ScenarioTranslation, BodyDefaults) {
  const TranslatedScenario t = translate_scenario(parse(R"(
    domain { nx: 16 ny: 16 }
    bodies { shape: BODY_SHAPE_CHAIN length: 3 centre { x: 5 y: 5 } }
    bodies { name: "named" shape: BODY_SHAPE_DISK radius: 2 centre { x: 10 y: 10 } spacing: 0.5 }
  )"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  ASSERT_EQ(t.scene.bodies.size(), 2u);
  const solid::BodySpec& chain = t.scene.bodies[0];
  EXPECT_EQ(chain.name, "body0");
  EXPECT_EQ(chain.shape, solid::BodyShape::kChain);
  EXPECT_EQ(chain.axis, 0);
  EXPECT_EQ(chain.spacing, 1.0);
  EXPECT_EQ(chain.velocity, (solid::Vec3{0, 0, 0}));
  EXPECT_EQ(chain.load, (solid::Vec3{0, 0, 0}));
  EXPECT_EQ(t.scene.bodies[1].name, "named");
  EXPECT_EQ(t.scene.bodies[1].spacing, 0.5);
  EXPECT_EQ(t.scene.bodies[1].radius, 2.0);
}

// An optional field set to zero is an explicit choice, not the default.
TEST(ScenarioTranslation, ExplicitZeroIsNotTheDefault) {
  const TranslatedScenario t = translate_scenario(parse(R"(
    domain { nx: 8 ny: 8 }
    fluid { enabled: false }
    bodies { shape: BODY_SHAPE_RECTANGLE size: [2, 2] centre { x: 4 y: 4 } }
    contact { enabled: false restitution: 0 }
    stability { check_interval: 7 max_mach: 0.1 }
  )"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  EXPECT_FALSE(t.scene.with_fluid);
  EXPECT_FALSE(t.scene.contact.enabled);
  EXPECT_EQ(t.scene.contact.restitution, 0.0);
  EXPECT_EQ(t.scene.monitor.interval, 7);
  EXPECT_EQ(t.scene.monitor.limits.max_mach, 0.1);
  EXPECT_EQ(errors_of("domain { nx: 8 ny: 8 } fluid { omega: 0 }").size(), 1u);
}

// ---- Enums.

TEST(ScenarioTranslation, EveryEnumValueIsMapped) {
  struct LatticeCase {
    v1::Lattice in;
    scene::LatticeKind out;
    int nz;
  };
  for (const LatticeCase c : {LatticeCase{v1::LATTICE_UNSPECIFIED, scene::LatticeKind::kD2Q9, 1},
                              LatticeCase{v1::LATTICE_D2Q9, scene::LatticeKind::kD2Q9, 1},
                              LatticeCase{v1::LATTICE_D2Q7, scene::LatticeKind::kD2Q7, 1},
                              LatticeCase{v1::LATTICE_D3Q19, scene::LatticeKind::kD3Q19, 4}}) {
    v1::Scenario s = parse("domain { nx: 4 ny: 4 }");
    s.set_lattice(c.in);
    s.mutable_domain()->set_nz(c.nz);
    const TranslatedScenario t = translate_scenario(s);
    EXPECT_TRUE(t.ok()) << v1::Lattice_Name(c.in) << listed(t.errors);
    EXPECT_EQ(t.scene.lattice, c.out) << v1::Lattice_Name(c.in);
  }
  const std::pair<v1::Precision, scene::Precision> precisions[] = {
      {v1::PRECISION_UNSPECIFIED, scene::Precision::kDouble},
      {v1::PRECISION_DOUBLE, scene::Precision::kDouble},
      {v1::PRECISION_FLOAT, scene::Precision::kFloat}};
  for (const auto& [in, out] : precisions) {
    v1::Scenario s = parse("domain { nx: 4 ny: 4 }");
    s.set_precision(in);
    EXPECT_EQ(translate_scenario(s).scene.precision, out) << v1::Precision_Name(in);
  }
  const std::pair<v1::Streaming, fluid::StreamingScheme> schemes[] = {
      {v1::STREAMING_UNSPECIFIED, fluid::StreamingScheme::kInPlace},
      {v1::STREAMING_IN_PLACE, fluid::StreamingScheme::kInPlace},
      {v1::STREAMING_TWO_BUFFER, fluid::StreamingScheme::kTwoBuffer}};
  for (const auto& [in, out] : schemes) {
    v1::Scenario s = parse("domain { nx: 4 ny: 4 }");
    s.mutable_fluid()->set_streaming(in);
    EXPECT_EQ(translate_scenario(s).scene.fluid.streaming, out) << v1::Streaming_Name(in);
  }
  const std::pair<v1::Collision, fluid::CollisionModel> collisions[] = {
      {v1::COLLISION_UNSPECIFIED, fluid::CollisionModel::kBgk},
      {v1::COLLISION_BGK, fluid::CollisionModel::kBgk},
      {v1::COLLISION_TRT, fluid::CollisionModel::kTrt},
      {v1::COLLISION_REGULARIZED, fluid::CollisionModel::kRegularized}};
  for (const auto& [in, out] : collisions) {
    v1::Scenario s = parse("domain { nx: 4 ny: 4 }");
    s.mutable_fluid()->set_collision(in);
    const TranslatedScenario t = translate_scenario(s);
    EXPECT_TRUE(t.ok()) << v1::Collision_Name(in) << listed(t.errors);
    EXPECT_EQ(t.scene.fluid.collision, out) << v1::Collision_Name(in);
  }
  const std::pair<v1::ExchangeRule, coupling::ExchangeRule> rules[] = {
      {v1::EXCHANGE_RULE_UNSPECIFIED, coupling::ExchangeRule::kCommonVelocity},
      {v1::EXCHANGE_RULE_COMMON_VELOCITY, coupling::ExchangeRule::kCommonVelocity},
      {v1::EXCHANGE_RULE_PAIRWISE, coupling::ExchangeRule::kPairwise}};
  for (const auto& [in, out] : rules) {
    v1::Scenario s = parse("domain { nx: 4 ny: 4 }");
    s.set_exchange(in);
    EXPECT_EQ(translate_scenario(s).scene.exchange, out) << v1::ExchangeRule_Name(in);
  }
}

TEST(ScenarioTranslation, WallKindsMapOnEverySide) {
  const std::pair<const char*, fluid::WallKind> kinds[] = {{"WALL_KIND_UNSPECIFIED", fluid::WallKind::kPeriodic},
                                                           {"WALL_KIND_PERIODIC", fluid::WallKind::kPeriodic},
                                                           {"WALL_KIND_BOUNCE_BACK", fluid::WallKind::kBounceBack},
                                                           {"WALL_KIND_MOVING_WALL", fluid::WallKind::kMovingWall},
                                                           {"WALL_KIND_FREE_SLIP", fluid::WallKind::kFreeSlip},
                                                           // x sides only: the others are errors, but mapped
                                                           {"WALL_KIND_VELOCITY_INLET", fluid::WallKind::kVelocityInlet},
                                                           {"WALL_KIND_PRESSURE_OUTLET", fluid::WallKind::kPressureOutlet}};
  for (const auto& [name, kind] : kinds) {
    const std::string side = std::string("{ kind: ") + name + " }";
    const TranslatedScenario t =
        translate_scenario(parse("lattice: LATTICE_D3Q19 domain { nx: 4 ny: 4 nz: 4 x_low " + side + " x_high " + side +
                                 " y_low " + side + " y_high " + side + " z_low " + side + " z_high " + side + " }"));
    for (int s = 0; s < 6; ++s) EXPECT_EQ(t.scene.fluid.sides[s].kind, kind) << name << " on side " << s;
  }
  // Side vectors arrive on their own side.
  const TranslatedScenario t = translate_scenario(parse(R"(
    domain { nx: 8 ny: 8
      y_low { kind: WALL_KIND_MOVING_WALL wall_velocity { x: 0.01 } }
      y_high { kind: WALL_KIND_FREE_SLIP traction { x: 2e-4 } } }
  )"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  EXPECT_EQ(t.scene.fluid.sides[fluid::kYLow].wall_velocity, (fluid::Vec3{0.01, 0, 0}));
  EXPECT_EQ(t.scene.fluid.sides[fluid::kYHigh].traction, (fluid::Vec3{2e-4, 0, 0}));
}

TEST(ScenarioTranslation, BodyShapesAndChainAxesMap) {
  const TranslatedScenario t = translate_scenario(parse(R"(
    lattice: LATTICE_D3Q19
    domain { nx: 16 ny: 16 nz: 16 }
    bodies { shape: BODY_SHAPE_RECTANGLE size: [2, 3, 4] centre { x: 8 y: 8 z: 8 } }
    bodies { shape: BODY_SHAPE_DISK radius: 2.5 centre { x: 8 y: 8 z: 8 } }
    bodies { shape: BODY_SHAPE_CHAIN length: 3 centre { x: 8 y: 8 z: 8 } }
    bodies { shape: BODY_SHAPE_CHAIN length: 3 axis: AXIS_X centre { x: 8 y: 8 z: 8 } }
    bodies { shape: BODY_SHAPE_CHAIN length: 3 axis: AXIS_Y centre { x: 8 y: 8 z: 8 } }
    bodies { shape: BODY_SHAPE_CHAIN length: 3 axis: AXIS_Z centre { x: 8 y: 8 z: 8 } }
    bodies { shape: BODY_SHAPE_LABELS centre { x: 8 y: 8 z: 8 }
             labels { i: 0 } labels { i: 1 } labels { i: 1 j: 1 k: 2 } labels { i: 1 j: 1 k: 1 } labels { i: 1 j: 1 } }
  )"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  const auto& b = t.scene.bodies;
  ASSERT_EQ(b.size(), 7u);
  EXPECT_EQ(b[0].shape, solid::BodyShape::kRectangle);
  EXPECT_EQ(b[0].size, (std::array<int, 3>{2, 3, 4}));
  EXPECT_EQ(b[1].shape, solid::BodyShape::kDisk);
  EXPECT_EQ(b[1].radius, 2.5);
  EXPECT_EQ(b[2].shape, solid::BodyShape::kChain);
  EXPECT_EQ(b[2].length, 3);
  EXPECT_EQ(b[2].axis, 0);  // AXIS_UNSPECIFIED means x
  EXPECT_EQ(b[3].axis, 0);
  EXPECT_EQ(b[4].axis, 1);
  EXPECT_EQ(b[5].axis, 2);
  EXPECT_EQ(b[6].shape, solid::BodyShape::kLabels);
  EXPECT_EQ(b[6].labels, (std::vector<solid::Label>{{0, 0, 0}, {1, 0, 0}, {1, 1, 2}, {1, 1, 1}, {1, 1, 0}}));
  EXPECT_EQ(b[0].centre, (solid::Vec3{8, 8, 8}));
  // A 2D rectangle has two extents; the core's third is 1.
  const TranslatedScenario flat = translate_scenario(
      parse("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_RECTANGLE size: [3, 2] centre { x: 4 y: 4 } }"));
  ASSERT_TRUE(flat.ok()) << listed(flat.errors);
  EXPECT_EQ(flat.scene.bodies[0].size, (std::array<int, 3>{3, 2, 1}));
}

TEST(ScenarioTranslation, UnknownEnumNumbersAreReported) {
  EXPECT_EQ(
      errors_of("lattice: 7 domain { nx: 4 ny: 4 }"),
      std::vector<std::string>{"scenario.lattice: unknown value 7; use LATTICE_D2Q9, LATTICE_D2Q7 or LATTICE_D3Q19"});
  const auto errors = errors_of(R"(
    precision: 9 exchange: 5
    domain { nx: 4 ny: 4 y_low { kind: 8 } y_high { kind: WALL_KIND_BOUNCE_BACK } }
    fluid { streaming: 3 collision: 4 }
    bodies { shape: 11 }
    bodies { shape: BODY_SHAPE_CHAIN length: 2 axis: 6 centre { x: 2 y: 2 } }
  )");
  EXPECT_ERROR(errors, "scenario.precision: unknown value 9; use PRECISION_DOUBLE or PRECISION_FLOAT");
  EXPECT_ERROR(errors, "scenario.exchange: unknown value 5");
  EXPECT_ERROR(errors, "scenario.domain.y_low.kind: unknown value 8; use WALL_KIND_PERIODIC, WALL_KIND_BOUNCE_BACK");
  EXPECT_ERROR(errors, "scenario.fluid.streaming: unknown value 3");
  EXPECT_ERROR(errors, "scenario.fluid.collision: unknown value 4; use COLLISION_BGK, COLLISION_TRT or COLLISION_REGULARIZED");
  EXPECT_ERROR(errors, "scenario.bodies[0].shape: unknown value 11");
  EXPECT_ERROR(errors, "scenario.bodies[1].axis: unknown value 6");
  // The core's own reports of the same fields are not repeated.
  EXPECT_EQ(errors.size(), 7u) << listed(errors);
}

// ---- Errors, with their full field paths.

TEST(ScenarioTranslation, NearEdgeParametersAreWarnedOnTheirProtoPaths) {
  const auto t = translate_scenario(parse(channel_with(
      "fluid { omega: 1.97 } bodies { shape: BODY_SHAPE_DISK radius: 2 centre { x: 8 y: 4 } velocity { x: 0.06 } }")));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  ASSERT_EQ(t.warnings.size(), 2u) << listed(t.warnings);
  EXPECT_EQ(t.warnings[0].rfind("scenario.fluid.omega: 1.97 is above 1.95", 0), 0u) << t.warnings[0];
  // D2Q7: c_s = 1/2, so 0.06 is Mach 0.12.
  EXPECT_EQ(t.warnings[1].rfind("scenario.bodies[0].velocity: initial Mach number 0.12 is above 0.1", 0), 0u)
      << t.warnings[1];
  EXPECT_TRUE(translate_scenario(parse(channel_with(""))).warnings.empty());
}

TEST(ScenarioTranslation, OmegaOutsideItsRange) {
  EXPECT_ERROR(errors_of("domain { nx: 4 ny: 4 } fluid { omega: 0 }"), "scenario.fluid.omega: must lie in (0, 2)");
  const auto errors = errors_of("domain { nx: 4 ny: 4 } fluid { omega: 2.5 }");
  ASSERT_EQ(errors.size(), 1u) << listed(errors);
  EXPECT_EQ(errors[0].rfind("scenario.fluid.omega: must lie in (0, 2) for a stable, positive viscosity, got 2.5", 0),
            0u)
      << errors[0];
}

TEST(ScenarioTranslation, TrtMagicIsMappedAndMustBePositive) {
  const TranslatedScenario t =
      translate_scenario(parse("domain { nx: 4 ny: 4 } fluid { collision: COLLISION_TRT trt_magic: 0.25 }"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  EXPECT_EQ(t.scene.fluid.collision, fluid::CollisionModel::kTrt);
  EXPECT_EQ(t.scene.fluid.trt_magic, 0.25);
  for (const char* bad : {"0", "-0.1", "nan", "inf"}) {
    const auto errors =
        errors_of(std::string("domain { nx: 4 ny: 4 } fluid { collision: COLLISION_TRT trt_magic: ") + bad + " }");
    ASSERT_EQ(errors.size(), 1u) << bad << listed(errors);
    EXPECT_EQ(errors[0].rfind("scenario.fluid.trt_magic: must be positive, got ", 0), 0u) << errors[0];
  }
}

TEST(ScenarioTranslation, EachCollisionOperatorBuildsAndRuns) {
  for (const char* collision : {"COLLISION_BGK", "COLLISION_TRT", "COLLISION_REGULARIZED"}) {
    const TranslatedScenario t = translate_scenario(parse(channel_with(
        std::string("fluid { omega: 1.3 body_force { x: 1e-5 } collision: ") + collision + " }")));
    ASSERT_TRUE(t.ok()) << collision << listed(t.errors);
    auto simulation = scene::build_simulation(t.scene);
    simulation->run(3);
    EXPECT_EQ(simulation->step_count(), 3) << collision;
  }
}

TEST(ScenarioTranslation, GridProblemsNameTheDomain) {
  EXPECT_EQ(errors_of("domain { nx: 0 ny: 4 }"),
            std::vector<std::string>{"scenario.domain.nx: must be at least 1, got 0"});
  EXPECT_EQ(errors_of("domain { nx: 4 ny: -2 }"),
            std::vector<std::string>{"scenario.domain.ny: must be at least 1, got -2"});
  EXPECT_EQ(errors_of("lattice: LATTICE_D2Q7"),
            std::vector<std::string>{"scenario.domain: required: the box's nodes along x and y (nx, ny >= 1)"});
  EXPECT_EQ(errors_of("domain { nx: 4 ny: 4 nz: 3 }"),
            std::vector<std::string>{"scenario.domain.nz: must be 1 on a 2D lattice (D2Q9), got 3"});
  // More than 2^31 nodes, and a 3D grid whose node count overflows 64 bits: one error each.
  const auto big = errors_of("domain { nx: 65536 ny: 32769 }");
  ASSERT_EQ(big.size(), 1u) << listed(big);
  EXPECT_EQ(big[0].rfind("scenario.domain: 65536 x 32769 x 1 = ", 0), 0u) << big[0];
  EXPECT_NE(big[0].find("more than the limit of 2^31"), std::string::npos) << big[0];
  EXPECT_TRUE(translate_scenario(parse("domain { nx: 65536 ny: 32768 }")).ok()) << "exactly 2^31 nodes is allowed";
  const auto huge = errors_of("lattice: LATTICE_D3Q19 domain { nx: 2147483647 ny: 2147483647 nz: 2147483647 }");
  ASSERT_EQ(huge.size(), 1u) << listed(huge);
  EXPECT_EQ(huge[0].rfind("scenario.domain: 2147483647 x 2147483647 x 2147483647", 0), 0u) << huge[0];
}

TEST(ScenarioTranslation, BodyOutsideTheDomain) {
  const auto errors = errors_of(channel_with("bodies { shape: BODY_SHAPE_DISK radius: 2 centre { x: 10 y: 1 } }"));
  ASSERT_EQ(errors.size(), 1u) << listed(errors);
  EXPECT_EQ(
      errors[0].rfind("scenario.bodies[0].centre: particle at (10, -1) lies on or beyond the y_low wall (at -0.433", 0),
      0u)
      << errors[0];
}

TEST(ScenarioTranslation, DuplicateBodyNamesAreRefused) {
  // Streams and H5MD files name bodies: two bodies cannot share a name.
  const auto errors = errors_of(channel_with(
      "bodies { name: \"disk\" shape: BODY_SHAPE_DISK radius: 2 centre { x: 6 y: 4 } }"
      "bodies { name: \"disk\" shape: BODY_SHAPE_DISK radius: 2 centre { x: 14 y: 4 } }"));
  ASSERT_EQ(errors.size(), 1u) << listed(errors);
  EXPECT_EQ(errors[0], "scenario.bodies[1].name: \"disk\" is already the name of bodies[0]");
}

TEST(ScenarioTranslation, BodyShapeIsRequired) {
  EXPECT_EQ(errors_of("domain { nx: 8 ny: 8 } bodies { centre { x: 4 y: 4 } }"),
            std::vector<std::string>{"scenario.bodies[0].shape: required (rectangle, disk, chain or labels)"});
  // Without fluid, the core (which never sees a body without a shape) does not add "needs a body".
  EXPECT_EQ(errors_of("domain { nx: 8 ny: 8 } fluid { enabled: false } bodies { centre { x: 4 y: 4 } }"),
            std::vector<std::string>{"scenario.bodies[0].shape: required (rectangle, disk, chain or labels)"});
}

TEST(ScenarioTranslation, RectangleSizeHasOneValuePerAxis) {
  EXPECT_EQ(
      errors_of("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_RECTANGLE size: [2, 2, 2] centre { x: 4 y: 4 } }"),
      std::vector<std::string>{"scenario.bodies[0].size: a rectangle needs 2 values (particles along x and y), got 3"});
  EXPECT_EQ(errors_of("lattice: LATTICE_D3Q19 domain { nx: 8 ny: 8 nz: 8 } "
                      "bodies { shape: BODY_SHAPE_RECTANGLE size: 4 centre { x: 4 y: 4 z: 4 } }"),
            std::vector<std::string>{
                "scenario.bodies[0].size: a rectangle needs 3 values (particles along x, y and z), got 1"});
  EXPECT_ERROR(
      errors_of("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_RECTANGLE size: [0, 3] centre { x: 4 y: 4 } }"),
      "scenario.bodies[0].size: every extent must be at least 1 particle");
}

TEST(ScenarioTranslation, StabilityLimits) {
  EXPECT_EQ(errors_of("domain { nx: 4 ny: 4 } stability { max_mach: 0 }"),
            std::vector<std::string>{"scenario.stability.max_mach: must be a positive finite number, got 0"});
  EXPECT_EQ(errors_of("domain { nx: 4 ny: 4 } stability { max_mach: -0.1 }"),
            std::vector<std::string>{"scenario.stability.max_mach: must be a positive finite number, got -0.1"});
  EXPECT_EQ(errors_of("domain { nx: 4 ny: 4 } stability { max_mach: inf }"),
            std::vector<std::string>{"scenario.stability.max_mach: must be a positive finite number, got inf"});
  EXPECT_EQ(errors_of("domain { nx: 4 ny: 4 } stability { check_interval: 0 }"),
            std::vector<std::string>{"scenario.stability.check_interval: must be at least 1, got 0"});
  const auto band = translate_scenario(parse("domain { nx: 4 ny: 4 } stability { min_density: 0.9 max_density: 1.1 }"));
  EXPECT_TRUE(band.ok()) << listed(band.errors);
  EXPECT_EQ(band.scene.monitor.limits.min_density, 0.9);
  EXPECT_EQ(band.scene.monitor.limits.max_density, 1.1);
  EXPECT_EQ(errors_of("domain { nx: 4 ny: 4 } stability { min_density: 1 max_density: 0.5 }"),
            (std::vector<std::string>{
                "scenario.stability.min_density: must lie in [0, 1) (a fraction of rho0), got 1",
                "scenario.stability.max_density: must be above 1 (a multiple of rho0; infinity for none), got 0.5"}));
}

TEST(ScenarioTranslation, OutputsAreCheckedOnTheirPaths) {
  const std::string disk = R"(bodies { name: "disk" shape: BODY_SHAPE_DISK radius: 2 centre { x: 8 y: 4 } })";
  const auto good = translate_scenario(parse(channel_with(
      disk + R"(outputs { particles_every: 10 particle_bodies: "disk" profile_every: 5 final_fields: true
                          checkpoint_every: 1000 })")));
  ASSERT_TRUE(good.ok()) << listed(good.errors);
  EXPECT_EQ(good.outputs.particles_every, 10);
  EXPECT_EQ(good.outputs.particle_bodies, std::vector<std::string>{"disk"});
  EXPECT_EQ(good.outputs.profile_every, 5);
  EXPECT_TRUE(good.outputs.final_fields);
  EXPECT_EQ(good.outputs.checkpoint_every, 1000);
  EXPECT_TRUE(translate_scenario(parse(kChannel)).ok());  // no outputs: nothing recorded, nothing to check
  EXPECT_FALSE(translate_scenario(parse(kChannel)).outputs.records_frames());

  const auto errors = errors_of(channel_with(
      disk + R"(outputs { particles_every: -1 particle_bodies: "plate" fields_every: 1099511627777 })"));
  EXPECT_ERROR(errors, "scenario.outputs.particles_every: must lie in [0, 2^40] steps (0: none), got -1");
  EXPECT_ERROR(errors, "scenario.outputs.fields_every: must lie in [0, 2^40]");
  EXPECT_ERROR(errors, "scenario.outputs.particle_bodies[0]: no body of that name");
  EXPECT_ERROR(errors, "scenario.outputs.particle_bodies: set particles_every to record them");
  EXPECT_ERROR(errors_of(channel_with("fluid { enabled: false } outputs { profile_every: 10 }")),
               "scenario.outputs: velocity profiles and fields need a fluid");
  EXPECT_ERROR(errors_of(channel_with("outputs { particles_every: 10 }")),
               "scenario.outputs.particles_every: the scenario has no bodies");
}

TEST(ScenarioTranslation, EveryErrorIsReportedTogether) {
  const auto errors = errors_of(channel_with(R"(
    fluid { omega: 2.5 rho0: -1 }
    bodies { shape: BODY_SHAPE_DISK radius: 2 centre { x: 10 y: 1 } }
    bodies { radius: 3 }
    bodies { shape: BODY_SHAPE_DISK radius: 2 centre { x: 10 y: 30 } }
    contact { restitution: 1.5 }
    stability { max_mach: 0 }
  )"));
  EXPECT_ERROR(errors, "scenario.fluid.omega: must lie in (0, 2)");
  EXPECT_ERROR(errors, "scenario.fluid.rho0: must be a positive finite density");
  EXPECT_ERROR(errors, "scenario.bodies[0].centre: particle at (10, -1) lies on or beyond the y_low wall");
  EXPECT_ERROR(errors, "scenario.bodies[1].shape: required");
  // The core never saw body 1; its report on the third body still names bodies[2].
  EXPECT_ERROR(errors, "scenario.bodies[2].centre: particle at ");
  EXPECT_ERROR(errors, "scenario.contact.restitution: must lie in [0, 1]");
  EXPECT_ERROR(errors, "scenario.stability.max_mach: must be a positive finite number");
  EXPECT_EQ(errors.size(), 7u) << listed(errors);
}

// Each field the core names comes back on its proto path, never on the bare "scenario: " fallback.
TEST(ScenarioTranslation, EveryCoreFieldHasItsProtoPath) {
  struct Case {
    std::string scenario, error;
  };
  const Case cases[] = {
      {"domain { nx: 4 ny: 4 } fluid { rho0: 0 }", "scenario.fluid.rho0: must be a positive finite density"},
      {"domain { nx: 4 ny: 4 } fluid { threads: 0 }", "scenario.fluid.threads: must be at least 1, got 0"},
      {"domain { nx: 4 ny: 4 } fluid { body_force { x: nan } }", "scenario.fluid.body_force: must be finite"},
      {"domain { nx: 4 ny: 4 } fluid { enabled: false }",
       "scenario.bodies: a scene without fluid needs at least one body"},
      {"domain { nx: 4 ny: 4 } fluid { enabled: false body_force { x: 1e-5 } } "
       "bodies { shape: BODY_SHAPE_CHAIN length: 2 centre { x: 2 y: 2 } }",
       "scenario.fluid.body_force: is set but the scene has no fluid to push"},
      {"domain { nx: 4 ny: 4 y_low { kind: WALL_KIND_BOUNCE_BACK } }",
       "scenario.domain.y_low.kind: periodic must be set on both y_low and y_high"},
      {"domain { nx: 4 ny: 4 x_low { kind: WALL_KIND_FREE_SLIP } x_high { kind: WALL_KIND_FREE_SLIP } }",
       "scenario.domain.x_low.kind: free-slip walls are supported on y and z sides only"},
      {"domain { nx: 4 ny: 4 z_low { kind: WALL_KIND_BOUNCE_BACK } z_high { kind: WALL_KIND_BOUNCE_BACK } }",
       "scenario.domain.z_low.kind: a 2D lattice has no z walls; use periodic"},
      {"domain { nx: 4 ny: 4 y_low { kind: WALL_KIND_MOVING_WALL wall_velocity { y: 0.1 } } "
       "y_high { kind: WALL_KIND_BOUNCE_BACK } }",
       "scenario.domain.y_low.wall_velocity: must be tangential to the wall"},
      {"domain { nx: 4 ny: 4 y_low { kind: WALL_KIND_BOUNCE_BACK traction { x: 0.1 } } "
       "y_high { kind: WALL_KIND_BOUNCE_BACK } }",
       "scenario.domain.y_low.traction: is only used by a free-slip wall"},
      {"lattice: LATTICE_D2Q7 domain { nx: 4 ny: 5 }",
       "scenario.domain.ny: a hexagonal (D2Q7) lattice periodic in y needs an even ny"},
      {"domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_DISK radius: 0.5 centre { x: 4 y: 4 } }",
       "scenario.bodies[0].radius: must be at least 1"},
      {"domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_CHAIN length: 1 centre { x: 4 y: 4 } }",
       "scenario.bodies[0].length: a chain needs at least 2 particles"},
      {"domain { nx: 8 ny: 8 } "
       "bodies { shape: BODY_SHAPE_LABELS labels { i: 1 } labels { i: 1 } centre { x: 4 y: 4 } }",
       "scenario.bodies[0].labels: label (1, 0, 0) appears twice"},
      {"domain { nx: 8 ny: 8 } "
       "bodies { shape: BODY_SHAPE_LABELS labels { i: 1 } labels { i: 2 k: 1 } centre { x: 4 y: 4 } }",
       "scenario.bodies[0].labels: a 2D label has a zero third component"},
      {"domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_CHAIN length: 2 spacing: 0 centre { x: 4 y: 4 } }",
       "scenario.bodies[0].spacing: must be a positive number"},
      {"domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_CHAIN length: 2 velocity { x: inf } centre { x: 4 y: 4 } }",
       "scenario.bodies[0].velocity: must be finite"},
      {"domain { nx: 8 ny: 8 } contact { restitution: -0.5 }", "scenario.contact.restitution: must lie in [0, 1]"},
  };
  for (const Case& c : cases) {
    const auto errors = errors_of(c.scenario);
    EXPECT_ERROR(errors, c.error) << "\nfor: " << c.scenario;
    EXPECT_EQ(count_starting(errors, "scenario: "), 0) << listed(errors);
  }
}

TEST(ScenarioTranslation, MessageLevelChecks) {
  // A field of another shape.
  EXPECT_EQ(
      errors_of(
          "domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_RECTANGLE size: [2, 2] radius: 3 centre { x: 4 y: 4 } }"),
      std::vector<std::string>{"scenario.bodies[0].radius: is only used by BODY_SHAPE_DISK, not BODY_SHAPE_RECTANGLE"});
  // A chain along z on a 2D lattice, said once and in the API's words.
  EXPECT_EQ(
      errors_of(
          "domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_CHAIN length: 2 axis: AXIS_Z centre { x: 4 y: 4 } }"),
      std::vector<std::string>{"scenario.bodies[0].axis: AXIS_Z on a 2D lattice; use AXIS_X or AXIS_Y"});
  // z of a vector is ignored in 2D (scenario.proto), but a z side's vector is a mistake.
  const TranslatedScenario t =
      translate_scenario(parse("domain { nx: 8 ny: 8 } fluid { body_force { x: 1e-6 z: 3 } } "
                               "bodies { shape: BODY_SHAPE_CHAIN length: 2 centre { x: 4 y: 4 z: 9 } load { z: 1 } }"));
  ASSERT_TRUE(t.ok()) << listed(t.errors);
  EXPECT_EQ(t.scene.fluid.body_force, (fluid::Vec3{1e-6, 0, 0}));
  EXPECT_EQ(t.scene.bodies[0].centre, (solid::Vec3{4, 4, 0}));
  EXPECT_EQ(errors_of("domain { nx: 8 ny: 8 z_high { traction { x: 1 } } }"),
            std::vector<std::string>{"scenario.domain.z_high.traction: a 2D lattice has no z sides"});
}

// Sizes that would make validation itself overflow or list billions of labels, or a build start
// thousands of threads, are refused first.
TEST(ScenarioTranslation, AbsurdBodiesAreRefusedCheaply) {
  EXPECT_ERROR(
      errors_of(
          "domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_RECTANGLE size: [100000, 100000] centre { x: 4 y: 4 } }"),
      "scenario.bodies[0].size: 1e+10 particles, more than the limit of 2^24 per body");
  EXPECT_ERROR(errors_of("domain { nx: 8 ny: 8 } "
                         "bodies { shape: BODY_SHAPE_RECTANGLE size: [-100000, -100000] centre { x: 4 y: 4 } }"),
               "scenario.bodies[0].size: every extent must be at least 1 particle");
  EXPECT_EQ(errors_of("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_DISK radius: inf centre { x: 4 y: 4 } }"),
            std::vector<std::string>{"scenario.bodies[0].radius: must be a finite number, got inf"});
  EXPECT_ERROR(errors_of("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_DISK radius: 1e6 centre { x: 4 y: 4 } }"),
               "scenario.bodies[0].radius: a disk of radius 1e+06 spans");
  EXPECT_ERROR(
      errors_of("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_CHAIN length: 2000000000 centre { x: 4 y: 4 } }"),
      "scenario.bodies[0].length: 2000000000 particles, more than the limit");
  EXPECT_EQ(errors_of("domain { nx: 8 ny: 8 } fluid { threads: 100000 }"),
            std::vector<std::string>{"scenario.fluid.threads: must be at most 256, got 100000"});
  EXPECT_ERROR(
      errors_of("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_LABELS labels { i: 2147483647 } labels { } }"),
      "scenario.bodies[0].labels[0]: components must lie within +-2^30");
}

// ---- Names and many problems.

// Names are one line of at most 256 bytes: they are logged, listed, printed on terminals and used
// as keys of output files. Each error names the field and the reason, without echoing the name.
TEST(ScenarioTranslation, NamesAreOneLineOfAtMost256Bytes) {
  const auto named = [](const std::string& scenario_name, const std::string& body_name) {
    v1::Scenario s = parse("domain { nx: 8 ny: 8 } bodies { shape: BODY_SHAPE_CHAIN length: 2 centre { x: 4 y: 4 } }");
    s.set_name(scenario_name);
    s.mutable_bodies(0)->set_name(body_name);
    return translate_scenario(s).errors;
  };
  EXPECT_EQ(named(std::string(256, 's'), std::string(256, 'b')), std::vector<std::string>{});
  EXPECT_EQ(named("plain name, with punctuation: \xc3\xa9 \xe2\x82\xac", "disk #1"), std::vector<std::string>{});
  EXPECT_EQ(named(std::string(257, 's'), std::string(100000, 'b')),
            (std::vector<std::string>{"scenario.name: 257 bytes, more than the limit of 256",
                                      "scenario.bodies[0].name: 100000 bytes, more than the limit of 256"}));
  const std::string line = ": a name is one line of printable text; it holds the control character ";
  EXPECT_EQ(named("run\n2024-01-01 INFO forged", "ok"),
            std::vector<std::string>{"scenario.name" + line + "U+000A at byte 3"});
  EXPECT_EQ(named("ok", "tab\there"), std::vector<std::string>{"scenario.bodies[0].name" + line + "U+0009 at byte 3"});
  EXPECT_EQ(named("\x1b[2J", "ok"), std::vector<std::string>{"scenario.name" + line + "U+001B at byte 0"});
  EXPECT_EQ(named("del\x7f", "ok"), std::vector<std::string>{"scenario.name" + line + "U+007F at byte 3"});
  EXPECT_EQ(named("c1 \xc2\x9b", "ok"), std::vector<std::string>{"scenario.name" + line + "U+009B at byte 3"});
  EXPECT_EQ(named("ls \xe2\x80\xa8", "ok"), std::vector<std::string>{"scenario.name" + line + "U+2028 at byte 3"});
  // Two bodies of one refused name: the core's "already the name of" would restate the same field.
  v1::Scenario twice = parse("domain { nx: 8 ny: 8 } "
                             "bodies { shape: BODY_SHAPE_CHAIN length: 2 centre { x: 2 y: 2 } } "
                             "bodies { shape: BODY_SHAPE_CHAIN length: 2 centre { x: 6 y: 6 } }");
  twice.mutable_bodies(0)->set_name("a\rb");
  twice.mutable_bodies(1)->set_name("a\rb");
  EXPECT_EQ(translate_scenario(twice).errors,
            (std::vector<std::string>{"scenario.bodies[0].name" + line + "U+000D at byte 1",
                                      "scenario.bodies[1].name" + line + "U+000D at byte 1"}));
}

// 10^5 bodies of one name are one error with a count (the core's check is n log n, as is every
// pass of the translation; lbsolid-translation-bench measures them).
TEST(ScenarioTranslation, ManyBodiesOfOneNameAreOneErrorWithACount) {
  v1::Scenario s = parse("domain { nx: 8 ny: 8 }");
  v1::Body chain = parse("bodies { name: \"chain\" shape: BODY_SHAPE_CHAIN length: 2 centre { x: 4 y: 4 } }").bodies(0);
  for (int b = 0; b < 100000; ++b) *s.add_bodies() = chain;
  EXPECT_EQ(translate_scenario(s).errors,
            std::vector<std::string>{"scenario.bodies[1].name: \"chain\" is already the name of bodies[0] "
                                     "(100000 bodies share this name; the last is bodies[99999])"});
}

// Every problem of 10^5 bodies is kept (a caller in process sees them all); a client is sent the
// first ones and how many more.
TEST(ScenarioTranslation, EveryProblemOfManyBodiesIsKeptAndSummarised) {
  v1::Scenario s = parse("domain { nx: 8 ny: 8 }");
  // A lone label (core: needs 2 particles) and a stray radius (translation: not a disk's).
  v1::Body lone = parse("bodies { shape: BODY_SHAPE_LABELS labels { } radius: 1 centre { x: 4 y: 4 } }").bodies(0);
  constexpr int kBodies = 100000;
  for (int b = 0; b < kBodies; ++b) *s.add_bodies() = lone;
  const TranslatedScenario t = translate_scenario(s);
  ASSERT_EQ(t.errors.size(), 2u * kBodies);
  EXPECT_EQ(t.errors[0], "scenario.bodies[0].radius: is only used by BODY_SHAPE_DISK, not BODY_SHAPE_LABELS");
  EXPECT_EQ(t.errors[1], "scenario.bodies[1].radius: is only used by BODY_SHAPE_DISK, not BODY_SHAPE_LABELS");
  EXPECT_EQ(t.errors[kBodies], "scenario.bodies[0].labels: a body needs at least 2 particles");
  EXPECT_EQ(t.errors.back(), "scenario.bodies[99999].labels: a body needs at least 2 particles");
  const std::string summary = error_summary(t.errors);
  EXPECT_LE(summary.size(), kMaxSummaryBytes);
  EXPECT_EQ(summary.rfind(t.errors[0] + "; " + t.errors[1] + "; ", 0), 0u) << summary;
  EXPECT_TRUE(summary.ends_with("; " + t.errors[19] + "; ... and 199980 more problems")) << summary;
}

// Bytes of `text` once gRPC percent-encodes it as the grpc-message header: everything outside
// printable ASCII, and '%', takes 3.
std::size_t percent_encoded_size(const std::string& text) {
  std::size_t size = 0;
  for (unsigned char c : text) size += c < 0x20 || c > 0x7E || c == '%' ? 3 : 1;
  return size;
}

// A client refuses a status over its 8 KiB metadata limit as RESOURCE_EXHAUSTED, which means
// "retry": whatever the problems, the summary is at most 2 KiB, 6 KiB once encoded.
TEST(ErrorSummary, FitsInAStatusMessageWhateverTheProblems) {
  EXPECT_EQ(error_summary({}), "");
  const std::vector<std::string> few = {"scenario.fluid.omega: must lie in (0, 2), got 2.5",
                                        "scenario.domain.nx: must be at least 1, got 0"};
  EXPECT_EQ(error_summary(few), few[0] + "; " + few[1]);  // a short list is joined as before
  std::vector<std::string> twenty;
  for (int p = 0; p < 20; ++p)
    twenty.push_back("scenario.bodies[" + std::to_string(p) + "].radius: must be at least 1");
  std::string joined = twenty[0];
  for (int p = 1; p < 20; ++p) joined += "; " + twenty[p];
  EXPECT_EQ(error_summary(twenty), joined);
  twenty.push_back("scenario.bodies[20].radius: must be at least 1");
  EXPECT_EQ(error_summary(twenty), joined + "; ... and 1 more problem");

  // 130 problems of 100 bytes (the case that was retried forever): as many as fit, then a count.
  std::vector<std::string> many(130, "scenario.bodies[0].centre: " + std::string(73, 'x'));
  std::string summary = error_summary(many);
  EXPECT_LE(summary.size(), kMaxSummaryBytes);
  EXPECT_TRUE(summary.ends_with("; ... and 111 more problems")) << summary;  // 19 of 100 bytes fit

  // Problems that echo long text, in bytes that percent-encoding triples, each cut on a character.
  const std::string e_acute = "\xc3\xa9";
  std::string long_text;
  for (int c = 0; c < 5000; ++c) long_text += e_acute;
  std::vector<std::string> wide(200, "scenario.name: " + long_text);
  summary = error_summary(wide);
  EXPECT_LE(summary.size(), kMaxSummaryBytes);
  EXPECT_LE(percent_encoded_size(summary), 3 * kMaxSummaryBytes);
  EXPECT_LT(3 * kMaxSummaryBytes, 8192u - 1024u);  // room for the call's other headers
  // 256 bytes: "scenario.name: " (15) and 120 whole characters, the cut one left out.
  EXPECT_EQ(summary.rfind("scenario.name: " + long_text.substr(0, 240) + "...; ", 0), 0u) << summary;
  EXPECT_TRUE(summary.ends_with(" more problems")) << summary;
}

// From translation to summary: 200 bodies in pairs of one 256-byte name.
TEST(ErrorSummary, SharedLongNamesStayShort) {
  v1::Scenario s = parse("domain { nx: 8 ny: 8 }");
  for (int b = 0; b < 200; ++b) {
    v1::Body& body = *s.add_bodies();
    body.set_shape(v1::BODY_SHAPE_CHAIN);
    body.set_length(2);
    body.mutable_centre()->set_x(4);
    body.mutable_centre()->set_y(4);
    body.set_name(std::to_string(b / 2) + std::string(256 - std::to_string(b / 2).size(), 'n'));
  }
  const TranslatedScenario t = translate_scenario(s);
  ASSERT_EQ(t.errors.size(), 100u) << listed(t.errors);
  EXPECT_EQ(t.errors[0],
            "scenario.bodies[1].name: \"0" + std::string(63, 'n') + "...\" is already the name of bodies[0]");
  const std::string summary = error_summary(t.errors);
  EXPECT_LE(summary.size(), kMaxSummaryBytes);
  EXPECT_TRUE(summary.ends_with(" more problems")) << summary;
}

// The core's field "bodies[<index>]" is read without overflow: an index that does not fit, or that
// the core was not shown, is not a proto path (the message is then kept whole on "scenario").
TEST(ScenarioTranslation, CoreBodyIndicesAreReadWithoutOverflow) {
  const std::vector<int> original = {0, 2};
  EXPECT_EQ(core_field_path("bodies[1].radius", original), "scenario.bodies[2].radius");
  for (const char* field : {"bodies[2].radius", "bodies[-1].radius", "bodies[18446744073709551616].radius",
                            "bodies[99999999999999999999999999].radius", "bodies[].radius", "bodies[1x].radius",
                            "bodies[1"})
    EXPECT_EQ(core_field_path(field, original), std::nullopt) << field;
}

// ---- Log text.

TEST(LogText, OneQuotedLineWhateverTheText) {
  EXPECT_EQ(log_text("drag disk"), "\"drag disk\"");
  EXPECT_EQ(log_text(""), "\"\"");
  // A forged line, quotes and backslashes, every ASCII control character, DEL.
  EXPECT_EQ(log_text("run\n2024-01-01 INFO session 7: created \"x\""),
            "\"run\\n2024-01-01 INFO session 7: created \\\"x\\\"\"");
  EXPECT_EQ(log_text("a\rb\tc\\d"), "\"a\\rb\\tc\\\\d\"");
  EXPECT_EQ(log_text(std::string("\0\x01\x1b[31m\x1f\x7f", 9)), "\"\\x00\\x01\\x1b[31m\\x1f\\x7f\"");
  for (int c = 0; c < 0x20; ++c) {
    const std::string escaped = log_text(std::string(1, static_cast<char>(c)));
    for (char e : escaped) EXPECT_TRUE(e >= 0x20 && e < 0x7F) << "byte " << c << " gives " << escaped;
  }
  // UTF-8 passes; C1 controls and the Unicode line separators are escaped; broken UTF-8 is \xNN.
  EXPECT_EQ(log_text("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"), "\"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\"");
  EXPECT_EQ(log_text("\xc2\x85|\xc2\x9b|\xe2\x80\xa8|\xe2\x80\xa9"), "\"\\u0085|\\u009b|\\u2028|\\u2029\"");
  EXPECT_EQ(log_text("\xff|\xc3|\xc0\x8a|\xed\xa0\x80|\xe2\x80"),
            "\"\\xff|\\xc3|\\xc0\\x8a|\\xed\\xa0\\x80|\\xe2\\x80\"");
}

std::string quoted(const std::string& text) {
  std::string q = "\"";
  q += text;
  q += '"';
  return q;
}

TEST(LogText, LongTextIsCutOnACharacterWithItsSize) {
  EXPECT_EQ(log_text(std::string(200, 'a')), quoted(std::string(200, 'a')));
  EXPECT_EQ(log_text(std::string(5000, 'a')), quoted(std::string(200, 'a')) + "...(5000 bytes)");
  // 199 bytes and a 2-byte character across the limit: the character is left out, not split.
  EXPECT_EQ(log_text(std::string(199, 'a') + "\xc3\xa9" + "tail"), quoted(std::string(199, 'a')) + "...(205 bytes)");
  EXPECT_EQ(log_text("abcdef", 3), "\"abc\"...(6 bytes)");
  // Escapes lengthen the line at most 6-fold: bounded whatever the input.
  EXPECT_LE(log_text(std::string(100000, '\x01')).size(), 6u * 200 + 32);
}

// ---- Text.

TEST(ScenarioText, MalformedTextGivesLineAndColumn) {
  v1::Scenario s;
  std::string error;
  EXPECT_FALSE(parse_scenario_text("domain {\n  nx: 8\n  ny: oops\n}\n", &s, &error));
  EXPECT_EQ(error.rfind("line 3 column 7: ", 0), 0u) << error;
  EXPECT_FALSE(parse_scenario_text("# a comment\ndomain { nx: 8 }\nfluid { viscosity: 1 }\n", &s, &error));
  EXPECT_EQ(error.rfind("line 3 column 18: ", 0), 0u) << error;  // protobuf points just past the name
  EXPECT_NE(error.find("viscosity"), std::string::npos) << error;
  EXPECT_FALSE(parse_scenario_text("lattice: LATTICE_D4Q99", &s, &error));
  EXPECT_EQ(error.rfind("line 1 column ", 0), 0u) << error;
  EXPECT_FALSE(s.has_domain()) << "a failed parse leaves an empty scenario";
}

TEST(ScenarioText, MalformedJsonGivesLineAndColumn) {
  v1::Scenario s;
  std::string error;
  EXPECT_FALSE(parse_scenario_text("{\n  \"domain\": {\"nx\": 8,\n  }\n}", &s, &error));
  EXPECT_EQ(error, "line 3 column 3: expected a quoted field name");
  EXPECT_FALSE(parse_scenario_text("  {\"domain\": {\"nx\": 8}", &s, &error));
  EXPECT_EQ(error, "line 1 column 23: expected ',' or '}' after the value of \"domain\"");
  EXPECT_FALSE(parse_scenario_text("{\"lattice\": LATTICE_D2Q7}", &s, &error));
  EXPECT_EQ(error, "line 1 column 13: unexpected character 'L'; expected a value");
  EXPECT_FALSE(parse_scenario_text("{\"fluid\": {\"omega\": 1.e5}}", &s, &error));
  EXPECT_EQ(error, "line 1 column 23: expected a digit");
  // Well-formed JSON that is not a scenario: placed at the offending field's key.
  EXPECT_FALSE(parse_scenario_text("{\n  \"domain\": {\n    \"nx\": 8,\n    \"bogus\": 1\n  }\n}", &s, &error));
  EXPECT_EQ(error.rfind("line 4 column 5: ", 0), 0u) << error;
  EXPECT_FALSE(parse_scenario_text("{\"domain\": {\"ny\": 2,\n \"nx\": \"eight\"}}", &s, &error));
  EXPECT_EQ(error.rfind("line 2 column 2: ", 0), 0u) << error;
}

TEST(ScenarioText, JsonParsesToTheSameMessageAsText) {
  const v1::Scenario text = parse(R"(
    name: "json twin"
    lattice: LATTICE_D2Q7
    domain { nx: 20 ny: 10
             y_low { kind: WALL_KIND_FREE_SLIP traction { x: -1e-4 } }
             y_high { kind: WALL_KIND_FREE_SLIP traction { x: 1e-4 } } }
    fluid { omega: 1.2 body_force { x: 1e-6 } threads: 2 }
    bodies { name: "c" shape: BODY_SHAPE_CHAIN length: 4 axis: AXIS_Y spacing: 0.866 centre { x: 5 y: 4 } }
    bodies { shape: BODY_SHAPE_RECTANGLE size: [2, 3] centre { x: 12 y: 4 } }
    contact { enabled: false }
    stability { check_interval: 50 }
  )");
  const v1::Scenario json = parse(R"(
    {
      "name": "json twin",
      "lattice": "LATTICE_D2Q7",
      "domain": {"nx": 20, "ny": 10,
                 "yLow": {"kind": "WALL_KIND_FREE_SLIP", "traction": {"x": -1e-4}},
                 "y_high": {"kind": "WALL_KIND_FREE_SLIP", "traction": {"x": 1e-4}}},
      "fluid": {"omega": 1.2, "bodyForce": {"x": 1e-6}, "threads": 2},
      "bodies": [
        {"name": "c", "shape": "BODY_SHAPE_CHAIN", "length": 4, "axis": "AXIS_Y", "spacing": 0.866,
         "centre": {"x": 5, "y": 4}},
        {"shape": "BODY_SHAPE_RECTANGLE", "size": [2, 3], "centre": {"x": 12, "y": 4}}
      ],
      "contact": {"enabled": false},
      "stability": {"checkInterval": 50}
    }
  )");
  EXPECT_TRUE(MessageDifferencer::Equals(text, json)) << scenario_to_text(text) << "\nvs\n" << scenario_to_text(json);
  EXPECT_TRUE(translate_scenario(json).ok()) << listed(translate_scenario(json).errors);
}

TEST(ScenarioText, TextRoundTrip) {
  const v1::Scenario original = parse(R"(
    name: "round trip"
    lattice: LATTICE_D3Q19
    precision: PRECISION_FLOAT
    domain { nx: 8 ny: 6 nz: 4
             z_low { kind: WALL_KIND_MOVING_WALL wall_velocity { x: 0.02 } } z_high { kind: WALL_KIND_BOUNCE_BACK } }
    fluid { enabled: true omega: 0 rho0: 2 streaming: STREAMING_TWO_BUFFER }
    bodies { shape: BODY_SHAPE_LABELS labels { i: 0 } labels { i: 1 } spacing: 0.5 load { z: 1e-5 } }
    contact { restitution: 0.25 }
    exchange: EXCHANGE_RULE_PAIRWISE
    stability { max_mach: 0.3 }
  )");
  const std::string text = scenario_to_text(original);
  const v1::Scenario again = parse(text);
  EXPECT_TRUE(MessageDifferencer::Equals(original, again)) << text;
  // Presence survives: omega set to 0 stays set (and invalid), not the default 1.
  EXPECT_TRUE(again.fluid().has_omega());
  EXPECT_ERROR(translate_scenario(again).errors, "scenario.fluid.omega");
  EXPECT_EQ(scenario_to_text(again), text);
}

// ---- The shipped scenario files.

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// N of the header's "# steps: N ..." line, 0 without one.
long header_steps(const std::string& text) {
  const std::string tag = "\n# steps: ";
  const std::size_t at = text.find(tag);
  if (at == std::string::npos) return 0;
  return std::strtol(text.c_str() + at + tag.size(), nullptr, 10);
}

TEST(ScenarioFiles, EveryFileTranslatesBuildsAndRuns) {
  const std::filesystem::path dir = LBSOLID_SCENARIO_DIR;
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".textproto") names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  for (const char* expected :
       {"fig1_bouncing_sheet.textproto", "fig4_pulled_solid.textproto", "fig5_drag_disk.textproto",
        "fig6_chains_shear.textproto", "sedimentation_3d.textproto", "poiseuille_channel.textproto",
        "open_channel.textproto"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected << " missing from " << dir;
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const std::string text = read_file(dir / name);
    // Every header says how long to run it, in one form a script can read.
    EXPECT_GT(header_steps(text), 0) << "no \"# steps: N\" line";
    v1::Scenario scenario;
    std::string error;
    ASSERT_TRUE(parse_scenario_text(text, &scenario, &error)) << error;
    const TranslatedScenario t = translate_scenario(scenario);
    ASSERT_TRUE(t.ok()) << listed(t.errors);
    auto simulation = scene::build_simulation(t.scene);
    simulation->run(2);
    EXPECT_EQ(simulation->step_count(), 2);
    // The text form of what was read reads back the same.
    EXPECT_TRUE(MessageDifferencer::Equals(parse(scenario_to_text(scenario)), scenario));
  }
}

TEST(ScenarioFiles, DragDiskIsNamedForTheMainJob) {
  v1::Scenario scenario;
  std::string error;
  ASSERT_TRUE(parse_scenario_text(read_file(std::filesystem::path(LBSOLID_SCENARIO_DIR) / "fig5_drag_disk.textproto"),
                                  &scenario, &error))
      << error;
  const TranslatedScenario t = translate_scenario(scenario);
  ASSERT_EQ(t.scene.bodies.size(), 1u);
  EXPECT_EQ(t.scene.bodies[0].name, "disk");
  EXPECT_EQ(t.scene.bodies[0].shape, solid::BodyShape::kDisk);
  EXPECT_EQ(t.scene.lattice, scene::LatticeKind::kD2Q7);
}

}  // namespace
}  // namespace lbsolid::server
