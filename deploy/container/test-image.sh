#!/usr/bin/env bash
# The image runs the main job (issue 17): built by build-image.sh, lbsolidd in a container, the
# paper's Fig. 5 drag run submitted from the host's CLI, its particles summarised, the daemon
# stopped by SIGTERM.
#   deploy/container/test-image.sh [--no-build] [BUILD_DIR] [TAG]   (defaults as in build-image.sh;
#                                                                   --no-build: test the image there is)
# 1. the image's user is 65532, not root, and its lbsolidd prints the project's version;
# 2. the daemon, started with the image's own data directory on a free loopback port (host network),
#    answers grpc.health.v1 SERVING (for the server and for lbsolid.v1.Simulation) and the CLI;
#    `submit --out` gets every file, `lbsolid-drag-summary` fits them;
# 3. `podman stop` (SIGTERM) ends it with exit code 0: every session saved.
# Runtime: runc (crun fails on this sandbox's hybrid cgroups), no default ulimits (containers.conf).
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
build_image=1
if [ "${1:-}" = --no-build ]; then build_image=0; shift; fi
build=$(cd "${1:-$source_dir/build}" && pwd)
version=$(sed -n 's/^version: *//p' "$source_dir/CITATION.cff")
tag=${2:-lbsolid:$version}
work=$(mktemp -d)
name="lbsolid-image-test-$$"
cleanup() {
  podman rm -f "$name" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "image test: $*" >&2; podman logs "$name" 2>/dev/null | tail -n 20 >&2 || true; exit 1; }
printf '[containers]\ndefault_ulimits = []\n[engine]\nruntime = "runc"\n' >"$work/containers.conf"
export CONTAINERS_CONF="$work/containers.conf"
if [ "$build_image" = 1 ]; then "$source_dir/deploy/container/build-image.sh" "$build" "$tag"; fi

# 1. Who it runs as, and what.
user=$(podman image inspect --format '{{.Config.User}}' "$tag") || fail "no image $tag (run build-image.sh)"
[ "$user" = "65532:65532" ] || fail "the image runs as '$user', not 65532:65532"
uid=$(podman run --rm --network=none --entrypoint /usr/bin/id "$tag" -u)
[ "$uid" = 65532 ] || fail "a container's uid is $uid"
podman run --rm --network=none "$tag" --version | grep -q "lbsolidd $version" || fail "lbsolidd --version"

# 2. The main job against the container's daemon.
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
podman run -d --name "$name" --network=host "$tag" --listen="127.0.0.1:$port" --data_dir=/var/lib/lbsolid \
  --log_level=warn >/dev/null
cli="$build/client-examples/cli/lbsolid"
for _ in $(seq 100); do "$cli" --server "127.0.0.1:$port" info >/dev/null 2>&1 && break; sleep 0.1; done
"$cli" --server "127.0.0.1:$port" info >/dev/null || fail "the container's daemon does not answer"
/usr/bin/python3 - "$port" <<'PY' || fail "grpc.health.v1 does not answer SERVING"
import sys, grpc
channel = grpc.insecure_channel(f"127.0.0.1:{sys.argv[1]}")
check = channel.unary_unary("/grpc.health.v1.Health/Check", request_serializer=lambda b: b,
                            response_deserializer=lambda b: b)
for service in ("", "lbsolid.v1.Simulation"):
    request = b"" if not service else b"\x0a" + bytes([len(service)]) + service.encode()
    assert check(request, timeout=5) == b"\x08\x01", service  # status: SERVING
PY
"$cli" --server "127.0.0.1:$port" submit "$source_dir/client-examples/scenarios/fig5_drag_disk.textproto" \
  --out "$work/out" >"$work/submit.log" 2>&1 || { cat "$work/submit.log"; fail "the main job failed"; }
"$build/client-examples/drag-summary/lbsolid-drag-summary" "$work/out" >"$work/summary.log" ||
  { cat "$work/summary.log"; fail "lbsolid-drag-summary failed"; }
grep -E "c_d|Re" "$work/summary.log" | head -n 3

# 3. SIGTERM: saved and exit 0.
podman stop --time 60 "$name" >/dev/null
code=$(podman inspect --format '{{.State.ExitCode}}' "$name")
[ "$code" = 0 ] || fail "lbsolidd exited $code after SIGTERM"
echo "image test: passed ($tag)"
