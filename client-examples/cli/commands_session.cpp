// The commands that act on one session (or list them) with a single unary call, and run --wait.
#include "commands.h"
#include "daemon_placement.h"
#include "json_writer.h"
#include "message_format.h"
#include "progress_bar.h"
#include "rpc_client.h"
#include "session_follow.h"

namespace lbsolid::cli {
namespace {

using lbsolid::v1::Session;

int print_session(const CommandLine& line, const Session& session, int exit_code = kExitOk) {
  CommandResult result = session_result(line.command, session);
  result.exit_code = exit_code;
  emit(line, result, session_line(session));
  return exit_code;
}

// Pause, Resume, Cancel: a request holding only the session id, answered with the session.
template <class Request>
int session_call(const CommandLine& line, const char* rpc,
                 grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Session*)) {
  Daemon daemon(daemon_of_session(line.global, line.positional.at(0)));
  Request request;
  request.set_session_id(line.positional.at(0));
  return print_session(line, daemon.call(rpc, method, request));
}

}  // namespace

int outcome_exit_code(const Session& session) {
  return session.state() == lbsolid::v1::SESSION_STATE_DONE ? kExitOk : kExitRunFailed;
}

int cmd_status(const CommandLine& line) {
  Daemon daemon(daemon_of_session(line.global, line.positional.at(0)));
  lbsolid::v1::GetSessionRequest request;
  request.set_session_id(line.positional.at(0));
  const Session session = daemon.call("GetSession", &Stub::GetSession, request);
  emit(line, session_result(line.command, session), session_text(session));
  return kExitOk;
}

int cmd_list(const CommandLine& line) {
  std::vector<std::string> sessions;
  std::string text;
  for (const DaemonAddress& server : listed_servers(line.global.server)) {  // every daemon's, in --server order
    Daemon daemon(on_daemon(line.global, server));
    const auto response = daemon.call("ListSessions", &Stub::ListSessions, lbsolid::v1::ListSessionsRequest());
    for (const auto& s : response.sessions()) {
      sessions.push_back(session_json(s, /*with_scenario=*/false));  // `status ID` shows a scenario
      text += session_line(s) + "\n";
    }
  }
  if (text.empty()) text = "no sessions";
  CommandResult result;
  result.command = line.command;
  emit(line, result.add("sessions", json_array(sessions)), text);
  return kExitOk;
}

int cmd_info(const CommandLine& line) {
  Daemon daemon(first_daemon(line.global));
  const auto info = daemon.call("GetServerInfo", &Stub::GetServerInfo, lbsolid::v1::GetServerInfoRequest());
  if (info.api_version() != "lbsolid.v1")
    std::fprintf(stderr, "lbsolid: warning: the daemon speaks %s, this client lbsolid.v1\n",
                 info.api_version().c_str());
  CommandResult result;
  result.command = line.command;
  emit(line, result.add("server", server_info_json(info)), server_info_text(info));
  return kExitOk;
}

int cmd_run(const CommandLine& line) {
  const RunOptions options = run_options(line);
  Daemon daemon(daemon_of_session(line.global, options.session_id));
  lbsolid::v1::RunRequest request;
  request.set_session_id(options.session_id);
  request.set_steps(options.steps);
  const Session started = daemon.call("Run", &Stub::Run, request);
  if (!options.wait) return print_session(line, started);
  ProgressReporter progress;
  const Session done = follow_session(daemon, options.session_id, progress);
  progress.finish();
  return print_session(line, done, outcome_exit_code(done));
}

int cmd_pause(const CommandLine& line) { return session_call(line, "Pause", &Stub::Pause); }
int cmd_resume(const CommandLine& line) { return session_call(line, "Resume", &Stub::Resume); }
int cmd_cancel(const CommandLine& line) { return session_call(line, "Cancel", &Stub::Cancel); }

int cmd_delete(const CommandLine& line) {
  Daemon daemon(daemon_of_session(line.global, line.positional.at(0)));
  lbsolid::v1::DeleteSessionRequest request;
  request.set_session_id(line.positional.at(0));
  daemon.call("DeleteSession", &Stub::DeleteSession, request);
  CommandResult result;
  result.command = line.command;
  result.session_id = request.session_id();
  emit(line, result.add("deleted", "true"), "deleted " + request.session_id());
  return kExitOk;
}

int cmd_checkpoint(const CommandLine& line) {
  Daemon daemon(daemon_of_session(line.global, line.positional.at(0)));
  lbsolid::v1::CheckpointRequest request;
  request.set_session_id(line.positional.at(0));
  const auto checkpoint = daemon.call("Checkpoint", &Stub::Checkpoint, request);
  // Human output is the id alone, so that `id=$(lbsolid checkpoint s-000001)` works.
  CommandResult result;
  result.command = line.command;
  result.session_id = request.session_id();
  result.step = checkpoint.step();
  emit(line, result.add("checkpoint", checkpoint_json(checkpoint)), checkpoint.checkpoint_id());
  return kExitOk;
}

int cmd_restore(const CommandLine& line) {
  Daemon daemon(first_daemon(line.global));
  lbsolid::v1::RestoreRequest request;
  request.set_checkpoint_id(line.positional.at(0));
  // A request id always, so that retrying after a lost answer does not restore twice.
  request.set_request_id(line.has("request-id") ? line.flags.at("request-id") : random_request_id());
  if (request.request_id().empty()) throw UsageError("--request-id: must not be empty");
  return print_session(line, daemon.call("Restore", &Stub::Restore, request));
}

}  // namespace lbsolid::cli
