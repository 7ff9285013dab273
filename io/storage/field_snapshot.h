#pragma once
// Field snapshots for ParaView: density and velocity at one step appended to an HDF5 file
// (/fields/step_<step>/density [nz][ny][nx], /fields/step_<step>/velocity [nz][ny][nx][3], x
// fastest), and beside it an XDMF file (<file stem>.xdmf) describing every snapshot in the file as
// a temporal collection of CoRectMesh grids, axes in ZYX order as XDMF expects. The XDMF file is
// rewritten through a temporary file and a rename.
#include <array>
#include <string>

#include "scene/simulation.h"
#include "io/storage/xdmf_text.h"  // xdmf_path_for

namespace lbsolid::server::storage {

struct SnapshotGeometry {
  std::array<double, 3> spacing{1, 1, 1};  // node spacing along x, y, z (D2Q7: y = sqrt(3)/2)
  std::array<double, 3> origin{0, 0, 0};
};

// Creates the file if needed. Throws std::runtime_error naming the path and the cause, or
// std::invalid_argument if a snapshot of this step is already there or the shape differs from the
// file's earlier snapshots.
void append_field_snapshot(const std::string& h5_path, const scene::FluidFields& fields, long step,
                           const SnapshotGeometry& geometry);

}  // namespace lbsolid::server::storage
