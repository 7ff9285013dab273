#!/usr/bin/env bash
# A DNS name that resolves to several daemons (issue 17), as a Kubernetes headless Service names
# every replica: three lbsolidd on 127.0.0.1, 127.0.0.2 and 127.0.0.3 at one port, and the name
# daemons.test listing the three in a hosts file that only the CLI's calls see (a private mount
# namespace binds it over /etc/hosts; nothing outside the test changes).
#   dns_name_daemons_test.sh LBSOLIDD LBSOLID SOURCE_DIR
# 1. Six jobs submitted through `--server daemons.test:PORT` with --wait: every daemon idle at each
#    placement, so the fewest-sessions rule deals them 2/2/2; each ends DONE.
# 2. `status ID` through the name finds each job on the daemon its endpoint names; `list` lists all six.
# 3. Over TLS, each address's certificate is checked for the name: three TLS daemons with a
#    certificate for daemons.test answer the CLI's `list` and the Python Cluster through it; with
#    one for elsewhere.test, the CLI's call fails because the peer is not daemons.test.
# 4. The Python client's Cluster("daemons.test:PORT") holds the three daemons and finds the jobs
#    where they are (with LBSOLID_PYTHON_STUBS set, as CMake does when the Python stubs are built).
set -euo pipefail
daemon=$1 cli=$2 source=$3
test_name="DNS-name daemons test"
source "$(dirname "$0")/daemons_test_lib.sh"

# A private mount namespace: as root directly, otherwise inside a user namespace of one's own.
namespace=(unshare -m)
[ "$(id -u)" = 0 ] || namespace=(unshare -rm)
printf '127.0.0.1 localhost\n127.0.0.1 daemons.test\n127.0.0.2 daemons.test\n127.0.0.3 daemons.test\n' > "$work/hosts"
"${namespace[@]}" sh -c 'mount --bind "$1" /etc/hosts && getent ahosts daemons.test' sh "$work/hosts" > "$work/resolved" ||
  fail "cannot bind a hosts file in a private mount namespace (${namespace[*]}): this test needs one"
[ "$(awk '$2 == "STREAM" {print $1}' "$work/resolved" | sort -u | wc -l)" = 3 ] || { cat "$work/resolved"; fail "daemons.test did not resolve to 3 addresses"; }

# Three daemons at one port free on the three addresses (another process may take it meanwhile:
# try again); sets `port`. Extra flags go to every daemon.
start_three() {
  local attempt k ok
  for attempt in 1 2 3; do
    port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
    local started=()
    for k in 1 2 3; do
      rm -f "$work/port-$k"
      "$daemon" --listen "127.0.0.$k:$port" --advertise_address "127.0.0.$k:$port" --data_dir "$work/data-$port-$k" \
        --workers 1 --port_file "$work/port-$k" --log_level warn "$@" &
      started+=($!)
      pids+=($!)
    done
    ok=1
    for k in 1 2 3; do
      for _ in $(seq 200); do [ -s "$work/port-$k" ] && break; kill -0 "${started[$((k - 1))]}" 2>/dev/null || break; sleep 0.05; done
      [ -s "$work/port-$k" ] || ok=0
    done
    [ "$ok" = 1 ] && return 0
    for k in "${started[@]}"; do kill -TERM "$k" 2>/dev/null && wait "$k" || true; done
  done
  fail "three daemons on one port did not start"
}
start_three

in_namespace() { "${namespace[@]}" sh -c 'mount --bind "$1" /etc/hosts && shift && exec "$@"' sh "$work/hosts" "$@"; }
lb() { in_namespace "$cli" --server "daemons.test:$port" "$@"; }
scenario="$source/client-examples/scenarios/fig5_drag_disk.textproto"

declare -A count
ids=() endpoints=()
for k in $(seq 6); do
  out=$(lb --json submit "$scenario" --steps 100 --wait --set "bodies[0].load.x=${k}e-6") || fail "job $k failed"
  state=$(echo "$out" | field '["session"]["state"]')
  [ "$state" = DONE ] || fail "job $k ended $state"
  endpoint=$(echo "$out" | field '["session"]["endpoint"]')
  count[$endpoint]=$(( ${count[$endpoint]:-0} + 1 ))
  ids+=("$(echo "$out" | field '["session_id"]')")
  endpoints+=("$endpoint")
