#!/usr/bin/env bash
# The main job: sets everything up (deploy/setup.sh), starts lbsolidd on a free loopback port,
# submits the paper's drag experiment (Fig. 5: a disk pulled through a D2Q7 channel) through the
# lbsolid CLI, waits for it, and writes under ./out:
#   particles.h5   H5MD: the disk's particles and centre-of-mass velocity u(t), the scenario
#                  (open particles.xdmf beside it in ParaView)
#   fields.h5      density and velocity at the last step (open fields.xdmf in ParaView)
#   status.json    state, steps, checksums of the files, error if any
#   summary.txt    u(t), its exponential fit, the drag coefficient c_d and the Reynolds number
# then stops the daemon (SIGTERM). Extra arguments go to `lbsolid submit` (e.g. --steps 4000).
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/setup.sh

scenario=client-examples/scenarios/fig5_drag_disk.textproto  # its "# steps:" line says how many
out=out
data="$out/daemon-data"  # this run's daemon only: a rerun starts clean instead of recovering old sessions
rm -rf "$data"
mkdir -p "$out" "$data"
rm -f "$out"/particles.h5 "$out"/particles.xdmf "$out"/fields.h5 "$out"/fields.xdmf "$out"/status.json "$out"/summary.txt

build/server/lbsolidd --listen 127.0.0.1:0 --port_file "$data/port" --data_dir "$data" --log_level warn &
daemon=$!
stop_daemon() { kill -TERM "$daemon" 2>/dev/null && wait "$daemon" || true; }
trap stop_daemon EXIT
for _ in $(seq 200); do [ -s "$data/port" ] && break; sleep 0.05; done
[ -s "$data/port" ] || { echo "run: lbsolidd did not start" >&2; exit 3; }
server="127.0.0.1:$(cat "$data/port")"

echo "run: lbsolidd on $server; submitting $scenario"
build/client-examples/cli/lbsolid --server "$server" submit "$scenario" --out "$out" "$@"
build/client-examples/drag-summary/lbsolid-drag-summary "$out"
echo "run: results in $out/ (summary.txt, particles.h5 + particles.xdmf, fields.h5 + fields.xdmf, status.json)"
