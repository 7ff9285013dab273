#!/usr/bin/python3
"""deploy/k8s/lbsolidd.yaml against the daemon it deploys (kubectl cannot validate without a
cluster's API server, so this is a structural check, plus the daemon itself):
  - a Service and a StatefulSet; the Service's target port is the container's API port, the one
    --listen names;
  - the data volume (a volumeClaimTemplate) is mounted where --data_dir points;
  - native gRPC probes on the port --health_listen names, readiness by the service name;
  - terminationGracePeriodSeconds is the systemd unit's TimeoutStopSec (the same save to wait for);
  - the memory limit holds --max_memory with headroom, the CPU limit the workers and fluid threads;
  - non-root, read-only root file system, no privilege escalation;
  - every argument is a flag `lbsolidd --help` lists, and the daemon started with the manifest's
    own flags (the addresses moved to loopback, TLS and tokens left out) answers the readiness
    probe's health check SERVING on its health port.

    LBSOLIDD=build/server/lbsolidd /usr/bin/python3 tests/deploy/k8s_manifests_test.py
"""
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import grpc
import yaml

ROOT = Path(__file__).resolve().parents[2]
MANIFEST = ROOT / "deploy" / "k8s" / "lbsolidd.yaml"
UNIT = ROOT / "deploy" / "lbsolidd.service.in"
SERVICE_NAME = "lbsolid.v1.Simulation"
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)


def quantity_bytes(text):
    units = {"Ki": 2**10, "Mi": 2**20, "Gi": 2**30, "Ti": 2**40}
    match = re.fullmatch(r"(\d+)(Ki|Mi|Gi|Ti)?", str(text))
    return int(match[1]) * units.get(match[2], 1)


def flags_of(args):
    out = {}
    for arg in args:
        name, _, value = arg.partition("=")
        out[name] = value
    return out


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def health(port, service):
    channel = grpc.insecure_channel(f"127.0.0.1:{port}")
    check_call = channel.unary_unary("/grpc.health.v1.Health/Check", request_serializer=lambda b: b,
                                     response_deserializer=lambda b: b)
    request = b"" if not service else b"\x0a" + bytes([len(service)]) + service.encode()
    try:
        return check_call(request, timeout=5)
    finally:
        channel.close()