done
for k in 1 2 3; do
  [ "${count[127.0.0.$k:$port]:-0}" = 2 ] || fail "127.0.0.$k:$port got ${count[127.0.0.$k:$port]:-0} jobs, not 2"
done
echo "DNS-name daemons test: 6 jobs DONE through daemons.test:$port, 2 on each of its 3 addresses"

for k in $(seq 6); do
  endpoint=$(lb --json status "${ids[$((k - 1))]}" | field '["session"]["endpoint"]')
  [ "$endpoint" = "${endpoints[$((k - 1))]}" ] || fail "status ${ids[$((k - 1))]} answered from $endpoint"
done
listed=$(lb --json list | field '["sessions"].__len__()')
[ "$listed" = 6 ] || fail "list through the name showed $listed sessions, not 6"
echo "DNS-name daemons test: every job found again through the name"
plain_port=$port

certificate() {  # certificate NAME FILE-STEM: a key and a certificate for DNS name NAME, signed by the test CA
  openssl req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout "$2.key" -out "$2.csr" -subj "/CN=$1" 2>/dev/null
  printf 'subjectAltName=DNS:%s\n' "$1" > "$2.san"
  openssl x509 -req -in "$2.csr" -CA "$work/ca.pem" -CAkey "$work/ca.key" -CAcreateserial -out "$2.pem" -days 1 \
    -extfile "$2.san" 2>/dev/null
}
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout "$work/ca.key" -out "$work/ca.pem" \
  -days 1 -subj "/CN=lbsolid test CA" 2>/dev/null
certificate daemons.test "$work/right"
certificate elsewhere.test "$work/wrong"
start_three --tls_cert "$work/right.pem" --tls_key "$work/right.key"
in_namespace "$cli" --server "daemons.test:$port" --tls-ca "$work/ca.pem" list 2> "$work/tls.err" ||
  { cat "$work/tls.err"; fail "TLS through the name"; }
! grep -q warning "$work/tls.err" || { cat "$work/tls.err"; fail "a TLS daemon was skipped"; }
# The Python Cluster too (when its stubs are given): three clients over TLS, each answering.
if [ -n "${LBSOLID_PYTHON_STUBS:-}" ]; then
  in_namespace /usr/bin/python3 - "$source/client-examples/python" "daemons.test:$port" "$work/ca.pem" <<'PY' ||
import sys
sys.path.insert(0, sys.argv[1])
from lbsolid_client import Cluster
with Cluster(sys.argv[2], timeout=30, tls_ca=sys.argv[3]) as cluster:
    assert len(cluster.clients) == 3, f"{len(cluster.clients)} clients"
    endpoints = sorted(client.info().endpoint for client in cluster.clients)
    assert len(set(endpoints)) == 3, endpoints
PY
    fail "the Python Cluster over TLS through the name"
fi
start_three --tls_cert "$work/wrong.pem" --tls_key "$work/wrong.key"
in_namespace "$cli" --server "daemons.test:$port" --tls-ca "$work/ca.pem" list 2> "$work/wrong.err" &&
  fail "daemons with a certificate for elsewhere.test answered through daemons.test"
grep -q "Peer name daemons.test is not in peer certificate" "$work/wrong.err" ||
  { cat "$work/wrong.err"; fail "the refusal does not say that the name was checked"; }
echo "DNS-name daemons test: over TLS each address is checked for the name (refused for another name)"
port=$plain_port

[ -n "${LBSOLID_PYTHON_STUBS:-}" ] || { echo "DNS-name daemons test: passed (the CLI only: no Python stubs given)"; exit 0; }
in_namespace /usr/bin/python3 - "$source/client-examples/python" "daemons.test:$port" "${ids[@]}" "${endpoints[@]}" <<'PY' ||
import sys
sys.path.insert(0, sys.argv[1])
from lbsolid_client import Cluster
ids, endpoints = sys.argv[3:9], sys.argv[9:15]
with Cluster(sys.argv[2], timeout=30) as cluster:
    answering = sorted(client.info().endpoint for client in cluster.clients)
    expected = sorted(set(endpoints))
    assert answering == expected, f"the Cluster holds {answering}, not {expected}"
    for session_id, endpoint in zip(ids, endpoints):
        found = cluster.session(session_id).get().endpoint
        assert found == endpoint, f"{session_id} found on {found}, not {endpoint}"
    assert len(cluster.list()) == 6
PY
  fail "the Python Cluster through the name"
echo "DNS-name daemons test: the Python Cluster through the name holds the 3 daemons and finds each job; passed"
