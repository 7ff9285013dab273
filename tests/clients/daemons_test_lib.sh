# Shared by the shell tests that start daemons of their own (sourced, not run):
#   test_name="..."; source daemons_test_lib.sh
# Gives `work` (a fresh directory), `pids` (daemons to stop: each gets SIGTERM at exit, then the
# directory goes), `fail MESSAGE` and `field PYTHON-SUBSCRIPT` (reads one value of the JSON on stdin).
work=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null && wait "$pid" || true; done
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "$test_name: $*" >&2; exit 1; }
field() { /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); print(d$1)"; }
