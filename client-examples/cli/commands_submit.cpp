// submit: parse the scenario locally, create the session (idempotent on the request id), run it,
// and with --wait / --out follow it to the end (and record it).
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "message_format.h"
#include "progress_bar.h"
#include "result_writer.h"
#include "rpc_client.h"
#include "run_recording.h"
#include "scenario_file.h"
#include "session_follow.h"

namespace lbsolid::cli {
namespace {

using lbsolid::v1::Session;

// A session that is new from this call (or from an earlier attempt that stopped before Run): it
// must be run. A retried submit finds its session already running or finished and only attaches,
// so the retry does not add another N steps.
bool needs_run(const Session& s) {
  return s.state() == lbsolid::v1::SESSION_STATE_CREATED && s.step() == 0 && s.target_step() == 0;
}

Session start(Daemon& daemon, const Session& created, long steps) {
  if (!needs_run(created)) {
    std::fprintf(stderr, "lbsolid: request id %s names session %s (%s, step %lld/%lld): attaching to it\n",
                 created.request_id().c_str(), created.id().c_str(), state_name(created.state()).c_str(),
                 static_cast<long long>(created.step()), static_cast<long long>(created.target_step()));
    // A daemon that restarted brings its sessions back PAUSED; the submit being retried asked for
    // the run to reach its target, so it goes on.
    if (created.state() != lbsolid::v1::SESSION_STATE_PAUSED) return created;
    lbsolid::v1::ResumeRequest resume;
    resume.set_session_id(created.id());
    return daemon.call("Resume", &Stub::Resume, resume);
  }
  lbsolid::v1::RunRequest run;
  run.set_session_id(created.id());
  run.set_steps(steps);
  return daemon.call("Run", &Stub::Run, run);
}

std::string files_text(const std::string& dir, const RunRecord& record) {
  std::string text;
  for (const auto& f : record.files)
    text += "wrote " + (std::filesystem::path(dir) / f.name).string() + " (" + std::to_string(f.bytes) + " bytes)\n";
  text += "wrote " + (std::filesystem::path(dir) / "status.json").string();
  if (!record.error.empty()) text += "\nerror: " + record.error;
  return text;
}

}  // namespace

int cmd_submit(const CommandLine& line) {
  const SubmitOptions options = submit_options(line);
  const lbsolid::v1::Scenario scenario = load_scenario(options.file);
  if (!options.out_dir.empty()) prepare_output_directory(options.out_dir);
  Daemon daemon(line.global);

  lbsolid::v1::CreateSessionRequest create;
  *create.mutable_scenario() = scenario;
  create.set_request_id(options.request_id.empty() ? random_request_id() : options.request_id);
  const Session created = daemon.call("CreateSession", &Stub::CreateSession, create);
  // Near-edge parameters (omega above 1.95, ...) run, but the user should know (stderr: --json
  // keeps stdout to one object, which carries them too).
  for (const auto& warning : created.warnings()) std::fprintf(stderr, "lbsolid: warning: %s\n", warning.c_str());

  if (!options.wait) {
    const Session started = start(daemon, created, options.steps);
    emit(line, session_json(started), session_line(started));
    return kExitOk;
  }
  ProgressReporter progress;
  if (options.out_dir.empty()) {
    start(daemon, created, options.steps);
    const Session done = follow_session(daemon, created.id(), progress);
    progress.finish();
    emit(line, session_json(done), session_line(done));
    return outcome_exit_code(done);
  }

  // --out: from here on every failure ends up in status.json rather than being thrown.
  RunRecording recording(daemon, created, scenario, options);
  recording.wait_streams_registered();
  Session last = created;
  std::string error;
  int exit_code = kExitOk;
  try {
    last = start(daemon, created, options.steps);
    last = follow_session(daemon, created.id(), progress, &last);
    exit_code = outcome_exit_code(last);
  } catch (const RpcError& e) {
    error = e.what();
    exit_code = e.exit_code();
    std::fprintf(stderr, "lbsolid: %s\n", e.what());
  }
  progress.finish();
  const RunRecord record = recording.finish(last, error, exit_code);
  emit(line, status_json(record), session_line(last) + "\n" + files_text(options.out_dir, record));
  return record.exit_code;
}

}  // namespace lbsolid::cli
