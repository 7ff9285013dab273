#include "server/auth/token_table.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "absl/strings/str_cat.h"
#include "io/storage/sha256.h"

namespace lbsolid::server::auth {

std::string owner_name_problem(const std::string& name) {
  if (name.empty() || name.size() > 64) return absl::StrCat("must have 1 to 64 characters, has ", name.size());
  for (const char c : name) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                         c == '_' || c == '-' || c == '@';
    if (!allowed) return "may hold only letters, digits and . _ - @";
  }
  return "";
}

namespace {

bool is_sha256_hex(std::string_view text) {
  if (text.size() != 64) return false;
  for (const char c : text)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

absl::StatusOr<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("--tokens_file: cannot read ", path));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

absl::StatusOr<TokenMap> parse_tokens(std::string_view text) {
  TokenMap tokens;
  int line_number = 0;
  std::istringstream lines{std::string(text)};
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    std::istringstream fields(line);
    std::vector<std::string> words;
    for (std::string word; fields >> word;) words.push_back(word);
    if (words.empty() || words[0].front() == '#') continue;
    const auto bad = [&](const std::string& why) {
      return absl::InvalidArgumentError(absl::StrCat("line ", line_number, ": ", why));
    };
    if (words.size() != 3) return bad("expected `<sha256 hex> <owner> <role>`");
    if (!is_sha256_hex(words[0])) return bad("the hash must be 64 lowercase hex digits (sha256sum of the token)");
    Identity identity{words[1]};
    if (const auto problem = owner_name_problem(identity.owner); !problem.empty()) return bad("owner: " + problem);
    if (words[2] == "admin") identity.role = Role::kAdmin;
    else if (words[2] != "user") return bad("role: must be user or admin");
    if (!tokens.emplace(words[0], identity).second) return bad("this hash appears twice");
  }
  return tokens;
}

TokenTable::TokenTable(std::string path) : path_(std::move(path)) {
  if (const auto status = reload(); !status.ok()) throw std::runtime_error(std::string(status.message()));
}

absl::Status TokenTable::reload() {
  const auto text = read_file(path_);
  if (!text.ok()) return text.status();
  auto tokens = parse_tokens(*text);
  if (!tokens.ok()) return absl::InvalidArgumentError(absl::StrCat("--tokens_file ", path_, ": ", tokens.status().message()));
  auto table = std::make_shared<const TokenMap>(*std::move(tokens));
  std::lock_guard lock(mutex_);
  tokens_ = std::move(table);
  return absl::OkStatus();
}

std::optional<Identity> TokenTable::find(std::string_view token) const {
  std::shared_ptr<const TokenMap> tokens;
  {
    std::lock_guard lock(mutex_);
    tokens = tokens_;
  }
  const auto it = tokens->find(storage::sha256_hex(token));
  if (it == tokens->end()) return std::nullopt;
  return it->second;
}

std::size_t TokenTable::size() const {
  std::lock_guard lock(mutex_);
  return tokens_->size();
}

}  // namespace lbsolid::server::auth
