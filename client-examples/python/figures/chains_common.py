"""What the chain figures (fig6_chains.py, fig7_relaxation.py) share: the paper's sheared D2Q7
channel built as a protobuf Scenario, chains placed in Python with a seeded generator, concurrent
runs through the daemon, and the straight-line fits the figures are read from.

The set-up is that of tests/physics/chains_fig6_test.cpp and scenarios/fig6_chains_shear.textproto:
a D2Q7 fluid (the paper's lattice, omega = 1) periodic in x between two free-slip walls that pull
the wall layers with tractions -sigma (low) and +sigma (high). On D2Q7 a node covers 1 x sqrt(3)/2,
so the mass per unit area is rho / (sqrt(3)/2) and the steady free gradient is sigma / (rho nu).
Perpendicular chains lie along y with rest spacing sqrt(3)/2 (one particle per fluid layer), their
centres spread evenly in y over the band where they fit between the walls and at random x; parallel
chains lie along x with their centres moved onto the nearest layer, so each stays on one layer.
"""
import math
import threading
from dataclasses import dataclass

import numpy as np

import figure_common  # noqa: F401,E402  (puts lbsolid_client on sys.path)
from lbsolid_client import scenario_pb2 as sc  # noqa: E402

ROW = math.sqrt(3.0) / 2.0  # D2Q7 row spacing
CLEARANCE = 0.25            # how far a perpendicular chain's end starts from a wall


def viscosity(omega: float) -> float:
    """D2Q7 BGK kinematic viscosity, c_s^2 = 1/4."""
    return (1.0 / omega - 0.5) / 4.0


def density_per_area(rho: float = 1.0) -> float:
    return rho / ROW


def free_gradient(sigma: float, omega: float = 1.0, rho: float = 1.0) -> float:
    """Steady du_x/dy of the free fluid: sigma / (rho nu), rho per unit area."""
    return sigma / (density_per_area(rho) * viscosity(omega))


def channel_height(ny: int) -> float:
    """Distance between the two free-slip walls (half a row outside the first and last rows)."""
    return ny * ROW


@dataclass
class Channel:
    nx: int = 128
    ny: int = 40
    sigma: float = 2.5e-4
    omega: float = 1.0
    rho: float = 1.0

    def scenario(self, name: str) -> "sc.Scenario":
        s = sc.Scenario(name=name, lattice=sc.LATTICE_D2Q7)
        d = s.domain
        d.nx, d.ny = self.nx, self.ny
        d.x_low.kind = d.x_high.kind = sc.WALL_KIND_PERIODIC
        d.y_low.kind = d.y_high.kind = sc.WALL_KIND_FREE_SLIP
        d.y_low.traction.x, d.y_high.traction.x = -self.sigma, self.sigma
        s.fluid.omega, s.fluid.rho0 = self.omega, self.rho
        return s

    def centre_band(self, length: int):
        """Heights where the centre of a perpendicular chain of `length` fits between the walls."""
        half_extent = 0.5 * (length - 1) * ROW
        low = -0.5 * ROW + half_extent + CLEARANCE
        high = (self.ny - 0.5) * ROW - half_extent - CLEARANCE
        if high < low:
            raise ValueError(f"a chain of {length} does not fit across {self.ny} rows")
        return low, high

    def fit_rows(self, length: int):
        """Rows crossed by the full density of perpendicular chains (as in the C++ test)."""
        low, high = self.centre_band(length)
        half_extent = 0.5 * (length - 1) * ROW
        return (math.ceil((low + half_extent) / ROW), math.floor((high - half_extent) / ROW))


def add_chains(scenario, channel: Channel, count: int, length: int, parallel_flags, rng, prefix="chain"):
    """Adds `count` chains; chain k lies along x when parallel_flags[k], else along y.

    Centres evenly spread in y over the perpendicular band (parallel ones snapped to the nearest
    layer), x uniform in [0, nx) from `rng` (a numpy Generator): a statistically uniform suspension.
    """
    low, high = channel.centre_band(length)
    band = high - low
    for k in range(count):
        y = low + (k + 0.5) * band / count
        x = channel.nx * rng.random()
        b = scenario.bodies.add(name=f"{prefix}{k:04d}", shape=sc.BODY_SHAPE_CHAIN, length=length, spacing=ROW)
        if parallel_flags[k]:
            b.axis = sc.AXIS_X
            y = round(y / ROW) * ROW
        else:
            b.axis = sc.AXIS_Y
        b.centre.x, b.centre.y = x, y
    return scenario


def add_layer_chains(scenario, channel: Channel, count: int, length: int, rng, prefix="par"):
    """Parallel chains spread evenly over ALL rows (wall layers included), x at random."""
    for k in range(count):
        row = int((k + 0.5) * channel.ny / count)
        b = scenario.bodies.add(name=f"{prefix}{k:04d}", shape=sc.BODY_SHAPE_CHAIN, length=length,
                                spacing=ROW, axis=sc.AXIS_X)
        b.centre.x, b.centre.y = channel.nx * rng.random(), row * ROW
    return scenario


def mixed_flags(count: int, parallel_fraction: float, rng):
    """Orientation flags: round(count * parallel_fraction) parallel, in random order."""
    flags = np.zeros(count, dtype=bool)
    flags[: int(round(count * parallel_fraction))] = True
    rng.shuffle(flags)
    return flags


def run_concurrently(client, scenarios: dict, steps, every: int) -> dict:
    """Creates every session first, then one thread per session runs and records its profiles.

    steps: one count for all, or a dict name -> steps.
    Returns name -> Recording; re-raises the first failure (a diverged session names its step).
    """
    sessions = {name: client.create(s) for name, s in scenarios.items()}
    records, errors = {}, []

    def work(name, session):
        try:
            count = steps[name] if isinstance(steps, dict) else steps
            records[name] = session.run_and_record(count, profiles_every=every, progress=False)
        except Exception as error:  # noqa: BLE001  (reported below, with the session's name)
            errors.append((name, error))

    threads = [threading.Thread(target=work, args=item) for item in sessions.items()]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for session in sessions.values():
        try:
            session.delete()
        except Exception:  # noqa: BLE001  (cleanup only)
            pass
    if errors:
        name, error = errors[0]
        raise RuntimeError(f"session '{name}' failed: {error}") from error
    return {name: records[name] for name in scenarios}


def profile_array(recording):
    """(steps, heights, u) with u[frame, row]."""
    steps = np.array([p.step for p in recording.profiles])
    return steps, recording.profiles[0].y.copy(), np.array([p.u_x for p in recording.profiles])


def mean_profile(recording, from_step: int):
    """u_x(y) averaged over the frames at or after `from_step`; also the heights."""
    steps, y, u = profile_array(recording)
    return y, u[steps >= from_step].mean(axis=0)


@dataclass
class LineFit:
    slope: float
    intercept: float
    r2: float
    chi2: float  # sum of squared residuals


def fit_line(x, y) -> LineFit:
    x, y = np.asarray(x, float), np.asarray(y, float)
    slope, intercept = np.polyfit(x, y, 1)
    residual = y - (slope * x + intercept)
    total = np.sum((y - y.mean()) ** 2)
    chi2 = float(np.sum(residual ** 2))
    return LineFit(float(slope), float(intercept), 1.0 - chi2 / total if total > 0 else 1.0, chi2)


def bulk_fit(y, u, rows) -> LineFit:
    """The line through rows[0]..rows[1] (inclusive), against their heights."""
    first, last = rows
    return fit_line(y[first:last + 1], u[first:last + 1])
