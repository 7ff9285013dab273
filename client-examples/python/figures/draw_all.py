"""Redraws every figure of the paper through lbsolidd and prints the paper's values beside ours.

    /usr/bin/python3 client-examples/python/figures/draw_all.py [--quick] [--address HOST:PORT] [--out DIR]

Without --address it starts a private daemon on a free loopback port. Each figure writes its PNG
and CSV into --out (default out/figures); the table of paper against ours goes to summary.md and
summary.csv there. --quick runs small versions of every experiment (a few minutes in all);
--strict exits 1 when a row fails the bound it is checked against (the CI test uses both).
"""
import importlib
import sys
import time
from pathlib import Path

from figure_common import connect, failed_checks, parse_args, print_rows, write_csv

FIGURES = ["fig1_bouncing_sheet", "fig4_slip", "fig5_drag", "fig6_chains", "fig7_relaxation", "fig8_rotating_chains",
           "rotation_validation", "seaweed", "seaweed_flapping", "fracture",
           "schafer_turek"]


def write_markdown(path: Path, rows, quick: bool, seconds: dict):
    lines = [f"Paper against ours ({'--quick' if quick else 'full'} run)", "",
             "| Figure | Quantity | Paper | Ours | Check | Note |", "|---|---|---|---|---|---|"]
    for r in rows:
        check = f"{r.verdict()}: {r.check}" if r.check else ""
        cells = [r.figure, r.quantity, r.paper, r.ours, check, r.note]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")  # |u| must not split a cell
    lines += ["", "Wall time per figure: " + ", ".join(f"{k} {v:.0f} s" for k, v in seconds.items())]
    path.write_text("\n".join(lines) + "\n")


def main(argv=None):
    args = parse_args("figures", argv)
    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    client, daemon = connect(args.address)
    rows, seconds = [], {}
    try:
        for name in FIGURES:
            module = importlib.import_module(name)
            started = time.monotonic()
            print(f"== {name} ({'quick' if args.quick else 'full'})", flush=True)
            figure_rows = module.draw(client, out_dir, args.quick)
            seconds[name] = time.monotonic() - started
            print_rows(figure_rows)
            rows += figure_rows
    finally:
        client.close()
        if daemon:
            daemon.stop()
    write_csv(out_dir / "summary.csv", ["figure", "quantity", "paper", "ours", "note", "check", "verdict"],
              [[r.figure, r.quantity, r.paper, r.ours, r.note, r.check, r.verdict()] for r in rows])
    write_markdown(out_dir / "summary.md", rows, args.quick, seconds)
    print(f"\nall figures: {sum(seconds.values()):.0f} s; table in {out_dir / 'summary.md'}")
    failures = failed_checks(rows)
    for r in failures:
        print(f"FAILED: {r.figure} {r.quantity}: {r.ours} does not meet {r.check}", file=sys.stderr)
    return 1 if failures and args.strict else 0


if __name__ == "__main__":
    sys.exit(main())
