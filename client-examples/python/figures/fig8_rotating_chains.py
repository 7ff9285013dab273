"""Fig. 8, beyond the paper: a suspension of chains that can rotate, against the paper's held chains.

The paper (section 4, conclusions) finds that chains perpendicular to a shear flow raise the
apparent viscosity while the fluid stays Newtonian (Fig. 6: gradient linear in stress), because its
chains cannot turn; it expects chains that can rotate to give "a non Newtonian behavior", set by
"the characteristic time for the response of the polymers to a local velocity gradient and the time
for the rotation". Here the same chains get `rotation: true` (co-rotational springs, docs/internals.md
"Rotating bodies") and the apparent viscosity is measured over a decade of stress.

Set-up (chains_common.py, as Fig. 6): D2Q7, omega = 1 (nu = 1/8), a channel periodic in x between
free-slip walls pulled by -sigma/+sigma; chains of 8 particles laid perpendicular to the flow
(along y, spacing sqrt(3)/2), centres spread evenly in y over the band where they fit, x from a
seeded generator, at Fig. 6's density of 0.5 particles per fluid node. Full: 128 x 40 nodes, 320
chains, six stresses log-spaced from 8e-5 to 8e-4. Quick: 64 x 40, 160 chains, three stresses over
the same decade, shorter runs. At each stress three runs: the free fluid, the chains with rotation
off (the paper's model) and with rotation on. The top stress keeps the free fluid's wall speed at
0.1 (Mach 0.2 on D2Q7, c_s = 1/2) and the rotating chains' Reynolds number G a^2/nu below 0.4; a
decade below it the runs are already 10 times longer (see the strain clock).

The strain clock: chains that do not feel their own elasticity (Weissenberg number G t_c << 1, below)
and no inertia turn as a function of the strain G t alone, so a run at a tenth of the stress needs
ten times the steps to reach the same state. Each rotating run therefore lasts the same nominal
strain sigma t / mu_fluid (the free fluid's gradient times the steps) and is averaged after the same
warm-up strain (at least min_warmup steps, many times the channel's viscous time H^2/(pi^2 nu) ~
1000 steps). Equal step counts at every stress would compare chains still turning at the low
stresses with aligned ones at the high stresses: a start-up transient that looks like shear
thinning (the first look ran 3000 steps at every stress, strain 6 to 240). The free and held runs
reach their steady state within the viscous time and run a fixed number of steps (held chains,
though, pass one another only slowly, and their mu_app wanders by a few per cent with their
arrangement).

Measured:
- mu_app / mu_fluid = free gradient / gradient with chains, both from the straight line through the
  rows crossed by the full density of chains (Fig. 6's fit), on the profile averaged after the
  warm-up; steadiness: the same from the first and the second half of the averaging window. The
  start-up panel shows mu_app in bins of strain (against the free run's gradient in the same bin
  while it lasts, so the fluid's own spin-up is not counted): curves that fall onto one another are
  a rate-independent suspension.
- the chains' orientation: phi is the chain's angle to the x axis, pi/2 + the body's orientation
  (the best-fit turn from its rest shape, in (-pi, pi]); the nematic order <cos 2 phi> (+1 aligned
  with the flow, -1 perpendicular, 0 isotropic), the mean acute angle to the flow arccos|cos phi|
  (0 to pi/2), and the mean rate of turn from the unwrapped orientation, as a period 2 pi / rate
  against Jeffery's 2 pi (r + 1/r) / G for a rod of aspect ratio r = L sqrt(3)/2 (a reference only:
  a chain is neither an ellipse nor alone), all over chains and body frames after the warm-up.
- the characteristic times: the rotation time 1/G; the chain's response time t_c, measured through
  the daemon: one held chain in fluid at rest started with a small spin (Body.angular_velocity)
  turns, and its fixed springs pull it back: t_c is the time from its largest turn to 1/e of it;
  the elastic wave time L - 1 steps, derived from the model (eq. 6 with M = 1 and no force moves each
  f_k one link per step unchanged, so a deformation crosses a chain in L - 1 steps); and how fast a
  rotating chain's spin follows the fluid (the same start with rotation on: the time for its spin to
  fall to 1/e). Their ratio Wi = G t_c and the chain Reynolds number Re = G a^2 / nu (a = L sqrt(3)/4,
  the half length) for each stress.
- a control: at a fixed nu, Wi, Re, the Mach number and the chains' hops between nodes all grow with
  G together. One more rotating run (and its free fluid and t_c) at three times the viscosity (omega
  0.5) and three times the top stress has the top run's free gradient, wall speed and strain clock
  with a third of its Reynolds number.

What came out (full run; the quick one, in a channel half as long and over a seventh of the
strain, draws the same picture: held 12.1-12.5, rotating 1.31-1.44, thickening 9%): held chains
11.2-11.5 times the fluid's viscosity at every stress, gradient linear in stress (R^2 0.9996),
Newtonian as in Fig. 6. Rotating chains lie down along the flow (<cos 2 phi> 0.84-0.90, 10-13
degrees from it, the director 6-7 degrees into the extensional quadrant) and raise the viscosity
only 1.38-1.51 times: not the thinning the paper expected but a mild thickening, 9% over the decade
(+0.13 +- 0.01 per decade of stress), with the order falling and the chains turning over more
often as the rate rises. With Wi = G t_c <= 0.02 (t_c = 4.5 steps) the chains' elastic response is
far faster than any turn of the flow; Re <= 0.35. At three times the viscosity and the top shear
rate mu_app is 1.13: the lattice chains' hydrodynamic effect depends on nu itself, so neither time
the paper names (nor inertia) can be singled out as the cause. What does thin is the start-up,
within the first ~30 strain, at every stress alike. About 5.5 minutes on two shared cores (quick: about 20 s).

    /usr/bin/python3 client-examples/python/figures/fig8_rotating_chains.py [--quick] [--out DIR] [--address HOST:PORT]
"""
import math
from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np

