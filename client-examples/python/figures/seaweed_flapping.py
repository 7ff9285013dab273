"""Seaweed flapping in a fast current (issue 18, beyond the paper): the seaweed figure's filament
(seaweed.py) at Reynolds numbers where the flow behind it no longer stays steady.

Set-up (built here): a D2Q9 channel 256 x 64, periodic in x between two bounce-back walls, TRT at
omega 1.8 (nu = 0.0185), driven by a body force g per node; a chain of 20 particles (spacing 1)
standing along y at x = 64, anchored at its bottom particle two nodes above the floor. For each
drive one run from rest; particle frames every EVERY steps. Over the second half of each run: the
tip's x (minus the anchor's), its mean (the deflection), half its range (the amplitude), its
period (upward crossings of the mean, with a hysteresis of a quarter of the range so that jitter
is not counted), and the mean flow speed <u> from the profiles; Re = <u> (L - 1) / nu, and the
Strouhal number St = f (L - 1) / <u> with f = 1 / period.

What to expect: at Re of order one (seaweed.py) the filament bends and settles. Faster, the wake
behind a bluff obstacle sheds (a cylinder's from Re near 47), and a filament with no bending
stiffness follows the shedding: it flaps, at a frequency set by the flow, f ~ St <u> / L with St a
number of order 0.1-0.2 that changes little with Re. Measured in process before this script: steady
at Re 44, flapping from Re 56 on, St 0.11 at Re 56-95; at g = 2.5e-5 (Re above 100) the flow's
start from rest overshoots Mach 0.5 and the monitor stops the run (the hard case
tests/hard_cases/flapping_filament_test.cpp runs the top drive here, g = 2e-5).

Full: g = 2.5e-6 .. 2e-5 (6 values), 100000 steps each (the channel's viscous time ny^2/(pi^2 nu)
is about 22000 steps, and near the onset the flapping takes tens of thousands of steps to grow),
frames every 10 steps: about a minute. Quick: g = 2e-5 (it flaps within 10000 steps), 20000
steps: about 3 s.

    /usr/bin/python3 client-examples/python/figures/seaweed_flapping.py [--quick] [--out DIR] [--address HOST:PORT]
"""
import math
from dataclasses import dataclass

import numpy as np
from google.protobuf import text_format

from figure_common import Row, run_figure, write_csv
from lbsolid_client import scenario_pb2

FIGURE = "seaweed_flapping"
NX, NY, LENGTH = 256, 64, 20
OMEGA = 1.8
NU = (1.0 / OMEGA - 0.5) / 3.0  # D2Q9: c_s^2 = 1/3
SOUND = math.sqrt(1.0 / 3.0)
BOTTOM_Y = 1.5
EVERY = 10          # steps between particle frames: a period is 1800 steps or more
PROFILE_EVERY = 500
FLAPPING = 0.05     # a tip whose half range is above this fraction of its deflection flaps
FULL = ((2.5e-6, 5e-6, 7.5e-6, 1e-5, 1.5e-5, 2e-5), 100_000)
QUICK = ((2e-5,), 20_000)


@dataclass
class Run:
    g: float
    steps: np.ndarray     # frame steps over the second half
    tip: np.ndarray       # tip x - anchor x there
    shapes: np.ndarray    # (frames, particles, 2) there
    speed: float          # <u_x>, channel mean over the second half's profiles
    top_speed: float      # largest row speed there
    deflection: float = 0.0
    amplitude: float = 0.0
    period: float = 0.0   # steps; 0: no oscillation found

    @property
    def flaps(self) -> bool:
        return self.amplitude > FLAPPING * abs(self.deflection) and self.period > 0

    @property
    def reynolds(self) -> float:
        return self.speed * (LENGTH - 1) / NU

    @property
    def strouhal(self) -> float:
        return (LENGTH - 1) / (self.period * self.speed) if self.period else math.nan


