#pragma once
// The one place where the API's Scenario (proto/lbsolid/v1/scenario.proto) becomes a core::Scene.
// Defaults of absent optional fields are filled in here; every problem, whether found in the
// message itself (an unspecified body shape, a size with the wrong number of values) or by the
// core's validation, is reported with the field's full path in the message:
//   "scenario.fluid.omega: must lie in (0, 2), got 2.5"
//   "scenario.bodies[0].centre: particle at (10, -1) lies on or beyond the y_low wall (at -0.433)"
#include <string>
#include <vector>

#include "lbsolid/v1/scenario.pb.h"
#include "scene/scene.h"
#include "io/api/error_summary.h"

namespace lbsolid::server {

// What the daemon records for a session (lbsolid.v1.Outputs, checked): intervals in steps, 0 for none.
struct OutputPlan {
  long particles_every = 0;
  std::vector<std::string> particle_bodies;  // names; empty: every body
  long profile_every = 0;
  long fields_every = 0;
  bool final_fields = false;
  long checkpoint_every = 0;
  bool records_frames() const { return particles_every > 0 || profile_every > 0 || fields_every > 0 || final_fields; }
};

struct TranslatedScenario {
  scene::Scene scene;
  OutputPlan outputs;
  // Every problem, empty when the scene can be built; a client is sent error_summary(errors)
  // (io/api/error_summary.h), which fits in a gRPC status however many there are.
  std::vector<std::string> errors;
  std::vector<std::string> warnings;  // parameters near the edge of stability, "<path>: <reason>"
  bool ok() const { return errors.empty(); }
};

TranslatedScenario translate_scenario(const lbsolid::v1::Scenario& scenario);

// Parses a scenario file's text: protobuf text format, or JSON of the same message when the first
// non-blank character is '{'. Returns false with "line L column C: reason" in *error.
bool parse_scenario_text(const std::string& text, lbsolid::v1::Scenario* scenario, std::string* error);

// Protobuf text format of the scenario (what checkpoints and H5MD files store).
std::string scenario_to_text(const lbsolid::v1::Scenario& scenario);

}  // namespace lbsolid::server
