"""The paper's Fig. 1: a square LB-solid sheet with an initial momentum bouncing in a closed box.

Set-up (client-examples/scenarios/fig1_bouncing_sheet.textproto, as tests/solid/wall_contact_test.cpp):
a 6 x 6 sheet in a 24 x 16 box with walls on all four sides (half-way between nodes, at -1/2 and
n - 1/2), no fluid, starting at (0.31, 0.17) per step. The wall contact force -(1 + e)(Psi.n) n stops
a particle at the wall; with restitution e = 1 the bounce is elastic. We record the body frame
every step and measure:
  - bounces: sign changes of a component of the mean velocity;
  - straightness: on each contact-free stretch (mean velocity unchanged step to step, as the test
    defines it) the largest distance of the centre of mass from the chord joining its ends;
  - the eq. 9 energy E = sum_k |f_k|^2 (conserved with e = 1) against the kinetic energy of the mean
    motion M |u|^2 / 2. For a rigidly moving sheet the two are equal; their difference is the
    energy held in the sheet's deformation (it rises during a bounce);
  - a second run with e = 0 (energy lost at every contact) for contrast.

    /usr/bin/python3 client-examples/python/figures/fig1_bouncing_sheet.py [--quick] [--out DIR] [--address HOST:PORT]
"""
from dataclasses import dataclass

import numpy as np

from figure_common import SCENARIOS, Row, load_scenario, run_figure, write_csv
from slip_lattice import walls

FIGURE = "fig1_bouncing_sheet"
FREE = 1e-14  # a step is contact-free when no mean velocity component changes by more (the test's bound)


@dataclass
class Path:
    step: np.ndarray      # (n,)
    com: np.ndarray       # (n, 2) centre of mass
    velocity: np.ndarray  # (n, 2) mean velocity
    energy: np.ndarray    # (n,) eq. 9
    kinetic: np.ndarray   # (n,) M |u|^2 / 2
    frames: list          # the recorded frames (particle positions for snapshots)


def bouncing_sheet(restitution: float):
    scenario = load_scenario(SCENARIOS / "fig1_bouncing_sheet.textproto")
    scenario.contact.restitution = restitution
    return scenario


def record(client, scenario, steps: int) -> Path:
    session = client.create(scenario)
    try:
        name = scenario.bodies[0].name
        frames = [f.bodies[name] for f in session.run_and_record(steps, particles_every=1, bodies=[name]).particles]
    finally:
        session.delete()
    velocity = np.array([b.mean_velocity[:2] for b in frames])
    return Path(np.arange(len(frames)), np.array([b.centre_of_mass[:2] for b in frames]), velocity,
                np.array([b.energy for b in frames]),
                np.array([0.5 * b.mass * v @ v for b, v in zip(frames, velocity)]), frames)


def bounces(path: Path) -> int:
    v = path.velocity
    return int(np.sum(v[1:] * v[:-1] < 0))


def free_stretches(path: Path):
    """[first, last] frame index of each maximal run of contact-free steps (at least 2 steps)."""
    free = np.all(np.abs(np.diff(path.velocity, axis=0)) < FREE, axis=1)  # step k+1 free
    stretches, start = [], None
    for k, is_free in enumerate(np.append(free, False)):
        if is_free and start is None:
            start = k
        elif not is_free and start is not None:
            if k - start >= 2:
                stretches.append((start, k))
            start = None
    return stretches


def deviation_from_chord(points: np.ndarray) -> float:
    """Largest distance of the points from the straight line through the first and the last."""
    chord = points[-1] - points[0]
    normal = np.array([-chord[1], chord[0]]) / np.linalg.norm(chord)
    return float(np.max(np.abs((points - points[0]) @ normal)))


