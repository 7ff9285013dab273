#pragma once
// The daemon's listener: plaintext, TLS or mutual TLS, and the bearer-token check that runs
// before a call reaches the service (an AuthMetadataProcessor, which gRPC calls on secure
// listeners only; on a plaintext one the service asks the same Authenticator itself, see
// caller.h). Plaintext is allowed only on loopback or a Unix socket unless the operator says
// --allow_insecure.
#include <grpcpp/security/server_credentials.h>

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "server/auth/authenticator.h"

namespace lbsolid::server::auth {

struct TransportOptions {
  std::string listen;          // host:port, [v6]:port or unix:PATH
  std::string tls_cert;        // PEM files; both or neither
  std::string tls_key;
  std::string tls_client_ca;   // PEM; set: client certificates required and verified against it
  bool allow_insecure = false; // plaintext on a non-loopback address
  unsigned reload_interval_s = 60;  // the PEM files are read again this often (renewed certificates)
};

// True for unix:/unix-abstract: addresses, localhost and the loopback ranges 127.0.0.0/8 and ::1.
bool is_local_address(const std::string& listen);

// --advertise_address: where clients reach this daemon, handed to them in every Session. Empty
// (none), unix:PATH, or HOST:PORT with a port in [1, 65535]; printable ASCII without spaces, at
// most 255 characters. Otherwise INVALID_ARGUMENT naming the flag and the reason.
absl::Status check_advertise_address(const std::string& address);

// The credentials to serve `options.listen` with, or an error naming the flag and the reason
// (missing or unreadable files; off loopback without --allow_insecure: plaintext, or no
// authentication). Secure
// credentials get a processor that authenticates every call with `authenticator` except the
// health and reflection services'.
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> server_credentials(
    const TransportOptions& options, std::shared_ptr<const Authenticator> authenticator);

// The auth-context properties the processor leaves for the service.
inline constexpr char kOwnerProperty[] = "lbsolid.owner";
inline constexpr char kRoleProperty[] = "lbsolid.role";

}  // namespace lbsolid::server::auth
