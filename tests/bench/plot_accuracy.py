#!/usr/bin/python3
"""Plot the accuracy report's CSV: error against wall time, log-log, one panel per problem and
one marker per method (collision x precision x lattice, and for the coupled array-drag problems
the particle spacing); the Pareto front of each panel is drawn as a step line. Problems absent
from the CSV (an older file, or a run with --problems) leave their panel empty. Debian's python3
with matplotlib (Agg backend: no display needed).

    /usr/bin/python3 tests/bench/plot_accuracy.py [accuracy.csv] [accuracy.png]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROBLEMS = [("shear_wave", "decaying shear wave (decay rate)"),
            ("poiseuille", "Poiseuille (L2 of the profile)"),
            ("disk_drag", "disk drag at Re = 1 (c_d vs Richardson)"),
            ("array_drag_2d", "coupled: square array of disks, D2Q9\n(F vs Sangani-Acrivos at a_cells)"),
            ("array_drag_3d", "coupled: cubic array of balls, D3Q19\n(F vs Hasimoto at a_cells)"),
            ("shear_rotation", "rotating disk in shear, D2Q9\n(rate vs gamma_dot / 2)"),
            ("jeffery", "rotating lattice ellipse 3b x b in shear, D2Q9\n(Jeffery period vs r = 3)")]
# The error levels each panel marks (the report's targets).
TARGETS = {"array_drag_2d": (0.1, 0.05, 0.02), "array_drag_3d": (0.1, 0.05, 0.02),
           "shear_rotation": (0.1, 0.03, 0.01), "jeffery": (0.3, 0.2, 0.1)}
# Colour by collision operator, marker shape by lattice (and spacing 1/2 for the arrays: a
# triangle), filled for double and hollow for float.
COLOURS = {"bgk": "tab:blue", "trt": "tab:orange", "regularized": "tab:green"}
MARKERS = {"D2Q9": "s", "D2Q7": "h", "D3Q19": "D"}
HALF_SPACING_MARKER = "^"


def read(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["error"] and float(r["error"]) > 0]
    for r in rows:
        r["error"], r["wall_s"] = float(r["error"]), max(float(r["wall_s"]), 1e-5)
        r["spacing"] = r.get("spacing") or ""  # only the array and rotation problems have one
    return rows


def marker(lattice, spacing):
    if spacing and float(spacing) != 1.0:
        return HALF_SPACING_MARKER
    return MARKERS.get(lattice, "o")


def label(collision, precision, lattice, spacing):
    return f"{collision}/{precision}/{lattice}" + (f"/s{float(spacing):g}" if spacing else "")


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
    columns = 3
    panels = (len(PROBLEMS) + columns - 1) // columns
    fig, grid = plt.subplots(panels, columns, figsize=(6 * columns, 5.2 * panels), squeeze=False)
    axes = [ax for row in grid for ax in row]
    for ax in axes[len(PROBLEMS):]:
        ax.axis("off")
    legend = {}
    for ax, (problem, title) in zip(axes, PROBLEMS):
        mine = [r for r in rows if r["problem"] == problem]
        methods = sorted({(r["collision"], r["precision"], r["lattice"], r["spacing"]) for r in mine})
        for collision, precision, lattice, spacing in methods:
            runs = sorted((r for r in mine if (r["collision"], r["precision"], r["lattice"], r["spacing"]) ==
                           (collision, precision, lattice, spacing)), key=lambda r: int(r["resolution"]))
            colour = COLOURS.get(collision, "gray")
            ax.plot([r["wall_s"] for r in runs], [r["error"] for r in runs], "-", color=colour, alpha=0.35, lw=1)
            name = label(collision, precision, lattice, spacing)
            line, = ax.plot([r["wall_s"] for r in runs], [r["error"] for r in runs], linestyle="none",
                            marker=marker(lattice, spacing), markersize=7, color=colour,
                            markerfacecolor=colour if precision == "double" else "none", label=name)
            legend.setdefault(name, line)
        front = pareto([(r["wall_s"], r["error"]) for r in mine])
        if front:
            line, = ax.step([t for t, _ in front], [e for _, e in front], where="post", color="black", lw=1.2,
                            ls="--", label="Pareto front")
            legend.setdefault("Pareto front", line)
        for target in TARGETS.get(problem, (0.1, 0.01, 0.001)):
            ax.axhline(target, color="gray", lw=0.6, ls=":")
        if not mine:
            ax.text(0.5, 0.5, "not in this CSV", transform=ax.transAxes, ha="center", color="gray")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time per run [s] (one core)")
        ax.set_ylabel("relative error")
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.3)
    # Every method of every panel once, in the empty last cell (or below the panels).
    spare = axes[len(PROBLEMS)] if len(axes) > len(PROBLEMS) else None
    if spare is not None:
        spare.legend(list(legend.values()), list(legend.keys()), loc="center", ncol=2, fontsize=7.5, frameon=False)
    else:
        fig.legend(list(legend.values()), list(legend.keys()), loc="lower center", ncol=7, fontsize=8, frameon=False)
    fig.suptitle("What accuracy costs: error against wall time (marker: lattice, triangle: particle spacing 1/2; "
                 "colour: collision; hollow: float)")
    fig.tight_layout(rect=(0, 0.0 if spare is not None else 0.08, 1, 0.96))
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
