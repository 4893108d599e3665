"""The outlines a scene is drawn with, computed once in Python so every front end draws plain
polylines: a spring's coil, a damper's dashpot, circles and a box's edges in 3-D.

Arrays carry the frames first: ``a`` and ``b`` of shape (F, d) give outlines (F, N, d).

>>> coil = coil_line(np.array([[0.0, 0.0]]), np.array([[1.0, 0.0]]), turns=4, width=0.1)
>>> coil.shape, coil[0, 0].tolist(), coil[0, -1].tolist()
((1, 11, 2), [0.0, 0.0], [1.0, 0.0])
"""

from __future__ import annotations

import numpy as np

#: A spring's lead (straight part) at each end, as a fraction of its length.
LEAD = 0.12


def across(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The vector a -> b, its length (F, 1) and the unit normal to it in the plane (F, 2)."""
    along = b - a
    length = np.linalg.norm(along, axis=-1, keepdims=True)
    unit = np.divide(along, length, out=np.zeros_like(along), where=length > 0)
    normal = np.stack([-unit[:, 1], unit[:, 0]], axis=-1)
    return along, length, normal


def coil_line(a: np.ndarray, b: np.ndarray, turns: int, width: float) -> np.ndarray:
    """A spring from ``a`` to ``b`` (F, 2): a lead of :data:`LEAD` of its length at each end,
    between them ``turns`` zigzags of half-width ``width`` (so the coil stretches with the
    spring and its pitch shows the strain); (F, 2 turns + 4, 2)."""
    along, _, normal = across(a, b)
    fractions = np.concatenate(
        [[0.0, LEAD], np.linspace(LEAD, 1 - LEAD, 2 * turns + 1)[1:-1], [1 - LEAD, 1.0]]
    )
    sides = np.zeros_like(fractions)
    sides[2:-2] = np.where(np.arange(2 * turns - 1) % 2 == 0, 1.0, -1.0)
    return (
        a[:, None, :]
        + fractions[None, :, None] * along[:, None, :]
        + sides[None, :, None] * width * normal[:, None, :]
    )


def dashpot_line(a: np.ndarray, b: np.ndarray, width: float) -> np.ndarray:
    """A damper from ``a`` to ``b`` (F, 2) as one polyline: a rod from ``a`` to the piston
    (a bar across), the cylinder (open towards ``a``) fixed at ``b``'s end with its length
    a third of the rest distance, so the piston slides in it; (F, 10, 2)."""
    along, length, normal = across(a, b)
    unit = np.divide(along, length, out=np.zeros_like(along), where=length > 0)
    cylinder = 0.45 * length  # the cylinder's open end, from b
    piston = b - 0.3 * length * unit
    mouth = b - cylinder * unit
    w = width * normal
    return np.stack(
        [a, piston, piston + 0.8 * w, piston - 0.8 * w, piston,
         mouth + w, b + w, b - w, mouth - w, b],
        axis=1,
    )  # fmt: skip


def circle_points(
    centre: np.ndarray, first: np.ndarray, second: np.ndarray, radius: float, count: int = 33
) -> np.ndarray:
    """The circle of ``radius`` about ``centre`` in the plane of the unit vectors ``first``
    and ``second`` (all (F, d)): (F, count, d), closed (first point repeated last)."""
    angles = np.linspace(0.0, 2 * np.pi, count)
    return (
        centre[:, None, :]
        + radius * np.cos(angles)[None, :, None] * first[:, None, :]
        + radius * np.sin(angles)[None, :, None] * second[:, None, :]
    )


#: The corners of a box (signs along body x, y, z) in an order that walks its 12 edges.
BOX_WALK = (
    (-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, -1), (-1, -1, 1),
    (1, -1, 1), (1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1), (1, 1, 1), (-1, 1, 1),
    (-1, 1, -1), (-1, 1, 1), (-1, -1, 1),
)  # fmt: skip


def box_line(centre: np.ndarray, rotation: np.ndarray, half: np.ndarray) -> np.ndarray:
    """A box's 12 edges as one polyline: ``centre`` (F, 3), ``rotation`` (F, 3, 3) body ->
    world, ``half`` its half-lengths along the body axes; (F, 16, 3)."""
    corners = np.array(BOX_WALK, dtype=float) * half  # (16, 3) in body axes
    return centre[:, None, :] + np.einsum("fij,kj->fki", rotation, corners)
