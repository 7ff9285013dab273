#!/usr/bin/env bash
# Sets everything up (deploy/setup.sh) and runs the main job. Until the lbsolidd service exists
# the main job is the fluid demo: a channel flow's steady profile beside the analytic parabola.
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/setup.sh
build/client-examples/channel-demo/lbsolid-channel-demo "$@"
