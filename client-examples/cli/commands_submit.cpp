// submit: parse the scenario locally, create the session (idempotent on the request id), run it,
// and with --wait / --out follow it to the end (and record it).
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "daemon_placement.h"
#include "message_format.h"
#include "progress_bar.h"
#include "result_writer.h"
#include "rpc_client.h"
#include "output_download.h"
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

// What `submit --out` records, unless the scenario file declares its own outputs: every body's
// particles and the velocity profile at the frame intervals, and the fields at the end.
void declare_outputs(lbsolid::v1::Scenario& scenario, const SubmitOptions& options) {
  if (scenario.has_outputs()) return;
  auto* outputs = scenario.mutable_outputs();
  if (scenario.bodies_size() > 0) outputs->set_particles_every(options.particles_every);
  if (has_fluid(scenario)) {
    outputs->set_profile_every(options.profile_every);
    outputs->set_final_fields(true);
  }
}

Session start(Daemon& daemon, const Session& created, long steps) {
  // A retried submit must ask for what the first one did: its request id names a run of another
  // length otherwise, and attaching to it would pass that run off as this one.
  if (created.target_step() != 0 && created.target_step() != steps && !needs_run(created))
    throw CliError(kExitBadInput, "--steps: request id " + created.request_id() + " names session " + created.id() +
                                      ", run to step " + std::to_string(created.target_step()) + ", not " +
                                      std::to_string(steps) + "; give another --request-id for another run");
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

std::string files_text(const std::string& dir, const CommandResult& result) {
  std::string text;
  for (const auto& f : result.files)
    text += "wrote " + (std::filesystem::path(dir) / f.name).string() + " (" + std::to_string(f.bytes) + " bytes)\n";
  text += "wrote " + (std::filesystem::path(dir) / "status.json").string();
  if (result.error) text += "\nerror: " + result.error->message;
  return text;
}

}  // namespace

int cmd_submit(const CommandLine& line) {
  const SubmitOptions options = submit_options(line);
  lbsolid::v1::Scenario scenario = load_scenario(options.file, options.overrides);
  if (!options.out_dir.empty()) {
    prepare_output_directory(options.out_dir);
    declare_outputs(scenario, options);
  }
  lbsolid::v1::CreateSessionRequest create;
  *create.mutable_scenario() = scenario;
  create.set_request_id(options.request_id.empty() ? random_request_id() : options.request_id);
  // Of several daemons, the least loaded, or the one a retry of this request id reached before.
  Daemon daemon(daemon_for_new_session(line.global, options.request_id));
  const Session created = daemon.call("CreateSession", &Stub::CreateSession, create);
  // Near-edge parameters (omega above 1.95, ...) run, but the user should know (stderr: --json
  // keeps stdout to one object, which carries them too).
  for (const auto& warning : created.warnings()) std::fprintf(stderr, "lbsolid: warning: %s\n", warning.c_str());

  if (!options.wait) {
    const Session started = start(daemon, created, options.steps);
    emit(line, session_result(line.command, started), session_line(started));
    return kExitOk;
  }
  ProgressReporter progress;
  if (options.out_dir.empty()) {
    start(daemon, created, options.steps);
    const Session done = follow_session(daemon, created.id(), progress);
    progress.finish();
    CommandResult result = session_result(line.command, done);
    result.exit_code = outcome_exit_code(done);
    emit(line, result, session_line(done));
    return result.exit_code;
  }

  // --out: the daemon records the run (scenario.outputs); from here on every failure ends up in
  // status.json rather than being thrown.
  Session last = created;
  std::vector<FileEntry> files;
  std::optional<ResultError> error;
  int exit_code = kExitOk;
  try {
    last = start(daemon, created, options.steps);
    last = follow_session(daemon, created.id(), progress, &last);
    exit_code = outcome_exit_code(last);
    progress.finish();
    files = download_outputs(daemon, created.id(), options.out_dir, /*with_checkpoints=*/false);
  } catch (const CliError& e) {
    error = result_error(e);
  } catch (const RpcError& e) {
    error = result_error(e);
  }
  progress.finish();
  if (error) std::fprintf(stderr, "lbsolid: %s\n", error->message.c_str());
  CommandResult record = session_result(line.command, last);
  record.files = std::move(files);
  record.wrote_files = true;
  record.error = error;
  record.exit_code = error ? error->exit_code : exit_code;
  try {
    write_file_atomically((std::filesystem::path(options.out_dir) / "status.json").string(), result_json(record) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lbsolid: %s\n", e.what());
    if (!record.error) record.error = ResultError{"BAD_INPUT", "", e.what(), kExitBadInput};
    if (record.exit_code == kExitOk) record.exit_code = kExitBadInput;
  }
  emit(line, record, session_line(last) + "\n" + files_text(options.out_dir, record));
  return record.exit_code;
}

}  // namespace lbsolid::cli
