"""End to end: the Python client against a real lbsolidd, checked against the core run in process.

The daemon runs on a free loopback port (LocalDaemon); lbsolid-reference runs the same scenario file
through the same translation and core in process and prints, as exact hexadecimal floats, what the
client should receive. Every number must match to the last bit (float64 ==, not a tolerance): the
daemon adds nothing to the physics, and the wire carries doubles exactly.

Run by ctest (python_client_matches_core) with LBSOLIDD, LBSOLID_REFERENCE and LBSOLID_PYTHON_STUBS
set by CMake; by hand: /usr/bin/python3 tests/clients/python_client_test.py from the repository root
after a build in ./build.
"""
import hashlib
import os
import subprocess
import tempfile
import sys
import unittest
from pathlib import Path

import numpy as np

REPOSITORY = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPOSITORY / "client-examples" / "python"))

from lbsolid_client.daemon_names import expand_dns_names, resolve_tcp  # noqa: E402
from lbsolid_client import (Client, Cluster, InvalidArgument, LocalDaemon, NotFound, SessionFailed,  # noqa: E402
                            load_scenario, retryable)

SCENARIO = Path(__file__).resolve().parent / "python_small_scenario.textproto"
REFERENCE = Path(os.environ.get("LBSOLID_REFERENCE", REPOSITORY / "build" / "tests" / "lbsolid-reference"))
STEPS = 300
EVERY = 20


def hex_values(words):
    return np.array([float.fromhex(w) for w in words], dtype=np.float64)


def reference_run(steps, profiles_every=0, particles_every=0, fields=False):
    """Parses lbsolid-reference's records into profiles, bodies per step, and fields."""
    args = [str(REFERENCE), str(SCENARIO), "--steps", str(steps)]
    if profiles_every:
        args += ["--profiles-every", str(profiles_every)]
    if particles_every:
        args += ["--particles-every", str(particles_every)]
    if fields:
        args.append("--fields")
    text = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    profiles, bodies, field_values = [], {}, {}
    for line in text.splitlines():
        words = line.split()
        if words[0] == "profile":
            step, n = int(words[1]), int(words[2])
            values = hex_values(words[3:])
            profiles.append((step, values[:n], values[n:]))
        elif words[0] == "body":
            step, name, n = int(words[1]), words[2], int(words[3])
            v = hex_values(words[4:])
            bodies.setdefault(step, {})[name] = {
                "position": v[:3 * n].reshape(-1, 3), "velocity": v[3 * n:6 * n].reshape(-1, 3),
                "centre_of_mass": v[6 * n:6 * n + 3], "mean_velocity": v[6 * n + 3:6 * n + 6],
                "mass": v[6 * n + 6], "energy": v[6 * n + 7],
                "angular_momentum": v[6 * n + 8:6 * n + 11], "angular_velocity": v[6 * n + 11:6 * n + 14],
                "orientation": v[6 * n + 14], "orientation_quaternion": v[6 * n + 15:6 * n + 19],
                "torque": v[6 * n + 19:6 * n + 22]}
        elif words[0] == "field":
            field_values[words[1]] = (int(words[2]), hex_values(words[4:]))
    return profiles, bodies, field_values


