#pragma once
// Reading a scenario file on the client, so a bad file is reported with its line and column
// before the daemon is involved, and the facts about a scenario the recording needs.
#include <array>
#include <string>

#include "lbsolid/v1/scenario.pb.h"

namespace lbsolid::cli {

// Throws CliError (exit 2): "FILE: cannot read: reason" or "FILE: line L column C: reason".
lbsolid::v1::Scenario load_scenario(const std::string& path);

bool has_fluid(const lbsolid::v1::Scenario& scenario);  // fluid.enabled, default true
int dimension(const lbsolid::v1::Scenario& scenario);   // 3 for D3Q19, else 2
// Node spacing per axis (D2Q7 rows are sqrt(3)/2 apart), and the box's edge lengths.
std::array<double, 3> node_spacing(const lbsolid::v1::Scenario& scenario);
std::array<double, 3> box_edges(const lbsolid::v1::Scenario& scenario);
// Per axis: both sides periodic (an unspecified side is periodic).
std::array<bool, 3> periodic_axes(const lbsolid::v1::Scenario& scenario);

}  // namespace lbsolid::cli
