#pragma once
// How the CLI reaches a daemon on a network: TLS (--tls-ca: the CA that signed the daemon's
// certificate), mutual TLS (--tls-cert and --tls-key: the client's own certificate) and a bearer
// token (--token-file, else $LBSOLID_TOKEN), sent as `authorization: Bearer <token>` on every
// call. The token goes through an interceptor, not gRPC's call credentials, so that it also
// reaches a daemon on loopback or a Unix socket without TLS (call credentials need TLS).
#include <grpcpp/grpcpp.h>

#include <memory>

#include "cli_options.h"

namespace lbsolid::cli {

// Throws UsageError naming the flag if a file cannot be read or the flags do not go together.
std::shared_ptr<grpc::Channel> open_channel(const GlobalOptions& options, const grpc::ChannelArguments& args);

}  // namespace lbsolid::cli
