#!/usr/bin/env bash
# The Debian package, installed into a fresh root, runs the main job (issue 17).
#   tests/install/install_package_test.sh BUILD_DIR [CPACK]   (CPACK: the cpack to use; default: on PATH)
# 1. cpack -G DEB builds the package from BUILD_DIR's install rules (cmake/packaging.cmake);
# 2. its Depends are Debian packages, met by what this machine has installed;
# 3. dpkg-deb -x unpacks it into an empty directory: the fresh root;
# 4. every program there answers --version with the project's version;
# 5. its systemd unit: `systemd-analyze verify` clean and `systemd-analyze security` exposure 3.0
#    or lower (its ExecStart pointed at the unpacked binary, since /usr/bin/lbsolidd is not there);
# 6. the main job (deploy/run.sh's, the paper's Fig. 5 drag): lbsolidd started with the unit's own
#    ExecStart flags (--listen and --data_dir moved to a free loopback port and a scratch
#    directory), the scenario from the package's share/lbsolid, submitted with the package's
#    lbsolid, summarised with its lbsolid-drag-summary;
# 7. the package's Python client, imported from outside the source tree with nothing but the root
#    on PYTHONPATH, steps a session on that daemon.
set -euo pipefail
build=$(cd "$1" && pwd)
cpack=${2:-cpack}
work=$(mktemp -d)
daemon=""
cleanup() {
  if [ -n "$daemon" ]; then kill -TERM "$daemon" 2>/dev/null && wait "$daemon" || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "install test: $*" >&2; exit 1; }

# 1. The package.
(cd "$build" && "$cpack" -G DEB -B "$work/package" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack failed"; }
deb=$(ls "$work"/package/lbsolid_*.deb)
version=$(dpkg-deb -f "$deb" Version)
echo "install test: built $(basename "$deb") ($(stat -c %s "$deb") bytes)"

# 2. Depends: Debian runtime packages (found by dpkg-shlibdeps), met here.
depends=$(dpkg-deb -f "$deb" Depends)
echo "install test: Depends: $depends"
[ -n "$depends" ] || fail "the package declares no dependencies"
# dpkg-checkbuilddeps weighs a relation list against what is installed, versions and virtual
# packages (libspdlog1.10 provides libspdlog1.10-fmt9) included; it wants a control file to read.
printf 'Source: lbsolid-install-test\n\nPackage: lbsolid-install-test\nArchitecture: any\n' >"$work/control"
unmet=$(dpkg-checkbuilddeps -d "$depends" "$work/control" 2>&1) || fail "the package's dependencies are not met here: $unmet"

# 3. The fresh root.
root="$work/root"
mkdir "$root"
dpkg-deb -x "$deb" "$root"
for f in usr/bin/lbsolidd usr/bin/lbsolid usr/bin/lbsolid-drag-summary usr/lib/systemd/system/lbsolidd.service \
         usr/share/lbsolid/proto/lbsolid/v1/simulation.proto usr/share/lbsolid/proto/lbsolid/v1/scenario.proto \
         usr/share/lbsolid/scenarios/fig5_drag_disk.textproto usr/lib/python3/dist-packages/lbsolid_client/client.py \
         usr/lib/python3/dist-packages/lbsolid/v1/simulation_pb2_grpc.py usr/share/doc/lbsolid/README.md \
         usr/share/doc/lbsolid/docs/internals.md; do
  [ -e "$root/$f" ] || fail "the package lacks /$f"
done
outside=$(cd "$root" && find . -type f ! -path './usr/*' | head -n 3)
[ -z "$outside" ] || fail "files outside /usr: $outside"

# 4. Versions.
for program in lbsolidd lbsolid lbsolid-drag-summary; do
  answer=$("$root/usr/bin/$program" --version)
  echo "install test: $program --version: $answer"
  case "$answer" in *"$version"*) ;; *) fail "$program --version does not name $version" ;; esac
done

