#!/usr/bin/python3
"""Plot the accuracy report's CSV: error against wall time, log-log, one panel per problem and
one marker per method (collision x precision x lattice); the Pareto front of each panel is drawn
as a step line. Debian's python3 with matplotlib (Agg backend: no display needed).

    /usr/bin/python3 tests/bench/plot_accuracy.py [accuracy.csv] [accuracy.png]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROBLEMS = [("shear_wave", "decaying shear wave (decay rate)"),
            ("poiseuille", "Poiseuille (L2 of the profile)"),
            ("disk_drag", "disk drag at Re = 1 (c_d vs Richardson)")]
# Colour by collision operator, marker shape by lattice, filled for double and hollow for float.
COLOURS = {"bgk": "tab:blue", "trt": "tab:orange", "regularized": "tab:green"}
MARKERS = {"D2Q9": "s", "D2Q7": "h"}


def read(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["error"] and float(r["error"]) > 0]
    for r in rows:
        r["error"], r["wall_s"] = float(r["error"]), max(float(r["wall_s"]), 1e-5)
    return rows


def pareto(points):
    front, best = [], float("inf")
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else "accuracy.csv"
    out = sys.argv[2] if len(sys.argv) > 2 else "accuracy.png"
    rows = read(src)
    fig, axes = plt.subplots(1, len(PROBLEMS), figsize=(6 * len(PROBLEMS), 5.2))
    for ax, (problem, title) in zip(axes, PROBLEMS):
        mine = [r for r in rows if r["problem"] == problem]
        methods = sorted({(r["collision"], r["precision"], r["lattice"]) for r in mine})
        for collision, precision, lattice in methods:
            runs = sorted((r for r in mine if (r["collision"], r["precision"], r["lattice"]) ==
                           (collision, precision, lattice)), key=lambda r: int(r["resolution"]))
            colour = COLOURS.get(collision, "gray")
            ax.plot([r["wall_s"] for r in runs], [r["error"] for r in runs], "-", color=colour, alpha=0.35, lw=1)
            ax.plot([r["wall_s"] for r in runs], [r["error"] for r in runs], linestyle="none",
                    marker=MARKERS.get(lattice, "o"), markersize=7, color=colour,
                    markerfacecolor=colour if precision == "double" else "none",
                    label=f"{collision}/{precision}/{lattice}")
        front = pareto([(r["wall_s"], r["error"]) for r in mine])
        if front:
            ax.step([t for t, _ in front], [e for _, e in front], where="post", color="black", lw=1.2,
                    ls="--", label="Pareto front")
        for target in (0.1, 0.01, 0.001):
            ax.axhline(target, color="gray", lw=0.6, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time per run [s] (one core)")
        ax.set_ylabel("relative error")
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=7, fontsize=8, frameon=False)
    fig.suptitle("What accuracy costs: error against wall time (marker: lattice; colour: collision; hollow: float)")
    fig.tight_layout(rect=(0, 0.08, 1, 0.96))
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
