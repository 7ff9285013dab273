// libFuzzer target: JSON scenario files. Only inputs whose first non-blank character is '{' are
// taken (the rest would go to the text-format parser, fuzz_scenario_text's job), so the effort goes
// into the JSON path: the position-finding json::Locator (io/api/json_locator.h), protobuf's
// JsonStringToMessage, the error's field path; then scenario_checks.h. Seeds: the example
// scenarios printed as JSON (tests/fuzz/make_seeds.cpp).
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
  if (size > 64 * 1024) return -1;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t first = text.find_first_not_of(" \t\r\n\f\v");
  if (first == std::string::npos || text[first] != '{') return -1;  // not JSON: not this target's input
  lbsolid::fuzz::check_scenario_text(text);
  return 0;
}