# 5. The unit.
unit="$root/usr/lib/systemd/system/lbsolidd.service"
grep -q '^ExecStart=/usr/bin/lbsolidd ' "$unit" || fail "the unit does not start /usr/bin/lbsolidd"
mkdir "$work/unit"
sed "s|^ExecStart=/usr/bin/|ExecStart=$root/usr/bin/|" "$unit" >"$work/unit/lbsolidd.service"
verify=$(systemd-analyze verify "$work/unit/lbsolidd.service" 2>&1) || fail "systemd-analyze verify: $verify"
[ -z "$verify" ] || fail "systemd-analyze verify is not clean: $verify"
exposure=$(systemd-analyze security --offline=true "$unit" 2>&1 | sed -n 's/.*Overall exposure level for lbsolidd.service: \([0-9.]*\).*/\1/p')
[ -n "$exposure" ] || fail "systemd-analyze security gave no exposure level"
echo "install test: systemd-analyze security: exposure $exposure (at most 3.0)"
awk -v e="$exposure" 'BEGIN { exit !(e <= 3.0) }' || fail "exposure $exposure is above 3.0"

# 6. The main job, the daemon started as the unit starts it.
read -r -a exec_start <<<"$(sed -n 's/^ExecStart=//p' "$unit")"
flags=()
for ((k = 1; k < ${#exec_start[@]}; ++k)); do
  case "${exec_start[k]}" in
    --listen | --data_dir) ((++k)) ;;  # replaced below
    *) flags+=("${exec_start[k]}") ;;
  esac
done
data="$work/data"
mkdir "$data"
"$root/usr/bin/lbsolidd" "${flags[@]}" --listen 127.0.0.1:0 --port_file "$work/port" --data_dir "$data" \
  --log_level warn &
daemon=$!
for _ in $(seq 200); do [ -s "$work/port" ] && break; sleep 0.05; done
[ -s "$work/port" ] || fail "the installed lbsolidd did not start with the unit's flags (${flags[*]})"
server="127.0.0.1:$(cat "$work/port")"
scenario="$root/usr/share/lbsolid/scenarios/fig5_drag_disk.textproto"
"$root/usr/bin/lbsolid" --server "$server" submit "$scenario" --out "$work/out" >"$work/submit.log" 2>&1 ||
  { cat "$work/submit.log"; fail "lbsolid submit failed"; }
"$root/usr/bin/lbsolid-drag-summary" "$work/out" >"$work/summary.log" 2>&1 || { cat "$work/summary.log"; fail "lbsolid-drag-summary failed"; }
for f in particles.h5 fields.h5 fields.xdmf status.json summary.txt; do
  [ -s "$work/out/$f" ] || fail "the main job did not write $f"
done
grep -q '"state": *"DONE"' "$work/out/status.json" || fail "the main job's status is not DONE: $(cat "$work/out/status.json")"
echo "install test: main job: $(grep -i -m 2 -E 'c_d|reynolds' "$work/out/summary.txt" | tr '\n' ' ')"

# 7. The Python client from the package alone.
(cd "$work" && env -u LBSOLID_BUILD_DIR -u LBSOLID_PYTHON_STUBS -u LBSOLIDD PYTHONPATH="$root/usr/lib/python3/dist-packages" \
  /usr/bin/python3 - "$server" "$root" <<'EOF'
import sys
import lbsolid_client
from lbsolid.v1 import simulation_pb2
from lbsolid_client import Client, load_scenario

server, root = sys.argv[1], sys.argv[2]
for module in (lbsolid_client, simulation_pb2):
    assert module.__file__.startswith(root), f"{module.__name__} came from {module.__file__}, not the package"
with Client(server) as client:
    session = client.create(load_scenario(f"{root}/usr/share/lbsolid/scenarios/poiseuille_channel.textproto"))
    reached = session.step(20).session.step
    assert reached == 20, f"stepped to {reached}, not 20"
    session.delete()
print("install test: the package's Python client stepped a session to 20")
EOF
) || fail "the package's Python client failed"
echo "install test: passed"
