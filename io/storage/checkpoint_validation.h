#pragma once
// What a checkpoint must hold to be a state a run can continue from, checked before a checkpoint
// is written (a bad state never replaces a good file) and after one is read (the checksums say the
// file holds what was written; this says what was written is possible). Private to io/storage.
#include "io/storage/checkpoint_file.h"

namespace lbsolid::server::storage {

// The largest step or target a checkpoint may hold: 2^53, the last integer a double holds exactly
// (clients see step counts as JSON numbers), and far beyond any run (at 10^8 steps per second,
// 2^53 steps take almost three years), while step arithmetic on it cannot overflow a long.
inline constexpr long kMaxCheckpointStep = 1L << 53;

// Throws std::runtime_error naming the field or dataset and the reason: a step or target_step
// outside [0, 2^53]; fluid steps that differ from the step (the fluid steps once per step from
// step 0); buffers not 1 or 2; current outside [0, buffers); cells < 1; populations not a whole
// number of populations of every cell; momenta not one per particle, incoming links not a whole
// number per particle; any population, position, incoming link or momentum that is NaN or infinite.
void check_checkpoint_contents(const CheckpointContents& contents);

}  // namespace lbsolid::server::storage
