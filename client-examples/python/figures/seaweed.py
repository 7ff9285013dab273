"""Seaweed in a current (issue 18, beyond the paper): a flexible filament anchored at the floor of a channel.

Set-up (built here, no scenario file): a D2Q9 channel periodic in x between two bounce-back walls
(half-way: at y = -0.5 and y = ny - 0.5), fluid omega 1 (nu = 1/6), driven by a body force g per node
along x. A chain of L particles (spacing 1) stands along y at x = nx/4, its lowest particle at
y = 1.5, two nodes above the floor; only that particle is anchored (`anchor_labels {i: 0 j: 0 k: 0}`:
the chain's labels run (0,0,0), (0,1,0), ... upwards, and the first particle of each frame is the
one that stays put, checked below). The anchor holds it where it was placed while it still exchanges
momentum with the fluid, and reports what it absorbed each step (`anchor_force`): at steady state the
drag of the flow on the whole filament, handed down the chain.

For each drive (a decade, log-spaced) one run from rest to steady state; particle frames every
EVERY steps, velocity profiles every PROFILE_EVERY. Measured over the last quarter of each run
(means): the tip deflection (x of the top particle minus x of the bottom one), the mean flow speed
(u_x averaged over the channel, from the profiles), the anchor force; and there the tip's oscillation
(half its range in x) and its drift (a run is steady when the range is under 1% of the deflection).

What to expect from the model: the paper's springs keep their orientation (no `rotation`), so the
chain resists a transverse displacement of each link like a shear spring of unit stiffness (the
static test of docs/internals.md: each link deforms by the load it carries). The tip deflection is
then the sum over the links of the drag each carries, linear in the loads; the flow is at Reynolds
numbers of order one, so drag and deflection grow about linearly with the drive, a little faster at
the top through inertia. Neither the chain (no bending stiffness, and no elastic instability in
linear springs) nor the flow (Re ~ 1, far below vortex shedding) should flap. What is left at the end
is a lattice effect: a particle that comes to rest on a cell boundary (half-integer x) changes its
nearest node back and forth, a limit cycle of a few steps (at the top drive of the full run: particle
2, a 6-step cycle, the anchor force swinging by 2% and the tip by 1e-4). That is why frames are taken
every step and the force and deflection averaged over the last quarter: frames every 10 steps caught
only three phases of that cycle and put the force 1% high.

Full: 64 x 32 nodes, L = 12, g = 3e-5 .. 3e-4 (4 values), 12000 steps (the channel's viscous time
ny^2 / (pi^2 nu) is about 620 steps; the chain settles with its fluid): about 7 s, mostly the
streamed frames (the runs themselves take a fraction of a second). Quick: 32 x 16, L = 8, g = 2e-5
and 2e-4, 3000 steps (viscous time 160 steps): about 2 s.

    /usr/bin/python3 client-examples/python/figures/seaweed.py [--quick] [--out DIR] [--address HOST:PORT]
"""
import math
from dataclasses import dataclass

import numpy as np
from google.protobuf import text_format

from figure_common import Row, run_figure, write_csv
from lbsolid_client import scenario_pb2

FIGURE = "seaweed"
OMEGA = 1.0
NU = (1.0 / OMEGA - 0.5) / 3.0  # D2Q9: c_s^2 = 1/3
SOUND = math.sqrt(1.0 / 3.0)
BOTTOM_Y = 1.5        # the anchored particle, two nodes above the half-way floor at -0.5
STEADY = 0.01         # range of the tip deflection over the last quarter, relative: "steady" below this
FLAP = 0.01           # a tip x oscillation above this fraction of the deflection would be called flapping
ANCHOR_HELD = 1e-12   # how far the anchored particle may move (it is held exactly, MODEL.md section 5)
EVERY = 1             # a particle frame every step: the anchor force can cycle with a period of a few
                      # steps (a particle on a node boundary, below), which a coarser sampling aliases
PROFILE_EVERY = 100
MAX_PERIOD = 500      # longest cycle looked for in the last quarter (steps)


@dataclass
class Setup:
    nx: int
    ny: int
    length: int     # particles in the filament
    steps: int
    drives: tuple   # body force per node, along x