import chains_common as cc
from figure_common import Row, run_figure, run_in_parallel, write_csv
from lbsolid_client import scenario_pb2 as sc

FIGURE = "fig8_rotating_chains"
SEED = 2008
IN_FLIGHT = 3            # sessions recorded at once (the daemon's workers share the steps anyway)
PROFILE_STRAIN = 0.02    # nominal strain between recorded profiles of a rotating run
SPIN = 1e-3              # radians per step: the small start of the response-time runs
RESPONSE_STEPS = 200
BLOCKS = 8               # the averaging window's blocks, for a standard error
HELD_TURN_BOUND = 0.05   # rad: a held chain's mean |turn| in shear (its springs keep it; see table())


@dataclass
class Setup:
    nx: int
    ny: int
    chains: int
    length: int
    sigmas: tuple
    strain: float        # nominal strain of a rotating run (free gradient x steps)
    warm_strain: float   # nominal strain before the averaging window
    min_warmup: int      # steps: the warm-up is at least this
    fixed_steps: int     # free and held runs
    fixed_warmup: int
    frame_strain: float  # nominal strain between body frames of a rotating run
    bin_strain: float    # width of the start-up panel's strain bins
    control_omega: float = 0.5  # the control run's fluid (nu 3/8: three times the viscosity)


def decade(low, high, count):
    return tuple(float(low * (high / low) ** (k / (count - 1))) for k in range(count))


FULL = Setup(128, 40, 320, 8, decade(8e-5, 8e-4, 6), 450.0, 50.0, 10000, 100000, 20000, 0.25, 10.0)
QUICK = Setup(64, 40, 160, 8, decade(8e-5, 8e-4, 3), 60.0, 20.0, 8000, 16000, 8000, 0.5, 4.0)


# --- runs -------------------------------------------------------------------------------------------

@dataclass
class Job:
    name: tuple
    scenario: object
    steps: int
    warmup: int
    profiles_every: int
    frames_every: int


@dataclass
class Record:
    """What a run leaves: profiles and, per body frame, each chain's orientation and spin."""
    profile_steps: np.ndarray
    y: np.ndarray
    u: np.ndarray             # [profile frame, row]
    frame_steps: np.ndarray
    orientation: np.ndarray   # [body frame, chain], radians
    spin: np.ndarray          # [body frame, chain], angular velocity about z


def chain_turns(frame):
    """What a rotating run keeps of a body frame: the step, each chain's orientation and spin."""
    return frame.step, [b.orientation for b in frame.bodies], [b.angular_velocity.z for b in frame.bodies]


def record(session, steps, profiles_every, frames_every):
    """Session.run_and_record, keeping of each body frame only the chains' orientation and spin (the
    positions of every particle in hundreds of frames would take gigabytes in Python objects)."""
    r = session.run_and_record(steps, profiles_every=profiles_every, particles_every=frames_every,
                               progress=False, keep_particles=chain_turns)
    frames = r.particles
    chains = len(frames[0][1]) if frames else 0
    return Record(np.array([p.step for p in r.profiles]), r.profiles[0].y, np.array([p.u_x for p in r.profiles]),
                  np.array([f[0] for f in frames], dtype=np.int64),
                  np.array([f[1] for f in frames], dtype=float).reshape(len(frames), chains),
                  np.array([f[2] for f in frames], dtype=float).reshape(len(frames), chains))


def run_job(client, job):
    """One job's session: created, recorded, deleted (whatever happened)."""
    session = client.create(job.scenario)
    try:
        return record(session, job.steps, job.profiles_every, job.frames_every)
    finally:
        try:
            session.delete()
        except Exception:  # noqa: BLE001  (cleanup only)
            pass


def run_jobs(client, jobs):
    """Every job, IN_FLIGHT at a time, longest first; name -> Record."""
    return run_in_parallel([(job.name, job.steps, lambda job=job: run_job(client, job)) for job in jobs], IN_FLIGHT)


def suspension(setup: Setup, sigma: float, kind: str, omega: float = 1.0):
    channel = cc.Channel(setup.nx, setup.ny, sigma, omega)
    scenario = channel.scenario(f"Fig. 8: {kind}, sigma {sigma:.3g}, omega {omega:g}")
    if kind != "free":
        rng = np.random.default_rng(SEED)  # the same chains in the held and the rotating runs
        cc.add_chains(scenario, channel, setup.chains, setup.length, [False] * setup.chains, rng)
        for body in scenario.bodies:
            body.rotation = kind == "rotating"
    return scenario


