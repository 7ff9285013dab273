"""Fracture on impact (issue 18, beyond the paper): LB solids whose links break hit a wall.

No fluid: a body moves at speed v toward the x_low wall of a closed box (contact, restitution 1),
its links breaking when the force they carry passes T (`fracture { max_force: T }`). The force a
link carries is its eq.-11 extension (a vector spring of stiffness 1). What the wave rule predicts:

- A chain (interior particles of mass M = 1): the front particle is stopped, and every step the
  compression front stops one more particle moving at v, so the link behind the front carries the
  momentum flux M v = v. It breaks for v > T and stays whole below.
- A sheet: bulk particles weigh M = 2 (four links), so the flux per row approaches 2 v; the edge
  rows (M = 3/2) lower it a little. It cannot exceed 2 v, so nothing breaks for v < T / 2, and
  the sheet breaks a little above T / 2 (measured in-process for 6 rows: the largest link force
  is 1.92 v).

(a) scans v / T for both and counts the broken links after the impact; (b) is a strip of frames of
a sheet hitting the wall at 3 T: the compression wave that runs back from the wall breaks links
as it goes, and the sheet shatters into pieces (many of them single particles, shed: out of the
dynamics where they broke free, what they held booked with the body). Every frame also checks the masses: each break takes 1/2 from each end,
so the body's mass is its placed mass less the number of broken links, exactly.

Full: chain of 10, sheet 10 x 6, 11 speeds, strip of a 16 x 8 sheet; about 10 s. Quick: 5 speeds.

    /usr/bin/python3 client-examples/python/figures/fracture.py [--quick] [--out DIR] [--address HOST:PORT]
"""
from dataclasses import dataclass

import numpy as np
from google.protobuf import text_format

from figure_common import Row, run_figure, write_csv
from lbsolid_client import scenario_pb2

FIGURE = "fracture"
THRESHOLD = 1e-2   # T, the links' max_force
GAP = 0.5          # the front particle starts at x = 1 + GAP, 1.5 + GAP from the wall at x = -1/2
FULL_SPEEDS = (0.3, 0.45, 0.49, 0.55, 0.6, 0.8, 0.98, 1.02, 1.2, 1.5, 2.0)
QUICK_SPEEDS = (0.45, 0.6, 0.98, 1.02, 2.0)
STRIP_SPEED = 3.0  # v / T of the strip of frames: measured, a 16 x 8 sheet shatters from 2.5 T on
STRIP_SIZE = (16, 8)


@dataclass
class Impact:
    shape: str        # "chain" or "sheet"
    ratio: float      # v / T
    broken: int       # links broken when the run ends
    first_step: int   # the step of the first break (0: none)
    mass_error: float  # largest |mass - (placed mass - broken count)| over the frames
    frames: list = None


def scenario(width: int, height: int, speed: float):
    """A width x height body (height 1: a chain along x) moving at -speed toward the x_low wall."""
    shape = (f"shape: BODY_SHAPE_CHAIN length: {width}" if height == 1
             else f"shape: BODY_SHAPE_RECTANGLE size: [{width}, {height}]")
    ny = height + 8
    text = f"""
name: "fracture on impact, v {speed:g}"
lattice: LATTICE_D2Q9
domain {{
  nx: {4 * width}  ny: {ny}
  x_low {{ kind: WALL_KIND_BOUNCE_BACK }}  x_high {{ kind: WALL_KIND_BOUNCE_BACK }}
  y_low {{ kind: WALL_KIND_BOUNCE_BACK }}  y_high {{ kind: WALL_KIND_BOUNCE_BACK }}
}}
fluid {{ enabled: false }}
bodies {{
  name: "body"  {shape}
  centre {{ x: {(width - 1) / 2 + 1 + GAP!r}  y: {ny / 2!r} }}
  velocity {{ x: {-speed!r} }}
  fracture {{ max_force: {THRESHOLD!r} }}
}}
"""
    return text_format.Parse(text, scenario_pb2.Scenario())


def impact(client, width, height, ratio, every=None, after=4) -> Impact:
    speed = ratio * THRESHOLD
    # it reaches the wall after (1.5 + GAP) / v steps; `after` widths more cover the compression
    # front's round trip (2 widths) and the pieces leaving
    steps = int((1.5 + GAP) / speed) + after * width
    session = client.create(scenario(width, height, speed))
    try:
        rec = session.run_and_record(steps, particles_every=every or steps, bodies=["body"], progress=False)
    finally:
        session.delete()
    placed_mass = rec.particles[0].bodies["body"].mass
    mass_error = max(abs(f.bodies["body"].mass - (placed_mass - f.bodies["body"].broken_link_count))
                     for f in rec.particles)
    breaks = np.concatenate([f.bodies["body"].broken_links for f in rec.particles])
    first = int(breaks[:, 0].min()) if len(breaks) else 0
    return Impact("chain" if height == 1 else "sheet", ratio, rec.particles[-1].bodies["body"].broken_link_count,
                  first, mass_error, rec.particles)


