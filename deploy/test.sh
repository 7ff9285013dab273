#!/usr/bin/env bash
# Sets everything up (deploy/setup.sh) and runs the whole test suite; exits non-zero on any failure:
#   1. every test of the main (Release) build;
#   2. the core, server, session and service tests again under ASan+UBSan and under TSan, where a
#      sanitizer report anywhere, the daemons the tests start included, fails (deploy/sanitizers.sh);
#   3. the fuzz targets: every kept regression input, then 15 s of fuzzing each (deploy/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/setup.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 900
deploy/sanitizers.sh
deploy/fuzz.sh
