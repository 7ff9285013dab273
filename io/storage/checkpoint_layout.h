#pragma once
// The HDF5 layout of a checkpoint, format 4, with its checksums (checkpoint_checksum.h):
//   /                   attrs format = "lbsolid-checkpoint", format_version = 4, lbsolid_version,
//                       git_revision, session_id, session_name, request_id, owner, done, started,
//                       target_step, step, sha256 (of the root record)
// Format 3 is the same without the fracture datasets; format 2 also without owner (read as the
// local owner's, kLegacyOwner).
//   /scenario           string dataset: the scenario text, byte for byte; attr sha256
//   /fluid              (with a fluid) attrs steps, current, pulled, stepped, buffers, cells
//   /fluid/populations  float64 [buffers * Q * cells], exactly FluidRawState::populations; attr sha256
//   /solid              (with bodies) positions [n][3], incoming [m][3], momentum [n][3], float64,
//                       each with attr sha256
//   /solid/broken_links (a body broke) float64 [b][6]: step, particle, link, x, y, z; attr sha256
//   /solid/shed_momentum (a particle was shed) float64 [bodies][3]; attr sha256
// Booleans are int32 0/1. Strings are fixed-length and exact (hdf5_io.h). Objects use the HDF5 1.8
// format, whose headers carry HDF5's own checksums.
// Private to io/storage: no plausibility checks (checkpoint_validation.h) and no temporary
// file (checkpoint_file.cpp) here, so tests can write files the public writer refuses.
#include <string>

#include "io/storage/checkpoint_file.h"

namespace lbsolid::server::storage {

// The owner of a session saved before owners existed (format 2): the one identity of a daemon
// that authenticates nobody (server/auth/identity.h kLocalOwner).
inline constexpr char kLegacyOwner[] = "local";

// Creates (or truncates) file_path and writes the checkpoint into it, flushed and closed. Throws
// std::runtime_error naming the object that failed.
void write_checkpoint_layout(const std::string& file_path, const CheckpointContents& contents,
                             const WriterInfo& writer);

// Throws std::runtime_error naming what failed: not HDF5, not a checkpoint, a format version other
// other than 2 to 4, a missing or malformed object, a checksum that does not match ("dataset
// /fluid/populations: checksum mismatch").
CheckpointContents read_checkpoint_layout(const std::string& file_path);

}  // namespace lbsolid::server::storage
