#pragma once
// Session ids: "s-" and 32 lowercase hex digits (128 random bits from the operating system), so an
// id is never handed out twice, not even after a crash that lost every file naming the old one.
// Every id that reaches a file path, whether from the network or read back from disk, passes
// valid_session_id() first.
#include <string>
#include <string_view>

namespace lbsolid::server {

std::string new_session_id();
bool valid_session_id(std::string_view id);
// "<session id>/step-<digits>" (at most 18 digits, so it fits a long).
bool valid_checkpoint_id(std::string_view id);

}  // namespace lbsolid::server
