#include "daemon_placement.h"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "cli_error.h"
#include "rpc_client.h"

namespace lbsolid::cli {
namespace {

GlobalOptions on(const GlobalOptions& options, const std::string& server) {
  GlobalOptions one = options;
  one.server = server;
  return one;
}

void warn_unreachable(const std::string& server, const RpcError& e) {
  std::fprintf(stderr, "lbsolid: warning: %s skipped: %s\n", server.c_str(), e.what());
}

// The daemon holding a session of this request id (the caller's own), if one does.
std::optional<std::string> holder_of_request(const GlobalOptions& options, const std::vector<std::string>& servers,
                                             const std::string& request_id) {
  for (const std::string& server : servers) {
    try {
      Daemon daemon(on(options, server));
      const auto listed = daemon.call("ListSessions", &Stub::ListSessions, lbsolid::v1::ListSessionsRequest());
      for (const auto& session : listed.sessions())
        if (session.request_id() == request_id) return server;
    } catch (const RpcError& e) {
      warn_unreachable(server, e);
    }
  }
  return std::nullopt;
}

}  // namespace

std::vector<std::string> listed_servers(const std::string& server) {
  std::vector<std::string> servers;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = server.find(',', begin);
    const std::string entry = server.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    if (entry.empty()) throw UsageError("--server: an empty address in '" + server + "'");
    servers.push_back(entry);
    if (comma == std::string::npos) return servers;
    begin = comma + 1;
  }
}

std::size_t least_loaded(const std::vector<DaemonLoad>& loads) {
  std::size_t best = 0;
  for (std::size_t k = 1; k < loads.size(); ++k) {
    // running / workers compared without division: a.running * b.workers < b.running * a.workers.
    const DaemonLoad& a = loads[k];
    const DaemonLoad& b = loads[best];
    const long lhs = static_cast<long>(a.running_sessions) * std::max(b.workers, 1);
    const long rhs = static_cast<long>(b.running_sessions) * std::max(a.workers, 1);
    if (lhs < rhs || (lhs == rhs && a.sessions < b.sessions)) best = k;
  }
  return best;
}

GlobalOptions first_daemon(const GlobalOptions& options) { return on(options, listed_servers(options.server).front()); }

GlobalOptions daemon_for_new_session(const GlobalOptions& options, const std::string& request_id) {
  const std::vector<std::string> servers = listed_servers(options.server);
  if (servers.size() == 1) return options;
  if (!request_id.empty())
    if (const auto holder = holder_of_request(options, servers, request_id)) return on(options, *holder);
  std::vector<std::string> reachable;
  std::vector<DaemonLoad> loads;
  std::optional<RpcError> last_error;
  for (const std::string& server : servers) {
    try {
      Daemon daemon(on(options, server));
      const auto info = daemon.call("GetServerInfo", &Stub::GetServerInfo, lbsolid::v1::GetServerInfoRequest());
      reachable.push_back(server);
      loads.push_back({info.running_sessions(), info.workers(), info.sessions()});
    } catch (const RpcError& e) {
      warn_unreachable(server, e);
      last_error = e;
    }
  }
  if (reachable.empty()) throw *last_error;
  return on(options, reachable[least_loaded(loads)]);
}

GlobalOptions daemon_of_session(const GlobalOptions& options, const std::string& session_id) {
  const std::vector<std::string> servers = listed_servers(options.server);
  if (servers.size() == 1) return options;
  std::optional<RpcError> unreachable;
  for (const std::string& server : servers) {
    try {
      Daemon daemon(on(options, server));
      lbsolid::v1::GetSessionRequest request;
      request.set_session_id(session_id);
      daemon.call("GetSession", &Stub::GetSession, request);
      return on(options, server);
    } catch (const RpcError& e) {
      if (e.code != grpc::StatusCode::NOT_FOUND) {
        warn_unreachable(server, e);
        unreachable = e;
      }
    }
  }
  // A daemon that did not answer may hold it: say so rather than "not found".
  if (unreachable) throw *unreachable;
  throw RpcError("GetSession", grpc::Status(grpc::StatusCode::NOT_FOUND,
                                            "session_id: " + session_id + " is on none of the " +
                                                std::to_string(servers.size()) + " daemons of --server"));
}

}  // namespace lbsolid::cli
