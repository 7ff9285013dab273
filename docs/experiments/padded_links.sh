#!/bin/sh
# A measurement, not part of the build (docs/performance.md, "The 3D figure's swings"): links
# scene_steps.cpp against one build of the library several ways, each with a function of PAD
# bytes of no-ops ahead of the library (which moves all its code by that much), and runs each
# link ROUNDS times on vCPU 1. Where the linker puts the D3Q19 kernel moved the 3D scene by up to
# 1.8 ms a step on this VM; comparing two builds, compare the medians over several links of each.
#   docs/experiments/padded_links.sh LIBRARY [SCENE] [ROUNDS]   (from the tree's root)
set -eu
lib=${1:?"usage: $0 path/to/liblbsolid_core.a [scene] [rounds]"}
scene=${2:-3d}
rounds=${3:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags="-std=c++20 -O3 -DNDEBUG -ffp-contract=off"
g++ $flags -Icore -Itests -c docs/experiments/scene_steps.cpp -o "$work/main.o"
for pad in 16 64 192 512 1024 2048; do
  echo "__attribute__((used, aligned(16))) void pad_function(void) { __asm__ volatile(\".skip $pad, 0x90\"); }" >"$work/pad$pad.c"
  gcc -O2 -c "$work/pad$pad.c" -o "$work/pad$pad.o"
  g++ "$work/main.o" "$work/pad$pad.o" "$lib" -lpthread -o "$work/steps$pad"
done
for round in $(seq "$rounds"); do
  for pad in 16 64 192 512 1024 2048; do
    printf 'pad %4s: ' "$pad"
    taskset -c 1 "$work/steps$pad" "$scene" 100 1
  done
done
