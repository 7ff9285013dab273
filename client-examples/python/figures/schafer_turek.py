"""Schafer & Turek's cylinder in a channel (1996), through the daemon (issue 18): the cylinder an
anchored LB-solid disk, drag and lift read off what its anchors absorb.

The benchmark's geometry in units of the diameter D: a channel 22 D long and 4.1 D high between
no-slip walls, the cylinder's centre 2 D from the inlet and 2 D above the lower wall (0.05 D below
the middle: the lift comes from that); a parabolic inflow of peak U_m = 3/2 U_mean (velocity inlet),
a pressure outlet. Re = U_mean D / nu; C_d,l = 2 F_x,y / (rho U_mean^2 D) with F the force on the
anchors (BodyFrame.anchor_force); St = D / (U_mean T), T the period of the lift. D2Q9, TRT
(Lambda 3/16), the scenes of tests/bench/schafer_turek.cpp (lbsolid-schafer-turek, which measured
the same cases in process: docs/accuracy.md).

- 2D-1, Re 20, U_m 0.1: steady. Six flow-through times (22 D / U_mean), then the last step's drag
  and lift. Reference: Cd in [5.57, 5.59], Cl in [0.0104, 0.0110].
- 2D-2, Re 100, U_m 0.15: periodic shedding. Twelve flow-through times; over the second half, the
  largest drag and lift (frames every EVERY steps: a peak sampled 4 steps off within a period of
  about 670 steps reads low by under 2e-4 of the amplitude) and the period from the lift's upward
  zero crossings (interpolated). Reference: Cd_max [3.22, 3.24], Cl_max [0.99, 1.01],
  St [0.295, 0.305].

What to expect: the LB-solid disk is not a sharp wall (fluid slips through its outer layer), so it
takes a little less mean drag than a solid cylinder of diameter D: the model's value, not tuned.

Full: 2D-1 at D = 10, 20 and 40, 2D-2 at D = 20 (about 2 minutes). Quick: 2D-1 at D = 10
(about 5 s).

    /usr/bin/python3 client-examples/python/figures/schafer_turek.py [--quick] [--out DIR] [--address HOST:PORT]
"""
import math
from dataclasses import dataclass

import numpy as np
from google.protobuf import text_format

from figure_common import Row, run_figure, write_csv
from lbsolid_client import scenario_pb2

FIGURE = "schafer_turek"
EVERY = 4  # steps between the 2D-2 frames


@dataclass(frozen=True)
class Case:
    name: str
    reynolds: float
    peak: float       # U_m, lattice units: Mach 0.17 and 0.26 on D2Q9
    flow_throughs: float
    reference: dict   # quantity -> (low, high)


CASE_2D1 = Case("2D-1", 20, 0.1, 6, {"Cd": (5.57, 5.59), "Cl": (0.0104, 0.0110)})
CASE_2D2 = Case("2D-2", 100, 0.15, 12, {"Cd_max": (3.22, 3.24), "Cl_max": (0.99, 1.01), "St": (0.295, 0.305)})
FULL = ((CASE_2D1, 10), (CASE_2D1, 20), (CASE_2D1, 40), (CASE_2D2, 20))
QUICK = ((CASE_2D1, 10),)


@dataclass
class Result:
    case: Case
    d: int
    omega: float
    steps: int
    values: dict      # quantity -> measured
    history: np.ndarray = None  # (frames, 3): step, Cd, Cl (2D-2)


def mean_speed(case: Case) -> float:
    return 2.0 / 3.0 * case.peak


def omega_of(case: Case, d: int) -> float:
    return 1.0 / (3.0 * mean_speed(case) * d / case.reynolds + 0.5)


def channel(case: Case, d: int):
    text = f"""
name: "Schafer-Turek {case.name}, D {d}"
lattice: LATTICE_D2Q9
domain {{
  nx: {22 * d}  ny: {round(4.1 * d)}
  x_low {{ kind: WALL_KIND_VELOCITY_INLET inflow_speed: {case.peak!r} inflow_profile: INFLOW_PROFILE_PARABOLIC }}
  x_high {{ kind: WALL_KIND_PRESSURE_OUTLET }}
  y_low {{ kind: WALL_KIND_BOUNCE_BACK }}  y_high {{ kind: WALL_KIND_BOUNCE_BACK }}
}}
fluid {{ omega: {omega_of(case, d)!r} collision: COLLISION_TRT }}
stability {{ check_interval: 500 }}
bodies {{
  name: "cylinder"  shape: BODY_SHAPE_DISK  radius: {d / 2!r}
  centre {{ x: {2.0 * d - 0.5!r}  y: {2.0 * d - 0.5!r} }}
  anchored: true
}}
"""
    # the walls and the inlet stand half-way beyond the end nodes (-1/2): the centre 2 D from both
    return text_format.Parse(text, scenario_pb2.Scenario())


def coefficients(force, case: Case, d: int):
    scale = 2.0 / (mean_speed(case) ** 2 * d)  # rho0 = 1
    return force[0] * scale, force[1] * scale


def anchor_force(frame):
    body = next(b for b in frame.bodies if b.name == "cylinder")
    return frame.step, (body.anchor_force.x, body.anchor_force.y)


