"""A small client for lbsolidd: create a session, run it, watch it, fetch what it computed.

    client = Client("127.0.0.1:50051")
    session = client.create(load_scenario("fig5_drag_disk.textproto"))
    record = session.run_and_record(15000, particles_every=100, bodies=["disk"])
    u = [frame.bodies["disk"].mean_velocity[0] for frame in record.particles]

Every call has a deadline (`timeout`, seconds). Errors from the daemon arrive as typed errors
(errors.py: InvalidArgument, NotFound, ... each a grpc.RpcError with code(), details(), and the
field at fault and the reason when the daemon names one); a session that fails while running
raises SessionFailed with the daemon's "step N: cause". `retryable(error)` says whether retrying the
same call can help (as the CLI's exit code 3 does).
"""
import hashlib
import os
import tempfile
import threading
import uuid
from dataclasses import dataclass, field
from pathlib import Path

import grpc
import numpy as np
from google.protobuf import json_format, text_format

from ._stubs import scenario_pb2, simulation_pb2 as pb, simulation_pb2_grpc
from .credentials import open_channel
from .errors import TypedStub
from .h5md import recording_from_h5md
from .progress import ProgressBar

FINAL_STATES = (pb.SESSION_STATE_DONE, pb.SESSION_STATE_FAILED, pb.SESSION_STATE_CANCELLED)


class SessionFailed(RuntimeError):
    """The session ended FAILED or CANCELLED; the message is the daemon's."""


_RETRYABLE = {grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.DEADLINE_EXCEEDED, grpc.StatusCode.RESOURCE_EXHAUSTED,
              grpc.StatusCode.ABORTED, grpc.StatusCode.INTERNAL, grpc.StatusCode.UNKNOWN,
              grpc.StatusCode.CANCELLED}


def retryable(error: grpc.RpcError) -> bool:
    """Whether the same call may pass when retried. Not for rejections of the request itself, nor
    for two that arrive under transient codes: INTERNAL with no message (gRPC could not parse the
    request) and RESOURCE_EXHAUSTED for a message over gRPC's size limit."""
    code, details = error.code(), error.details() or ""
    if code == grpc.StatusCode.INTERNAL and not details:
        return False
    if code == grpc.StatusCode.RESOURCE_EXHAUSTED and "message larger than max" in details:
        return False
    return code in _RETRYABLE


def load_scenario(path) -> "scenario_pb2.Scenario":
    """A scenario file: protobuf text format, or JSON when its first non-blank character is '{'."""
    text = Path(path).read_text()
    scenario = scenario_pb2.Scenario()
    if text.lstrip().startswith("{"):
        json_format.Parse(text, scenario)
    else:
        text_format.Parse(text, scenario)
    return scenario


@dataclass
class Profile:
    """u_x averaged along x (and z) for each row y, at one step."""
    step: int
    y: np.ndarray
    u_x: np.ndarray


@dataclass
class Body:
    name: str
    position: np.ndarray       # (particles, 3)
    velocity: np.ndarray       # (particles, 3), u_s = Psi / M
    centre_of_mass: np.ndarray  # (3,)
    mean_velocity: np.ndarray   # (3,)
    mass: float
    energy: float               # sum_k |f_k|^2 over the body (MODEL.md eq. 9)
    angular_momentum: np.ndarray = None  # (3,), about the centre of mass
    angular_velocity: np.ndarray = None  # (3,), the inertia tensor solved for it (2D: along z)
    orientation: float = float("nan")    # 2D: radians, the best-fit turn from the rest shape
    orientation_quaternion: np.ndarray = None  # (4,) w, x, y, z: the same turn, 2D and 3D, w >= 0
    torque: np.ndarray = None  # (3,) in the last step, about the centre of mass (scenes with a rotating body)
    anchor_force: np.ndarray = None  # (3,) absorbed by the body's anchors in the last step (drag, lift)
    broken_link_count: int = 0       # a breaking body: its links broken so far
    # the links that broke since the stream's previous frame (all so far in its first), one row each:
    # step, particle (its lower end, an index in the body), link (0 +x, 1 +y, 2 +z), x, y, z
    broken_links: np.ndarray = None  # (breaks, 6)


@dataclass
class Particles:
    step: int
    bodies: dict               # name -> Body


@dataclass
class Field:
    name: str
    step: int
    values: np.ndarray         # [nz, ny, nx] or [nz, ny, nx, 3], x fastest
    spacing: np.ndarray        # node spacing along x, y, z


