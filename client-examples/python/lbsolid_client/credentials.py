"""How a Client reaches a daemon on a network: TLS (the CA that signed the daemon's certificate),
mutual TLS (the client's own certificate and key) and a bearer token, sent as
`authorization: Bearer <token>` on every call.

The token travels through an interceptor, not gRPC's call credentials, so that it also reaches a
daemon on loopback or a Unix socket without TLS (call credentials need TLS), as the CLI's does.
"""
import collections
import os
from pathlib import Path

import grpc


class _CallDetails(collections.namedtuple(
        "_CallDetails", ("method", "timeout", "metadata", "credentials", "wait_for_ready", "compression")),
        grpc.ClientCallDetails):
    pass


class _BearerToken(grpc.UnaryUnaryClientInterceptor, grpc.UnaryStreamClientInterceptor):
    def __init__(self, token: str):
        self._header = ("authorization", f"Bearer {token}")

    def _with_token(self, details):
        metadata = list(details.metadata or []) + [self._header]
        return _CallDetails(details.method, details.timeout, metadata, details.credentials,
                            getattr(details, "wait_for_ready", None), getattr(details, "compression", None))

    def intercept_unary_unary(self, continuation, details, request):
        return continuation(self._with_token(details), request)

    def intercept_unary_stream(self, continuation, details, request):
        return continuation(self._with_token(details), request)


def _read(path):
    return Path(path).read_bytes() if path else None


def open_channel(address: str, tls_ca=None, client_cert=None, client_key=None, token=None, options=None):
    """A channel to `address`: plaintext, or TLS trusting `tls_ca` (a PEM file), with the client
    certificate `client_cert`/`client_key` for mutual TLS; `token` (default $LBSOLID_TOKEN) is sent
    with every call."""
    if (client_cert is None) != (client_key is None):
        raise ValueError("client_cert and client_key: give both or neither")
    if client_cert and not tls_ca:
        raise ValueError("client_cert: needs tls_ca (a client certificate is sent over TLS)")
    options = options or []
    if tls_ca:
        credentials = grpc.ssl_channel_credentials(root_certificates=_read(tls_ca),
                                                   private_key=_read(client_key),
                                                   certificate_chain=_read(client_cert))
        channel = grpc.secure_channel(address, credentials, options=options)
    else:
        channel = grpc.insecure_channel(address, options=options)
    token = token if token is not None else os.environ.get("LBSOLID_TOKEN")
    if token:
        channel = grpc.intercept_channel(channel, _BearerToken(token.strip()))
    return channel
