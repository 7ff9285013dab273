#!/usr/bin/env bash
# The portable build's fluid kernels against a -march=native build of the same source, on this
# machine (issue 17: within 5%). Builds lbsolid-bench alone with LBSOLID_NATIVE=ON in
# build-native/ (the portable one is build/, from deploy/setup.sh), then runs the two binaries in
# turns, ROUNDS times (default 5), one thread, kernels only (`--quick`, or with --full the
# benchmark's longer runs on twice the working set: 3 s a kernel instead of 0.5), and prints per kernel the MLUPS of
# each and portable/native for the best run of each and as the median of the rounds' ratios.
# Runs in turns because this kind of machine drifts: two runs of one binary minutes apart can
# differ by more than the 5% in question.
#   tests/bench/portable_vs_native.sh [ROUNDS] [--full]
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-5}
length=--quick
[ "${2:-}" = --full ] && length=
portable=build/tests/lbsolid-bench
[ -x "$portable" ] || { echo "portable_vs_native: $portable missing: run deploy/setup.sh first" >&2; exit 2; }

cmake -S . -B build-native -G Ninja -DCMAKE_BUILD_TYPE=Release -DLBSOLID_NATIVE=ON \
  -DLBSOLID_BUILD_SERVER=OFF -DLBSOLID_BUILD_EXAMPLES=OFF -DLBSOLID_BUILD_TESTS=OFF >/dev/null
cmake --build build-native --parallel "$(nproc)" --target lbsolid-bench >/dev/null
native=build-native/tests/lbsolid-bench

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for ((r = 1; r <= rounds; r++)); do
  # Alternate which goes first, so that neither always runs on the warmer (or busier) machine.
  if ((r % 2)); then order=(portable native); else order=(native portable); fi
  for build in "${order[@]}"; do
    binary=$portable; [ "$build" = native ] && binary=$native
    "$binary" --kernels-only $length --threads 1 --json > "$out/$build.$r.json"
  done
  echo "portable_vs_native: round $r of $rounds done" >&2
done

/usr/bin/python3 - "$out" "$rounds" <<'EOF'
import json, statistics, sys
folder, rounds = sys.argv[1], int(sys.argv[2])
def load(build, r):
    with open(f"{folder}/{build}.{r}.json") as f:
        doc = json.load(f)
    return doc["kernel_isa"], {(x["lattice"], x["precision"], x["streaming"]): x["mlups"]
                               for x in doc["results"] if x["threads"] == 1}
runs = {b: [load(b, r) for r in range(1, rounds + 1)] for b in ("portable", "native")}
print(f"portable (kernels: {runs['portable'][0][0]}) against native, {rounds} rounds, one thread, MLUPS")
print(f"{'kernel':<30} {'portable best':>13} {'native best':>11} {'best/best':>9} {'median ratio':>12} {'ratio range':>13}")
for key in runs["portable"][0][1]:
    p = [run[1][key] for run in runs["portable"]]
    n = [run[1][key] for run in runs["native"]]
    ratios = [a / b for a, b in zip(p, n)]
    print(f"{' '.join(key):<30} {max(p):13.1f} {max(n):11.1f} {max(p) / max(n):9.3f} "
          f"{statistics.median(ratios):12.3f} {min(ratios):6.3f}-{max(ratios):.3f}")
EOF
