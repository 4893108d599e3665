"""The view of a 3-D scene on the page: a projection P (2 x 3) taking world points to the
panel's (horizontal, vertical) axes, orthographic.

"xy", "xz", "yz" look along the missing axis (the first named axis to the right, the second
up); "isometric" looks from azimuth -60 degrees and elevation 30 degrees, z up (matplotlib's
default 3-D view):

    right = (-sin a, cos a, 0),   up = (-sin e cos a, -sin e sin a, cos e).

"auto" picks the plane a motion stays in (every point's coordinate along one world axis
constant: a cylinder rolling down an incline in the x-z plane is seen from the side), else the
isometric view.

>>> projection_matrix("xz")
array([[1., 0., 0.],
       [0., 0., 1.]])
"""

from __future__ import annotations

import numpy as np

from lagrangian.errors import Problem, SimulationInputError, raise_if_problems

#: The projections by name.
PROJECTIONS = ("auto", "xy", "xz", "yz", "isometric")
AZIMUTH = np.radians(-60.0)
ELEVATION = np.radians(30.0)


def projection_matrix(name: str) -> np.ndarray:
    """The 2 x 3 matrix of the view ``name`` (one of :data:`PROJECTIONS` but "auto")."""
    axes = {"x": 0, "y": 1, "z": 2}
    if len(name) == 2 and all(c in axes for c in name):
        matrix = np.zeros((2, 3))
        matrix[0, axes[name[0]]] = matrix[1, axes[name[1]]] = 1.0
        return matrix
    a, e = AZIMUTH, ELEVATION
    right = [-np.sin(a), np.cos(a), 0.0]
    up = [-np.sin(e) * np.cos(a), -np.sin(e) * np.sin(a), np.cos(e)]
    return np.array([right, up])


def chosen_projection(name: str, positions: np.ndarray) -> tuple[str, np.ndarray]:
    """The view asked for, or for "auto" the plane in which ``positions`` (frames, points,
    3) stay (their coordinate along the other axis constant), else isometric; its name and
    matrix.  SimulationInputError for an unknown name."""
    if name not in PROJECTIONS:
        fix = "use one of " + ", ".join(PROJECTIONS)
        problem = Problem("projection", f"{name!r} is not a projection", fix)
        raise_if_problems([problem], "Cannot draw the scene", SimulationInputError)
    if name != "auto":
        return name, projection_matrix(name)
    finite = positions[np.all(np.isfinite(positions), axis=-1)]
    if finite.size:
        spread = np.ptp(finite.reshape(-1, 3), axis=0)
        scale = max(float(np.max(np.abs(finite))), 1e-12)
        for plane, still in (("xz", 1), ("xy", 2), ("yz", 0)):
            moving = [k for k in range(3) if k != still]
            if spread[still] <= 1e-9 * scale and max(spread[moving]) > 0:
                return plane, projection_matrix(plane)
    return "isometric", projection_matrix("isometric")
