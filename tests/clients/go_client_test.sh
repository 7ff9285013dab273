#!/bin/sh
# go_client_matches_core: the Go client (client-examples/go/lbsolid-go-profiles) against a real
# lbsolidd. Starts the daemon on a free loopback port, has the client run SCENARIO for STEPS steps
# watching profiles every EVERY steps (lossless), runs lbsolid-reference on the same file in
# process, and checks with lbsolid-go-compare that every frame (step, y, u_x) is equal bit for bit,
# with the same number of frames and at least one. The daemon is stopped (SIGTERM) in every case.
#
#   go_client_test.sh LBSOLIDD REFERENCE GO_PROFILES GO_COMPARE SCENARIO STEPS EVERY
set -eu
if [ $# -ne 7 ]; then
  echo "usage: $0 LBSOLIDD REFERENCE GO_PROFILES GO_COMPARE SCENARIO STEPS EVERY" >&2
  exit 2
fi
lbsolidd=$1 reference=$2 client=$3 compare=$4 scenario=$5 steps=$6 every=$7

work=$(mktemp -d "${TMPDIR:-/tmp}/lbsolid-go-client-test.XXXXXX")
daemon_pid=

stop_daemon() {
  [ -n "$daemon_pid" ] || return 0
  kill -TERM "$daemon_pid" 2>/dev/null || true
  # SIGTERM checkpoints the sessions, then exits; give it 10 s before SIGKILL.
  i=0
  while kill -0 "$daemon_pid" 2>/dev/null && [ $i -lt 200 ]; do
    sleep 0.05
    i=$((i + 1))
  done
  kill -KILL "$daemon_pid" 2>/dev/null || true
  status=0
  wait "$daemon_pid" || status=$?
  echo "lbsolidd stopped (exit status $status)"
  daemon_pid=
}
cleanup() {
  stop_daemon
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

fail() {
  echo "FAIL: $*" >&2
  if [ -s "$work/daemon.log" ]; then
    echo "--- lbsolidd log (last 20 lines):" >&2
    tail -n 20 "$work/daemon.log" >&2
  fi
  exit 1
}

# Starts lbsolidd with the given extra flags on a free port and sets $address. Under timeout(1)
# (which passes SIGTERM on): should this script be killed before its trap runs (ctest's 120 s
# limit), the daemon still goes away on its own.
start_daemon() {  # data directory, flags...
  data=$1
  shift
  rm -f "$work/port"
  timeout 110 "$lbsolidd" --listen 127.0.0.1:0 --port_file "$work/port" --data_dir "$data" \
    --log_level warn "$@" >"$work/daemon.log" 2>&1 &
  daemon_pid=$!
  # The daemon writes the port file through a rename once it serves: it is whole when it appears.
  i=0
  while [ ! -s "$work/port" ]; do
    kill -0 "$daemon_pid" 2>/dev/null || { wait "$daemon_pid" || true; daemon_pid=; fail "lbsolidd $* exited at start"; }
    [ $i -lt 400 ] || fail "lbsolidd $* did not write its port file within 20 s"
    sleep 0.05
    i=$((i + 1))
  done
  address=127.0.0.1:$(cat "$work/port")
}

start_daemon "$work/data" --workers 2
echo "lbsolidd serves on $address"

"$client" --address "$address" --scenario "$scenario" --steps "$steps" --every "$every" --print-hex \
  --timeout 30 --stream-timeout 90 --outputs "$work/outputs" >"$work/client.txt" 2>"$work/client.err" ||
  fail "lbsolid-go-profiles exited with status $?: $(cat "$work/client.err")"
# The recorded files it copied: each as the daemon named it (coreutils' sha256sum, not the client's).
for name in particles.h5 fields.h5 fields.xdmf; do
  named=$(sed -n "s/^downloaded $name [0-9]* //p" "$work/client.err")
  [ -n "$named" ] || fail "the client did not download $name"
  [ "$(sha256sum "$work/outputs/$name" | cut -d' ' -f1)" = "$named" ] || fail "$name differs from what the daemon named"
done
"$reference" "$scenario" --steps "$steps" --profiles-every "$every" >"$work/reference.txt" ||
  fail "lbsolid-reference exited with status $?"
echo "client: $(grep -c '^profile ' "$work/client.txt" || true) frames; reference: $(grep -c '^profile ' "$work/reference.txt" || true) frames"

"$compare" "$work/client.txt" "$work/reference.txt" || fail "the Go client's frames differ from the core's (above)"
echo "PASS: the Go client received exactly what the core computes"
stop_daemon

# TLS and a bearer token: a throwaway CA and a certificate for 127.0.0.1, a tokens file of hashes.
printf 'subjectAltName=DNS:localhost,IP:127.0.0.1\n' >"$work/san.cnf"
ec="-newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes"
(cd "$work" &&
  openssl req -x509 $ec -keyout ca.key -out ca.pem -days 2 -subj "/CN=go test CA" &&
  openssl req $ec -keyout daemon.key -out daemon.csr -subj "/CN=localhost" &&
  openssl x509 -req -in daemon.csr -CA ca.pem -CAkey ca.key -CAcreateserial -out daemon.pem -days 2 \
    -extfile san.cnf) >"$work/openssl.log" 2>&1 || fail "openssl: $(cat "$work/openssl.log")"
echo "$(printf %s go-secret | sha256sum | cut -d' ' -f1) go-user user" >"$work/tokens"
printf 'go-secret\n' >"$work/token"
start_daemon "$work/data-tls" --tls_cert "$work/daemon.pem" --tls_key "$work/daemon.key" --tokens_file "$work/tokens"
tls="--address $address --scenario $scenario --steps $steps --every $every --timeout 30 --tls-ca $work/ca.pem"
"$client" $tls --token-file "$work/token" >/dev/null 2>"$work/client.err" ||
  fail "lbsolid-go-profiles over TLS with its token exited with status $?: $(cat "$work/client.err")"
status=0
"$client" $tls >/dev/null 2>"$work/client.err" || status=$?
[ $status -eq 2 ] || fail "without a token the client exited $status, not 2: $(cat "$work/client.err")"
grep -q UNAUTHENTICATED "$work/client.err" || fail "without a token: $(cat "$work/client.err")"
echo "PASS: over TLS the token is taken and its absence refused (exit 2)"
