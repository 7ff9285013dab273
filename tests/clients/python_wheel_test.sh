#!/usr/bin/env bash
# The Python client as a wheel, built and installed offline with Debian's pip and setuptools
# (issue 17), then used from outside the source tree:
#   tests/clients/python_wheel_test.sh SOURCE_DIR LBSOLIDD VERSION
# The package's sources (client-examples/python, proto/) are copied to a scratch tree first, since
# pip builds a local directory in place. The wheel must carry the stubs (lbsolid/v1) and the
# project's version; installed with --target into an empty directory and nothing else on
# PYTHONPATH, it must import from there and step a session on a private daemon.
set -euo pipefail
source=$1 daemon=$2 version=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "python wheel test: $*" >&2; exit 1; }

mkdir -p "$work/src/client-examples"
cp -r "$source/proto" "$work/src/"
cp -r "$source/client-examples/python" "$work/src/client-examples/"
rm -rf "$work/src/client-examples/python/figures"  # not part of the package
/usr/bin/python3 -m pip wheel --no-build-isolation --no-deps --no-index --quiet \
  "$work/src/client-examples/python" -w "$work/wheels" || fail "pip wheel failed"
wheel=$(ls "$work"/wheels/lbsolid_client-*.whl)
case "$(basename "$wheel")" in "lbsolid_client-$version-"*) ;; *) fail "$(basename "$wheel") is not version $version" ;; esac
listing=$(/usr/bin/python3 -m zipfile -l "$wheel")
for f in lbsolid_client/client.py lbsolid/v1/simulation_pb2.py lbsolid/v1/simulation_pb2_grpc.py lbsolid/v1/scenario_pb2.py; do
  grep -q "^$f " <<<"$listing" || fail "the wheel lacks $f"
done
/usr/bin/python3 -m pip install --no-deps --no-index --quiet --target "$work/site" "$wheel" 2>/dev/null ||
  fail "pip install --target failed"

cd "$work"
env -u LBSOLID_BUILD_DIR -u LBSOLID_PYTHON_STUBS LBSOLIDD="$daemon" PYTHONPATH="$work/site" \
  /usr/bin/python3 - "$work/site" <<'PY' || fail "the installed client failed"
import sys
import lbsolid_client
from lbsolid.v1 import simulation_pb2
from lbsolid_client import Client, LocalDaemon, scenario_pb2

site = sys.argv[1]
for module in (lbsolid_client, simulation_pb2):
    assert module.__file__.startswith(site), f"{module.__name__} came from {module.__file__}, not the wheel"
scenario = scenario_pb2.Scenario(name="wheel")
scenario.domain.nx, scenario.domain.ny = 16, 8
with LocalDaemon() as daemon, Client(daemon.address) as client:
    session = client.create(scenario)
    reached = session.step(12).session.step
    assert reached == 12, f"stepped to {reached}, not 12"
print("python wheel test: the wheel's client stepped a session to 12")
PY
echo "python wheel test: passed ($(basename "$wheel"))"
