#include "declared_steps.h"

#include <fstream>

#include "cli_options.h"

namespace lbsolid::cli {

namespace {

std::string_view skip_spaces(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return s;
}

}  // namespace

long declared_steps(std::istream& text, const std::string& name) {
  std::string line;
  for (int number = 1; std::getline(text, line); ++number) {
    std::string_view rest = skip_spaces(line);
    if (rest.empty() || rest.front() != '#') continue;
    rest = skip_spaces(rest.substr(1));
    if (rest.substr(0, 6) != "steps:") continue;
    rest = skip_spaces(rest.substr(6));
    const std::string digits(rest.substr(0, rest.find_first_not_of("0123456789")));
    return parse_long(name + " line " + std::to_string(number) + " '# steps:'", digits, 1);
  }
  return 0;
}

long declared_steps(const std::string& path) {
  std::ifstream in(path);
  return in ? declared_steps(in, path) : 0;
}

}  // namespace lbsolid::cli