def response_scenario(length: int, rotation: bool, omega: float = 1.0):
    """One perpendicular chain in a fluid at rest (free-slip walls, no traction), spun a little."""
    channel = cc.Channel(64, 40, 0.0, omega)
    scenario = channel.scenario(f"Fig. 8: response of a chain of {length}, rotation {rotation}")
    scenario.domain.y_low.traction.x = scenario.domain.y_high.traction.x = 0.0
    body = scenario.bodies.add(name="chain", shape=sc.BODY_SHAPE_CHAIN, length=length, spacing=cc.ROW,
                               axis=sc.AXIS_Y, rotation=rotation)
    body.centre.x, body.centre.y = 32.0, 19.5 * cc.ROW
    body.angular_velocity.z = SPIN
    return scenario


def control_sigma(setup: Setup) -> float:
    """The stress that gives the control fluid the top stress's free gradient (same G and Mach)."""
    return setup.sigmas[-1] * cc.viscosity(setup.control_omega) / cc.viscosity(1.0)


def rotating_job(setup: Setup, sigma: float, omega: float, name):
    gradient = cc.free_gradient(sigma, omega)
    # The same strain in every averaging window; a warm-up lengthened to min_warmup lengthens the run.
    warmup = max(int(round(setup.warm_strain / gradient)), setup.min_warmup)
    steps = warmup + int(round((setup.strain - setup.warm_strain) / gradient))
    return Job(name, suspension(setup, sigma, "rotating", omega), steps, warmup,
               max(10, int(round(PROFILE_STRAIN / gradient))), max(1, int(round(setup.frame_strain / gradient))))