def bit_equal(a, b):
    """Equal as float64 values, element by element (both zero signs count as equal, NaN never)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and bool(np.all(a == b))


class PythonClientMatchesCore(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.daemon = LocalDaemon().start()
        cls.client = Client(cls.daemon.address, timeout=30).wait_ready()

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.daemon.stop()

    def test_streamed_frames_and_fields_equal_the_core_bit_for_bit(self):
        session = self.client.create(load_scenario(SCENARIO))
        record = session.run_and_record(STEPS, profiles_every=EVERY, particles_every=EVERY, progress=False)
        fields = session.fields()
        expected_profiles, expected_bodies, expected_fields = reference_run(STEPS, EVERY, EVERY, fields=True)

        self.assertEqual(record.session.step, STEPS)
        self.assertEqual(len(expected_profiles), STEPS // EVERY + 1)
        self.assertEqual([p.step for p in record.profiles], [step for step, _, _ in expected_profiles])
        for got, (step, y, u_x) in zip(record.profiles, expected_profiles):
            self.assertTrue(bit_equal(got.y, y), f"profile y at step {step}")
            self.assertTrue(bit_equal(got.u_x, u_x), f"profile u_x at step {step}: {got.u_x} vs {u_x}")
        # The run moves things: a comparison of frames that never change would prove little.
        self.assertGreater(np.abs(record.profiles[-1].u_x).max(), 1e-4)

        self.assertEqual([f.step for f in record.particles], sorted(expected_bodies))
        for frame in record.particles:
            expected = expected_bodies[frame.step]
            self.assertEqual(sorted(frame.bodies), sorted(expected))
            for name, body in frame.bodies.items():
                for quantity, value in expected[name].items():
                    self.assertTrue(bit_equal(getattr(body, quantity), value),
                                    f"step {frame.step} body {name} {quantity}: {getattr(body, quantity)} vs {value}")
        plate_start = record.particles[0].bodies["plate"].centre_of_mass
        plate_end = record.particles[-1].bodies["plate"].centre_of_mass
        self.assertGreater(plate_end[0] - plate_start[0], 0.1)  # it moved 0.33 along its load
        # The chain is a rotating body: its torque is recorded and not zero once the run steps.
        self.assertGreater(max(np.abs(f.bodies["chain"].torque).max() for f in record.particles[1:]), 0)
        turned = [f.bodies["chain"].orientation for f in record.particles]
        # The chain turns, its springs with it: first with its spin, then with the shear (-0.13 rad
        # by step 300, the same in every run: the run is deterministic).
        self.assertGreater(abs(turned[-1] - turned[0]), 0.1)

        for name in ("density", "velocity"):
            step, values = expected_fields[name]
            self.assertEqual(fields[name].step, step)
            self.assertTrue(bit_equal(fields[name].values.reshape(-1), values), f"field {name}")

    def test_checkpoint_restored_and_run_on_equals_one_uninterrupted_run(self):
        half = STEPS // 2
        first = self.client.create(load_scenario(SCENARIO))
        first.run(half)
        self.assertEqual(first.wait(progress=False).step, half)
        checkpoint = first.checkpoint()
        self.assertEqual(checkpoint.step, half)

        restored = self.client.restore(checkpoint.checkpoint_id)
        restored.run(STEPS - half)
        self.assertEqual(restored.wait(progress=False).step, STEPS)
        _, _, expected_fields = reference_run(STEPS, fields=True)
        fields = restored.fields()
        for name in ("density", "velocity"):
            self.assertTrue(bit_equal(fields[name].values.reshape(-1), expected_fields[name][1]), f"field {name}")

    def test_a_diverging_run_raises_session_failed_with_the_daemons_cause(self):
        scenario = load_scenario(SCENARIO)
        scenario.fluid.body_force.x = 0.01  # drives the channel past the Mach limit within a few hundred steps
        scenario.stability.check_interval = 1  # checked every step: caught at the Mach limit, before any blow-up
        session = self.client.create(scenario)
        with self.assertRaises(SessionFailed) as caught:
            session.run_and_record(5000, profiles_every=50, progress=False)
        self.assertIn("FAILED", str(caught.exception))
        self.assertRegex(str(caught.exception), r"step \d+: Mach number")

    def test_recording_a_done_session_is_refused_not_silently_short(self):
        session = self.client.create(load_scenario(SCENARIO))
        session.run_and_record(20, profiles_every=10, progress=False)
        with self.assertRaisesRegex(ValueError, "is DONE"):
            session.run_and_record(20, profiles_every=10, progress=False)
        # Advanced with Step, it is PAUSED and records again, from where it stands.
        session.step(1)
        record = session.run_and_record(19, profiles_every=10, progress=False)
        self.assertEqual([p.step for p in record.profiles], [21, 30, 40])

    def test_a_done_session_is_read_back_from_what_the_daemon_recorded(self):
        scenario = load_scenario(SCENARIO)
        scenario.outputs.profile_every = EVERY
        scenario.outputs.particles_every = EVERY
        session = self.client.create(scenario)
        session.run(STEPS)
        self.assertEqual(session.wait(progress=False).step, STEPS)
        # A retried script finds it DONE: the frames come from the daemon's particles.h5.
        record = session.run_and_record(STEPS, profiles_every=EVERY, particles_every=EVERY, progress=False)
        expected_profiles, expected_bodies, _ = reference_run(STEPS, EVERY, EVERY)
        self.assertEqual([p.step for p in record.profiles], [step for step, _, _ in expected_profiles])
        for got, (step, y, u_x) in zip(record.profiles, expected_profiles):
            self.assertTrue(bit_equal(got.y, y), f"profile y at step {step}")
            self.assertTrue(bit_equal(got.u_x, u_x), f"profile u_x at step {step}")
        self.assertEqual([f.step for f in record.particles], sorted(expected_bodies))
        for frame in record.particles:
            for name, body in frame.bodies.items():
                for quantity in ("position", "velocity", "centre_of_mass", "mean_velocity", "angular_momentum",
                                 "angular_velocity", "orientation", "orientation_quaternion", "torque"):
                    self.assertTrue(bit_equal(getattr(body, quantity), expected_bodies[frame.step][name][quantity]),
                                    f"step {frame.step} body {name} {quantity}")
        listed = {f.name: f for f in session.outputs()}
        self.assertIn("particles.h5", listed)
        with tempfile.TemporaryDirectory() as tmp:
            copy = Path(tmp) / "particles.h5"
            session.download("particles.h5", copy)
            self.assertEqual(hashlib.sha256(copy.read_bytes()).hexdigest(), listed["particles.h5"].sha256)
            self.assertEqual([p.name for p in Path(tmp).iterdir()], ["particles.h5"])  # no part file left

    def test_a_breaking_bodys_links_read_back_from_a_done_session_as_streamed(self):
        # A chain of 20 pulled by +-1.01 T at its ends breaks link by link from both ends in steps
        # 2 to 11 (tests/physics/fracture_test.cpp). Frames every 3 steps: each lists the breaks
        # since the previous one, streamed and read back from particles.h5 alike.
        from google.protobuf import text_format
        from lbsolid_client import scenario_pb2
        scenario = text_format.Parse("""
            name: "torn chain" lattice: LATTICE_D2Q9
            domain { nx: 160 ny: 160 } fluid { enabled: false } contact { enabled: false }
            outputs { particles_every: 3 }
            bodies { name: "chain" shape: BODY_SHAPE_CHAIN length: 20 centre { x: 80 y: 80 }
                     point_loads { label { i: 0 } force { x: -0.00101 } }
                     point_loads { label { i: 19 } force { x: 0.00101 } }
                     fracture { max_force: 0.001 } }""", scenario_pb2.Scenario())
        streamed = self.client.create(scenario).run_and_record(15, particles_every=3, progress=False)
        done = self.client.create(scenario)
        done.run(15)
        done.wait(progress=False)
        read_back = done.run_and_record(15, particles_every=3, progress=False)
        self.assertEqual([f.step for f in read_back.particles], [f.step for f in streamed.particles])
        for got, want in zip(read_back.particles, streamed.particles):
            a, b = got.bodies["chain"], want.bodies["chain"]
            self.assertEqual(a.broken_link_count, b.broken_link_count, f"step {got.step}")
            self.assertTrue(bit_equal(a.broken_links, b.broken_links), f"step {got.step}")
        last = streamed.particles[-1].bodies["chain"]
        self.assertEqual(last.broken_link_count, 19)
        self.assertEqual(sum(len(f.bodies["chain"].broken_links) for f in streamed.particles), 19)

    def test_an_anchored_disk_reports_the_force_that_holds_it(self):
        # A periodic D2Q9 box driven by g per node around an anchored disk: at steady state the
        # anchors hold the whole drive, g x 1200 nodes (the core test AnchoredDisk measures it
        # within 2e-5 after 6000 steps; 1e-3 here), and the disk never moves.
        from google.protobuf import text_format
        from lbsolid_client import scenario_pb2
        scenario = text_format.Parse("""
            name: "anchored disk" lattice: LATTICE_D2Q9
            domain { nx: 40 ny: 30 x_low { kind: WALL_KIND_PERIODIC } x_high { kind: WALL_KIND_PERIODIC }
                     y_low { kind: WALL_KIND_PERIODIC } y_high { kind: WALL_KIND_PERIODIC } }
            fluid { omega: 1 body_force { x: 2e-6 } }
            bodies { name: "disk" shape: BODY_SHAPE_DISK radius: 4 centre { x: 20.2 y: 15.3 } anchored: true }
        """, scenario_pb2.Scenario())
        session = self.client.create(scenario)
        record = session.run_and_record(6000, particles_every=1000, progress=False)
        first, last = record.particles[0].bodies["disk"], record.particles[-1].bodies["disk"]
        self.assertEqual(record.particles[-1].step, 6000)
        np.testing.assert_array_equal(last.position, first.position)
        drive = 2e-6 * 40 * 30
        self.assertAlmostEqual(last.anchor_force[0] / drive, 1.0, delta=1e-3)
        self.assertLess(abs(last.anchor_force[1]), 1e-6 * drive)

    def test_bad_input_names_the_field(self):
        import grpc
        scenario = load_scenario(SCENARIO)
        scenario.fluid.omega = 2.5
        with self.assertRaises(InvalidArgument) as caught:  # typed, and still a grpc.RpcError
            self.client.create(scenario)
        self.assertIsInstance(caught.exception, grpc.RpcError)
        self.assertEqual(caught.exception.code(), grpc.StatusCode.INVALID_ARGUMENT)
        self.assertEqual(caught.exception.field, "scenario.fluid.omega")
        self.assertTrue(caught.exception.reason.startswith("must lie in (0, 2)"), caught.exception.reason)
        self.assertEqual(caught.exception.rpc, "CreateSession")
        self.assertFalse(retryable(caught.exception))
        with self.assertRaises(NotFound) as missing:
            self.client.session("s-0123456789abcdef0123456789abcdef").get()
        self.assertEqual(missing.exception.field, "session_id")
        # A stream's refusal arrives as the stream is read: typed as well.
        with self.assertRaises(NotFound):
            list(self.client.session("s-0123456789abcdef0123456789abcdef").watch_profiles(every=1))

    def test_a_request_over_the_message_limit_is_not_retryable(self):
        # gRPC refuses it as RESOURCE_EXHAUSTED, a code that is otherwise worth a retry; this one
        # fails the same way every time, so an orchestrator must not retry it.
        import grpc
        scenario = load_scenario(SCENARIO)
        scenario.name = "x" * (5 << 20)
        with self.assertRaises(grpc.RpcError) as caught:
            self.client.create(scenario)
        self.assertEqual(caught.exception.code(), grpc.StatusCode.RESOURCE_EXHAUSTED)
        self.assertFalse(retryable(caught.exception), caught.exception.details())


def openssl(directory, *args):
    subprocess.run(["openssl", *args], cwd=directory, check=True, capture_output=True)


class PythonClientOverTls(unittest.TestCase):
    """TLS with a throwaway CA made here by openssl, and a bearer token checked against its hash."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="lbsolid-py-tls-")
        d = Path(cls.tmp.name)
        (d / "san.cnf").write_text("subjectAltName=DNS:localhost,IP:127.0.0.1\n")
        ec = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"]
        openssl(d, "req", "-x509", *ec, "-keyout", "ca.key", "-out", "ca.pem", "-days", "2", "-subj", "/CN=py test CA")
        openssl(d, "req", *ec, "-keyout", "daemon.key", "-out", "daemon.csr", "-subj", "/CN=localhost")
        openssl(d, "x509", "-req", "-in", "daemon.csr", "-CA", "ca.pem", "-CAkey", "ca.key", "-CAcreateserial",
                "-out", "daemon.pem", "-days", "2", "-extfile", "san.cnf")
        (d / "tokens").write_text(hashlib.sha256(b"py-secret").hexdigest() + " py-user user\n")
        cls.ca = d / "ca.pem"
        cls.daemon = LocalDaemon(extra_args=["--tls_cert", str(d / "daemon.pem"), "--tls_key", str(d / "daemon.key"),
                                             "--tokens_file", str(d / "tokens")]).start()

    @classmethod
    def tearDownClass(cls):
        cls.daemon.stop()
        cls.tmp.cleanup()

    def test_a_token_over_tls_owns_what_it_creates(self):
        with Client(self.daemon.address, tls_ca=self.ca, token="py-secret").wait_ready() as client:
            session = client.create(load_scenario(SCENARIO))
            self.assertEqual(session.get().owner, "py-user")
            self.assertEqual([s.id for s in client.list()], [session.id])

    def test_no_token_or_a_wrong_one_is_unauthenticated_and_not_retryable(self):
        import grpc
        for token in ("", "guessed"):
            with Client(self.daemon.address, tls_ca=self.ca, token=token) as client:
                with self.assertRaises(grpc.RpcError) as caught:
                    client.info()
                self.assertEqual(caught.exception.code(), grpc.StatusCode.UNAUTHENTICATED, token)
                self.assertFalse(retryable(caught.exception))


