#pragma once
// The input format of fuzz_service, shared with the seed maker (make_seeds.cpp):
//
//   input := call*            at most kMaxCalls calls are made; the rest is ignored
//   call  := method:u8 length:u16 (little endian) payload[length]
//
// method % kMethodCount picks one of the service's unary methods (the Method enum); the payload
// is parsed as that method's request message in binary protobuf (a payload that does not parse is
// skipped, as gRPC would refuse it). A truncated last call is dropped. A session_id or checkpoint_id
// "$" b tail stands for an id answered by an earlier call of the same input (fuzz_service.cpp).
#include <cstddef>
#include <cstdint>
#include <string>

namespace lbsolid::fuzz {

enum class Method : std::uint8_t {
  kCreateSession,
  kGetSession,
  kListSessions,
  kDeleteSession,
  kRun,
  kStep,
  kPause,
  kResume,
  kCancel,
  kCheckpoint,
  kRestore,
  kGetServerInfo,
  kValidateScenario,
  kListOutputs,  // new methods go last: the kept regression inputs name the others by the numbers above
};
inline constexpr int kMethodCount = 14;
inline constexpr int kMaxCalls = 16;

inline std::string encode_call(Method method, const std::string& payload) {
  std::string out;
  out.push_back(static_cast<char>(method));
  out.push_back(static_cast<char>(payload.size() & 0xff));
  out.push_back(static_cast<char>((payload.size() >> 8) & 0xff));
  return out + payload;
}

}  // namespace lbsolid::fuzz
