"""A DNS name that resolves to several addresses stands for that many daemons, as in
`lbsolid --server` (client-examples/cli/daemon_names.h): a Kubernetes headless Service names every
replica of a StatefulSet this way, and left to gRPC such a name would reach one replica only."""
import ipaddress
import socket


def resolve_tcp(host):
    """The numeric addresses of `host` for TCP, in the resolver's order, each once; [] if it does
    not resolve."""
    try:
        found = socket.getaddrinfo(host, None, type=socket.SOCK_STREAM)
    except socket.gaierror:
        return []
    addresses = []
    for family, _, _, _, sockaddr in found:
        if family in (socket.AF_INET, socket.AF_INET6) and sockaddr[0] not in addresses:
            addresses.append(sockaddr[0])
    return addresses


def _never_resolved(entry):
    schemes = ("unix:", "unix-abstract:", "dns:", "ipv4:", "ipv6:")
    return entry.startswith(schemes) or "://" in entry or entry.startswith("[")


def _is_ip_literal(host):
    try:
        ipaddress.ip_address(host)
        return True
    except ValueError:
        return False


def expand_dns_names(entries, resolve=resolve_tcp):
    """[(target, name)]: every entry as listed with name None, except HOST:PORT entries whose HOST
    resolves to two or more addresses: one ("IP:PORT" or "[IPv6]:PORT", HOST) per address. Unix
    sockets, targets with a scheme, IP literals and entries without a port are never resolved."""
    daemons = []
    for entry in entries:
        host, colon, port = entry.rpartition(":")
        if _never_resolved(entry) or not colon or not host or not port or _is_ip_literal(host):
            daemons.append((entry, None))
            continue
        addresses = resolve(host)
        if len(addresses) < 2:
            daemons.append((entry, None))
            continue
        daemons.extend(((f"[{a}]" if ":" in a else a) + ":" + port, host) for a in addresses)
    return daemons
