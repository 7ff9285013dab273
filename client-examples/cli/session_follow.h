#pragma once
// Following a run to its end (submit --wait, run --wait): WatchSession on a thread feeds the
// progress display, while the calling thread polls GetSession now and then, with the usual
// deadline. The stream has no deadline (a run may take hours); the poll is what notices a daemon
// that went away, a session that ended before the stream was registered, or a stream that ended
// early (then it is opened again).
#include <string>

#include "lbsolid/v1/simulation.pb.h"
#include "progress_bar.h"
#include "rpc_client.h"

namespace lbsolid::cli {

// Returns the session once it is DONE, FAILED or CANCELLED. Throws RpcError when the daemon
// rejects the watch or the poll (NOT_FOUND: deleted meanwhile), or fails three polls in a row;
// then *last_seen (if given; it starts as the caller's last copy) holds the state and step last
// heard of, for the record of a run that could not be followed to its end.
lbsolid::v1::Session follow_session(Daemon& daemon, const std::string& session_id, ProgressReporter& progress,
                                    lbsolid::v1::Session* last_seen = nullptr);

}  // namespace lbsolid::cli
