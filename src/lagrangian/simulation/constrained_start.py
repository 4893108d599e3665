"""The initial state of a constrained run: taken as given when it satisfies the constraints,
moved onto them when asked (:func:`lagrangian.constraints.project_state`), refused otherwise.

Every integrator that holds constraints (the multiplier form, the variational one) starts the
same way; each measures the residual its own way and hands it here.

>>> import lagrangian as lg, sympy as sp
>>> from lagrangian.numerics.compile import compile_equations
>>> from lagrangian.simulation.inputs import resolve_inputs
>>> x, y, x_dot, y_dot = sp.symbols("x y x_dot y_dot")
>>> ring = lg.System(coordinates=[x, y], kinetic=(x_dot**2 + y_dot**2) / 2,
...     constraints=[lg.Holonomic(x**2 + y**2 - 1)])
>>> compiled = compile_equations(lg.derive(ring))
>>> start = {"x": 2.0, "y": 0.0, "x_dot": 0.0, "y_dot": 1.0}  # h = x**2 + y**2 - 1 = 3
>>> inputs = resolve_inputs(compiled, {"initial": start, "t_span": 1.0}, {}, {})
>>> start_on_constraints(ring, compiled.coordinates, inputs, 3.0, project_initial=True).x0
array([1., 0., 0., 1.])
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from lagrangian.constraints import project_state
from lagrangian.errors import SimulationError
from lagrangian.model import System
from lagrangian.simulation.inputs import Inputs

#: Largest constraint residual of an initial state accepted as is.
INITIAL_TOLERANCE = 1e-9


def start_on_constraints(
    system: System,
    coordinates: Sequence[str],
    inputs: Inputs,
    residual: float,
    project_initial: bool,
) -> Inputs:
    """``inputs`` when the largest constraint residual of its initial state is within
    ``INITIAL_TOLERANCE``; else, with ``project_initial``, the inputs with that state projected
    onto the constraints; else SimulationError saying how to fix it.  ``coordinates`` name
    the first half of the state x0 = [q; q_dot]."""
    if residual <= INITIAL_TOLERANCE:  # False for NaN: a state where h is not defined
        return inputs
    if not project_initial:
        raise SimulationError(
            f"The initial state violates the constraints: the largest residual is "
            f"{residual:.3g} (> {INITIAL_TOLERANCE:g}). Move it onto them with "
            "lagrangian.constraints.project_state, or pass project_initial=True."
        )
    n = len(coordinates)
    state: dict[str, float] = {**inputs.parameters, "t": inputs.t_span[0]}
    state.update(zip(coordinates, inputs.x0[:n].tolist()))
    state.update((name + "_dot", float(v)) for name, v in zip(coordinates, inputs.x0[n:]))
    projected = {symbol.name: value for symbol, value in project_state(system, state).items()}
    x0 = [projected[name] for name in coordinates] + [
        projected[f"{name}_dot"] for name in coordinates
    ]
    return dataclasses.replace(inputs, x0=np.array(x0, dtype=float))