def channel(g: float):
    text = f"""
name: "seaweed flapping, g {g:g}"
lattice: LATTICE_D2Q9
domain {{
  nx: {NX}  ny: {NY}
  x_low {{ kind: WALL_KIND_PERIODIC }}  x_high {{ kind: WALL_KIND_PERIODIC }}
  y_low {{ kind: WALL_KIND_BOUNCE_BACK }}  y_high {{ kind: WALL_KIND_BOUNCE_BACK }}
}}
fluid {{ omega: {OMEGA} collision: COLLISION_TRT body_force {{ x: {g!r} }} }}
bodies {{
  name: "weed"  shape: BODY_SHAPE_CHAIN  length: {LENGTH}  axis: AXIS_Y
  centre {{ x: {NX / 4!r}  y: {BOTTOM_Y + (LENGTH - 1) / 2!r} }}
  anchor_labels {{ i: 0 j: 0 k: 0 }}
}}
"""
    return text_format.Parse(text, scenario_pb2.Scenario())


def shape_only(frame):
    body = next(b for b in frame.bodies if b.name == "weed")
    return frame.step, np.array(body.position, dtype=np.float64).reshape(-1, 3)[:, :2]


def period_of(signal: np.ndarray, every: int) -> float:
    """Mean steps between upward crossings of the mean, counting one only after the signal went a
    quarter of its range below the mean (hysteresis); 0 with fewer than two."""
    mean, quarter = signal.mean(), np.ptp(signal) / 4
    crossings, armed = [], False
    for k in range(1, len(signal)):
        if signal[k] < mean - quarter:
            armed = True
        elif armed and signal[k - 1] < mean <= signal[k]:
            crossings.append(k)
            armed = False
    if len(crossings) < 2:
        return 0.0
    return (crossings[-1] - crossings[0]) / (len(crossings) - 1) * every


