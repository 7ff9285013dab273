// lbsolid: the command-line client of lbsolidd. Parses the command line, runs one command and
// turns whatever it throws into a message (human on stderr, or a JSON object on stdout with
// --json) and the documented exit code (exit_codes.h).
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cli_error.h"
#include "cli_options.h"
#include "commands.h"
#include "result_writer.h"
#include "io/version.h"

namespace {

using namespace lbsolid::cli;

using Command = int (*)(const CommandLine&);

const std::map<std::string, Command>& commands() {
  static const std::map<std::string, Command> table = {
      {"submit", cmd_submit}, {"status", cmd_status},   {"list", cmd_list},       {"info", cmd_info},
      {"run", cmd_run},       {"pause", cmd_pause},     {"resume", cmd_resume},   {"cancel", cmd_cancel},
      {"delete", cmd_delete}, {"checkpoint", cmd_checkpoint}, {"restore", cmd_restore}, {"watch", cmd_watch},
      {"fetch", cmd_fetch},   {"validate", cmd_validate},
  };
  return table;
}

// Prints the failure (stderr; with --json also the result object on stdout) and returns its exit
// code. `line` is null when the command line itself did not parse (a UsageError may still say
// which command it named).
int report(bool json, const CommandLine* line, const std::exception& failure) {
  const ResultError error = result_error(failure);
  std::fprintf(stderr, "lbsolid: %s\n", error.message.c_str());
  if (!json && error.code == "USAGE") std::fputs("Try 'lbsolid --help'.\n", stderr);
  if (json) {
    CommandResult result;
    if (const auto* usage = dynamic_cast<const UsageError*>(&failure)) result.command = usage->command;
    if (line) {
      result.command = line->command;
      const CommandSpec* spec = find_command(line->command);
      // Commands about a session echo its id, so a script can tell which one failed.
      if (spec && !spec->positionals.empty() && spec->positionals[0] == "ID" && !line->positional.empty())
        result.session_id = line->positional[0];
    }
    result.error = error;
    result.exit_code = error.exit_code;
    std::printf("%s\n", result_json(result).c_str());
    std::fflush(stdout);
  }
  return error.exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  // Known before parsing, so that even a usage error is reported as JSON when asked.
  bool json = false;
  for (const auto& arg : args) json = json || arg == "--json";
  std::optional<CommandLine> line;
  try {
    line = parse_command_line(args, std::getenv("LBSOLID_SERVER"));
    if (line->version) {
      std::printf("lbsolid %s (%s)\n", LBSOLID_VERSION, LBSOLID_GIT_REVISION);
      return kExitOk;
    }
    if (line->help) {
      const CommandSpec* spec = line->command.empty() ? nullptr : find_command(line->command);
      std::fputs(spec ? command_usage(*spec).c_str() : usage_text().c_str(), stdout);
      return kExitOk;
    }
    return commands().at(line->command)(*line);
  } catch (const std::exception& e) {
    return report(json, line ? &*line : nullptr, e);
  }
}