FULL = Setup(64, 32, 12, 12_000, tuple(3e-5 * 10 ** (k / 3) for k in range(4)))
QUICK = Setup(32, 16, 8, 3_000, (2e-5, 2e-4))


@dataclass
class Sway:
    g: float
    steps: np.ndarray        # of the particle frames
    tip: np.ndarray          # tip x minus bottom x, per frame
    shape: np.ndarray        # final positions (particles, 3), bottom first
    placed: np.ndarray       # the first frame's positions (the rest shape as placed)
    anchor_moved: float      # largest displacement of the anchored particle over the frames
    y_range: tuple           # lowest and highest particle y over all frames
    force: np.ndarray        # anchor force (frames, 3)
    speed: float = 0.0       # u_x averaged over the channel (last quarter of the profiles)
    top_speed: float = 0.0   # largest row speed (x-averaged), for the Mach number
    deflection: float = 0.0  # tip deflection, mean over the last quarter
    anchor_force: np.ndarray = None  # (3,) mean over the last quarter
    swing: float = 0.0       # range of the anchor force x over the last quarter / its mean
    overshoot: float = 0.0   # largest tip deflection of the run / the steady one, less 1
    period: int = 0          # the last quarter's tip and force repeat with this period (steps); 0: none found
    hopper: int = -1         # the particle that moves most over the last quarter (bottom first)
    hop_range: float = 0.0   # its range in x there
    boundary: float = 0.0    # its mean x distance from the nearest cell boundary (half-integer x)
    lift: float = 0.0        # final tip y minus its placed y (the chain stretches or shrinks)
    flap: float = 0.0        # half the range of the tip's x over the last quarter
    drift: float = 0.0       # range of the tip deflection over the last quarter / |deflection|


def channel(setup: Setup, g: float):
    text = f"""
name: "seaweed: a filament anchored at the floor, g {g:g}"
lattice: LATTICE_D2Q9
domain {{
  nx: {setup.nx}  ny: {setup.ny}
  x_low {{ kind: WALL_KIND_PERIODIC }}  x_high {{ kind: WALL_KIND_PERIODIC }}
  y_low {{ kind: WALL_KIND_BOUNCE_BACK }}  y_high {{ kind: WALL_KIND_BOUNCE_BACK }}
}}
fluid {{ omega: {OMEGA} body_force {{ x: {g!r} }} }}
bodies {{
  name: "weed"  shape: BODY_SHAPE_CHAIN  length: {setup.length}  axis: AXIS_Y
  centre {{ x: {setup.nx / 4!r}  y: {BOTTOM_Y + (setup.length - 1) / 2!r} }}
  anchor_labels {{ i: 0 j: 0 k: 0 }}
}}
"""
    return text_format.Parse(text, scenario_pb2.Scenario())


def free_speed(setup: Setup, g: float) -> float:
    """Mean speed of the filament-free Poiseuille flow between half-way walls ny apart: g ny^2 / (12 nu)."""
    return g * setup.ny ** 2 / (12 * NU)


def sway(client, setup: Setup, g: float) -> Sway:
    session = client.create(channel(setup, g))
    try:
        rec = session.run_and_record(setup.steps, profiles_every=PROFILE_EVERY, particles_every=EVERY,
                                     bodies=["weed"], progress=False)
    finally:
        session.delete()
    steps, pos = rec.trajectory("weed")           # (frames, particles, 3)
    placed = pos[0]
    # the bottom (anchored) particle is the lowest as placed, the tip the highest
    bottom, top = int(np.argmin(placed[:, 1])), int(np.argmax(placed[:, 1]))
    order = np.argsort(placed[:, 1])
    s = Sway(g, steps, pos[:, top, 0] - pos[:, bottom, 0], pos[-1][order], placed[order],
             float(np.max(np.linalg.norm(pos[:, bottom] - placed[bottom], axis=1))),
             (float(pos[:, :, 1].min()), float(pos[:, :, 1].max())),
             np.array([f.bodies["weed"].anchor_force for f in rec.particles]))
    if bottom != 0:  # the labels run upwards from (0,0,0): the anchor must be the first particle
        s.anchor_moved = math.inf
    late = [p for p in rec.profiles if p.step >= 0.75 * setup.steps]
    s.speed = float(np.mean([p.u_x.mean() for p in late]))
    s.top_speed = float(max(p.u_x.max() for p in late))
    last = steps >= 0.75 * setup.steps
    s.deflection = float(s.tip[last].mean())
    s.anchor_force = s.force[last].mean(axis=0)
    s.swing = float(np.ptp(s.force[last, 0]) / s.anchor_force[0])
    s.overshoot = float(s.tip.max() / s.deflection - 1)
    s.lift = float(pos[last, top, 1].mean() - placed[top, 1])
    tip_x = pos[last, top, 0]
    s.flap = float(np.ptp(tip_x)) / 2
    s.drift = float(np.ptp(s.tip[last])) / abs(s.deflection)
    s.period = cycle(np.column_stack([s.tip[last], s.force[last, 0]]))
    moving = np.ptp(pos[last][:, order, 0], axis=0)
    s.hopper = int(np.argmax(moving))
    s.hop_range = float(moving[s.hopper])
    x = pos[last][:, order[s.hopper], 0]
    s.boundary = float(np.mean(np.abs(x - np.floor(x) - 0.5)))
    return s


