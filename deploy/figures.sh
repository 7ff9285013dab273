#!/usr/bin/env bash
# Redraws the paper's figures (Figs. 1, 4, 5, 6, 7) and two beyond it (Fig. 8, rotating bodies) through lbsolidd: sets everything up
# (deploy/setup.sh), then client-examples/python/figures/draw_all.py starts a private daemon on a
# free loopback port, runs every experiment as sessions on it with the Python client, and writes
# a PNG and a CSV per figure plus summary.md / summary.csv (the paper's values beside ours) to
# out/figures (or --out DIR). --quick runs small versions in about 35 s.
set -euo pipefail
cd "$(dirname "$0")/.."
deploy/setup.sh
exec /usr/bin/python3 client-examples/python/figures/draw_all.py --out out/figures "$@"
