#pragma once
// What every scenario fuzz target does with a Scenario it managed to parse: translate it, check
// the invariants the daemon relies on, and build and step the scene when it is small enough.
//
// Oracles (each aborts, so libFuzzer keeps the input):
//   - a scenario that translates without errors is one scene::validate_scene() accepts (the daemon
//     builds what translate_scenario() accepts; the builder throws on what validation refuses);
//   - its text form (what checkpoints store, scenario_to_text) parses back to the same message
//     (restoring a checkpoint parses that text);
//   - build_simulation() does not throw on it, and a few steps run (an InstabilityError from the
//     scene's own monitor is an answer, not a failure).
// Bounds, so that no input costs more than a few milliseconds or megabytes: a scene is built only
// when its grid has at most kMaxCells nodes and its bodies at most kMaxParticles particles
// (counted from the spec, before anything is allocated), with at most two kernel threads.
#include <google/protobuf/util/field_comparator.h>
#include <google/protobuf/util/message_differencer.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "scene/instability_error.h"
#include "scene/simulation.h"
#include "io/api/scenario_translation.h"

namespace lbsolid::fuzz {

inline constexpr double kMaxCells = 1e5;
inline constexpr double kMaxParticles = 1e4;
inline constexpr int kSteps = 2;

[[noreturn]] inline void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz oracle failed: %s\n%s\n", what, detail.c_str());
  std::abort();
}

// Particles a body spec asks for, from its numbers alone (an upper bound; no allocation).
inline double particles_asked(const solid::BodySpec& body, int dimension) {
  switch (body.shape) {
    case solid::BodyShape::kRectangle:
      return std::abs(double(body.size[0])) * std::abs(double(body.size[1])) *
             (dimension == 3 ? std::abs(double(body.size[2])) : 1.0);
    case solid::BodyShape::kDisk: {
      const double side = 2 * std::abs(body.radius) + 3;
      return dimension == 3 ? side * side * side : side * side;
    }
    case solid::BodyShape::kChain:
      return std::abs(double(body.length));
    case solid::BodyShape::kLabels:
      return double(body.labels.size());
  }
  return 0;
}

inline bool small_enough(const scene::Scene& scene) {
  const double cells = double(scene.fluid.nx) * double(scene.fluid.ny) * double(scene.fluid.nz);
  if (!(cells <= kMaxCells)) return false;
  const int dimension = scene::lattice_dimension(scene.lattice);
  double particles = 0;
  for (const auto& body : scene.bodies) particles += particles_asked(body, dimension);
  return particles <= kMaxParticles && scene.fluid.threads <= 2;
}

inline void check_scenario(const lbsolid::v1::Scenario& scenario) {
  const server::TranslatedScenario translated = server::translate_scenario(scenario);
  if (!translated.ok()) return;

  // The text a checkpoint stores must parse back to the same scenario.
  const std::string text = server::scenario_to_text(scenario);
  lbsolid::v1::Scenario reparsed;
  std::string error;
  if (!server::parse_scenario_text(text, &reparsed, &error))
    fail("scenario_to_text does not parse back", error + "\n--- text:\n" + text);
  google::protobuf::util::DefaultFieldComparator comparator;
  comparator.set_treat_nan_as_equal(true);  // NaN in a field translation ignores is still NaN
  google::protobuf::util::MessageDifferencer differencer;
  differencer.set_field_comparator(&comparator);
  differencer.set_message_field_comparison(google::protobuf::util::MessageDifferencer::EQUIVALENT);
  if (!differencer.Compare(scenario, reparsed))
    fail("scenario_to_text parses back to another scenario", text);

  if (!small_enough(translated.scene)) return;
  const std::vector<std::string> problems = scene::validate_scene(translated.scene);
  if (!problems.empty()) fail("translate_scenario accepted a scene validate_scene refuses", problems.front());
  auto simulation = scene::build_simulation(translated.scene);  // throws (and so aborts) on a refusal
  try {
    simulation->run(kSteps);
  } catch (const scene::InstabilityError&) {
    // the scene's own monitor stopped it: a correct answer
  }
}

// A scenario file's text (protobuf text or JSON): a refusal must say why; what parses goes
// through check_scenario().
inline void check_scenario_text(const std::string& text) {
  lbsolid::v1::Scenario scenario;
  std::string error;
  if (!server::parse_scenario_text(text, &scenario, &error)) {
    if (error.empty()) fail("parse_scenario_text failed without a message", text);
    return;
  }
  check_scenario(scenario);
}

}  // namespace lbsolid::fuzz
