#include "server/session/session_id.h"

#include <algorithm>
#include <cstdint>
#include <random>

namespace lbsolid::server {

namespace {

constexpr std::string_view kPrefix = "s-";
constexpr std::size_t kHexDigits = 32;
constexpr std::string_view kStepPrefix = "step-";
constexpr std::size_t kMaxStepDigits = 18;

bool lowercase_hex(char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); }
bool digit(char c) { return c >= '0' && c <= '9'; }

}  // namespace

std::string new_session_id() {
  // std::random_device reads the kernel's random source (getrandom) on Linux with libstdc++.
  thread_local std::random_device source;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id(kPrefix);
  for (std::size_t k = 0; k < kHexDigits; k += 8) {
    std::uint32_t bits = source();
    for (int n = 0; n < 8; ++n, bits >>= 4) id += kHex[bits & 0xf];
  }
  return id;
}

bool valid_session_id(std::string_view id) {
  return id.size() == kPrefix.size() + kHexDigits && id.substr(0, kPrefix.size()) == kPrefix &&
         std::all_of(id.begin() + kPrefix.size(), id.end(), lowercase_hex);
}

bool valid_checkpoint_id(std::string_view id) {
  const auto slash = id.find('/');
  if (slash == std::string_view::npos || !valid_session_id(id.substr(0, slash))) return false;
  const std::string_view step = id.substr(slash + 1);
  if (step.substr(0, kStepPrefix.size()) != kStepPrefix) return false;
  const std::string_view digits = step.substr(kStepPrefix.size());
  return !digits.empty() && digits.size() <= kMaxStepDigits && std::all_of(digits.begin(), digits.end(), digit);
}

}  // namespace lbsolid::server
