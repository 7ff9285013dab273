#pragma once
// How the daemon's messages are shown: one JSON object each for --json (state names such as
// "DONE", snake_case keys, 64-bit integers as numbers), short human text otherwise.
#include <string>

#include "lbsolid/v1/simulation.pb.h"
#include "result_writer.h"

namespace lbsolid::cli {

std::string state_name(lbsolid::v1::SessionState state);  // "DONE", "RUNNING", ...
bool is_final(lbsolid::v1::SessionState state);            // DONE, FAILED, CANCELLED

std::string session_json(const lbsolid::v1::Session& session, bool with_scenario = true);
// The result of a command about one session: its id, state, step, target and message, and the
// whole session under "session".
CommandResult session_result(const std::string& command, const lbsolid::v1::Session& session,
                             bool with_scenario = true);
std::string session_line(const lbsolid::v1::Session& session);   // "s-000001  RUNNING  step 0/100  name"
std::string session_text(const lbsolid::v1::Session& session);   // several lines, for `status`

std::string server_info_json(const lbsolid::v1::ServerInfo& info);
std::string server_info_text(const lbsolid::v1::ServerInfo& info);

std::string checkpoint_json(const lbsolid::v1::CheckpointResponse& checkpoint);

std::string profile_frame_json(const lbsolid::v1::ProfileFrame& frame);
std::string profile_frame_text(const lbsolid::v1::ProfileFrame& frame);
std::string particle_frame_json(const lbsolid::v1::ParticleFrame& frame);
std::string particle_frame_text(const lbsolid::v1::ParticleFrame& frame);

// Protobuf JSON of the scenario (field names as in the .proto), for embedding.
std::string scenario_json(const lbsolid::v1::Scenario& scenario);

}  // namespace lbsolid::cli
