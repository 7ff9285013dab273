// lbsolid: the command-line client of lbsolidd. Parses the command line, runs one command and
// turns whatever it throws into a message (human on stderr, or a JSON object on stdout with
// --json) and the documented exit code (exit_codes.h).
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "cli_error.h"
#include "cli_options.h"
#include "commands.h"
#include "json_writer.h"

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

int report(bool json, const std::string& code, const std::string& rpc, const std::string& message, int exit_code) {
  std::fprintf(stderr, "lbsolid: %s\n", message.c_str());
  if (json) {
    JsonObject error;
    error.string("code", code);
    if (!rpc.empty()) error.string("rpc", rpc);
    error.string("message", message).integer("exit_code", exit_code);
    std::printf("%s\n", JsonObject().raw("error", error.str()).str().c_str());
    std::fflush(stdout);
  }
  return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  // Known before parsing, so that even a usage error is reported as JSON when asked.
  bool json = false;
  for (const auto& arg : args) json = json || arg == "--json";
  try {
    const CommandLine line = parse_command_line(args, std::getenv("LBSOLID_SERVER"));
    if (line.help) {
      const CommandSpec* spec = line.command.empty() ? nullptr : find_command(line.command);
      std::fputs(spec ? command_usage(*spec).c_str() : usage_text().c_str(), stdout);
      return kExitOk;
    }
    return commands().at(line.command)(line);
  } catch (const UsageError& e) {
    report(json, "USAGE", "", e.what(), kExitBadInput);
    if (!json) std::fputs("Try 'lbsolid --help'.\n", stderr);
    return kExitBadInput;
  } catch (const RpcError& e) {
    return report(json, status_code_name(e.code), e.rpc, e.what(), e.exit_code());
  } catch (const CliError& e) {
    return report(json, e.exit_code == kExitBadInput ? "BAD_INPUT" : "TRANSIENT", "", e.what(), e.exit_code);
  } catch (const std::exception& e) {
    return report(json, "INTERNAL", "", e.what(), kExitTransient);
  }
}
