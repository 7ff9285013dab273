#pragma once
// The tokens file (--tokens_file): one line per token, `<sha256 hex of the token> <owner> <role>`
// with role `user` or `admin`; blank lines and lines starting with `#` are ignored. Only hashes
// are stored, so the file leaks no token. The table is reloaded on SIGHUP: a reload that fails
// keeps the tokens in force and says why, so a typo cannot lock everyone out.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "server/auth/identity.h"

namespace lbsolid::server::auth {

using TokenMap = std::map<std::string, Identity>;  // by the token's SHA-256, lowercase hex

// Parses a tokens file's text; an error names the line and the reason.
absl::StatusOr<TokenMap> parse_tokens(std::string_view text);

class TokenTable {
 public:
  // Loads `path`; throws std::runtime_error naming the path, the line and the reason.
  explicit TokenTable(std::string path);
  // Reads the file again; on error the tokens in force stay and the error is returned.
  absl::Status reload();
  // The identity a bearer token maps to, if any.
  std::optional<Identity> find(std::string_view token) const;
  std::size_t size() const;

 private:
  const std::string path_;
  mutable std::mutex mutex_;
  std::shared_ptr<const TokenMap> tokens_;
};

}  // namespace lbsolid::server::auth
