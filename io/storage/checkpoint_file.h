#pragma once
// Checkpoints: the complete state of one session (scene/simulation.h SimulationState) and the
// scenario it was built from, in one HDF5 file with format-version attributes and SHA-256
// checksums of everything in it (checkpoint_layout.h). Written to a temporary file of its own
// beside the target, flushed and fsync'ed, then renamed over it: a crash, or another write of the
// same target at the same time, leaves one whole checkpoint, never a mix.
#include <string>

#include "scene/simulation.h"

namespace lbsolid::server::storage {

// 2: every dataset and the root carry a SHA-256 (1 had none and is no longer read).
// 3: the root also names the session's owner (a version 2 file belongs to the local owner).
inline constexpr int kCheckpointFormatVersion = 4;

struct CheckpointContents {
  std::string scenario_text;  // the lbsolid.v1.Scenario in protobuf text format
  std::string session_id;     // the session it was taken from
  std::string session_name;
  std::string request_id;     // the client's request id it was created with (may be empty)
  std::string owner;          // the identity the session belongs to (server/auth/identity.h)
  bool done = false;          // the session had reached its target (it comes back DONE)
  bool started = false;       // it had been run or stepped (false: it comes back CREATED)
  long target_step = 0;       // the session's target when it was taken (0: none)
  scene::SimulationState state;
};

struct WriterInfo {
  std::string version;       // lbsolid version
  std::string git_revision;  // of the writing build
};

// Succeeds only once the whole file is written, fsync'ed and renamed over path. Throws
// std::runtime_error naming the path and the cause, the old file, if any, untouched: contents a
// run could not continue from (checkpoint_validation.h: NaN values, impossible counters), or a
// failed write.
void write_checkpoint(const std::string& path, const CheckpointContents& contents, const WriterInfo& writer);

// Throws std::runtime_error naming the path, the dataset or attribute, and the cause: missing, not
// HDF5, not a checkpoint, a format version other than 2 or 3, a checksum mismatch (the file was damaged
// or altered), a dataset of the wrong size, contents a run could not continue from.
CheckpointContents read_checkpoint(const std::string& path);

}  // namespace lbsolid::server::storage
