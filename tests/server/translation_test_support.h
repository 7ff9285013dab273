#pragma once
// Shared by the scenario-translation tests: a scenario from its text, translated, and how their
// messages are listed and looked for.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/api/scenario_translation.h"

namespace lbsolid::server::testing {

inline TranslatedScenario translated(const std::string& text) {
  lbsolid::v1::Scenario scenario;
  std::string error;
  EXPECT_TRUE(parse_scenario_text(text, &scenario, &error)) << error << "\nin:\n" << text;
  return translate_scenario(scenario);
}

inline std::string listed(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& e : lines) out += "\n  " + e;
  return out.empty() ? " (none)" : out;
}

// Exactly one of `scenario`'s translation errors starts with `error`.
inline void expect_one_error_starting(const std::string& scenario, const std::string& error) {
  const auto t = translated(scenario);
  int found = 0;
  for (const auto& e : t.errors) found += e.rfind(error, 0) == 0;
  EXPECT_EQ(found, 1) << "expected one error starting \"" << error << "\"; got" << listed(t.errors)
                      << "\nfor: " << scenario;
}

}  // namespace lbsolid::server::testing
