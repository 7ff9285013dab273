#include "rpc_client.h"

#include <chrono>
#include <cstdint>
#include <random>

#include "channel_security.h"

namespace lbsolid::cli {

Daemon::Daemon(const GlobalOptions& options) : options_(options) {
  grpc::ChannelArguments args;
  // Frames of large bodies can exceed gRPC's 4 MiB default; the daemon enforces its own limit
  // (ServerInfo.max_message_bytes), so the client accepts whatever it sends.
  args.SetMaxReceiveMessageSize(-1);
  // Keepalive for streams followed without a deadline: a ping every 5.5 minutes detects a dead
  // connection without tripping a default server's ping policy (at most one ping per 5 minutes
  // when it sends no data), which would close the connection with "too many pings".
  args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, 330'000);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 20'000);
  args.SetInt(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA, 0);
  channel_ = open_channel(options, args);
  stub_ = lbsolid::v1::Simulation::NewStub(channel_);
}

void Daemon::set_deadline(grpc::ClientContext& context) const { set_deadline(context, options_.timeout_s); }

void Daemon::set_deadline(grpc::ClientContext& context, double seconds) const {
  const auto timeout = std::chrono::duration<double>(seconds);
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::duration_cast<std::chrono::system_clock::duration>(timeout));
}

std::string random_request_id() {
  std::random_device device;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id;
  for (int word = 0; word < 4; ++word) {  // 4 x 32 bits from the OS entropy source
    std::uint32_t bits = device();
    for (int nibble = 0; nibble < 8; ++nibble, bits >>= 4) id += kHex[bits & 15];
  }
  return id;
}

}  // namespace lbsolid::cli
