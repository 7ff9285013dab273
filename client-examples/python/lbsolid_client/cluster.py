"""Several daemons behind one object, as `lbsolid --server A,B,C` does:

    with Cluster(["node-0:50051", "node-1:50051"]) as cluster:
        session = cluster.create(scenario)      # on the least loaded daemon
        cluster.session(session.id).wait()      # found again on the daemon that holds it

A DNS name that resolves to several addresses counts as that many daemons (daemon_names.py).
A new session goes to the daemon with the fewest running sessions per worker, then the fewest
sessions held, then the first listed; with a request id seen before, to the daemon that already
holds it, so that a retried create answers with its first session. A Session keeps the Client of
its own daemon: every later call goes there. Unreachable daemons are skipped (at least one must
answer). Two clients placing at the same moment may choose the same daemon: nothing reserves a
place between the question and the create.
"""
import grpc

from .client import Client, Session
from .daemon_names import expand_dns_names
from .errors import NotFound


class Cluster:
    def __init__(self, addresses, **client_options):
        """`addresses`: a list, or one string of comma-separated addresses; `client_options`: what
        Client takes (timeout, tls_ca, token, ...), the same for every daemon."""
        if isinstance(addresses, str):
            addresses = addresses.split(",")
        if not addresses or any(not a for a in addresses):
            raise ValueError(f"addresses: an empty address in {addresses!r}")
        self.clients = [Client(target, **self._for_name(name, client_options))
                        for target, name in expand_dns_names(addresses)]

    @staticmethod
    def _for_name(name, client_options):
        """An address resolved from `name`: over TLS, the certificate must bear the name."""
        if name is None or not client_options.get("tls_ca"):
            return client_options
        options = list(client_options.get("options") or []) + [("grpc.ssl_target_name_override", name)]
        return {**client_options, "options": options}

    def close(self):
        for client in self.clients:
            client.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def _answering(self, call):
        """(client, call(client)) for each daemon that answers, in order."""
        answers, last_error = [], None
        for client in self.clients:
            try:
                answers.append((client, call(client)))
            except grpc.RpcError as error:
                if error.code() not in (grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.DEADLINE_EXCEEDED):
                    raise
                last_error = error
        if not answers:
            raise last_error
        return answers

    def least_loaded(self) -> Client:
        def load(entry):
            index, (client, info) = entry
            return (info.running_sessions / max(info.workers, 1), info.sessions, index)
        return min(enumerate(self._answering(lambda c: c.info())), key=load)[1][0]

    def create(self, scenario, request_id: str = None) -> Session:
        if request_id:
            for client, sessions in self._answering(lambda c: c.list()):
                if any(s.request_id == request_id for s in sessions):
                    return client.create(scenario, request_id)  # the daemon answers with that session
        return self.least_loaded().create(scenario, request_id)

    def session(self, session_id: str) -> Session:
        """The session on the daemon that holds it; NotFound when none does."""
        for client in self.clients:
            try:
                session = client.session(session_id)
                session.get()
                return session
            except NotFound:
                continue
        raise NotFound("GetSession", grpc.StatusCode.NOT_FOUND,
                       f"session_id: {session_id} is on none of the {len(self.clients)} daemons")

    def list(self):
        """Every daemon's sessions, daemon by daemon."""
        return [s for _, sessions in self._answering(lambda c: c.list()) for s in sessions]
