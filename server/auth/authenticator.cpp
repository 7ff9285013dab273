#include "server/auth/authenticator.h"

#include <string>

namespace lbsolid::server::auth {

absl::StatusOr<Identity> Authenticator::identify(std::optional<std::string_view> authorization,
                                                 std::string_view certificate_name) const {
  if (authorization) {
    if (!tokens_)
      return absl::UnauthenticatedError("authorization: this daemon takes no bearer tokens (it has no --tokens_file)");
    constexpr std::string_view kScheme = "Bearer ";
    if (authorization->substr(0, kScheme.size()) != kScheme)
      return absl::UnauthenticatedError("authorization: expected `Bearer <token>`");
    if (auto identity = tokens_->find(authorization->substr(kScheme.size()))) return *identity;
    return absl::UnauthenticatedError("authorization: unknown or revoked token");
  }
  if (!certificate_name.empty()) {
    Identity identity{std::string(certificate_name), Role::kUser};
    if (const auto problem = owner_name_problem(identity.owner); !problem.empty())
      return absl::UnauthenticatedError("client certificate: its common name cannot name an owner: " + problem);
    return identity;
  }
  if (authenticates())
    return absl::UnauthenticatedError(
        tokens_ ? "authorization: missing (send the metadata `authorization: Bearer <token>`)"
                : "client certificate: missing");
  return local_admin();
}

}  // namespace lbsolid::server::auth
