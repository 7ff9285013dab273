#pragma once
// Stream frames into an H5MD file: a ParticleFrame gives each body's particles (position and
// velocity, `dimension` values per particle) and its mean motion, a ProfileFrame the velocity
// profile. The daemon's recording and the CLI's write particles.h5 through these, so both files
// have one layout.
#include "lbsolid/v1/simulation.pb.h"
#include "io/storage/h5md_file.h"

namespace lbsolid::server::recording {

void append_particle_frame(storage::H5mdWriter& writer, const lbsolid::v1::ParticleFrame& frame, int dimension);
void append_profile_frame(storage::H5mdWriter& writer, const lbsolid::v1::ProfileFrame& frame);

}  // namespace lbsolid::server::recording
