#pragma once
// Several daemons behind one CLI: --server (or $LBSOLID_SERVER) may list them, comma separated.
// A new session goes to the least loaded (fewest RUNNING sessions per worker, then fewest
// sessions held, then the first listed), or, when its --request-id was used before, to the daemon
// that already holds it, so that a retried submit finds its first session; every later call about
// a session goes to the daemon that holds it. With one daemon listed nothing is asked. A DNS name
// that resolves to several addresses counts as that many daemons (daemon_names.h).
#include <string>
#include <vector>

#include "cli_options.h"
#include "daemon_names.h"

namespace lbsolid::cli {

// The daemons of `server`, in order, DNS names of several addresses expanded; UsageError naming
// --server for an empty entry.
std::vector<DaemonAddress> listed_servers(const std::string& server);

// The options with `server` set to that one daemon.
GlobalOptions on_daemon(const GlobalOptions& options, const DaemonAddress& daemon);

// The options with `server` set to the first daemon listed (calls about no session: info,
// validate, restore).
GlobalOptions first_daemon(const GlobalOptions& options);

// The options with `server` set to the daemon a new session (of `request_id`, if the user chose
// one) goes to. Unreachable daemons are skipped with a warning on stderr; none reachable: the
// last one's RpcError.
GlobalOptions daemon_for_new_session(const GlobalOptions& options, const std::string& request_id);

// The options with `server` set to the daemon that holds `session_id`; RpcError NOT_FOUND when
// none of them does.
GlobalOptions daemon_of_session(const GlobalOptions& options, const std::string& session_id);

// The least loaded of these figures (index into the vectors); ties go to the earlier one.
struct DaemonLoad {
  int running_sessions = 0;
  int workers = 1;
  int sessions = 0;
};
std::size_t least_loaded(const std::vector<DaemonLoad>& loads);

}  // namespace lbsolid::cli