def jobs_for(setup: Setup):
    jobs = []
    for sigma in setup.sigmas:
        jobs.append(rotating_job(setup, sigma, 1.0, ("rotating", sigma)))
        jobs.append(Job(("held", sigma), suspension(setup, sigma, "held"), setup.fixed_steps, setup.fixed_warmup,
                        20, setup.fixed_steps // 100))
        jobs.append(Job(("free", sigma), suspension(setup, sigma, "free"), setup.fixed_steps, setup.fixed_warmup,
                        20, 0))
    sigma_c, omega_c = control_sigma(setup), setup.control_omega
    jobs.append(rotating_job(setup, sigma_c, omega_c, ("control", "rotating")))
    jobs.append(Job(("control", "free"), suspension(setup, sigma_c, "free", omega_c), setup.fixed_steps,
                    setup.fixed_warmup, 20, 0))
    for omega in (1.0, omega_c):
        for rotation in (False, True):
            jobs.append(Job(("response", rotation, omega), response_scenario(setup.length, rotation, omega),
                            RESPONSE_STEPS, 0, RESPONSE_STEPS, 1))
    return jobs


# --- analysis ---------------------------------------------------------------------------------------

def window_gradient(rec: Record, rows, first, last):
    """Fig. 6's bulk fit on the profile averaged over the frames with first <= step < last."""
    chosen = (rec.profile_steps >= first) & (rec.profile_steps < last)
    return cc.bulk_fit(rec.y, rec.u[chosen].mean(axis=0), rows)


def orientation_stats(rec: Record, first: int):
    """Averages over chains and the body frames at or after step `first`."""
    chosen = rec.frame_steps >= first
    theta = rec.orientation[chosen]
    phi = 0.5 * math.pi + theta                     # angle to the x axis
    cos2, sin2 = float(np.mean(np.cos(2 * phi))), float(np.mean(np.sin(2 * phi)))
    turned = np.unwrap(theta, axis=0)               # the frames are close enough: < 0.6 rad apart
    steps = rec.frame_steps[chosen]
    rate = -float(np.mean(turned[-1] - turned[0])) / float(steps[-1] - steps[0])  # clockwise > 0
    return dict(order=cos2, director=0.5 * math.atan2(sin2, cos2),
                acute=float(np.mean(np.arccos(np.minimum(1.0, np.abs(np.cos(phi)))))),
                mean_abs_turn=float(np.mean(np.abs(theta))), rate=rate,
                largest_step=float(np.max(np.abs(np.diff(turned, axis=0)))) if len(steps) > 1 else 0.0)


def response_times(records, omega=1.0):
    """(t_c: held chain, from its largest turn to 1/e of it; t_s: rotating chain's spin to 1/e)."""
    def crossing(steps, values, level, start):
        for k in range(start, len(values) - 1):
            if values[k + 1] < level <= values[k]:
                return steps[k] + (values[k] - level) / (values[k] - values[k + 1]) * (steps[k + 1] - steps[k])
        return float("nan")

    held = records[("response", False, omega)]
    turn = held.orientation[:, 0]
    peak = int(np.argmax(turn))
    t_c = crossing(held.frame_steps, turn, turn[peak] / math.e, peak) - held.frame_steps[peak]
    spun = records[("response", True, omega)]
    spin = spun.spin[:, 0]
    t_s = crossing(spun.frame_steps, spin, spin[0] / math.e, 0) - spun.frame_steps[0]
    return dict(t_c=float(t_c), t_s=float(t_s), peak_step=int(held.frame_steps[peak]), peak=float(turn[peak]),
                held_steps=held.frame_steps, held_turn=turn, spun_steps=spun.frame_steps, spin=spin)


def window_stats(rec: Record, rows, first, end, free_slope):
    """mu_app over the window [first, end): whole, its two halves, and the standard error of the mean
    over BLOCKS equal blocks (blocks a few tens of strain long are still correlated: a lower bound)."""
    edges = np.linspace(first, end, BLOCKS + 1)
    blocks = [free_slope / window_gradient(rec, rows, a, b).slope for a, b in zip(edges[:-1], edges[1:])]
    middle = (first + end) // 2
    halves = [free_slope / window_gradient(rec, rows, a, b).slope for a, b in ((first, middle), (middle, end))]
    fit = window_gradient(rec, rows, first, end)
    return fit, dict(gradient=fit.slope, r2=fit.r2, mu=free_slope / fit.slope, halves=halves,
                     sem=float(np.std(blocks, ddof=1) / math.sqrt(BLOCKS)))


def free_in_bin(rec: Record, rows, first, last, steps, steady):
    """The free fluid's gradient over the same steps while the free run lasts (so that the start-up
    panel does not count the fluid's own spin-up), its steady gradient after."""
    return window_gradient(rec, rows, first, last).slope if last <= steps + 1 else steady


def analyse(setup: Setup, jobs, records):
    rows = cc.Channel(setup.nx, setup.ny).fit_rows(setup.length)
    by_name = {j.name: j for j in jobs}
    out = {}
    for sigma in setup.sigmas:
        free_job = by_name[("free", sigma)]
        free = window_gradient(records[("free", sigma)], rows, free_job.warmup, free_job.steps + 1)
        entry = dict(free=free.slope)
        for kind in ("held", "rotating"):
            job, rec = by_name[(kind, sigma)], records[(kind, sigma)]
            fit, stats = window_stats(rec, rows, job.warmup, job.steps + 1, free.slope)
            width = setup.bin_strain / cc.free_gradient(sigma)
            edges = np.arange(0.0, job.steps + 1, width)
            startup = [(0.5 * (a + b) * cc.free_gradient(sigma),
                        free_in_bin(records[("free", sigma)], rows, a, b, free_job.steps, free.slope)
                        / window_gradient(rec, rows, a, b).slope) for a, b in zip(edges[:-1], edges[1:])]
            entry[kind] = dict(**stats, startup=np.array(startup),
                               orientation=orientation_stats(rec, job.warmup), warmup=job.warmup, steps=job.steps,
                               y=rec.y, u=rec.u[rec.profile_steps >= job.warmup].mean(axis=0))
        free_rec = records[("free", sigma)]
        entry["free_profile"] = free_rec.u[free_rec.profile_steps >= free_job.warmup].mean(axis=0)
        out[sigma] = entry
    control = by_name[("control", "rotating")]
    free_c = by_name[("control", "free")]
    free_slope = window_gradient(records[free_c.name], rows, free_c.warmup, free_c.steps + 1).slope
    rec = records[control.name]
    fit, stats = window_stats(rec, rows, control.warmup, control.steps + 1, free_slope)
    times_c = response_times(records, setup.control_omega)
    half = 0.5 * setup.length * cc.ROW
    out["control"] = dict(sigma=control_sigma(setup), omega=setup.control_omega, free=free_slope, **stats,
                          orientation=orientation_stats(rec, control.warmup), t_c=times_c["t_c"], t_s=times_c["t_s"],
                          wi=fit.slope * times_c["t_c"],
                          re=fit.slope * half ** 2 / cc.viscosity(setup.control_omega))
    return out, rows, response_times(records)


def derived(setup: Setup, entry, times):
    """Rotating chains' times and numbers at one stress."""
    G = entry["rotating"]["gradient"]
    r = setup.length * cc.ROW
    half = 0.5 * setup.length * cc.ROW
    rate = entry["rotating"]["orientation"]["rate"]
    return dict(G=G, rotation=1 / G, jeffery=2 * math.pi * (r + 1 / r) / G,
                period=2 * math.pi / rate if rate > 0 else float("inf"),
                wi=G * times["t_c"], re=G * half ** 2 / cc.viscosity(1.0), aspect=r)


# --- outputs ----------------------------------------------------------------------------------------

def plot(path, setup, results, rows, times):
    sigmas = np.array(setup.sigmas)
    fig, axes = plt.subplots(2, 3, figsize=(17, 9.5))
    (a_mu, a_wi, a_start), (a_or, a_times, a_prof) = axes
    for kind, marker, colour in (("held", "s", "C3"), ("rotating", "o", "C0")):
        mu = np.array([results[s][kind]["mu"] for s in sigmas])
        a_mu.errorbar(sigmas, mu, yerr=[results[s][kind]["sem"] for s in sigmas], fmt=marker + "-", color=colour,
                      capsize=3, label=f"{kind} chains (rotation {'on' if kind == 'rotating' else 'off'})")
    a_mu.axhline(1.0, color="k", lw=0.8, ls=":", label="free fluid")
    a_mu.set_xscale("log")
    a_mu.set_yscale("log")
    a_mu.set_xlabel("stress sigma")
    a_mu.set_ylabel("mu_app / mu_fluid = free gradient / gradient")
    a_mu.set_title(f"apparent viscosity (bars: standard error over {BLOCKS} blocks)", fontsize=10)
    a_mu.legend(fontsize=8)

    d = [derived(setup, results[s], times) for s in sigmas]
    control = results["control"]
    G = np.array([x["G"] for x in d])
    a_wi.errorbar(G, [results[s]["rotating"]["mu"] for s in sigmas],
                  yerr=[results[s]["rotating"]["sem"] for s in sigmas],
                  fmt="o-", color="C0", capsize=3, label="rotating chains, nu 1/8")
    a_wi.errorbar([control["gradient"]], [control["mu"]], yerr=[control["sem"]],
                  fmt="*", ms=12, color="C1", capsize=3,
                  label=f"control: nu {cc.viscosity(control['omega']):.3g}, sigma {control['sigma']:.2g} "
                        f"(Re {control['re']:.2g}, Wi {control['wi']:.2g})")
    a_wi.set_xscale("log")
    a_wi.set_xlabel("shear rate G = du_x/dy with rotating chains")
    a_wi.set_ylabel("mu_app / mu_fluid, rotating")
    t_c = times["t_c"]
    top = a_wi.secondary_xaxis("top", functions=(lambda g: g * t_c, lambda w: w / t_c))
    top.set_xlabel(f"Wi = G t_c (t_c = {t_c:.1f} steps); chain Re = G a^2/nu = {d[0]['re'] / d[0]['G']:.0f} G")
    a_wi.legend(fontsize=8, loc="lower center")

    colours = plt.cm.viridis(np.linspace(0, 0.9, len(sigmas)))
    for s, colour in zip(sigmas, colours):
        st = results[s]["rotating"]["startup"]
        a_start.plot(st[:, 0], st[:, 1], "-", color=colour, lw=1, label=f"sigma {s:.2g}")
    a_start.axvline(setup.warm_strain, color="k", lw=0.7, ls="--")
    a_start.set_xlabel("nominal strain sigma t / mu_fluid (dashed: the warm-up strain)")
    a_start.set_ylabel("mu_app / mu_fluid in the bin")
    a_start.set_title(f"rotating chains, start-up (bins of strain {setup.bin_strain:g})")
    a_start.legend(fontsize=7, ncol=2)

    o = [results[s]["rotating"]["orientation"] for s in sigmas]
    a_or.semilogx(G, [x["order"] for x in o], "o-", color="C0", label="<cos 2 phi>, rotating")
    held_G = np.array([results[s]["held"]["gradient"] for s in sigmas])
    a_or.semilogx(held_G, [results[s]["held"]["orientation"]["order"] for s in sigmas], "s-", color="C3",
                  label="<cos 2 phi>, held")
    control = results["control"]
    a_or.semilogx([control["gradient"]], [control["orientation"]["order"]], "*", ms=12, color="C1",
                  label=f"<cos 2 phi>, control (nu {cc.viscosity(control['omega']):.3g})")
    a_or.set_ylim(-1.05, 1.05)
    a_or.set_xlabel("shear rate G = du_x/dy with chains")
    a_or.set_ylabel("nematic order <cos 2 phi> (+1: along the flow)")
    right = a_or.twinx()
    right.semilogx(G, [math.degrees(x["acute"]) for x in o], "^--", color="C1", ms=4)
    right.set_ylabel("mean angle to the flow, degrees (triangles, rotating)", color="C1")
    right.set_ylim(0, 90)
    a_or.set_title("chains' orientation after the warm-up")
    a_or.legend(fontsize=8, loc="center left")

    a_times.loglog(G, [x["rotation"] for x in d], "o-", color="C0", label="rotation time 1/G")
    a_times.loglog(G, [x["jeffery"] for x in d], "--", color="C0",
                   label=f"Jeffery period 2 pi (r + 1/r)/G, r = {d[0]['aspect']:.1f} (reference)")
    finite = [(g, x["period"]) for g, x in zip(G, d) if math.isfinite(x["period"])]
    if finite:
        a_times.loglog(*zip(*finite), "^", color="C0", label="measured period 2 pi / <turn rate>")
    for value, label, colour in ((times["t_c"], "chain response t_c (measured)", "C3"),
                                 (setup.length - 1, "elastic wave time L - 1 (model)", "C1"),
                                 (times["t_s"], "spin follows the fluid (measured)", "C2")):
        a_times.axhline(value, color=colour, lw=1, label=f"{label}: {value:.1f}")
    a_times.set_xlabel("shear rate G with rotating chains")
    a_times.set_ylabel("steps")
    a_times.set_title("characteristic times")
    a_times.legend(fontsize=7, loc="lower left", bbox_to_anchor=(0.0, 0.16))

    middle = sigmas[len(sigmas) // 2]
    entry = results[middle]
    y = entry["rotating"]["y"]
    for profile, label, colour in ((entry["free_profile"], "free", "k"), (entry["held"]["u"], "held", "C3"),
                                   (entry["rotating"]["u"], "rotating", "C0")):
        a_prof.plot(profile, y, ".", ms=4, color=colour, label=label)
    band = y[rows[0]:rows[1] + 1]
    for kind, colour in (("held", "C3"), ("rotating", "C0")):
        u = entry[kind]["u"]
        fit = cc.bulk_fit(y, u, rows)
        a_prof.plot(fit.slope * band + fit.intercept, band, "-", color=colour, lw=0.8)
    a_prof.set_xlabel("u_x (averaged along x and in time)")
    a_prof.set_ylabel("y")
    a_prof.set_title(f"profiles at sigma {middle:.2g} (lines: fits on rows {rows[0]}..{rows[1]})")
    a_prof.legend(fontsize=8)

    fig.suptitle(f"Fig. 8 (beyond the paper): {setup.chains} chains of {setup.length}, rotating or held, "
                 f"D2Q7 {setup.nx} x {setup.ny}, omega 1, "
                 f"{setup.chains * setup.length / (setup.nx * setup.ny):.2f} particles per node")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


CSV_HEADER = ["kind", "case", "sigma", "omega", "gradient", "mu_app", "mu_sem", "mu_first_half", "mu_second_half",
              "cos2phi", "acute_angle_rad", "mean_abs_turn_rad", "turn_rate_per_step", "rotation_time",
              "jeffery_period", "measured_period", "wi", "re", "step_or_strain", "value"]


def save_csv(path, setup, results, times):
    """kind "run": one line per run (free, held, rotating, control); "startup": mu_app of the rotating
    chains in one strain bin (step_or_strain: its nominal strain); "time": t_c, t_spin (value);
    "response": the response runs' held-chain turn and rotating-chain spin against the step."""
    blank = [""] * len(CSV_HEADER)

    def line(**cells):
        row = list(blank)
        for key, value in cells.items():
            row[CSV_HEADER.index(key)] = value
        return row

    def run_line(case, sigma, omega, k, extra=None):
        o = k["orientation"]
        return line(kind="run", case=case, sigma=sigma, omega=omega, gradient=k["gradient"], mu_app=k["mu"],
                    mu_sem=k["sem"], mu_first_half=k["halves"][0], mu_second_half=k["halves"][1],
                    cos2phi=o["order"], acute_angle_rad=o["acute"], mean_abs_turn_rad=o["mean_abs_turn"],
                    turn_rate_per_step=o["rate"], **(extra or {}))

    lines = []
    for s in setup.sigmas:
        e = results[s]
        x = derived(setup, e, times)
        lines.append(line(kind="run", case="free", sigma=s, omega=1.0, gradient=e["free"], mu_app=1.0))
        lines.append(run_line("held", s, 1.0, e["held"]))
        lines.append(run_line("rotating", s, 1.0, e["rotating"],
                              dict(rotation_time=x["rotation"], jeffery_period=x["jeffery"],
                                   measured_period=x["period"], wi=x["wi"], re=x["re"])))
    c = results["control"]
    lines.append(line(kind="run", case="control free", sigma=c["sigma"], omega=c["omega"], gradient=c["free"],
                      mu_app=1.0))
    lines.append(run_line("control rotating", c["sigma"], c["omega"], c,
                          dict(rotation_time=1 / c["gradient"], wi=c["wi"], re=c["re"])))
    for s in setup.sigmas:
        lines += [line(kind="startup", case="rotating", sigma=s, omega=1.0, step_or_strain=float(strain),
                       mu_app=float(mu)) for strain, mu in results[s]["rotating"]["startup"]]
    lines.append(line(kind="time", case="t_c", omega=1.0, value=times["t_c"]))
    lines.append(line(kind="time", case="t_spin", omega=1.0, value=times["t_s"]))
    lines.append(line(kind="time", case="t_c", omega=c["omega"], value=c["t_c"]))
    lines.append(line(kind="time", case="t_spin", omega=c["omega"], value=c["t_s"]))
    lines += [line(kind="response", case="held chain turn", omega=1.0, step_or_strain=int(t), value=float(v))
              for t, v in zip(times["held_steps"], times["held_turn"])]
    lines += [line(kind="response", case="rotating chain spin", omega=1.0, step_or_strain=int(t), value=float(v))
              for t, v in zip(times["spun_steps"], times["spin"])]
    write_csv(path, CSV_HEADER, lines)


def o_last_first(results, sigmas):
    """<cos 2 phi> of the rotating chains at the top stress less that at the lowest."""
    order = [results[s]["rotating"]["orientation"]["order"] for s in (sigmas[0], sigmas[-1])]
    return order[1] - order[0]


def table(setup, results, rows, times):
    sigmas = list(setup.sigmas)
    lo, hi = sigmas[0], sigmas[-1]
    mu = {k: [results[s][k]["mu"] for s in sigmas] for k in ("held", "rotating")}
    d = [derived(setup, results[s], times) for s in sigmas]
    free_dev = [results[s]["free"] / cc.free_gradient(s) - 1 for s in sigmas]
    held_fit = cc.fit_line(sigmas, [results[s]["held"]["gradient"] for s in sigmas])
    steady = {k: max(abs(results[s][k]["halves"][1] / results[s][k]["halves"][0] - 1) for s in sigmas)
              for k in ("held", "rotating")}
    o = [results[s]["rotating"]["orientation"] for s in sigmas]
    held_turn = max(results[s]["held"]["orientation"]["mean_abs_turn"] for s in sigmas)
    lean = max(results[s]["held"]["gradient"] for s in sigmas) * times["t_c"]
    held_strain = [results[s]["held"]["gradient"] * (setup.fixed_steps - setup.fixed_warmup) for s in sigmas]
    c = results["control"]
    at_re = float(np.interp(math.log(c["re"]), [math.log(x["re"]) for x in d], mu["rotating"]))
    ratio = {k: mu[k][0] / mu[k][-1] for k in mu}
    # mu_app against log10(sigma), weighted by the blocks' standard errors: the slope per decade
    x = np.log10(sigmas)
    w = 1 / np.array([results[s]["rotating"]["sem"] for s in sigmas]) ** 2
    xm = np.sum(w * x) / np.sum(w)
    per_decade = float(np.sum(w * (x - xm) * np.array(mu["rotating"])) / np.sum(w * (x - xm) ** 2))
    per_decade_err = float(1 / math.sqrt(np.sum(w * (x - xm) ** 2)))
    sem = {k: [results[s][k]["sem"] for s in sigmas] for k in ("held", "rotating")}
    startup = [results[s]["rotating"]["startup"] for s in sigmas]
    peak = [float(st[st[:, 0] < setup.warm_strain, 1].max()) for st in startup]
    dip = [float(st[st[:, 0] < setup.warm_strain, 1].min()) for st in startup]
    order_trend = "falling" if o_last_first(results, sigmas) < 0 else "rising"
    periods = [x["period"] * x["G"] for x in d]
    flips = "more often" if periods[-1] < periods[0] else "less often"
    control_side = ("below both" if c["mu"] < min(at_re, mu["rotating"][-1]) else
                    "above both" if c["mu"] > max(at_re, mu["rotating"][-1]) else "between them")
    where = (f"D2Q7 {setup.nx}x{setup.ny}, {setup.chains} chains of {setup.length} "
             f"({setup.chains * setup.length / (setup.nx * setup.ny):.2f} particles/node), sigma {lo:.2g}-{hi:.2g} "
             f"({len(sigmas)} values), fit rows {rows[0]}..{rows[1]}")
    clock = (f"nominal strain {setup.strain:g} per run, averaged after {setup.warm_strain:g} "
             f"(at least {setup.min_warmup} steps)")

    def span(values, fmt="{:.3g}"):
        return f"{fmt.format(min(values))}-{fmt.format(max(values))}"

    return [
        Row("Fig. 8", "mu_app/mu_fluid, held chains (rotation off)", "raised, Newtonian (Fig. 6)",
            span(mu["held"]), f"{where}; {setup.fixed_steps} steps, averaged after {setup.fixed_warmup}; halves of "
            f"the window differ by up to {steady['held']:.1%}: held chains pass one another slowly (strain G t "
            f"{span(held_strain, '{:.1f}')} in the window), and mu_app changes with their arrangement"),
        Row("Fig. 8", "mu_app/mu_fluid, rotating chains", "expected non-Newtonian (not shown)",
            span(mu["rotating"]), f"{clock}; by stress "
            + ", ".join(f"{s:.2g}: {m:.3f} +- {e:.3f}" for s, m, e in zip(sigmas, mu["rotating"], sem["rotating"]))
            + f" (standard error over {BLOCKS} blocks of {(setup.strain - setup.warm_strain) / BLOCKS:g} strain, "
            f"a lower bound: they are correlated); halves of a window differ by up to {steady['rotating']:.1%}"),
        Row("Fig. 8", "mu_app(lowest sigma) / mu_app(highest sigma)", "shear thinning expected (> 1)",
            f"rotating {ratio['rotating']:.3f}, held {ratio['held']:.3f}",
            f"over a factor {hi / lo:.0f} in stress. Rotating: {'thinning' if ratio['rotating'] > 1 else 'thickening'}"
            f" of {abs(ratio['rotating'] - 1):.1%}; d mu_app / d log10 sigma = {per_decade:+.3f} +- "
            f"{per_decade_err:.3f} (weighted by the blocks' errors); held: {abs(ratio['held'] - 1):.1%}, within the "
            "arrangement's "
            f"{steady['held']:.0%}. What thins is the start-up: in the first {setup.warm_strain:g} strain mu_app "
            f"peaks at {span(peak, '{:.2g}')} and falls to {span(dip, '{:.2g}')} as the chains lie down, at about "
            "the same strain at every stress (start-up panel)"),
        Row("Fig. 8", "held chains: gradient against stress", "linear (Fig. 6)",
            f"R^2 {held_fit.r2:.5f}", f"slope {held_fit.slope:.3g}, intercept {held_fit.intercept:.2g}; the paper's "
            "model: each layer's stress is linear in the gradients (Fig. 6 found the same)",
            check="linear: R^2 > 0.99", passed=held_fit.r2 > 0.99),
        Row("Fig. 8", "free gradient / sigma/(rho nu)", "sigma/(rho nu)",
            f"largest deviation {max(abs(v) for v in free_dev):.2%}",
            f"{len(sigmas)} stresses; {setup.fixed_steps} steps, averaged after {setup.fixed_warmup} "
            "(the channel's viscous time H^2/(pi^2 nu) ~ 1000 steps)",
            check="within 1% at every stress", passed=max(abs(v) for v in free_dev) < 0.01),
        Row("Fig. 8", "rotating against held chains", "rotation lets chains align (expected lower)",
            "mu_rot/mu_held " + span([r / h for r, h in zip(mu["rotating"], mu["held"])]),
            "chains that cannot turn couple the layers they span (Fig. 6); chains that turn lie down along the "
            "flow; a failure here means the rotation is not acting",
            check="lower at every stress", passed=all(r < h for r, h in zip(mu["rotating"], mu["held"]))),
        Row("Fig. 8", "orientation, rotating: <cos 2 phi>; mean angle to flow", "align with the flow (expected)",
            f"{span([x['order'] for x in o])}; {span([math.degrees(x['acute']) for x in o], '{:.1f}')} deg",
            f"{order_trend} with the shear rate: "
            + ", ".join(f"G {x['G']:.2g}: {y['order']:.3f}" for x, y in zip(d, o))
            + f"; director {span([math.degrees(x['director']) for x in o], '{:.1f}')} deg from x, into the "
            "extensional quadrant; held chains: <cos 2 phi> "
            + span([results[s]["held"]["orientation"]["order"] for s in sigmas], "{:.5f}")),
        Row("Fig. 8", "held chains' mean |turn| in shear (rad)", "cannot rotate (fixed springs)",
            f"{held_turn:.2g}", f"a turned held chain is pulled back within t_c = {times['t_c']:.1f} steps, so in "
            f"shear it leans by about G t_c <= {lean:.2g}; the bound is {HELD_TURN_BOUND / lean:.0f} times that",
            check=f"< {HELD_TURN_BOUND:g}", passed=held_turn < HELD_TURN_BOUND),
        Row("Fig. 8", "rotation: G x measured period (2 pi G / <turn rate>)", "not given",
            span([x["period"] * x["G"] for x in d], "{:.0f}"),
            f"Jeffery's 2 pi (r + 1/r) = {d[0]['jeffery'] * d[0]['G']:.1f} for r = {d[0]['aspect']:.2f} (length over "
            "one node; a reference only: these chains interact and are not ellipses): they lie near the flow "
            f"direction and turn over far less often than a Jeffery orbit would, {flips} at higher G; 1/G = "
            + span([x["rotation"] for x in d], "{:.0f}") + " steps; largest turn between body frames "
            f"{max(x['largest_step'] for x in o):.2f} rad (unwrapping needs < pi)"),
        Row("Fig. 8", "chain response time t_c; Wi = G t_c; Re = G a^2/nu", "named, not given",
            f"t_c {times['t_c']:.1f} steps; Wi {span([x['wi'] for x in d], '{:.2g}')}; "
            f"Re {span([x['re'] for x in d], '{:.2g}')}",
            f"t_c: a held chain of {setup.length} in fluid at rest, spun by {SPIN:g}/step, from its largest turn "
            f"(step {times['peak_step']}) to 1/e; the elastic wave time L - 1 = {setup.length - 1} steps (model); a "
            f"rotating chain's spin falls to 1/e in {times['t_s']:.1f} steps (it turns with its fluid). Wi << 1: "
            "the chains respond elastically far faster than the flow turns them"),
        Row("Fig. 8", "control: 3x the viscosity at the top shear rate", "not given",
            f"mu_app {c['mu']:.3f} (nu 1/8 at that G: {mu['rotating'][-1]:.3f}; at that Re: {at_re:.3f})",
            f"omega {c['omega']:g} (nu {cc.viscosity(c['omega']):.3g}), sigma {c['sigma']:.3g}: the top run's free "
            f"gradient, wall speed and strain clock, Re {c['re']:.2g}, Wi {c['wi']:.2g} (t_c {c['t_c']:.1f} steps); "
            f"halves differ by {abs(c['halves'][1] / c['halves'][0] - 1):.1%}; <cos 2 phi> "
            f"{c['orientation']['order']:.3f}. {control_side.capitalize()}"
            + (": the chains' coupling to the fluid depends on nu itself, so mu_app is not a function of Re and "
               "Wi alone and this control cannot single out inertia" if control_side != "between them" else "")),
    ]


def draw(client, out_dir, quick):
    setup = QUICK if quick else FULL
    jobs = jobs_for(setup)
    records = run_jobs(client, jobs)
    results, rows, times = analyse(setup, jobs, records)
    plot(out_dir / f"{FIGURE}.png", setup, results, rows, times)
    save_csv(out_dir / f"{FIGURE}.csv", setup, results, times)
    return table(setup, results, rows, times)


if __name__ == "__main__":
    run_figure(draw, FIGURE)
