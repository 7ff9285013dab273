"""Lattice geometry the figure scripts share, written out as the daemon's core has it.

D2Q7 (core/lattice/d2q7.h): node (x, y) sits at (x + (y mod 2)/2, y sqrt(3)/2), c_s^2 = 1/4.
D2Q9: node (x, y) at (x, y), c_s^2 = 1/3. Walls lie half-way between nodes, except D2Q7's x walls,
at -1/4 and nx - 1/4 (scene::wall_position in core/scene/scene.cpp says why).
The nearest node is the one a solid particle exchanges momentum with (core/coupling/node_locator.h).
Import it after figure_common, which puts lbsolid_client on the path.
"""
import math

import numpy as np

from lbsolid_client import scenario_pb2

D2Q7_ROW_SPACING = math.sqrt(3.0) / 2.0
SOUND_SPEED_SQUARED = {scenario_pb2.LATTICE_D2Q7: 0.25}  # D2Q9 and D3Q19: 1/3


def is_d2q7(scenario) -> bool:
    return scenario.lattice == scenario_pb2.LATTICE_D2Q7


def viscosity(scenario) -> float:
    """c_s^2 (1/omega - 1/2): BGK, TRT and regularized alike (scenario.proto)."""
    omega = scenario.fluid.omega if scenario.fluid.HasField("omega") else 1.0
    return SOUND_SPEED_SQUARED.get(scenario.lattice, 1.0 / 3.0) * (1.0 / omega - 0.5)


def sound_speed(scenario) -> float:
    return math.sqrt(SOUND_SPEED_SQUARED.get(scenario.lattice, 1.0 / 3.0))


def row_spacing(scenario) -> float:
    return D2Q7_ROW_SPACING if is_d2q7(scenario) else 1.0


def walls(scenario):
    """(x low, x high, y low, y high), as scene::wall_position places them: half a spacing beyond
    the outermost node, but on D2Q7 the x walls cut the slanted links of the zig-zag rows
    half-way, at -1/4 and nx - 1/4."""
    d, dy = scenario.domain, row_spacing(scenario)
    x_margin = 0.25 if is_d2q7(scenario) else 0.5
    return -x_margin, d.nx - x_margin, -0.5 * dy, (d.ny - 0.5) * dy


def periodic_axes(scenario):
    """(x periodic, y periodic); an unspecified side means periodic."""
    d = scenario.domain
    periodic = (scenario_pb2.WALL_KIND_UNSPECIFIED, scenario_pb2.WALL_KIND_PERIODIC)
    return d.x_low.kind in periodic, d.y_low.kind in periodic


def nearest_d2q7_nodes(positions: np.ndarray, scenario) -> np.ndarray:
    """(x, y) index of the D2Q7 node nearest each position, exactly as NodeLocator<D2Q7>::nearest.

    Of the two rows around the position the nearer node wins (the lower row on a tie); periodic
    axes wrap, walled axes clamp. On a periodic y axis the distance is measured to the unwrapped
    row (the nearest node may lie across the seam) and only the index is wrapped.
    """
    nx, ny = scenario.domain.nx, scenario.domain.ny
    periodic = periodic_axes(scenario)

    def fit(i, n, wrap):
        return np.mod(i, n) if wrap else np.clip(i, 0, n - 1)

    rx, ry = positions[:, 0], positions[:, 1]
    below = np.floor(ry / D2Q7_ROW_SPACING).astype(np.int64)
    best, best_d2 = None, np.full(len(rx), np.inf)
    for row in (below, below + 1):
        y = row if periodic[1] else fit(row, ny, False)
        shift = 0.5 * (y & 1)  # ny is even on D2Q7: the parity survives wrapping
        x = np.floor(rx - shift + 0.5).astype(np.int64)
        d2 = (x + shift - rx) ** 2 + (y * D2Q7_ROW_SPACING - ry) ** 2
        node = np.stack([fit(x, nx, periodic[0]), fit(y, ny, periodic[1])], axis=1)
        closer = d2 < best_d2
        best = node if best is None else np.where(closer[:, None], node, best)
        best_d2 = np.where(closer, d2, best_d2)
    return best
