// libFuzzer target: a Scenario in binary protobuf, as CreateSessionRequest carries it over gRPC,
// then scenario_checks.h (translation, the text round trip a checkpoint relies on, a tiny run).
// Seeds: the example scenarios serialized (tests/fuzz/make_seeds.cpp).
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_logging.h"
#include "fuzz/scenario_checks.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  lbsolid::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return -1;
  lbsolid::v1::Scenario scenario;
  if (!scenario.ParseFromArray(data, static_cast<int>(size))) return 0;
  lbsolid::fuzz::check_scenario(scenario);
  return 0;
}
