#include "daemon_names.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <sys/socket.h>

#include <algorithm>
#include <memory>

namespace lbsolid::cli {
namespace {

bool is_ipv4_literal(const std::string& host) {
  in_addr address{};
  return inet_pton(AF_INET, host.c_str(), &address) == 1;
}

// Entries gRPC reads as something other than a plain HOST:PORT: unix:PATH, dns:, ipv4:, ipv6:,
// scheme://..., a bracketed IPv6 literal.
bool never_resolved(const std::string& entry) {
  return entry.rfind("unix:", 0) == 0 || entry.rfind("unix-abstract:", 0) == 0 || entry.rfind("dns:", 0) == 0 ||
         entry.rfind("ipv4:", 0) == 0 || entry.rfind("ipv6:", 0) == 0 || entry.find("://") != std::string::npos ||
         entry.rfind('[', 0) == 0;
}

}  // namespace

std::vector<std::string> resolve_tcp(const std::string& host) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0) return {};
  const std::unique_ptr<addrinfo, decltype(&freeaddrinfo)> owned(found, &freeaddrinfo);
  std::vector<std::string> addresses;
  for (const addrinfo* a = found; a; a = a->ai_next) {
    char text[INET6_ADDRSTRLEN] = {};
    const void* raw = a->ai_family == AF_INET6 ? static_cast<const void*>(&reinterpret_cast<const sockaddr_in6*>(a->ai_addr)->sin6_addr)
                                               : static_cast<const void*>(&reinterpret_cast<const sockaddr_in*>(a->ai_addr)->sin_addr);
    if ((a->ai_family != AF_INET && a->ai_family != AF_INET6) || !inet_ntop(a->ai_family, raw, text, sizeof text))
      continue;
    if (std::find(addresses.begin(), addresses.end(), text) == addresses.end()) addresses.emplace_back(text);
  }
  return addresses;
}

std::vector<DaemonAddress> expand_dns_names(const std::vector<std::string>& entries, const Resolver& resolve) {
  std::vector<DaemonAddress> daemons;
  for (const std::string& entry : entries) {
    const std::size_t colon = entry.rfind(':');
    const std::string host = colon == std::string::npos ? "" : entry.substr(0, colon);
    if (never_resolved(entry) || host.empty() || colon + 1 == entry.size() || is_ipv4_literal(host)) {
      daemons.push_back({entry, ""});
      continue;
    }
    const std::string port = entry.substr(colon + 1);
    const std::vector<std::string> addresses = resolve(host);
    if (addresses.size() < 2) {
      daemons.push_back({entry, ""});  // one daemon (or gRPC's own error when it dials)
      continue;
    }
    for (const std::string& address : addresses)
      daemons.push_back({(address.find(':') != std::string::npos ? "[" + address + "]" : address) + ":" + port, host});
  }
  return daemons;
}

}  // namespace lbsolid::cli
