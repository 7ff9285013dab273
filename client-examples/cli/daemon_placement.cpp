#include "daemon_placement.h"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "cli_error.h"
#include "rpc_client.h"

namespace lbsolid::cli {
namespace {

void warn_unreachable(const DaemonAddress& server, const RpcError& e) {
  const std::string what = server.name.empty() ? server.target : server.target + " (" + server.name + ")";
  std::fprintf(stderr, "lbsolid: warning: %s skipped: %s\n", what.c_str(), e.what());
}

// The daemon holding a session of this request id (the caller's own), if one does.
std::optional<DaemonAddress> holder_of_request(const GlobalOptions& options, const std::vector<DaemonAddress>& servers,
                                               const std::string& request_id) {
  for (const DaemonAddress& server : servers) {
    try {
      Daemon daemon(on_daemon(options, server));
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

std::vector<DaemonAddress> listed_servers(const std::string& server) {
  std::vector<std::string> servers;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = server.find(',', begin);
    const std::string entry = server.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    if (entry.empty()) throw UsageError("--server: an empty address in '" + server + "'");
    servers.push_back(entry);
    if (comma == std::string::npos) return expand_dns_names(servers);
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

GlobalOptions on_daemon(const GlobalOptions& options, const DaemonAddress& daemon) {
  GlobalOptions one = options;
  one.server = daemon.target;
  one.server_name = daemon.name;
  return one;
}

GlobalOptions first_daemon(const GlobalOptions& options) {
  return on_daemon(options, listed_servers(options.server).front());
}

GlobalOptions daemon_for_new_session(const GlobalOptions& options, const std::string& request_id) {
  const std::vector<DaemonAddress> servers = listed_servers(options.server);
  if (servers.size() == 1) return on_daemon(options, servers.front());
  if (!request_id.empty())
    if (const auto holder = holder_of_request(options, servers, request_id)) return on_daemon(options, *holder);
  std::vector<DaemonAddress> reachable;
  std::vector<DaemonLoad> loads;
  std::optional<RpcError> last_error;
  for (const DaemonAddress& server : servers) {
    try {
      Daemon daemon(on_daemon(options, server));
      const auto info = daemon.call("GetServerInfo", &Stub::GetServerInfo, lbsolid::v1::GetServerInfoRequest());
      reachable.push_back(server);
      loads.push_back({info.running_sessions(), info.workers(), info.sessions()});
    } catch (const RpcError& e) {
      warn_unreachable(server, e);
      last_error = e;
    }
  }
  if (reachable.empty()) throw *last_error;
  return on_daemon(options, reachable[least_loaded(loads)]);
}

GlobalOptions daemon_of_session(const GlobalOptions& options, const std::string& session_id) {
  const std::vector<DaemonAddress> servers = listed_servers(options.server);
  if (servers.size() == 1) return on_daemon(options, servers.front());
  std::optional<RpcError> unreachable;
  for (const DaemonAddress& server : servers) {
    try {
      Daemon daemon(on_daemon(options, server));
      lbsolid::v1::GetSessionRequest request;
      request.set_session_id(session_id);
      daemon.call("GetSession", &Stub::GetSession, request);
      return on_daemon(options, server);
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