def plot(path, scans, strip):
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(13, 8.5))
    grid = fig.add_gridspec(2, 4, height_ratios=[1, 1])
    a_scan = fig.add_subplot(grid[0, :2])
    for shape, marker in (("chain", "o-"), ("sheet", "s-")):
        rows = [s for s in scans if s.shape == shape]
        a_scan.plot([s.ratio for s in rows], [s.broken for s in rows], marker, label=f"{shape} (measured)")
    a_scan.axvline(1.0, color="C0", ls="--", lw=1, label="chain: predicted onset v = T")
    a_scan.axvline(0.5, color="C1", ls="--", lw=1, label="sheet: no break below v = T/2 (flux <= 2 v)")
    a_scan.set(xlabel="impact speed v / T", ylabel="links broken", title="(a) links broken against impact speed")
    a_scan.grid(alpha=0.3)
    a_scan.legend(fontsize=8)

    a_time = fig.add_subplot(grid[0, 2:])
    steps = [f.step for f in strip.frames]
    a_time.plot(steps, [f.bodies["body"].broken_link_count for f in strip.frames], "-")
    a_time.set(xlabel="step", ylabel="links broken so far",
               title=f"(b) a {STRIP_SIZE[0]} x {STRIP_SIZE[1]} sheet at v = {STRIP_SPEED:g} T: breaks over time")
    a_time.grid(alpha=0.3)

    hit = strip.first_step
    picks = [hit, hit + STRIP_SIZE[0] // 2, hit + 2 * STRIP_SIZE[0], hit + 7 * STRIP_SIZE[0]]
    by_step = {f.step: f for f in strip.frames}
    for k, step in enumerate(picks):
        ax = fig.add_subplot(grid[1, k])
        frame = by_step[min(by_step, key=lambda s: abs(s - step))]
        body = frame.bodies["body"]
        # a shed particle (no link left) is out of the dynamics: zero velocity, where it broke free
        shed = np.all(body.velocity == 0, axis=1) & (body.broken_link_count > 0)
        ax.plot(body.position[~shed, 0], body.position[~shed, 1], "o", ms=3, label="linked")
        ax.plot(body.position[shed, 0], body.position[shed, 1], "o", ms=3, color="0.7", label="shed")
        broken = np.concatenate([f.bodies["body"].broken_links for f in strip.frames if f.step <= frame.step])
        if len(broken):
            ax.plot(broken[:, 3], broken[:, 4], "x", color="C3", ms=3, mew=0.6, label="broken links")
        ax.legend(fontsize=7, loc="upper right")
        ax.axvline(-0.5, color="k", lw=2)
        ax.set_xlim(-1, 2 * STRIP_SIZE[0])
        ax.set_ylim(-1, STRIP_SIZE[1] + 8)
        ax.set_aspect("equal")
        ax.set_title(f"step {frame.step}: {body.broken_link_count} broken", fontsize=9)
    fig.suptitle(f"Fracture on impact: LB solid links break past T = {THRESHOLD:g} (force = eq.-11 extension); "
                 "wall at x = -1/2, contact e = 1, no fluid")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw(client, out_dir, quick):
    speeds = QUICK_SPEEDS if quick else FULL_SPEEDS
    scans = [impact(client, 10, 1, r) for r in speeds] + [impact(client, 10, 6, r) for r in speeds]
    strip = impact(client, *STRIP_SIZE, STRIP_SPEED, every=1, after=8)
    write_csv(out_dir / f"{FIGURE}.csv", ["shape", "speed_over_threshold", "links_broken", "first_break_step"],
              [[s.shape, s.ratio, s.broken, s.first_step] for s in scans])
    plot(out_dir / f"{FIGURE}.png", scans, strip)
    return rows_for(scans, strip)


def rows_for(scans, strip):
    chain = [s for s in scans if s.shape == "chain"]
    sheet = [s for s in scans if s.shape == "sheet"]
    chain_whole = [s.ratio for s in chain if s.broken == 0]
    chain_broken = [s.ratio for s in chain if s.broken > 0]
    sheet_whole = [s.ratio for s in sheet if s.broken == 0]
    sheet_broken = [s.ratio for s in sheet if s.broken > 0]
    mass_error = max(s.mass_error for s in scans + [strip])
    return [
        Row("Fracture", "chain on a wall: onset of breaking (v / T)", "(issue 18) wave rule: v = T",
            f"whole up to {max(chain_whole, default=float('nan')):g}, broken from {min(chain_broken, default=float('nan')):g}",
            "chain of 10, M = 1: the link behind the compression front carries M v",
            # the prediction: links break exactly when v passes T, so whole at 0.98 T and broken at 1.02 T
            check="whole at every v < T, broken at every v > T",
            passed=all(r < 1 for r in chain_whole) and all(r > 1 for r in chain_broken) and bool(chain_broken)),
        Row("Fracture", "sheet on a wall: onset of breaking (v / T)", "(issue 18) between T/2 and T",
            f"whole up to {max(sheet_whole, default=float('nan')):g}, broken from {min(sheet_broken, default=float('nan')):g}",
            "sheet 10 x 6: bulk M = 2, so the flux per row is at most 2 v (1.92 v measured in-process)",
            # nothing can break below T/2 (flux <= 2 v); above T a row's link carries at least the chain's v
            check="whole at every v < T/2, broken at every v > T",
            passed=all(r >= 0.5 for r in sheet_broken) and all(r <= 1 for r in sheet_whole)),
        Row("Fracture", "mass = placed mass - broken links", "M = K/2 (MODEL.md)", f"largest error {mass_error:.1e}",
            f"every frame of every run ({len(scans)} impacts, and the strip's {len(strip.frames)} frames)",
            # masses are halves: the sum is exact in binary, so any error at all is a wrong mass
            check="== 0", passed=mass_error == 0),
        Row("Fracture", f"sheet {STRIP_SIZE[0]} x {STRIP_SIZE[1]} at v = {STRIP_SPEED:g} T", "(a demonstration)",
            f"{strip.broken} links broken", f"first break in step {strip.first_step}; frames every step"),
    ]


if __name__ == "__main__":
    run_figure(draw, FIGURE)
