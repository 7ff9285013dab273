#!/usr/bin/env bash
# Sets everything up (deploy/setup.sh) and runs the whole test suite; exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/setup.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 900