@dataclass
class Recording:
    session: "pb.Session"      # the session as it ended
    profiles: list = field(default_factory=list)   # [Profile]
    particles: list = field(default_factory=list)  # [Particles]

    def trajectory(self, body: str):
        """(steps, positions (frames, particles, 3)) of one body over the recorded frames."""
        steps = np.array([f.step for f in self.particles], dtype=np.int64)
        return steps, np.stack([f.bodies[body].position for f in self.particles])

    def body_series(self, body: str, quantity: str):
        """(steps, values) of one body quantity (centre_of_mass, mean_velocity, mass, energy,
        angular_momentum, angular_velocity, orientation, orientation_quaternion, torque)."""
        steps = np.array([f.step for f in self.particles], dtype=np.int64)
        return steps, np.array([getattr(f.bodies[body], quantity) for f in self.particles])


def _vector(v) -> np.ndarray:
    return np.array([v.x, v.y, v.z], dtype=np.float64)


def profile_from_proto(frame) -> Profile:
    return Profile(frame.step, np.array(frame.y, dtype=np.float64), np.array(frame.u_x, dtype=np.float64))


def particles_from_proto(frame) -> Particles:
    bodies = {}
    for b in frame.bodies:
        bodies[b.name] = Body(b.name,
                              np.array(b.position, dtype=np.float64).reshape(-1, 3),
                              np.array(b.velocity, dtype=np.float64).reshape(-1, 3),
                              _vector(b.centre_of_mass), _vector(b.mean_velocity), b.mass, b.energy,
                              _vector(b.angular_momentum), _vector(b.angular_velocity), b.orientation,
                              np.array([b.orientation_quaternion.w, b.orientation_quaternion.x,
                                        b.orientation_quaternion.y, b.orientation_quaternion.z], dtype=np.float64),
                              _vector(b.torque), _vector(b.anchor_force), b.broken_link_count,
                              np.array([[l.step, l.particle, l.link, l.position.x, l.position.y, l.position.z]
                                        for l in b.broken_links], dtype=np.float64).reshape(-1, 6))
    return Particles(frame.step, bodies)


class Client:
    def __init__(self, address: str, timeout: float = 30.0, options=None, tls_ca=None, client_cert=None,
                 client_key=None, token=None):
        """`tls_ca`, `client_cert`, `client_key` (PEM files) and `token` (default $LBSOLID_TOKEN):
        see credentials.open_channel."""
        self.address = address
        self.timeout = timeout
        self.channel = open_channel(address, tls_ca, client_cert, client_key, token, options)
        self.stub = TypedStub(simulation_pb2_grpc.SimulationStub(self.channel))

    def close(self):
        self.channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def wait_ready(self, timeout: float = 30.0):
        grpc.channel_ready_future(self.channel).result(timeout=timeout)
        return self

    def info(self):
        return self.stub.GetServerInfo(pb.GetServerInfoRequest(), timeout=self.timeout)

    def create(self, scenario, request_id: str = None) -> "Session":
        """Creates a session; a request id (default: a fresh UUID) makes a retried call harmless."""
        request = pb.CreateSessionRequest(scenario=scenario, request_id=request_id or str(uuid.uuid4()))
        created = self.stub.CreateSession(request, timeout=self.timeout)
        return Session(self, created.id, created)

    def session(self, session_id: str) -> "Session":
        return Session(self, session_id)

    def list(self):
        return list(self.stub.ListSessions(pb.ListSessionsRequest(), timeout=self.timeout).sessions)

    def restore(self, checkpoint_id: str, request_id: str = None) -> "Session":
        """A new session holding the checkpoint's state, ready to run on from its step."""
        request = pb.RestoreRequest(checkpoint_id=checkpoint_id, request_id=request_id or str(uuid.uuid4()))
        restored = self.stub.Restore(request, timeout=self.timeout)
        return Session(self, restored.id, restored)


