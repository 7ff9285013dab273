#include "server/auth/caller.h"

#include "server/auth/transport.h"

namespace lbsolid::server::auth {

namespace {

std::string property(const grpc::AuthContext& context, const char* name) {
  for (const auto& value : context.FindPropertyValues(name)) return std::string(value.data(), value.size());
  return "";
}

}  // namespace

absl::StatusOr<Identity> caller_of(const grpc::ServerContext& context, const Authenticator& authenticator) {
  const auto auth = context.auth_context();
  if (auth) {
    if (std::string owner = property(*auth, kOwnerProperty); !owner.empty())
      return Identity{std::move(owner), property(*auth, kRoleProperty) == "admin" ? Role::kAdmin : Role::kUser};
  }
  std::optional<std::string_view> authorization;
  const auto& metadata = context.client_metadata();
  if (const auto header = metadata.find("authorization"); header != metadata.end())
    authorization = std::string_view(header->second.data(), header->second.size());
  return authenticator.identify(authorization, "");
}

}  // namespace lbsolid::server::auth
