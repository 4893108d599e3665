"""A run in pieces: integrators that change the equations at an event (active sets of
unilateral constraints, modes of a switched right-hand side) integrate piece by piece and
join the pieces into one :class:`~lagrangian.simulation.integrators.protocol.Integration`.

>>> import numpy as np
>>> first = Integration(t=np.array([0.0, 1.0]), x=np.array([[0.0], [1.0]]), t_reached=1.0,
...                     x_reached=np.array([1.0]))
>>> second = Integration(t=np.array([1.0, 2.0]), x=np.array([[1.0], [0.5]]), t_reached=2.0,
...                      x_reached=np.array([0.5]))
>>> joined([first, second]).t
array([0., 1., 2.])
"""

from __future__ import annotations

import dataclasses

import numpy as np

from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.protocol import Integration


def continued_from(inputs: Inputs, t: float, x: np.ndarray) -> Inputs:
    """The inputs of the next piece, from the state x at t."""
    t_out = inputs.t_out
    return dataclasses.replace(
        inputs,
        x0=np.array(x, dtype=float),
        t_span=(t, inputs.t_span[1]),
        t_out=None if t_out is None else t_out[t_out >= t],
    )


def joined(pieces: list[Integration]) -> Integration:
    """The pieces end to end (a row repeated at a junction is kept once); the last piece
    says how the run ended.  Multipliers and residuals are joined when every piece has them."""
    keep = [pieces[0]]
    for piece in pieces[1:]:
        last = keep[-1].t[-1] if len(keep[-1].t) else -np.inf
        later = piece.t > last
        keep.append(
            dataclasses.replace(
                piece,
                t=piece.t[later],
                x=piece.x[later],
                multipliers=_rows(piece.multipliers, later),
                constraint_residual=_rows(piece.constraint_residual, later),
            )
        )
    return dataclasses.replace(
        pieces[-1],
        t=np.concatenate([p.t for p in keep]),
        x=np.concatenate([p.x for p in keep]),
        events=tuple(event for p in pieces for event in p.events),
        multipliers=_joined_rows([p.multipliers for p in keep]),
        constraint_residual=_joined_rows([p.constraint_residual for p in keep]),
    )


def _rows(values: np.ndarray | None, mask: np.ndarray) -> np.ndarray | None:
    return None if values is None else values[mask]


def _joined_rows(parts: list[np.ndarray | None]) -> np.ndarray | None:
    if any(part is None for part in parts):
        return None
    return np.concatenate(parts)  # type: ignore[arg-type]
