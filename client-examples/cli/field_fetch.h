#pragma once
// GetField: a header per field, then raw little-endian chunks at byte offsets. The chunks are put
// back together by offset and checked to cover each field exactly once (total_bytes) before the
// values are trusted; then they can be appended as a snapshot to an HDF5 + XDMF pair.
#include <array>
#include <string>

#include "rpc_client.h"
#include "scene/simulation.h"

namespace lbsolid::cli {

struct FetchedFields {
  long step = 0;
  lbsolid::scene::FluidFields fields;  // density and velocity, x fastest
  std::array<double, 3> spacing{1, 1, 1};
};

// Throws RpcError, or CliError (exit 3) if the stream breaks its own contract (a chunk outside
// the field, bytes missing, fields of different steps or shapes).
FetchedFields fetch_fields(Daemon& daemon, const std::string& session_id);

// Appends the snapshot to `h5_path` (and rewrites the .xdmf beside it). Throws CliError (exit 2).
void write_field_snapshot(const std::string& h5_path, const FetchedFields& fetched);

}  // namespace lbsolid::cli
