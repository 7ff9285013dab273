#pragma once
// The commands, one function each: parse their options from the command line, call the daemon,
// print one JSON object (--json, the schema of result_writer.h) or human text on stdout, return
// the exit code. Failures are thrown (UsageError, CliError, RpcError) and reported by main().
#include <cstdio>
#include <string>

#include "cli_options.h"
#include "lbsolid/v1/simulation.pb.h"
#include "result_writer.h"

namespace lbsolid::cli {

int cmd_submit(const CommandLine& line);      // commands_submit.cpp
int cmd_validate(const CommandLine& line);    // commands_validate.cpp
int cmd_status(const CommandLine& line);      // commands_session.cpp ...
int cmd_list(const CommandLine& line);
int cmd_info(const CommandLine& line);
int cmd_run(const CommandLine& line);
int cmd_pause(const CommandLine& line);
int cmd_resume(const CommandLine& line);
int cmd_cancel(const CommandLine& line);
int cmd_delete(const CommandLine& line);
int cmd_checkpoint(const CommandLine& line);
int cmd_restore(const CommandLine& line);
int cmd_watch(const CommandLine& line);       // commands_watch.cpp
int cmd_fetch(const CommandLine& line);       // commands_fetch.cpp

// Prints the result as JSON or `text` (a newline is added) on stdout, as --json asks, and
// flushes: output may be read line by line through a pipe.
inline void emit(const CommandLine& line, const CommandResult& result, const std::string& text) {
  const std::string out = line.global.json ? result_json(result) : text;
  std::fputs(out.c_str(), stdout);
  if (out.empty() || out.back() != '\n') std::fputc('\n', stdout);
  std::fflush(stdout);
}

// The exit code of a run that ended: 0 DONE, 1 FAILED or CANCELLED.
int outcome_exit_code(const lbsolid::v1::Session& session);

}  // namespace lbsolid::cli
