"""Typed errors for the daemon's refusals: every call of the client raises a subclass of
LbsolidError (itself a grpc.RpcError, so code() and details() work as before) named after the gRPC
code, with the field at fault when the daemon names one ("scenario.fluid.omega: must lie in ...").

    try:
        client.create(scenario)
    except InvalidArgument as error:
        print(error.field, error.reason)
"""
import re

import grpc


class LbsolidError(grpc.RpcError):
    """A call the daemon (or gRPC) refused: code, details, and the field and reason when named."""

    def __init__(self, rpc: str, code: grpc.StatusCode, details: str):
        super().__init__(f"{rpc}: {code.name}: {details or '(no message)'}")
        self.rpc = rpc
        self._code = code
        self._details = details or ""
        self.field, self.reason = _field_of(self._details)

    def code(self) -> grpc.StatusCode:
        return self._code

    def details(self) -> str:
        return self._details


class InvalidArgument(LbsolidError): pass
class NotFound(LbsolidError): pass
class AlreadyExists(LbsolidError): pass
class FailedPrecondition(LbsolidError): pass
class OutOfRange(LbsolidError): pass
class ResourceExhausted(LbsolidError): pass
class Unauthenticated(LbsolidError): pass
class PermissionDenied(LbsolidError): pass
class Unavailable(LbsolidError): pass
class DeadlineExceeded(LbsolidError): pass
class Aborted(LbsolidError): pass
class DataLoss(LbsolidError): pass
class Internal(LbsolidError): pass


_BY_CODE = {
    grpc.StatusCode.INVALID_ARGUMENT: InvalidArgument, grpc.StatusCode.NOT_FOUND: NotFound,
    grpc.StatusCode.ALREADY_EXISTS: AlreadyExists, grpc.StatusCode.FAILED_PRECONDITION: FailedPrecondition,
    grpc.StatusCode.OUT_OF_RANGE: OutOfRange, grpc.StatusCode.RESOURCE_EXHAUSTED: ResourceExhausted,
    grpc.StatusCode.UNAUTHENTICATED: Unauthenticated, grpc.StatusCode.PERMISSION_DENIED: PermissionDenied,
    grpc.StatusCode.UNAVAILABLE: Unavailable, grpc.StatusCode.DEADLINE_EXCEEDED: DeadlineExceeded,
    grpc.StatusCode.ABORTED: Aborted, grpc.StatusCode.DATA_LOSS: DataLoss, grpc.StatusCode.INTERNAL: Internal,
}

# "<field path>: <reason>", the path dotted words with optional [index]es.
_FIELD = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*(?:\[\d+\])?(?:\.[A-Za-z_][A-Za-z0-9_]*(?:\[\d+\])?)*): (.*)$", re.S)


def _field_of(details: str):
    match = _FIELD.match(details)
    return (match.group(1), match.group(2)) if match else (None, details)


def typed(rpc: str, error: grpc.RpcError) -> LbsolidError:
    """The typed form of an error a call raised (an LbsolidError stays as it is)."""
    if isinstance(error, LbsolidError):
        return error
    code = error.code() if hasattr(error, "code") else grpc.StatusCode.UNKNOWN
    details = error.details() if hasattr(error, "details") else str(error)
    return _BY_CODE.get(code, LbsolidError)(rpc, code, details)


class TypedStub:
    """The generated stub, whose calls raise typed errors: unary calls when made, streams as they
    are read (the iterator keeps the call's cancel())."""

    def __init__(self, stub):
        self._stub = stub

    def __getattr__(self, rpc):
        method = getattr(self._stub, rpc)

        def call(*args, **kwargs):
            try:
                result = method(*args, **kwargs)
            except grpc.RpcError as error:
                raise typed(rpc, error) from error
            return _TypedStream(rpc, result) if hasattr(result, "__next__") else result

        return call


class _TypedStream:
    def __init__(self, rpc, stream):
        self._rpc = rpc
        self._stream = stream

    def __iter__(self):
        return self

    def __next__(self):
        try:
            return next(self._stream)
        except grpc.RpcError as error:
            raise typed(self._rpc, error) from error

    def __getattr__(self, name):  # cancel(), code(), ... of the call
        return getattr(self._stream, name)
