#!/usr/bin/env bash
# libFuzzer runs of the fuzz targets (tests/fuzz/README.md). deploy/test.sh runs the short form.
#
#   deploy/fuzz.sh                 build-fuzz (clang, ASan+UBSan+libFuzzer), replay every
#                                  tests/fuzz/regressions/<target>/ input, then fuzz each target for
#                                  LBSOLID_FUZZ_SECONDS (default 15) from the seeds
#   deploy/fuzz.sh --long          the same, 10 minutes per target (or LBSOLID_FUZZ_SECONDS), the
#                                  corpus kept in build-fuzz/corpus/<target> for the next run
#   deploy/fuzz.sh [--long] TARGET...   only those targets
#
# A crash, a sanitizer report, an oracle's abort, a leak, a timeout (one input over 10 s) or an
# out-of-memory (over 2 GiB) stops that target's run, writes the input to
# build-fuzz/artifacts/<target>/ and makes the script exit 1. Keep it as a regression input:
#   cp build-fuzz/artifacts/<target>/crash-... tests/fuzz/regressions/<target>/<short-name>
# (ctest then replays it in every build, fuzz_regression.<target>.<short-name>).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
build=build-fuzz
jobs=$(nproc)
seconds=${LBSOLID_FUZZ_SECONDS:-15}
targets=()
for arg in "$@"; do
  case $arg in
    --long) seconds=${LBSOLID_FUZZ_SECONDS:-600} ;;
    fuzz_*) targets+=("$arg") ;;
    *) echo "usage: deploy/fuzz.sh [--long] [fuzz_TARGET...]" >&2; exit 2 ;;
  esac
done
if ((${#targets[@]} == 0)); then
  targets=(fuzz_scenario_text fuzz_scenario_json fuzz_scenario_binary fuzz_service)
fi
# Reports name functions and lines when llvm-symbolizer is there (llvm-14, deploy/debian-packages.txt).
symbolizer=""
if [ -x /usr/lib/llvm-14/bin/llvm-symbolizer ]; then symbolizer=":external_symbolizer_path=/usr/lib/llvm-14/bin/llvm-symbolizer"; fi
t0=$(date +%s)

cc=$(command -v clang-14 || command -v clang)
cxx=$(command -v clang++-14 || command -v clang++)
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
  -DLBSOLID_SANITIZE=address,undefined -DLBSOLID_FUZZ=ON -DLBSOLID_FORCE_INLINE=OFF -DLBSOLID_BUILD_BENCH=OFF -DLBSOLID_BUILD_EXAMPLES=OFF \
  >/dev/null
cmake --build "$build" --parallel "$jobs" --target make_seeds "${targets[@]}"
t1=$(date +%s)

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1$symbolizer"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1$symbolizer"

# Every kept regression input, through the sanitized fuzz binaries.
rm -rf "$build/seeds"
"$build/tests/fuzz/make_seeds" client-examples/scenarios "$build/seeds"
status=0
ctest --test-dir "$build" -L '^fuzz_regression$' --output-on-failure --parallel "$jobs" --timeout 300 || status=1
t2=$(date +%s)

for target in "${targets[@]}"; do
  corpus=$build/corpus/$target
  artifacts=$build/artifacts/$target
  mkdir -p "$corpus" "$artifacts"
  echo "fuzz: $target for ${seconds} s"
  # The first directory is where new inputs go; the seeds are only read. (The regression inputs
  # were replayed above; in the corpus, one of a bug still open would stop the run at its start.)
  if ! "$build/tests/fuzz/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=2048 -max_len=16384 -print_final_stats=1 -artifact_prefix="$artifacts/" \
      "$corpus" "$build/seeds/$target" >"$build/$target.log" 2>&1; then
    status=1
    echo "fuzz: $target FAILED; the input is in $artifacts/, the log in $build/$target.log:" >&2
    tail -n 80 "$build/$target.log" >&2
  else
    grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb|#[0-9]+ *DONE)' "$build/$target.log" || true
  fi
done
t3=$(date +%s)
echo "fuzz: build $((t1 - t0)) s, regressions $((t2 - t1)) s, fuzzing $((t3 - t2)) s, rc $status"
exit $status
