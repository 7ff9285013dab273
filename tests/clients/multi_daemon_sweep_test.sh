#!/usr/bin/env bash
# Several daemons behind one CLI (issue 17): three lbsolidd on Unix sockets, each advertising its
# own address, and `lbsolid --server A,B,C`.
#   multi_daemon_sweep_test.sh LBSOLIDD LBSOLID SOURCE_DIR
# 1. A 12-job load sweep, submitted one job after another with --wait: every daemon is idle at
#    each placement, so the fewest-sessions tie-break must deal the jobs 4/4/4 in --server order;
#    each job ends DONE at its step count on the daemon its endpoint names.
# 2. Every later call follows the session: `status ID` through the list finds each job.
# 3. A retried submit (same --request-id) answers with its first session, on its first daemon.
# 4. Least loaded: a long run on the daemon with the fewest sessions (which the tie-break would
#    choose next); the two new jobs go to the other two, whose running sessions are fewer.
set -euo pipefail
daemon=$1 cli=$2 source=$3
test_name="multi-daemon sweep test"
source "$(dirname "$0")/daemons_test_lib.sh"

addresses=()
for name in a b c; do
  address="unix:$work/$name.sock"
  "$daemon" --listen "$address" --advertise_address "$address" --data_dir "$work/data-$name" --workers 1 \
    --log_level warn &
  pids+=($!)
  addresses+=("$address")
done
for name in a b c; do
  for _ in $(seq 200); do [ -S "$work/$name.sock" ] && break; sleep 0.05; done
  [ -S "$work/$name.sock" ] || fail "lbsolidd $name did not start"
done
servers=$(IFS=,; echo "${addresses[*]}")
lb() { "$cli" --server "$servers" "$@"; }
scenario="$source/client-examples/scenarios/fig5_drag_disk.textproto"

# 1. The sweep: loads 1e-6 .. 1.2e-5, 300 steps each.
declare -A count
ids=()
for k in $(seq 12); do
  out=$(lb --json submit "$scenario" --steps 300 --wait --set "bodies[0].load.x=${k}e-6") || fail "job $k failed"
  id=$(echo "$out" | field '["session_id"]')
  endpoint=$(echo "$out" | field '["session"]["endpoint"]')
  state=$(echo "$out" | field '["session"]["state"]')
  step=$(echo "$out" | field '["session"]["step"]')
  [ "$state" = DONE ] && [ "$step" = 300 ] || fail "job $k: $state at step $step"
  count[$endpoint]=$(( ${count[$endpoint]:-0} + 1 ))
  expected=${addresses[$(( (k - 1) % 3 ))]}
  [ "$endpoint" = "$expected" ] || fail "job $k went to $endpoint, not $expected (all idle: fewest sessions, then order)"
  ids+=("$id")
done
for address in "${addresses[@]}"; do
  [ "${count[$address]}" = 4 ] || fail "$address got ${count[$address]} jobs, not 4"
done
echo "multi-daemon sweep test: 12 jobs DONE, 4 on each daemon"

# 2. Each job found through the list, on the daemon its endpoint named.
for k in $(seq 12); do
  id=${ids[$((k - 1))]}
  endpoint=$(lb --json status "$id" | field '["session"]["endpoint"]')
  [ "$endpoint" = "${addresses[$(( (k - 1) % 3 ))]}" ] || fail "status $id answered from $endpoint"
done
lb status s-00000000000000000000000000000000 >/dev/null 2>"$work/missing.err" && fail "an unknown id was found"
grep -q "on none of the 3 daemons" "$work/missing.err" || { cat "$work/missing.err"; fail "the unknown id's error"; }

# 3. A retried submit with the same request id: the same session, from the daemon that has it.
first=$(lb --json submit "$scenario" --steps 100 --request-id retry-1 | field '["session_id"]')
first_endpoint=$(lb --json status "$first" | field '["session"]["endpoint"]')
again=$(lb --json submit "$scenario" --steps 100 --request-id retry-1 | field '["session_id"]')
[ "$again" = "$first" ] || fail "the retried submit made $again, not $first"
echo "multi-daemon sweep test: a retried submit found its session $first on $first_endpoint"

# 4. A long run on the first daemon of the sessions' tie-break order, then two new jobs.
sessions() { "$cli" --server "$1" --json info | field '["server"]["sessions"]'; }
least=${addresses[0]}
for address in "${addresses[@]}"; do [ "$(sessions "$address")" -lt "$(sessions "$least")" ] && least=$address; done
long=$("$cli" --server "$least" --json submit "$scenario" --steps 100000000 | field '["session_id"]')
for k in 1 2; do
  endpoint=$(lb --json submit "$scenario" --steps 100000000 | field '["session"]["endpoint"]')
  [ "$endpoint" != "$least" ] || fail "new job $k went to $least, which has a running session"
done
for address in "${addresses[@]}"; do
  r=$("$cli" --server "$address" --json info | field '["server"]["running_sessions"]')
  [ "$r" = 1 ] || fail "$address runs $r sessions, not 1"
done
echo "multi-daemon sweep test: with a long run on $least, the new jobs went to the other two; passed"