class DnsNamesOfSeveralDaemons(unittest.TestCase):
    """A name resolving to several addresses is that many daemons (the CLI's rule, daemon_names.h);
    tests/clients/dns_name_daemons_test.sh runs a Cluster and the CLI through such a name."""

    def test_a_name_of_several_addresses_expands_and_the_rest_stays_as_listed(self):
        names = {"replicas.example": ["10.0.0.7", "10.0.0.8", "fd00::9"], "one.example": ["10.0.0.1"]}
        asked = []

        def resolve(host):
            asked.append(host)
            return names.get(host, [])
        entries = ["replicas.example:50051", "one.example:443", "absent.example:1", "unix:/run/l.sock",
                   "127.0.0.1:5", "[::1]:5", "dns:///replicas.example:5", "noport"]
        self.assertEqual(expand_dns_names(entries, resolve), [
            ("10.0.0.7:50051", "replicas.example"), ("10.0.0.8:50051", "replicas.example"),
            ("[fd00::9]:50051", "replicas.example"), ("one.example:443", None), ("absent.example:1", None),
            ("unix:/run/l.sock", None), ("127.0.0.1:5", None), ("[::1]:5", None),
            ("dns:///replicas.example:5", None), ("noport", None)])
        self.assertEqual(asked, ["replicas.example", "one.example", "absent.example"])

    def test_the_system_resolver_gives_each_address_once(self):
        self.assertEqual(resolve_tcp("127.0.0.1"), ["127.0.0.1"])
        self.assertEqual(resolve_tcp("name.invalid"), [])  # RFC 6761: never resolves


