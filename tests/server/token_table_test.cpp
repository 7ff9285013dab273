// The tokens file and the authenticator that maps a call's credentials to an identity: hashes
// only, every malformed line named, a failed reload keeping the tokens in force, and no answer that
// echoes a token. The hashes here are sha256sum's output for the token text (computed by coreutils,
// not by the code under test): printf %s alice-secret | sha256sum.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "server/auth/authenticator.h"
#include "server/auth/token_table.h"
#include "service/coreutils_sha256.h"
#include "service/daemon_process.h"

namespace lbsolid::testing {
namespace {

using server::auth::Authenticator;
using server::auth::parse_tokens;
using server::auth::Role;
using server::auth::TokenTable;


TEST(TokenTable, MapsTheHashOfATokenToItsOwnerAndRole) {
  const std::string text = "# owners\n\n" + coreutils_sha256("alice-secret") + " alice user\n" + coreutils_sha256("root-secret") +
                           "   ops.admin@site   admin\n";
  const auto tokens = parse_tokens(text);
  ASSERT_TRUE(tokens.ok()) << tokens.status();
  ASSERT_EQ(tokens->size(), 2u);
  EXPECT_EQ(tokens->at(coreutils_sha256("alice-secret")).owner, "alice");
  EXPECT_EQ(tokens->at(coreutils_sha256("alice-secret")).role, Role::kUser);
  EXPECT_EQ(tokens->at(coreutils_sha256("root-secret")).owner, "ops.admin@site");
  EXPECT_EQ(tokens->at(coreutils_sha256("root-secret")).role, Role::kAdmin);
}

TEST(TokenTable, EachMalformedLineIsNamedWithItsReason) {
  const std::string hash = coreutils_sha256("t");
  const struct {
    std::string text, expected;
  } cases[] = {
      {"\n" + hash + " alice\n", "line 2: expected `<sha256 hex> <owner> <role>`"},
      {"plain-token alice user\n", "line 1: the hash must be 64 lowercase hex digits"},
      {hash + " alice root\n", "line 1: role: must be user or admin"},
      {hash + " ../../x user\n", "line 1: owner: may hold only letters, digits and . _ - @"},
      {hash + " " + std::string(65, 'a') + " user\n", "line 1: owner: must have 1 to 64 characters, has 65"},
      {hash + " a user\n" + hash + " b user\n", "line 2: this hash appears twice"},
  };
  for (const auto& c : cases) {
    const auto tokens = parse_tokens(c.text);
    ASSERT_FALSE(tokens.ok()) << c.text;
    EXPECT_NE(std::string(tokens.status().message()).find(c.expected), std::string::npos) << tokens.status();
  }
}

TEST(TokenTable, AFailedReloadKeepsTheTokensInForce) {
  const ScopedDirectory dir("lbsolid-tokens");
  const std::string path = dir.path + "/tokens";
  std::ofstream(path) << coreutils_sha256("alice-secret") << " alice user\n";
  TokenTable table(path);
  ASSERT_TRUE(table.find("alice-secret"));
  std::ofstream(path) << "garbage\n";
  const auto reloaded = table.reload();
  EXPECT_FALSE(reloaded.ok());
  EXPECT_NE(std::string(reloaded.message()).find(path), std::string::npos) << reloaded;
  ASSERT_TRUE(table.find("alice-secret"));  // still in force
  std::ofstream(path) << coreutils_sha256("bob-secret") << " bob user\n";
  ASSERT_TRUE(table.reload().ok());
  EXPECT_FALSE(table.find("alice-secret"));  // revoked
  ASSERT_TRUE(table.find("bob-secret"));
  EXPECT_EQ(table.find("bob-secret")->owner, "bob");
  EXPECT_THROW(TokenTable(dir.path + "/absent"), std::runtime_error);
}

TEST(Authenticator, RefusesMissingWrongAndMalformedCredentialsWithoutEchoingThem) {
  const ScopedDirectory dir("lbsolid-tokens");
  const std::string path = dir.path + "/tokens";
  std::ofstream(path) << coreutils_sha256("alice-secret") << " alice user\n";
  const Authenticator authenticator(std::make_shared<TokenTable>(path), /*client_certificates=*/false);
  ASSERT_TRUE(authenticator.authenticates());
  const auto alice = authenticator.identify("Bearer alice-secret", "");
  ASSERT_TRUE(alice.ok()) << alice.status();
  EXPECT_EQ(alice->owner, "alice");
  for (const std::string bad : {"Bearer wrong-secret", "Basic alice-secret", "alice-secret", "Bearer "}) {
    const auto refused = authenticator.identify(bad, "");
    ASSERT_FALSE(refused.ok()) << bad;
    EXPECT_EQ(refused.status().code(), absl::StatusCode::kUnauthenticated);
    EXPECT_EQ(std::string(refused.status().message()).find("secret"), std::string::npos) << refused.status();
  }
  const auto missing = authenticator.identify(std::nullopt, "");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(std::string(missing.status().message()).find("authorization: missing"), std::string::npos);
}

TEST(Authenticator, ClientCertificatesNameTheOwnerAndNobodyIsTheLocalAdminWithoutAuthentication) {
  const Authenticator certificates(nullptr, /*client_certificates=*/true);
  const auto carol = certificates.identify(std::nullopt, "carol");
  ASSERT_TRUE(carol.ok()) << carol.status();
  EXPECT_EQ(carol->owner, "carol");
  EXPECT_EQ(carol->role, Role::kUser);
  EXPECT_FALSE(certificates.identify(std::nullopt, "").ok());
  EXPECT_FALSE(certificates.identify(std::nullopt, "carol/../x").ok());  // not an owner name
  EXPECT_FALSE(certificates.identify("Bearer x", "carol").ok());  // tokens not configured: refused, not ignored

  const Authenticator nobody(nullptr, false);
  EXPECT_FALSE(nobody.authenticates());
  const auto local = nobody.identify(std::nullopt, "");
  ASSERT_TRUE(local.ok());
  EXPECT_EQ(local->owner, "local");
  EXPECT_EQ(local->role, Role::kAdmin);
}

}  // namespace
}  // namespace lbsolid::testing