def measure(client, case: Case, d: int) -> Result:
    steps = int(case.flow_throughs * 22 * d / mean_speed(case))
    session = client.create(channel(case, d))
    try:
        if case.reynolds < 50:  # steady: the last step's force
            rec = session.run_and_record(steps, particles_every=steps, keep_particles=anchor_force, progress=False)
            cd, cl = coefficients(rec.particles[-1][1], case, d)
            return Result(case, d, omega_of(case, d), steps, {"Cd": cd, "Cl": cl})
        while session.get().step < steps // 2:  # the shedding settles (Step leaves it PAUSED, not DONE)
            session.step(min(10_000, steps // 2 - session.snapshot.step))  # Step takes at most 10000
        rec = session.run_and_record(steps - steps // 2, particles_every=EVERY, keep_particles=anchor_force,
                                     progress=False)
    finally:
        session.delete()
    history = np.array([(step, *coefficients(force, case, d)) for step, force in rec.particles])
    return Result(case, d, omega_of(case, d), steps,
                  {"Cd_max": float(history[:, 1].max()), "Cl_max": float(history[:, 2].max()),
                   "St": strouhal(history, case, d)}, history)


def strouhal(history, case: Case, d: int) -> float:
    """D / (U_mean T), T from the lift's upward zero crossings, linearly interpolated."""
    step, cl = history[:, 0], history[:, 2]
    up = np.nonzero((cl[:-1] < 0) & (cl[1:] >= 0))[0]
    crossings = step[up] + (step[up + 1] - step[up]) * (-cl[up]) / (cl[up + 1] - cl[up])
    if len(crossings) < 2:
        return math.nan
    period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    return d / (mean_speed(case) * period)


def plot(path, results):
    import matplotlib.pyplot as plt
    shedding = [r for r in results if r.history is not None]
    fig, axes = plt.subplots(1, 1 + len(shedding), figsize=(6 + 6 * len(shedding), 4.5), squeeze=False)
    a_cd = axes[0][0]
    steady = [r for r in results if r.case is CASE_2D1]
    a_cd.plot([r.d for r in steady], [r.values["Cd"] for r in steady], "o-", label="Cd, LB-solid disk")
    low, high = CASE_2D1.reference["Cd"]
    a_cd.axhspan(low, high, color="C1", alpha=0.3, label="reference interval")
    a_cd.set(xlabel="cells per diameter D", ylabel="Cd", title="(a) 2D-1, Re 20: drag against resolution")
    a_cd.grid(alpha=0.3)
    a_cd.legend(fontsize=8)
    for k, r in enumerate(shedding):
        ax = axes[0][1 + k]
        ax.plot(r.history[:, 0], r.history[:, 1], lw=1, label="Cd")
        ax.plot(r.history[:, 0], r.history[:, 2], lw=1, label="Cl")
        for q, color in (("Cd_max", "C0"), ("Cl_max", "C1")):
            ax.axhspan(*r.case.reference[q], color=color, alpha=0.3)
        ax.set(xlabel="step", title=f"(b) 2D-2, Re 100, D {r.d}: St {r.values['St']:.3f} "
                                    f"(reference {r.case.reference['St'][0]}-{r.case.reference['St'][1]})")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Schafer & Turek: the cylinder an anchored LB-solid disk (D2Q9, TRT, velocity inlet, "
                 "pressure outlet), through lbsolidd")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw(client, out_dir, quick):
    results = [measure(client, case, d) for case, d in (QUICK if quick else FULL)]
    write_csv(out_dir / f"{FIGURE}.csv", ["case", "D", "omega", "steps", "quantity", "measured", "reference_low",
                                           "reference_high"],
              [[r.case.name, r.d, r.omega, r.steps, q, v, *r.case.reference[q]] for r in results
               for q, v in r.values.items()])
    plot(out_dir / f"{FIGURE}.png", results)
    return rows_for(results)


def rows_for(results):
    rows = []
    for r in results:
        where = f"D {r.d}: {22 * r.d} x {round(4.1 * r.d)}, omega {r.omega:.3f}, {r.steps} steps"
        for q, v in r.values.items():
            low, high = r.case.reference[q]
            rows.append(Row("Schafer-Turek", f"{r.case.name} {q}", f"[{low:g}, {high:g}]", f"{v:.4g}", where))
    steady = [r for r in results if r.case is CASE_2D1]
    if len(steady) > 1:
        cd = [r.values["Cd"] for r in steady]
        rows.append(Row("Schafer-Turek", "2D-1 Cd converges with D", "(a sharp cylinder: in the interval)",
                        " -> ".join(f"{c:.4f}" for c in cd),
                        "the LB-solid disk is porous at its rim (fluid slips through its outer layer), so it "
                        "takes a little less drag than a sharp cylinder of diameter D (docs/accuracy.md)",
                        # refining must move the drag toward a limit, not away: the change shrinks
                        check="|Cd(D) - Cd(2D)| shrinks with D" if len(cd) > 2 else "",
                        passed=(abs(cd[-1] - cd[-2]) < abs(cd[-2] - cd[-3])) if len(cd) > 2 else None))
    for r in results:
        if r.case is CASE_2D2:
            low, high = r.case.reference["St"]
            st = r.values["St"]
            rows.append(Row("Schafer-Turek", f"2D-2 St at D {r.d}", f"[{low:g}, {high:g}]", f"{st:.4f}",
                            "the shedding frequency, set by the wake, is the quantity least sensitive to "
                            "the disk's porous rim",
                            # the benchmark's own interval: measured in process at 264f8a6 (0.297 at D 20)
                            check=f"in [{low:g}, {high:g}]", passed=low <= st <= high))
    return rows


if __name__ == "__main__":
    run_figure(draw, FIGURE)
