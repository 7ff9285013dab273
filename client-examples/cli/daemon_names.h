#pragma once
// A --server entry whose host is a DNS name naming several addresses stands for that many daemons,
// as if each address were listed (a Kubernetes headless Service names every replica of a
// StatefulSet this way). Left to gRPC, such a name would reach one of them only, and a later call
// about a session could land on a replica that does not hold it.
#include <functional>
#include <string>
#include <vector>

namespace lbsolid::cli {

struct DaemonAddress {
  std::string target;  // what the channel dials: the entry as listed, or one resolved "IP:PORT"
  std::string name;    // the DNS name it was resolved from (TLS checks the certificate for it); empty if listed as is
};

// The numeric addresses of `host` for TCP, in the resolver's order, each once; none if it does
// not resolve.
using Resolver = std::function<std::vector<std::string>(const std::string& host)>;
std::vector<std::string> resolve_tcp(const std::string& host);

// Every entry as listed, except `NAME:PORT` entries whose NAME resolves to two or more addresses:
// those become one DaemonAddress per address ("IP:PORT", "[IPv6]:PORT"). Unix sockets, targets
// with a scheme, IP literals and entries without a port are never resolved here.
std::vector<DaemonAddress> expand_dns_names(const std::vector<std::string>& entries,
                                            const Resolver& resolve = resolve_tcp);

}  // namespace lbsolid::cli
