"""The members of one block as Trajectories, whichever way they were integrated.

A block is integrated as one compiled batch (:func:`lagrangian.simulate_batch`, constrained
systems in the multiplier form too), and member by member with :func:`lagrangian.simulate`
where the batch refuses it (unilateral constraints, a member off the constraints).  Either
way each member becomes the
Trajectory a single ``simulate`` of it returns — its rows, the energy function h where it
differs from T + V, the momenta of the cyclic coordinates, the multipliers, the constraint
residual and which of its columns the system conserves
(:mod:`lagrangian.simulation.conservation`) — so that one piece of code
(:mod:`lagrangian.sweeps.chunk_run`) turns either into the arrays of the store.

The stop condition of a member run by ``simulate`` is the batch's
(:mod:`lagrangian.simulation.batch.stop`): called with one member's arrays as the batch calls
it, a terminal event where g goes from positive to negative, and a member whose g is negative
at its start stops at once.

>>> import lagrangian as lg
>>> system = lg.examples.cylinder_on_incline()
>>> member = simulate_member(system, {}, {"alpha": 0.5}, 1.0, {"samples": 3})
>>> member.multiplier_names, member.t
(('lambda_1',), array([0. , 0.5, 1. ]))
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from lagrangian.derivation import derive
from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.numerics.compile import compile_equations
from lagrangian.simulation.batch.result import Batch
from lagrangian.simulation.batch.run import StopCondition
from lagrangian.simulation.batch.stop import STOP_EVENT, negative_at_start, stop_event
from lagrangian.simulation.conservation import not_conserved
from lagrangian.simulation.conserved import (
    compile_conserved,
    conserved_columns,
    conserved_expressions,
    momentum_obstructions,
)
from lagrangian.simulation.outcome import rows_with_energies
from lagrangian.simulation.run import simulate
from lagrangian.simulation.trajectory import DOT, Event, Rows, Trajectory, trajectory_of_rows


def simulate_member(
    system: System,
    initial: Mapping[str, float],
    parameters: Mapping[str, float],
    t_span: float | tuple[float, float] | None,
    stepping: Mapping[str, Any],
    stop_when: StopCondition | None = None,
    **options: Any,
) -> Trajectory:
    """One member by :func:`lagrangian.simulate` (``options``: its backend, project_initial).

    Never raises for the member's own sake: a failed integration is a Trajectory with status
    ``failed``, and a member whose input simulate refuses (an initial state off the
    constraints) one without rows and that message."""
    events = (stop_event(stop_when),) if stop_when is not None else ()
    try:
        member = simulate(
            system,
            dict(initial),
            t_span,
            parameters=dict(parameters),
            events=events,
            raise_on_failure=False,
            **options,
            **stepping,
        )
    except SimulationInputError as error:  # this member's values (the client checked the first)
        return _without_rows(system, f"Cannot simulate this member: {error}")
    except Exception as error:  # one member's failure must not take the block with it
        return _without_rows(system, f"Integration failed: {type(error).__name__}: {error}")
    if stop_when is not None and _negative_at_start(stop_when, member):
        return _stopped_at_start(member)
    return member


def stop_time(member: Trajectory) -> float:
    """When the stop condition stopped ``member``, NaN when it did not."""
    times = [event.t for event in member.events if event.name == STOP_EVENT]
    return float(times[-1]) if times else float("nan")


def impact_count(member: Trajectory) -> int:
    """How many impacts ``member`` met (those with an impulse: a transition's reset is not
    one), as the single run's summary counts them."""
    return sum(1 for impact in member.impacts if impact.impulses)


def rest_time(member: Trajectory) -> float:
    """When a contact of ``member`` first came to rest (its bounces accumulated and it stays
    in contact: ``Impact.rest``), NaN when none did."""
    times = [impact.t for impact in member.impacts if impact.rest]
    return float(times[0]) if times else float("nan")


def _negative_at_start(stop_when: StopCondition, member: Trajectory) -> bool:
    if not len(member.t):
        return False
    return negative_at_start(stop_when, float(member.t[0]), member.q[0], member.q_dot[0])


def _stopped_at_start(member: Trajectory) -> Trajectory:
    """``member`` cut to its first row, stopped there (as a batch stops such a member)."""
    first = slice(0, 1)
    cut: dict[str, Any] = {
        "t": member.t[first],
        "q": member.q[first],
        "q_dot": member.q_dot[first],
        "energy": member.energy[first],
        "conserved": {name: values[first] for name, values in member.conserved.items()},
    }
    for name in ("energy_function", "multipliers", "constraint_residual"):
        values = getattr(member, name)
        cut[name] = None if values is None else values[first]
    t0 = float(member.t[0])
    names = (*member.coordinates, *(name + DOT for name in member.coordinates))
    event = Event(STOP_EVENT, t0, {name: float(member[name][0]) for name in names})
    message = f"Stopped by stop_when at t = {t0:.6g}."
    return dataclasses.replace(
        member,
        **cut,
        events=(event,),
        impacts=(),  # those of the run past its start, which the cut leaves out
        status="success",
        message=message,
        message_template=None,
    )


def _without_rows(system: System, message: str) -> Trajectory:
    n = len(system.coordinates)
    empty = Rows(np.zeros(0), np.zeros((0, n)), np.zeros((0, n)), np.zeros(0))
    coordinates = tuple(q.name for q in system.coordinates)
    return trajectory_of_rows(coordinates, empty, status="failed", message=message)


def batch_members(system: System, batch: Batch) -> list[Trajectory]:
    """Each member of ``batch`` as the Trajectory ``simulate`` would return: the rows of
    :meth:`Batch.trajectory`, with h where it differs from T + V, the momenta of the cyclic
    coordinates and the columns the system does not conserve at the member's parameters."""
    eom = derive(system)
    compiled = compile_equations(eom)
    quantities = conserved_expressions(eom, system, {})
    function, names = compile_conserved(eom, quantities), tuple(quantities)
    differs = compiled.energy_function_differs
    reasons: dict[tuple[float, ...], dict[str, str]] = {}  # members often share parameters
    members = []
    for i in range(len(batch)):
        member = batch.trajectory(i)
        p = np.array([batch.parameters[name][i] for name in compiled.parameters], dtype=float)
        key = tuple(p.tolist())
        if key not in reasons:
            values = dict(member.parameters)
            momenta = momentum_obstructions(eom, system, values)
            reasons[key] = not_conserved(eom, values, differs, momenta)
        if not (differs or names or reasons[key]):
            members.append(member)  # nothing to add: its E = T + V is all there is
            continue
        rows = rows_with_energies(compiled, p, member.t, member.q, member.q_dot)
        columns = conserved_columns(function, names, member.q, member.q_dot, member.t, p)
        members.append(
            dataclasses.replace(
                member,
                energy_function=rows.energy_function,
                conserved=columns,
                not_conserved=reasons[key],
            )
        )
    return members
