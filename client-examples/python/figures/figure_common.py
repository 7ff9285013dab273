"""What every figure script shares: its command line, the daemon it talks to, its output files,
and the "paper against ours" rows that draw_all.py gathers into one table.

A figure script defines
    FIGURE = "fig5"                               # file stem of its outputs
    def draw(client, out_dir, quick) -> [Row]     # runs through the daemon, writes PNG + CSV
and ends with `if __name__ == "__main__": run_figure(draw, FIGURE)`.
"""
import argparse
import csv
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # lbsolid_client

import matplotlib  # noqa: E402

matplotlib.use("Agg")  # headless: figures go to files

from lbsolid_client import Client, LocalDaemon, load_scenario  # noqa: E402,F401

SCENARIOS = HERE.parents[1] / "scenarios"


@dataclass
class Row:
    figure: str      # "Fig. 5"
    quantity: str    # what is compared
    paper: str       # the paper's value or statement
    ours: str        # what this run measured
    note: str = ""   # channel, counts, why they differ
    check: str = ""  # the bound this row is held to (from the paper or a conservation law), if any
    passed: Optional[bool] = None  # whether `ours` met `check`; None when the row is not checked

    def verdict(self) -> str:
        return "" if self.passed is None else ("ok" if self.passed else "FAILED")


def write_csv(path: Path, header, rows):
    """Writes a CSV with a header line; numbers with full precision (repr)."""
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        for row in rows:
            writer.writerow([repr(v) if isinstance(v, float) else v for v in row])


def print_rows(rows):
    for r in rows:
        check = f" [{r.verdict()}: {r.check}]" if r.check else ""
        print(f"  {r.figure:7s} {r.quantity:45s} paper: {r.paper:28s} ours: {r.ours:28s} {r.note}{check}")


def failed_checks(rows):
    return [r for r in rows if r.passed is False]


def parse_args(figure: str, argv=None):
    parser = argparse.ArgumentParser(description=f"Redraw the paper's {figure} through lbsolidd")
    parser.add_argument("--quick", action="store_true", help="a small, fast version (seconds to a minute)")
    parser.add_argument("--address", help="HOST:PORT of a running lbsolidd (default: start a private one)")
    parser.add_argument("--out", default="out/figures", help="directory for the PNG and CSV files")
    parser.add_argument("--strict", action="store_true", help="exit 1 when a checked row fails its bound")
    return parser.parse_args(argv)


def connect(address):
    """A client for `address`, or for a private daemon started here (returned to be stopped)."""
    daemon = None
    if not address:
        daemon = LocalDaemon().start()
        address = daemon.address
    return Client(address, timeout=60.0).wait_ready(), daemon


def run_figure(draw, figure: str, argv=None):
    args = parse_args(figure, argv)
    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    client, daemon = connect(args.address)
    try:
        started = time.monotonic()
        rows = draw(client, out_dir, args.quick)
        print(f"{figure}: {time.monotonic() - started:.1f} s, files in {out_dir}")
        print_rows(rows)
    finally:
        client.close()
        if daemon:
            daemon.stop()
    if args.strict and failed_checks(rows):
        sys.exit(1)
    return rows


def run_in_parallel(tasks, in_flight: int) -> dict:
    """tasks: (name, cost, work) triples, work() -> result. Runs them `in_flight` at a time, the
    costliest first (so the long runs do not end alone), and returns name -> result in the tasks'
    order. Stops starting new ones after a failure and re-raises the first, with its task's name
    (a diverged session names its step)."""
    queue = sorted(tasks, key=lambda t: -t[1])
    results, errors, lock = {}, [], threading.Lock()

    def worker():
        while True:
            with lock:
                if not queue or errors:
                    return
                name, _, work = queue.pop(0)
            try:
                results[name] = work()
            except Exception as error:  # noqa: BLE001  (reported below, with the task's name)
                with lock:
                    errors.append((name, error))

    threads = [threading.Thread(target=worker) for _ in range(in_flight)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        name, error = errors[0]
        raise RuntimeError(f"run {name!r} failed: {error}") from error
    return {name: results[name] for name, _, _ in tasks}