def plot(path_file, scenario, elastic: Path, inelastic: Path, stretches):
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle
    fig, (ax, ax_e) = plt.subplots(1, 2, figsize=(14, 6), gridspec_kw={"width_ratios": [1.25, 1]})
    x0, x1, y0, y1 = walls(scenario)
    ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, lw=3, color="k"))
    ax.plot(elastic.com[:, 0], elastic.com[:, 1], "-", color="tab:red", lw=0.8, label="centre of mass (contact)")
    for i, (a, b) in enumerate(stretches):
        ax.plot(elastic.com[a:b + 1, 0], elastic.com[a:b + 1, 1], "-", color="tab:blue", lw=1.2,
                label="contact-free stretch" if i == 0 else None)
    squeezed = int(np.argmax(elastic.energy - elastic.kinetic))
    for k, style in ((0, "o"), (squeezed, "s")):
        p = elastic.frames[k].position
        ax.plot(p[:, 0], p[:, 1], style, ms=4, mfc="none", label=f"particles at step {k}")
    ax.set(aspect="equal", xlim=(x0 - 1, x1 + 1), ylim=(y0 - 1, y1 + 1), xlabel="x", ylabel="y",
           title=f"centre-of-mass path, e = 1, {len(elastic.step) - 1} steps")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
    ax_e.plot(elastic.step, elastic.energy, label="E = sum |f_k|^2 (eq. 9), e = 1")
    ax_e.plot(elastic.step, elastic.kinetic, lw=0.8, label="M |u|^2 / 2 (mean motion), e = 1")
    ax_e.plot(inelastic.step, inelastic.energy, label="E (eq. 9), e = 0")
    ax_e.set(xlabel="step", ylabel="energy", title="energy of the sheet", ylim=(0, None))
    ax_e.legend(fontsize=8)
    ax_e.grid(alpha=0.3)
    fig.suptitle("Fig. 1: an LB-solid sheet bouncing in a closed box (no fluid)")
    fig.tight_layout()
    fig.savefig(path_file, dpi=120, bbox_inches="tight")
    plt.close(fig)


def draw(client, out_dir, quick):
    steps = 600 if quick else 1500
    scenario = bouncing_sheet(1.0)
    elastic, inelastic = record(client, scenario, steps), record(client, bouncing_sheet(0.0), steps)
    stretches = free_stretches(elastic)
    free_steps = sum(b - a for a, b in stretches)
    worst = max(deviation_from_chord(elastic.com[a:b + 1]) for a, b in stretches)
    drift = np.max(np.abs(elastic.energy - elastic.energy[0])) / elastic.energy[0]
    squeezed = int(np.argmax(elastic.energy - elastic.kinetic))
    stored = (elastic.energy - elastic.kinetic)[squeezed] / elastic.energy[0]
    speeds = [np.linalg.norm(elastic.velocity[a]) for a, _ in stretches]
    write_csv(out_dir / f"{FIGURE}.csv",
              ["step", "com_x", "com_y", "u_x", "u_y", "energy", "kinetic", "energy_e0", "com_x_e0", "com_y_e0"],
              [[int(k), *map(float, elastic.com[k]), *map(float, elastic.velocity[k]), float(elastic.energy[k]),
                float(elastic.kinetic[k]), float(inelastic.energy[k]), *map(float, inelastic.com[k])]
               for k in range(len(elastic.step))])
    plot(out_dir / f"{FIGURE}.png", scenario, elastic, inelastic, stretches)
    return [
        Row("Fig. 1", "bounces (sign changes of u_x, u_y)", "keeps bouncing", f"{bounces(elastic)} in {steps} steps",
            f"{len(stretches)} contact-free stretches, {free_steps} free steps"),
        Row("Fig. 1", "COM distance from a straight line between contacts", "straight line (momentum conserved)",
            f"{worst:.1e}", "largest over all contact-free stretches (lattice units)",
            check="< 1e-9 (round-off: eq. 8 conserves momentum)", passed=worst < 1e-9),
        Row("Fig. 1", "relative drift of E = sum |f_k|^2, e = 1", "elastic bounce (no number given)", f"{drift:.1e}",
            f"max |E - E0| / E0 over {steps} steps",
            check="< 1e-10 (eq. 10: E is unchanged by an elastic contact)", passed=drift < 1e-10),
        Row("Fig. 1", "mean-motion energy M|u|^2/2 at the end, e = 1", "(not discussed)",
            f"{100 * elastic.kinetic[-1] / elastic.energy[-1]:.1f}% of E",
            "E is conserved, but each bounce leaves part of it in undamped internal vibration; "
            f"at the deepest compression (step {squeezed}) the deformation holds {100 * stored:.1f}% of E; "
            f"speed between contacts {min(speeds) / speeds[0]:.3f}..1 x initial"),
        Row("Fig. 1", "E after the run, e = 0", "(not in the paper)",
            f"{inelastic.energy[-1] / inelastic.energy[0]:.3f} x E0", f"{bounces(inelastic)} velocity sign changes"),
    ]


if __name__ == "__main__":
    run_figure(draw, FIGURE)
