#pragma once
// `--set PATH=VALUE`: one scenario field changed on the command line, so that a sweep needs no
// edited copies of a file. PATH names the field as the daemon's errors do (dots between fields,
// [i] after a repeated one: fluid.omega, bodies[0].load.x, domain.y_high.wall_velocity.x); VALUE
// is parsed for the field's type (numbers whole and finite, bool true/false, an enum by its name
// or number, strings as given). The daemon then validates the scenario as it would the file.
#include <string>

#include "lbsolid/v1/scenario.pb.h"

namespace lbsolid::cli {

// Throws CliError (exit 2): "--set ASSIGNMENT: reason" (an unknown field, a repeated field without
// an index or one past its end, a message where a value belongs, a value of the wrong type).
void apply_override(lbsolid::v1::Scenario& scenario, const std::string& assignment);

}  // namespace lbsolid::cli
