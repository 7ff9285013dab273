#include "scenario_file.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cli_error.h"
#include "scenario_override.h"
#include "io/api/scenario_translation.h"

namespace lbsolid::cli {

lbsolid::v1::Scenario load_scenario(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CliError(kExitBadInput, path + ": cannot read: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw CliError(kExitBadInput, path + ": cannot read: " + std::strerror(errno));
  lbsolid::v1::Scenario scenario;
  std::string error;
  if (!lbsolid::server::parse_scenario_text(text.str(), &scenario, &error))
    throw CliError(kExitBadInput, path + ": " + error);
  return scenario;
}

lbsolid::v1::Scenario load_scenario(const std::string& path, const std::vector<std::string>& overrides) {
  lbsolid::v1::Scenario scenario = load_scenario(path);
  for (const auto& assignment : overrides) apply_override(scenario, assignment);
  return scenario;
}

}  // namespace lbsolid::cli
