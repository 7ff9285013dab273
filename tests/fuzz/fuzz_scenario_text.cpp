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
  lbsolid::fuzz::check_scenario_text(text);
  return 0;
}
