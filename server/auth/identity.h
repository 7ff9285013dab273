#pragma once
// Who makes a call: an owner name (sessions, checkpoints and outputs belong to one) and a role.
// A user acts on what it owns; an admin may list and act on everything.
#include <string>

namespace lbsolid::server::auth {

enum class Role { kUser, kAdmin };

struct Identity {
  std::string owner;
  Role role = Role::kUser;
  bool may_act_on(const std::string& session_owner) const { return role == Role::kAdmin || owner == session_owner; }
};

// The one identity of a daemon that authenticates nobody (no tokens file, no client
// certificates: plaintext on loopback or a Unix socket): every caller is this admin, and
// sessions saved before owners existed belong to it.
inline const std::string kLocalOwner = "local";
inline Identity local_admin() { return {kLocalOwner, Role::kAdmin}; }

// Owner names travel in logs, files and answers: 1 to 64 characters of [A-Za-z0-9._@-].
// Empty if `name` is one, otherwise the reason it is not.
std::string owner_name_problem(const std::string& name);

}  // namespace lbsolid::server::auth