def cycle(series: np.ndarray) -> int:
    """The shortest period (steps) with which every column of `series` repeats to 1e-6 of its range
    (a limit cycle; a decaying transient or round-off noise does not), 0 if none up to MAX_PERIOD or
    if nothing moves (ranges under 1e-12 of the values)."""
    scale = np.ptp(series, axis=0)
    if np.all(scale <= 1e-12 * np.abs(series).max(axis=0)):
        return 0
    for p in range(1, min(MAX_PERIOD, len(series) // 3) + 1):
        if np.all(np.abs(series[p:] - series[:-p]).max(axis=0) <= 1e-6 * scale):
            return p * EVERY
    return 0


def plot(path, setup, sways):
    import matplotlib.pyplot as plt
    fig, ((a_def, a_shape), (a_force, a_tip)) = plt.subplots(2, 2, figsize=(12, 9))
    u = np.array([s.speed for s in sways])
    d = np.array([s.deflection for s in sways])
    a_def.plot(u, d, "o-", label="measured (mean of the last quarter)")
    grid = np.linspace(0, u.max() * 1.05, 50)
    a_def.plot(grid, d[0] / u[0] * grid, "--", color="gray", label="linear from the lowest drive")
    a_def.set(xlabel="mean flow speed <u_x> (channel average)", ylabel="tip deflection x_tip - x_bottom",
              title="(a) tip deflection against flow speed")

    for k, s in enumerate(sways):
        x0 = s.placed[0, 0]
        a_shape.plot(s.shape[:, 0] - x0, s.shape[:, 1], "o-", ms=4, color=f"C{k}", label=f"g {s.g:.2g}")
    a_shape.plot(np.zeros(setup.length), sways[0].placed[:, 1], ":", color="k", lw=1, label="as placed")
    a_shape.plot([0], [sways[0].placed[0, 1]], "s", color="k", ms=8, mfc="none", label="anchor")
    for y in (-0.5, setup.ny - 0.5):
        a_shape.axhline(y, color="k", lw=2)
    a_shape.set_ylim(-1, setup.ny)
    a_shape.set(xlabel="x - x_anchor (not to scale with y)", ylabel="y",
                title="(b) filament shapes at steady state (walls: thick lines)")

    g = np.array([s.g for s in sways])
    f = np.array([s.anchor_force[0] for s in sways])
    a_force.loglog(g, f, "o-", label="anchor force x (measured)")
    a_force.loglog(g, f[0] / g[0] * g, "--", color="gray", label="proportional to g")
    a_force.loglog(g, g * setup.nx * setup.ny, ":", color="k", label="whole drive g nx ny")
    a_force.set(xlabel="drive g (per node)", ylabel="force", title="(c) anchor force against drive")

    for k, s in enumerate(sways):
        a_tip.plot(s.steps, s.tip / s.deflection, "-", color=f"C{k}", lw=1,
                   label=f"g {s.g:.2g}: half-range {s.flap:.1e} (last quarter)")
    a_tip.axvspan(0.75 * setup.steps, setup.steps, color="gray", alpha=0.15)
    a_tip.set(xlabel="step", ylabel="tip deflection / final", title="(d) approach to steady state (shaded: averaged)")

    for ax in (a_def, a_shape, a_force, a_tip):
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.suptitle(f"Seaweed: a chain of {setup.length} anchored at its bottom particle, D2Q9 channel "
                 f"{setup.nx} x {setup.ny}, omega {OMEGA:g}, {setup.steps} steps per drive")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_tables(out_dir, setup, sways):
    write_csv(out_dir / f"{FIGURE}.csv",
              ["g", "mean_speed", "free_poiseuille_speed", "tip_deflection", "tip_lift", "anchor_force_x",
               "anchor_force_y", "drive_total", "flap_half_range", "tip_drift_last_quarter", "reynolds_L", "steps",
               "nx", "ny", "length"],
              [[s.g, s.speed, free_speed(setup, s.g), s.deflection, s.lift, float(s.anchor_force[0]),
                float(s.anchor_force[1]), s.g * setup.nx * setup.ny, s.flap, s.drift,
                s.speed * (setup.length - 1) / NU, setup.steps, setup.nx, setup.ny, setup.length] for s in sways])
    write_csv(out_dir / f"{FIGURE}_shapes.csv", ["g", "particle", "x", "y"],
              [[s.g, k, float(p[0]), float(p[1])] for s in sways for k, p in enumerate(s.shape)])


def draw(client, out_dir, quick):
    setup = QUICK if quick else FULL
    sways = [sway(client, setup, g) for g in setup.drives]  # one after another: each takes well under a second
    write_tables(out_dir, setup, sways)
    plot(out_dir / f"{FIGURE}.png", setup, sways)
    return rows_for(setup, sways)


def increasing(values) -> bool:
    return all(b > a for a, b in zip(values, values[1:]))


def flapping_note(setup, sways, by_g):
    """What the tip does at the end of each run, in words: the measured row has no bound."""
    flapping = [s for s in sways if s.flap > FLAP * abs(s.deflection)]
    cycles = [s for s in sways if s.period]
    words = ("by drive " + by_g([s.flap for s in sways], "{:.1e}") + f" over the last {setup.steps // 4} steps "
             f"(frames every {EVERY}); "
             + (f"above {FLAP:.0%} of the deflection (flapping?) at " + ", ".join(f"g {s.g:.2g}" for s in flapping)
                if flapping else f"under {FLAP:.0%} of the deflection at every drive: no flapping"))
    for s in cycles:
        words += (f". At g {s.g:.2g} the residual motion is a {s.period}-step limit cycle (anchor force range "
                  f"{s.swing:.1%} of its mean): particle {s.hopper} (0 = anchor) moves most, by {s.hop_range:.1e} "
                  f"in x, {s.boundary:.1e} from a cell boundary (half-integer x), so its nearest node (the "
                  "exchange's coupling) flips back and forth: a lattice effect, not a flapping of the filament")
    still = [s for s in sways if not s.period]
    if still:
        words += (". No cycle at " + ", ".join(f"g {s.g:.2g}" for s in still) + " (the transient has decayed)")
    reynolds = sways[-1].speed * (setup.length - 1) / NU
    return (words + "; largest tip deflection of each run over the steady one, less 1: "
            + by_g([s.overshoot for s in sways], "{:.1e}") + "; tip lift (y) " + by_g([s.lift for s in sways], "{:.2g}")
            + ". The chain has no bending stiffness (only the shear-like stiffness of springs that keep their "
            f"orientation) and the flow is at Re <= {reynolds:.2g}")


def rows_for(setup, sways):
    n = setup.length - 1  # links between the anchor and the tip
    g = [s.g for s in sways]
    d = [s.deflection for s in sways]
    f = [float(s.anchor_force[0]) for s in sways]
    lever = [s.deflection / float(s.anchor_force[0]) for s in sways]
    where = (f"D2Q9 {setup.nx}x{setup.ny}, omega {OMEGA:g}, chain of {setup.length} anchored at y {BOTTOM_Y}, "
             f"g {g[0]:.2g}..{g[-1]:.2g} ({len(g)} values), {setup.steps} steps each")
    lo, hi = min(s.y_range[0] for s in sways), max(s.y_range[1] for s in sways)
    worst_drift = max(s.drift for s in sways)
    moved = max(s.anchor_moved for s in sways)
    mach = max(s.top_speed for s in sways) / SOUND
    blocked = [s.speed / free_speed(setup, s.g) for s in sways]
    share = [fx / (s.g * setup.nx * setup.ny) for fx, s in zip(f, sways)]

    def by_g(values, fmt):
        return ", ".join(f"g {x:.2g}: {fmt.format(v)}" for x, v in zip(g, values))

    return [
        Row("Seaweed", "tip deflection against drive", "(issue 18: not given)", by_g(d, "{:.4g}"),
            f"{where}; mean speed " + by_g([s.speed for s in sways], "{:.3g}") + "; deflection / speed "
            f"{d[-1] / sways[-1].speed / (d[0] / sways[0].speed):.3f} x that at the lowest drive (inertia: "
            f"Re = <u> (L-1)/nu up to {sways[-1].speed * n / NU:.2g})",
            # more current pushes harder on every particle (all downstream), and the vector springs answer
            # linearly: anything but a strictly growing deflection means the anchor or the drive is wrong
            check="grows strictly with g", passed=increasing(d)),
        Row("Seaweed", "anchor force x against drive", "(not given)", by_g(f, "{:.4g}"),
            "mean over the last quarter (every step); its range there / mean "
            + by_g([s.swing for s in sways], "{:.1e}")
            + "; share of the whole drive g nx ny the filament takes (the walls take the rest): "
            + by_g(share, "{:.3f}") + "; lift (force y) " + by_g([float(s.anchor_force[1]) for s in sways], "{:.2g}"),
            # the same argument for the force the anchor absorbs: the drag on the filament grows with the flow
            check="grows strictly with g", passed=increasing(f)),
        Row("Seaweed", "particles between the walls", "stay in the channel", f"y {lo:.3f} .. {hi:.3f}",
            f"all frames of all runs; nodes 0..{setup.ny - 1}, half-way walls at -0.5 and {setup.ny - 0.5}",
            # the filament must neither sink through the floor nor reach the ceiling: node rows 0..ny-1
            check=f"0 < y < {setup.ny - 1}", passed=0 < lo and hi < setup.ny - 1),
        Row("Seaweed", "anchored bottom particle: largest displacement", "held where placed", f"{moved:.2g}",
            "the particle of label (0,0,0), the lowest as placed and the first of each frame",
            # an anchor is infinite mass at rest: its position is kept exactly (round-off at most)
            check=f"< {ANCHOR_HELD:g}", passed=moved < ANCHOR_HELD),
        Row("Seaweed", "steady state: tip drift over the last quarter", "steady", f"{worst_drift:.2g}",
            "range of the tip deflection over the last quarter / its mean there, worst run; by drive "
            + by_g([s.drift for s in sways], "{:.1e}"),
            # the brief's criterion: the tip moves by under 1% over the last part of the run
            check=f"< {STEADY:g}", passed=worst_drift < STEADY),
        Row("Seaweed", "tip deflection / anchor force (links)", "(not given)", by_g(lever, "{:.3f}"),
            f"statics (docs/internals.md, anchored chain): each link deforms by the load it carries, so the tip "
            f"moves by sum_k k f_k over the free particles k = 1..{n} while the anchor absorbs sum_k f_k (its own "
            f"node's drag too): the load's mean lever arm; uniform drag on all {setup.length} particles gives "
            f"{n / 2:g}, drag all at the tip {n}",
            # with every particle pushed downstream the lever arm lies between 0 and the n links to the tip
            check=f"0 < ratio <= {n}", passed=all(0 < r <= n for r in lever)),
        Row("Seaweed", "flapping: tip x half-range, last quarter", "(not expected: see note)",
            f"{max(s.flap for s in sways):.2g} (largest)", flapping_note(setup, sways, by_g)),
        Row("Seaweed", "mean speed / filament-free Poiseuille", "(not given)", by_g(blocked, "{:.3f}"),
            f"free: g ny^2/(12 nu); Mach (x-averaged row speed / c_s) <= {mach:.2f}; the channel is periodic "
            f"in x, so the filament meets its own wake after {setup.nx} nodes"),
    ]


if __name__ == "__main__":
    run_figure(draw, FIGURE)
