"""A gas of hard disks in a square box: the kinetic theory's model system, built in Python
(it takes the number of disks).

n disks of mass m and radius r move freely in the box 0 <= x, y <= L.  Every wall and every
pair of disks is a unilateral constraint with e = 1 (elastic):

    x_i - r >= 0,   L - r - x_i >= 0,   y_i - r >= 0,   L - r - y_i >= 0,
    (x_i - x_j)^2 + (y_i - y_j)^2 - (2 r)^2 >= 0        every pair i < j,

so between impacts each disk flies in a straight line (M constant, no force; a parabola in
the uniform field (g_x, g_y), zero by default) and the impacts
are those of billiard balls: a wall reverses the normal velocity, two disks exchange the
normal components of their velocities.  The disks start on a square lattice, with speeds 1
in directions drawn from a fixed seed (the same gas on every call).  The built-in example
(``lagrangian simulate examples/hard_disk_gas``) has four disks; ``hard_disk_gas:N`` on the
command line builds N.

>>> gas = hard_disk_gas(3)
>>> len(gas.coordinates), len(gas.constraints)
(6, 15)
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from lagrangian.model import Particle, System, Unilateral

__all__ = ["hard_disk_gas"]

#: The seed of the directions of the initial velocities.
SEED = 2026


def hard_disk_gas(n: int = 4, radius: float | None = None, side: float = 1.0) -> System:
    """Gas of n elastic hard disks in a square box: every wall and disk contact unilateral, e = 1.

    The disks have mass m = 1 and radius r = ``radius`` (a fifth of the lattice spacing when
    not given: 0.1 for four disks, 0.02 for a hundred); the box has side L = ``side``.  They
    start on a square lattice with speed 1 in seeded directions and fly freely between
    impacts (a parabola in the optional field g_x, g_y).  On the command line
    ``examples/hard_disk_gas`` has four disks, ``hard_disk_gas:N`` has N."""
    if n < 1:
        raise ValueError(f"hard_disk_gas: n = {n}; give at least one disk")
    if radius is None:
        radius = side / math.ceil(math.sqrt(n)) / 5
    xs, ys = sp.symbols(f"x1:{n + 1}"), sp.symbols(f"y1:{n + 1}")
    m, r, big_l = sp.symbols("m r L")
    gx, gy = sp.symbols("g_x g_y")
    disks = [Particle(f"disk{i + 1}", m, (x, y)) for i, (x, y) in enumerate(zip(xs, ys))]
    constraints = []
    for i in range(n):
        x, y = xs[i], ys[i]
        walls = {"left": x - r, "right": big_l - r - x, "bottom": y - r, "top": big_l - r - y}
        constraints += [
            Unilateral(g, name=f"{wall}{i + 1}", restitution=1) for wall, g in walls.items()
        ]
    for i in range(n):
        for j in range(i + 1, n):
            gap = (xs[i] - xs[j]) ** 2 + (ys[i] - ys[j]) ** 2 - 4 * r**2
            constraints.append(Unilateral(gap, name=f"disks{i + 1}_{j + 1}", restitution=1))
    return System(
        name=f"hard_disk_gas_{n}",
        description=f"A gas of {n} elastic hard disks in a square box (walls and disk contacts)",
        coordinates=(*xs, *ys),
        parameters={m: 1.0, r: radius, big_l: side, gx: 0.0, gy: 0.0},
        particles=disks,
        gravity=(gx, gy),  # a uniform field on every disk, none by default
        constraints=constraints,
        initial=_lattice(xs, ys, n, radius, side),
        simulation={"t_end": 2.0, "samples": 201},
    )


def _lattice(
    xs: tuple[sp.Symbol, ...], ys: tuple[sp.Symbol, ...], n: int, radius: float, side: float
) -> dict[sp.Symbol, float]:
    """Centres on a square lattice filling the box, speeds 1 in seeded random directions."""
    per_row = math.ceil(math.sqrt(n))
    spacing = side / per_row
    if spacing < 2 * radius * 1.01:
        raise ValueError(
            f"hard_disk_gas: {n} disks of radius {radius} do not fit a box of side {side} on a "
            "lattice; give a smaller radius or fewer disks"
        )
    angles = np.random.default_rng(SEED).uniform(0.0, 2 * np.pi, n)
    initial: dict[sp.Symbol, float] = {}
    for k in range(n):
        row, column = divmod(k, per_row)
        initial[xs[k]] = (column + 0.5) * spacing
        initial[ys[k]] = (row + 0.5) * spacing
        initial[sp.Symbol(f"{xs[k].name}_dot")] = float(np.cos(angles[k]))
        initial[sp.Symbol(f"{ys[k].name}_dot")] = float(np.sin(angles[k]))
    return initial