class Session:
    def __init__(self, client: Client, session_id: str, snapshot=None):
        self.client = client
        self.id = session_id
        self.snapshot = snapshot  # the last Session message received

    @property
    def _stub(self):
        return self.client.stub

    def get(self):
        self.snapshot = self._stub.GetSession(pb.GetSessionRequest(session_id=self.id), timeout=self.client.timeout)
        return self.snapshot

    def run(self, steps: int):
        """Starts `steps` more steps in the background and returns at once (see wait)."""
        self.snapshot = self._stub.Run(pb.RunRequest(session_id=self.id, steps=steps), timeout=self.client.timeout)
        return self.snapshot

    def step(self, steps: int):
        """Takes up to `steps` steps before returning (fewer if the deadline comes first); PAUSED after."""
        response = self._stub.Step(pb.StepRequest(session_id=self.id, steps=steps), timeout=self.client.timeout)
        self.snapshot = response.session
        return response

    def pause(self):
        return self._stub.Pause(pb.PauseRequest(session_id=self.id), timeout=self.client.timeout)

    def resume(self):
        return self._stub.Resume(pb.ResumeRequest(session_id=self.id), timeout=self.client.timeout)

    def cancel(self):
        return self._stub.Cancel(pb.CancelRequest(session_id=self.id), timeout=self.client.timeout)

    def delete(self):
        self._stub.DeleteSession(pb.DeleteSessionRequest(session_id=self.id), timeout=self.client.timeout)

    def wait(self, progress=None, timeout: float = None, label: str = None):
        """Follows the session until it stops running (DONE, PAUSED, FAILED or CANCELLED).

        progress: draw a bar on stderr (default: when stderr is a terminal). Raises SessionFailed
        when the session ends FAILED or CANCELLED.
        """
        bar = ProgressBar(label or self.id)
        if progress is False:
            bar.enabled = False
        events = self._stub.WatchSession(pb.WatchSessionRequest(session_id=self.id, progress_interval_s=0.2),
                                         timeout=timeout)
        try:
            for event in events:
                kind = event.WhichOneof("event")
                if kind == "progress":
                    p = event.progress
                    bar.update(p.step, p.target_step, p.steps_per_second, p.estimated_seconds_left)
                elif kind == "state_changed" and event.state_changed.to != pb.SESSION_STATE_RUNNING:
                    break
        finally:
            events.cancel()
            bar.close()
        return self._raise_if_failed(self.get())

    def _raise_if_failed(self, snapshot):
        if snapshot.state in (pb.SESSION_STATE_FAILED, pb.SESSION_STATE_CANCELLED):
            state = pb.SessionState.Name(snapshot.state)
            raise SessionFailed(f"session {self.id} {state} at step {snapshot.step}: {snapshot.message}")
        return snapshot

    def watch_profiles(self, every: int, lossless: bool = True, timeout: float = None):
        """Profile frames every `every` steps: first the current state, then until the run ends."""
        delivery = pb.DELIVERY_MODE_EVERY_FRAME if lossless else pb.DELIVERY_MODE_LATEST_FRAME
        request = pb.WatchProfilesRequest(session_id=self.id, every=every, delivery=delivery)
        return self._stub.WatchProfiles(request, timeout=timeout)

    def watch_particles(self, every: int, bodies=(), lossless: bool = True, timeout: float = None):
        delivery = pb.DELIVERY_MODE_EVERY_FRAME if lossless else pb.DELIVERY_MODE_LATEST_FRAME
        request = pb.WatchParticlesRequest(session_id=self.id, every=every, delivery=delivery, bodies=list(bodies))
        return self._stub.WatchParticles(request, timeout=timeout)

    def outputs(self):
        """What the daemon recorded for the session (scenario.outputs) and its checkpoints, as
        OutputFile messages (name, bytes, sha256), made as of now."""
        request = pb.ListOutputsRequest(session_id=self.id)
        return list(self._stub.ListOutputs(request, timeout=self.timeout_for_listing()).files)

    def timeout_for_listing(self):
        return max(self.client.timeout, 300.0)  # the daemon may first make the files from its log

    def download(self, name: str, path, attempts: int = 5):
        """Copies the output `name` to `path`: into a hidden part file beside it, resumed from the
        bytes received when the stream breaks (naming the version, so a changed file is refused),
        checked against the daemon's SHA-256, then renamed. Returns the OutputFile."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        listed = {f.name: f for f in self.outputs()}
        if name not in listed:
            raise KeyError(f"session {self.id} has no output {name!r}; it has {sorted(listed)}")
        wanted = listed[name]
        fd, part = tempfile.mkstemp(prefix=f".{path.name}.part-", dir=path.parent)
        try:
            with os.fdopen(fd, "wb") as out:
                for attempt in range(1, attempts + 1):
                    request = pb.DownloadOutputRequest(session_id=self.id, name=name, offset=out.tell(),
                                                       sha256=wanted.sha256, chunk_bytes=3 << 20)
                    try:
                        for chunk in self._stub.DownloadOutput(request, timeout=3600):
                            if chunk.offset != out.tell():
                                raise RuntimeError(f"{name}: a chunk at offset {chunk.offset}, expected {out.tell()}")
                            out.write(chunk.data)
                        break
                    except grpc.RpcError as error:
                        if not retryable(error) or attempt == attempts:
                            raise
            digest = hashlib.sha256(Path(part).read_bytes()).hexdigest()
            if digest != wanted.sha256:
                raise RuntimeError(f"{name}: the copy's SHA-256 {digest} is not the daemon's {wanted.sha256}")
            os.replace(part, path)
        finally:
            if os.path.exists(part):
                os.unlink(part)
        return wanted

    def run_and_record(self, steps: int, profiles_every: int = 0, particles_every: int = 0, bodies=(),
                       progress=None, label: str = None, keep_particles=None) -> Recording:
        """Runs `steps` steps and records every profile and particle frame asked for, losing none.

        `keep_particles(frame)`, if given, turns each ParticleFrame message into what the recording
        keeps instead of a Particles (e.g. only the bodies' orientations, when every particle of
        hundreds of frames would not fit in memory); not for a DONE session.

        The streams are opened first and their first frame (the current state) awaited, so Run
        starts only once both are listening. A session that is DONE already (a retried script) is
        not run again: its frames are read from what the daemon recorded for it (scenario.outputs,
        particles.h5), those at multiples of the intervals asked for; mass and energy are not in
        that file and read NaN.
        """
        if self.get().state == pb.SESSION_STATE_DONE:
            if keep_particles is not None:
                raise ValueError(f"session {self.id} is DONE: its recorded frames cannot be kept by keep_particles")
            return self._recorded(profiles_every, particles_every, bodies)
        streams = []
        if profiles_every > 0:
            streams.append(("profiles", self.watch_profiles(profiles_every), profile_from_proto))
        if particles_every > 0:
            streams.append(("particles", self.watch_particles(particles_every, bodies),
                            keep_particles or particles_from_proto))
        collected = {name: [] for name, _, _ in streams}
        errors = []
        first_frames = [threading.Event() for _ in streams]

        def drain(index, name, stream, convert):
            try:
                for frame in stream:
                    collected[name].append(convert(frame))
                    first_frames[index].set()
            except grpc.RpcError as error:
                if error.code() != grpc.StatusCode.CANCELLED:
                    errors.append(error)
            finally:
                first_frames[index].set()

        threads = [threading.Thread(target=drain, args=(i, *s), daemon=True) for i, s in enumerate(streams)]
        for t in threads:
            t.start()
        try:
            for event in first_frames:
                if not event.wait(timeout=self.client.timeout):
                    raise TimeoutError(f"session {self.id}: no first frame within {self.client.timeout} s")
            if errors:
                raise errors[0]
            self.run(steps)
            final = self.wait(progress=progress, label=label)
            for t in threads:  # the streams end by themselves once the session is DONE
                t.join(timeout=self.client.timeout)
        finally:
            for _, stream, _ in streams:
                stream.cancel()
            for t in threads:
                t.join(timeout=self.client.timeout)
        if errors:
            raise errors[0]
        return Recording(final, collected.get("profiles", []), collected.get("particles", []))

    def _recorded(self, profiles_every, particles_every, bodies) -> Recording:
        if "particles.h5" not in {f.name for f in self.outputs()}:
            raise ValueError(
                f"session {self.id} is DONE and the daemon recorded nothing for it (no scenario.outputs): "
                "its frames are gone; declare outputs in the scenario, or record the whole run in one call")
        with tempfile.TemporaryDirectory(prefix="lbsolid-outputs-") as tmp:
            self.download("particles.h5", Path(tmp) / "particles.h5")
            return recording_from_h5md(Path(tmp) / "particles.h5", self.snapshot, profiles_every, particles_every,
                                       bodies)

    def fields(self, names=("density", "velocity"), chunk_bytes: int = 3 << 20) -> dict:
        """The whole fields at the current step, as numpy arrays (header shape, float64)."""
        request = pb.GetFieldRequest(session_id=self.id, fields=list(names), chunk_bytes=chunk_bytes)
        out, header, buffer, filled = {}, None, None, 0

        def finish():
            if header is not None:
                if filled != header.total_bytes:
                    raise IOError(f"field {header.name}: got {filled} of {header.total_bytes} bytes")
                # A view of the buffer, not a copy of it.
                values = np.frombuffer(buffer, dtype="<f8").reshape(tuple(header.shape))
                out[header.name] = Field(header.name, header.step, values, _vector(header.spacing))

        for message in self._stub.GetField(request, timeout=self.client.timeout):
            part = message.WhichOneof("part")
            if part == "header":
                finish()
                # The size is known: one buffer, each chunk copied into its place once.
                header, buffer, filled = message.header, bytearray(message.header.total_bytes), 0
            elif part == "chunk":
                data = message.chunk.data
                if message.chunk.offset != filled or filled + len(data) > len(buffer):
                    raise IOError(f"field {header.name}: {len(data)} bytes at offset {message.chunk.offset}, "
                                  f"expected offset {filled} of {len(buffer)}")
                buffer[filled:filled + len(data)] = data
                filled += len(data)
        finish()
        return out

    def field(self, name: str) -> Field:
        return self.fields([name])[name]

    def checkpoint(self):
        """Writes a checkpoint; returns its id (restore it with Client.restore) and file."""
        return self._stub.Checkpoint(pb.CheckpointRequest(session_id=self.id), timeout=self.client.timeout)
