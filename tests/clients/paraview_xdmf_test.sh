#!/usr/bin/env bash
# ParaView opens what `lbsolid submit --out` writes (issue 17): two runs through a private daemon,
# then Debian's pvpython reads their particles.xdmf and fields.xdmf and compares what it gets with
# the HDF5 files (paraview_xdmf_check.py).
#   paraview_xdmf_test.sh LBSOLIDD LBSOLID SOURCE_DIR PVPYTHON
# - Fig. 6's 60 chains, D2Q7 (2D: XY points, velocity_x and velocity_y, many bodies per step);
# - the 3D sedimentation ball, D3Q19 (XYZ points, a velocity vector, a 3D grid).
set -euo pipefail
daemon=$1 cli=$2 source=$3 pvpython=$4
test_name="paraview xdmf test"
source "$(dirname "$0")/daemons_test_lib.sh"

"$daemon" --listen "unix:$work/d.sock" --data_dir "$work/data" --workers 1 --log_level warn &
pids+=($!)
for _ in $(seq 200); do [ -S "$work/d.sock" ] && break; sleep 0.05; done
[ -S "$work/d.sock" ] || fail "lbsolidd did not start"

# Fig. 6 records its 60 bodies every 10th step (30 frames; every step made a 22 MB particles.xdmf).
for run in "fig6_chains_shear 300 10" "sedimentation_3d 200 1"; do
  read -r name steps every <<< "$run"
  "$cli" --server "unix:$work/d.sock" submit "$source/client-examples/scenarios/$name.textproto" \
    --steps "$steps" --particles-every "$every" --out "$work/$name" > "$work/$name.log" 2>&1 \
    || { cat "$work/$name.log"; fail "$name: submit failed"; }
  # ParaView logs to stderr, with stack traces on failure; keep it for a failure's message.
  "$pvpython" "$source/tests/clients/paraview_xdmf_check.py" "$work/$name" 2> "$work/$name.pv.err" \
    || { grep -v '^ *[0-9]* *0x' "$work/$name.pv.err" | tail -20; fail "$name: ParaView does not read what the files hold"; }
done
echo "paraview xdmf test: ParaView read both runs' particles and fields as the HDF5 files hold them"
