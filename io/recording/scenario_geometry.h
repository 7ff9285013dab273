#pragma once
// The facts about a scenario that recording its run needs (the H5MD box, the field snapshots'
// spacing), shared by the daemon's own recording and the CLI's.
#include <array>

#include "lbsolid/v1/scenario.pb.h"
#include "io/storage/h5md_file.h"

namespace lbsolid::server::recording {

bool has_fluid(const lbsolid::v1::Scenario& scenario);  // fluid.enabled, default true
int dimension(const lbsolid::v1::Scenario& scenario);   // 3 for D3Q19, else 2
// Node spacing per axis (D2Q7 rows are sqrt(3)/2 apart), and the box's edge lengths.
std::array<double, 3> node_spacing(const lbsolid::v1::Scenario& scenario);
std::array<double, 3> box_edges(const lbsolid::v1::Scenario& scenario);
// Per axis: both sides periodic (an unspecified side is periodic).
std::array<bool, 3> periodic_axes(const lbsolid::v1::Scenario& scenario);
storage::H5mdBox h5md_box(const lbsolid::v1::Scenario& scenario);

}  // namespace lbsolid::server::recording