def flap(client, g: float, steps: int) -> Run:
    session = client.create(channel(g))
    try:
        rec = session.run_and_record(steps, profiles_every=PROFILE_EVERY, particles_every=EVERY,
                                     bodies=["weed"], keep_particles=shape_only, progress=False)
    finally:
        session.delete()
    late = [(step, shape) for step, shape in rec.particles if step >= steps // 2]
    frame_steps = np.array([step for step, _ in late])
    shapes = np.stack([shape for _, shape in late])
    order = np.argsort(shapes[0][:, 1])  # bottom (the anchor) first
    shapes = shapes[:, order]
    tip = shapes[:, -1, 0] - shapes[:, 0, 0]
    profiles = [p for p in rec.profiles if p.step >= steps // 2]
    run = Run(g, frame_steps, tip, shapes, float(np.mean([p.u_x.mean() for p in profiles])),
              float(max(p.u_x.max() for p in profiles)))
    run.deflection = float(tip.mean())
    run.amplitude = float(np.ptp(tip)) / 2
    run.period = period_of(tip, EVERY)
    return run


def plot(path, runs):
    import matplotlib.pyplot as plt
    fig, ((a_tip, a_freq), (a_strip, a_amp)) = plt.subplots(2, 2, figsize=(13, 9))
    for k, r in enumerate(runs):
        a_tip.plot(r.steps, r.tip, lw=1, color=f"C{k}", label=f"g {r.g:.2g}: Re {r.reynolds:.0f}")
    a_tip.set(xlabel="step", ylabel="tip x - anchor x", title="(a) tip over the second half of each run")

    flapping = [r for r in runs if r.flaps]
    if flapping:
        u = np.array([r.speed for r in flapping])
        f = np.array([1 / r.period for r in flapping])
        a_freq.plot(u, f, "o", label="measured (flapping runs)")
        st = float(np.mean([r.strouhal for r in flapping]))
        grid = np.linspace(0, u.max() * 1.1, 20)
        a_freq.plot(grid, st * grid / (LENGTH - 1), "--", color="gray", label=f"f = St <u> / (L - 1), St {st:.3f}")
    a_freq.set(xlabel="mean flow speed <u_x>", ylabel="flapping frequency (1/steps)",
               title="(b) frequency against speed")

    top = runs[-1]
    if top.flaps:  # one period of the fastest run, eight frames
        per_frame = max(1, int(round(top.period / EVERY / 8)))
        for k in range(8):
            shape = top.shapes[-1 - (7 - k) * per_frame]
            a_strip.plot(shape[:, 0] - shape[0, 0] + 8 * k, shape[:, 1], "o-", ms=2, color=plt.cm.viridis(k / 7))
        a_strip.set_title(f"(c) g {top.g:.2g}: the filament over one period ({top.period:.0f} steps), "
                          "frames side by side (8 nodes apart)", fontsize=9)
    else:
        a_strip.plot(top.shapes[-1][:, 0] - top.shapes[-1][0, 0], top.shapes[-1][:, 1], "o-", ms=2)
        a_strip.set_title(f"(c) g {top.g:.2g}: final shape (no flapping)", fontsize=9)
    a_strip.axhline(-0.5, color="k", lw=2)
    a_strip.set(xlabel="x - x_anchor (+ 8 per frame)", ylabel="y")
    a_strip.set_aspect("equal")

    a_amp.plot([r.reynolds for r in runs], [r.amplitude for r in runs], "o-", label="half range of the tip's x")
    a_amp.plot([r.reynolds for r in runs], [r.deflection for r in runs], "s--", label="mean deflection")
    a_amp.set(xlabel="Re = <u> (L - 1) / nu", ylabel="nodes", title="(d) deflection and flapping amplitude")
    for ax in (a_tip, a_freq, a_amp):
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    fig.suptitle(f"Seaweed flapping: a chain of {LENGTH} anchored on the floor of a D2Q9 channel {NX} x {NY}, "
                 f"TRT omega {OMEGA}, through lbsolidd")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw(client, out_dir, quick):
    drives, steps = QUICK if quick else FULL
    runs = [flap(client, g, steps) for g in drives]
    write_csv(out_dir / f"{FIGURE}.csv", ["g", "mean_speed", "reynolds", "deflection", "amplitude", "period_steps",
                                           "strouhal", "flaps", "steps"],
              [[r.g, r.speed, r.reynolds, r.deflection, r.amplitude, r.period, r.strouhal, r.flaps, steps]
               for r in runs])
    plot(out_dir / f"{FIGURE}.png", runs)
    return rows_for(runs, steps)


def rows_for(runs, steps):
    flapping = [r for r in runs if r.flaps]
    steady = [r for r in runs if not r.flaps]
    mach = max(r.top_speed for r in runs) / SOUND
    where = f"D2Q9 {NX}x{NY}, TRT omega {OMEGA}, chain of {LENGTH}, {steps} steps per drive, Mach <= {mach:.2f}"
    rows = [Row("Seaweed flapping", "steady up to / flapping from (Re)", "(issue 18: flaps at higher speeds)",
                f"{max((r.reynolds for r in steady), default=math.nan):.0f} / "
                f"{min((r.reynolds for r in flapping), default=math.nan):.0f}",
                where + f"; flapping: tip half range above {FLAPPING:.0%} of its deflection")]
    if flapping:
        f = [1 / r.period for r in flapping]
        rows.append(Row("Seaweed flapping", "frequency against speed", "(not given)",
                        ", ".join(f"Re {r.reynolds:.0f}: {1 / r.period:.3g}" for r in flapping),
                        "St = f (L - 1) / <u>: " + ", ".join(f"{r.strouhal:.3f}" for r in flapping),
                        # a frequency set by the flow grows with it
                        check="grows strictly with <u>" if len(f) > 1 else "",
                        passed=all(b > a for a, b in zip(f, f[1:])) if len(f) > 1 else None))
    return rows


if __name__ == "__main__":
    run_figure(draw, FIGURE)
