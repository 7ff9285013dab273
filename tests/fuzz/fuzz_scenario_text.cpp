// libFuzzer target: a scenario file's text, as `lbsolid submit` and the daemon's restore read it
// (parse_scenario_text: protobuf text format, or JSON when it starts with '{'), then translation,
// validation and a tiny run (scenario_checks.h). Seeds: client-examples/scenarios/*.textproto.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_logging.h"
#include "fuzz/scenario_checks.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  lbsolid::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return -1;  // a scenario file is a few kB; longer inputs only cost time
  const std::string text(reinterpret_cast<const char*>(data), size);
  lbsolid::v1::Scenario scenario;
  std::string error;
  if (!lbsolid::server::parse_scenario_text(text, &scenario, &error)) {
    if (error.empty()) lbsolid::fuzz::fail("parse_scenario_text failed without a message", text);
    return 0;
  }
  lbsolid::fuzz::check_scenario(scenario);
  return 0;
}
