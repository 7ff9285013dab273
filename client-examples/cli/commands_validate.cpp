// validate: every problem the daemon finds in a scenario file, not only the first 20 a refused
// submit names (ValidateScenario), and its near-edge warnings; creates nothing. An orchestrator can
// run it before submit: exit 0 means the daemon accepts the scenario's content, 2 that it does not.
#include <cstdio>
#include <string>
#include <vector>

#include "commands.h"
#include "daemon_placement.h"
#include "json_writer.h"
#include "rpc_client.h"
#include "scenario_file.h"

namespace lbsolid::cli {
namespace {

// "N problems" / "N warnings", with the count of those the daemon left out of its answer.
std::string count_line(long long total, int listed, const char* what) {
  std::string line = std::to_string(total) + " " + what;
  if (total > listed) line += " (" + std::to_string(total - listed) + " not listed: the answer's 3 MiB limit)";
  return line;
}

}  // namespace

int cmd_validate(const CommandLine& line) {
  const std::string& file = line.positional[0];
  lbsolid::v1::ValidateScenarioRequest request;
  *request.mutable_scenario() = load_scenario(file, line.all("set"));
  Daemon daemon(first_daemon(line.global));
  const auto answer = daemon.call("ValidateScenario", &Stub::ValidateScenario, request);
  const std::vector<std::string> problems(answer.problems().begin(), answer.problems().end());
  const std::vector<std::string> warnings(answer.warnings().begin(), answer.warnings().end());
  const bool valid = answer.problems_total() == 0;

  std::string text = file + (valid ? ": valid" : ": invalid") + "\n";
  for (const auto& problem : problems) text += "  problem: " + problem + "\n";
  for (const auto& warning : warnings) text += "  warning: " + warning + "\n";
  text += count_line(answer.problems_total(), answer.problems_size(), "problems") + ", " +
          count_line(answer.warnings_total(), answer.warnings_size(), "warnings");
  CommandResult result;
  result.command = line.command;
  result.exit_code = valid ? kExitOk : kExitBadInput;
  if (!valid)
    result.error = ResultError{"BAD_INPUT", "", file + ": " + std::to_string(answer.problems_total()) + " problems",
                               kExitBadInput};
  result.add("validation", JsonObject()
                               .string("file", file)
                               .boolean("valid", valid)
                               .raw("problems", json_string_array(problems))
                               .integer("problems_total", answer.problems_total())
                               .raw("warnings", json_string_array(warnings))
                               .integer("warnings_total", answer.warnings_total())
                               .str());
  emit(line, result, text);
  return result.exit_code;
}

}  // namespace lbsolid::cli