def main():
    documents = [d for d in yaml.safe_load_all(MANIFEST.read_text()) if d]
    kinds = {d["kind"]: d for d in documents}
    check(set(kinds) == {"Service", "StatefulSet"}, f"kinds: {sorted(kinds)}")
    service, stateful = kinds["Service"], kinds["StatefulSet"]
    pod = stateful["spec"]["template"]["spec"]
    (container,) = pod["containers"]
    flags = flags_of(container["args"])
    ports = {p["name"]: p["containerPort"] for p in container["ports"]}

    listen_port = int(flags["--listen"].rsplit(":", 1)[1])
    health_port = int(flags["--health_listen"].rsplit(":", 1)[1])
    check(ports.get("grpc") == listen_port, f"container port grpc {ports.get('grpc')} is not --listen's {listen_port}")
    check(ports.get("health") == health_port, f"container port health is not --health_listen's {health_port}")
    check(service["spec"]["ports"][0]["targetPort"] in ("grpc", listen_port), "the Service does not target the API port")
    check(service["spec"]["selector"] == stateful["spec"]["selector"]["matchLabels"], "the Service selects other pods")
    check(stateful["spec"]["serviceName"] == service["metadata"]["name"], "serviceName is not the Service")
    # Each replica advertises its own stable name: <pod>.<governing headless Service>:<--listen's port>.
    check(service["spec"].get("clusterIP") == "None", "the Service is not headless: replicas get no names of their own")
    env = {e["name"]: e for e in container.get("env", [])}
    check(env.get("POD_NAME", {}).get("valueFrom", {}).get("fieldRef", {}).get("fieldPath") == "metadata.name",
          "POD_NAME is not the pod's name")
    check(flags.get("--advertise_address") == f"$(POD_NAME).{service['metadata']['name']}:{listen_port}",
          f"--advertise_address {flags.get('--advertise_address')} is not the replica's name and --listen's port")

    claims = {c["metadata"]["name"] for c in stateful["spec"]["volumeClaimTemplates"]}
    mounts = {m["name"]: m["mountPath"] for m in container["volumeMounts"]}
    check("data" in claims and mounts.get("data") == flags["--data_dir"],
          f"--data_dir {flags['--data_dir']} is not the claimed volume's mount ({mounts.get('data')})")
    for name, path in (("tls", flags["--tls_cert"]), ("tls", flags["--tls_key"]), ("tokens", flags["--tokens_file"])):
        check(path.startswith(mounts.get(name, "?") + "/"), f"{path} is not under the {name} secret's mount")

    for probe in ("readinessProbe", "livenessProbe"):
        grpc_probe = container[probe].get("grpc", {})
        check(grpc_probe.get("port") == health_port, f"{probe} is not a gRPC probe on --health_listen's port")
    check(container["readinessProbe"]["grpc"].get("service") == SERVICE_NAME, "readiness does not name the service")

    timeout = int(re.search(r"^TimeoutStopSec=(\d+)", UNIT.read_text(), re.M)[1])
    check(pod["terminationGracePeriodSeconds"] == timeout,
          f"terminationGracePeriodSeconds {pod['terminationGracePeriodSeconds']} is not the unit's TimeoutStopSec {timeout}")

    limits = container["resources"]["limits"]
    max_memory = int(flags["--max_memory"])
    check(quantity_bytes(limits["memory"]) >= max_memory * 1.2,
          f"memory limit {limits['memory']} leaves under 20% above --max_memory {max_memory}")
    check(float(limits["cpu"]) >= int(flags["--workers"]) + int(flags["--max_fluid_threads"]),
          "the CPU limit is below the workers and fluid threads")
    check(container["resources"]["requests"] == limits, "requests differ from limits (the pod could be squeezed)")

    security = container["securityContext"]
    check(pod["securityContext"].get("runAsNonRoot") is True, "may run as root")
    check(security.get("readOnlyRootFilesystem") is True, "the root file system is writable")
    check(security.get("allowPrivilegeEscalation") is False, "privilege escalation allowed")
    check(security.get("capabilities", {}).get("drop") == ["ALL"], "capabilities not dropped")

    daemon = os.environ.get("LBSOLIDD", str(ROOT / "build" / "server" / "lbsolidd"))
    help_text = subprocess.run([daemon, "--help"], capture_output=True, text=True).stdout
    for name in flags:
        check(f"{name} " in help_text or f"{name}\n" in help_text or f"{name} (" in help_text,
              f"{name} is not a flag lbsolidd --help lists")

    # The manifest's flags on a real daemon: addresses moved to loopback, TLS and tokens left out.
    with tempfile.TemporaryDirectory(prefix="lbsolid-k8s-") as tmp:
        port = free_port()
        kept = [a for a in container["args"]
                if not a.startswith(("--listen", "--health_listen", "--data_dir", "--tls_", "--tokens_file"))]
        process = subprocess.Popen([daemon, *kept, "--listen=127.0.0.1:0", f"--port_file={tmp}/port",
                                    f"--health_listen=127.0.0.1:{port}", f"--data_dir={tmp}/data", "--log_level=warn"])
        try:
            for _ in range(200):
                if Path(tmp, "port").exists():
                    break
                time.sleep(0.05)
            check(Path(tmp, "port").exists(), "lbsolidd did not start with the manifest's flags")
            for name in ("", SERVICE_NAME):
                check(health(port, name) == b"\x08\x01", f"the health port does not answer SERVING for '{name}'")
        finally:
            process.terminate()
            check(process.wait(timeout=30) == 0, "lbsolidd did not exit 0 on SIGTERM")

    for failure in failures:
        print("k8s manifest:", failure, file=sys.stderr)
    print("k8s manifest test:", "FAILED" if failures else "passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