class ClusterPlacesAndFollowsSessions(unittest.TestCase):
    """Three daemons behind a Cluster: new sessions on the least loaded, found again where they are."""

    def setUp(self):  # fresh daemons for each test: placement depends on what they hold
        self.daemons = [LocalDaemon(workers=1).start() for _ in range(3)]
        self.cluster = Cluster([d.address for d in self.daemons], timeout=30)

    def tearDown(self):
        self.cluster.close()
        for daemon in self.daemons:
            daemon.stop()

    def test_idle_daemons_are_dealt_in_turn_and_each_session_is_found_where_it_is(self):
        # Each run ends before the next create: all idle, so the fewest sessions held decide, in order.
        placed = []
        for _ in range(6):
            session = self.cluster.create(load_scenario(SCENARIO))
            session.run(50)
            session.wait(progress=False)
            placed.append(self.cluster.clients.index(session.client))
        self.assertEqual(placed, [0, 1, 2, 0, 1, 2])
        found = self.cluster.session(session.id)
        self.assertIs(found.client, session.client)
        self.assertEqual(found.get().step, 50)
        with self.assertRaises(NotFound) as caught:
            self.cluster.session("s-" + "0" * 32)
        self.assertIn("none of the 3 daemons", caught.exception.details())

    def test_a_retried_create_answers_with_its_first_session(self):
        first = self.cluster.create(load_scenario(SCENARIO), request_id="cluster-retry")
        again = self.cluster.create(load_scenario(SCENARIO), request_id="cluster-retry")
        self.assertEqual(again.id, first.id)
        self.assertIs(again.client, first.client)

    def test_a_daemon_with_a_running_session_is_passed_over(self):
        busy = self.cluster.clients[0]  # all idle and empty: the one the tie-break would choose
        long_run = busy.create(load_scenario(SCENARIO))
        long_run.run(10**9)
        try:
            chosen = self.cluster.create(load_scenario(SCENARIO))
            self.assertIsNot(chosen.client, busy)
        finally:
            long_run.cancel()


if __name__ == "__main__":
    unittest.main(verbosity=2)
