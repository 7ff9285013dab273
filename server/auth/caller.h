#pragma once
// The identity of the caller of a service method: left in the call's auth context by the token
// processor on a secure listener (transport.h), or, on a plaintext one, established here from the
// same credentials by the same Authenticator.
#include <grpcpp/server_context.h>

#include "absl/status/statusor.h"
#include "server/auth/authenticator.h"

namespace lbsolid::server::auth {

absl::StatusOr<Identity> caller_of(const grpc::ServerContext& context, const Authenticator& authenticator);

}  // namespace lbsolid::server::auth
