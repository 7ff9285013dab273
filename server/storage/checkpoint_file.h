#pragma once
// Checkpoints: the complete state of one session (scene/simulation.h SimulationState) and the
// scenario it was built from, in one HDF5 file with format-version attributes. Written to a
// temporary file beside the target, flushed and fsync'ed, then renamed over it: a crash leaves
// either the old checkpoint or the new one, never half of one.
#include <string>

#include "scene/simulation.h"

namespace lbsolid::server::storage {

inline constexpr int kCheckpointFormatVersion = 1;

struct CheckpointContents {
  std::string scenario_text;  // the lbsolid.v1.Scenario in protobuf text format
  std::string session_id;     // the session it was taken from
  std::string session_name;
  std::string request_id;     // the client's request id it was created with (may be empty)
  bool done = false;          // the session had reached its target (it comes back DONE)
  long target_step = 0;       // the session's target when it was taken (0: none)
  scene::SimulationState state;
};

struct WriterInfo {
  std::string version;       // lbsolid version
  std::string git_revision;  // of the writing build
};

// Throws std::runtime_error naming the path and the cause; the old file, if any, is untouched.
void write_checkpoint(const std::string& path, const CheckpointContents& contents, const WriterInfo& writer);

// Throws std::runtime_error naming the path and the cause: missing, not HDF5, not a checkpoint,
// a newer format version, a dataset of the wrong size.
CheckpointContents read_checkpoint(const std::string& path);

}  // namespace lbsolid::server::storage
