#pragma once
// Reading a scenario file on the client, so a bad file is reported with its line and column
// before the daemon is involved, and the facts about a scenario the recording needs.
#include <array>
#include <string>
#include <vector>

#include "lbsolid/v1/scenario.pb.h"
#include "io/recording/scenario_geometry.h"

namespace lbsolid::cli {

// Throws CliError (exit 2): "FILE: cannot read: reason" or "FILE: line L column C: reason".
lbsolid::v1::Scenario load_scenario(const std::string& path);
// The same with each --set PATH=VALUE applied in order (scenario_override.h; exit 2 on a bad one).
lbsolid::v1::Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides);

// The facts the recording needs, as the daemon's own recording reads them.
using lbsolid::server::recording::box_edges;
using lbsolid::server::recording::dimension;
using lbsolid::server::recording::has_fluid;
using lbsolid::server::recording::node_spacing;
using lbsolid::server::recording::periodic_axes;

}  // namespace lbsolid::cli
