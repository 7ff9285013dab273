// --advertise_address is handed to every client in each Session's endpoint, and clients then
// dial it: an address a client cannot use must stop the daemon at start, naming the flag.
#include <gtest/gtest.h>

#include <string>

#include "server/auth/transport.h"

namespace lbsolid::server::auth {
namespace {

TEST(AdvertiseAddress, TakesHostPortUnixOrNothing) {
  for (const std::string address : {"", "node-1.lbsolid.svc:50051", "10.0.0.7:1", "[::1]:65535", "unix:/run/lbsolid.sock"})
    EXPECT_TRUE(check_advertise_address(address).ok()) << address;
}

TEST(AdvertiseAddress, RefusesWhatNoClientCanDialNamingTheFlag) {
  const std::pair<std::string, std::string> cases[] = {
      {"node-1", "is not HOST:PORT"},
      {":50051", "is not HOST:PORT"},
      {"node-1:", "must be a number in [1, 65535]"},
      {"node-1:0", "must be a number in [1, 65535]"},
      {"node-1:65536", "must be a number in [1, 65535]"},
      {"node-1:5x", "must be a number in [1, 65535]"},
      {"node-1:999999999999", "must be a number in [1, 65535]"},
      {"node 1:50051", "without spaces"},
      {"node-1:50051\nforged log line", "without spaces"},
      {"unix:", "needs a path"},
      {std::string(300, 'a') + ":1", "longer than 255"},
  };
  for (const auto& [address, reason] : cases) {
    const absl::Status status = check_advertise_address(address);
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << address;
    EXPECT_NE(status.message().find("--advertise_address: "), std::string::npos) << status.message();
    EXPECT_NE(status.message().find(reason), std::string::npos) << address << ": " << status.message();
  }
}

}  // namespace
}  // namespace lbsolid::server::auth
