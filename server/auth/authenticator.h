#pragma once
// Who is calling, from a call's credentials: a bearer token (`authorization: Bearer <token>`,
// looked up in the tokens file) or, with mutual TLS, the verified client certificate's common
// name (an owner of role user). A daemon with neither configured authenticates nobody and every
// caller is the local admin (identity.h); it only listens on loopback or a Unix socket then.
#include <memory>
#include <optional>
#include <string_view>

#include "absl/status/statusor.h"
#include "server/auth/identity.h"
#include "server/auth/token_table.h"

namespace lbsolid::server::auth {

class Authenticator {
 public:
  // `tokens` may be null (no tokens file); `client_certificates`: mutual TLS is required.
  Authenticator(std::shared_ptr<TokenTable> tokens, bool client_certificates)
      : tokens_(std::move(tokens)), client_certificates_(client_certificates) {}

  bool authenticates() const { return tokens_ != nullptr || client_certificates_; }
  TokenTable* tokens() const { return tokens_.get(); }

  // `authorization`: the call's metadata of that name, if any; `certificate_name`: the verified
  // client certificate's common name, empty if none. UNAUTHENTICATED says what was wrong, never
  // echoing the token.
  absl::StatusOr<Identity> identify(std::optional<std::string_view> authorization,
                                    std::string_view certificate_name) const;

 private:
  std::shared_ptr<TokenTable> tokens_;
  bool client_certificates_;
};

}  // namespace lbsolid::server::auth
