"""Hamilton's principle with numbers: the action of a path, and the path that makes it stationary.

    A[q] = integral_{t0}^{t1} L(q, q_dot, t) dt,    delta A = 0 for every delta q with
    delta q(t0) = delta q(t1) = 0  <=>  q is the true motion (Goldstein 3rd ed., §2.1-2.3)

* :func:`action` integrates L along a Trajectory's samples (composite Simpson rule).
* :func:`stationary_path` solves the two-point boundary problem q(t0) = q_start,
  q(t1) = q_end by making the discrete action sum_k L_d(q_k, q_{k+1}) stationary (a
  variational integrator, midpoint rule).
* :func:`action_variation` evaluates A[q + eps eta] for a family of amplitudes eps; on the true
  path dA/deps = 0 at eps = 0.

>>> import lagrangian as lg
>>> path = stationary_path(lg.examples.simple_pendulum(), [0.0], [0.1], 0.5, nodes=20)
>>> round(float(path.q[10, 0]), 3), path.status  # sin(w t) / sin(w T) / 10 at t = T/2
(0.07, 'success')
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import simpson
from scipy.optimize import root

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Problem, SimulationError, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.simulation.inputs import parameter_values, time_span
from lagrangian.simulation.outcome import rows_with_energies
from lagrangian.simulation.trajectory import Trajectory, trajectory_of_rows
from lagrangian.simulation.variational.discrete import (
    LagrangianFunctions,
    prepare,
    residual_converged,
)
from lagrangian.symbolic.symbols import name_of

#: The method name recorded in the Trajectory of :func:`stationary_path`.
METHOD = "discrete action (midpoint rule)"


def action(system_or_eom: System | EquationsOfMotion, trajectory: Trajectory) -> float:
    """The action A = integral L(q, q_dot, t) dt along the samples of ``trajectory``.

    L is evaluated at every sample (parameters from ``trajectory.parameters`` over the
    defaults) and integrated by the composite Simpson rule (``scipy.integrate.simpson``), whose
    error is O(h^4) for a smooth L and even spacing h: 2001 samples over a few periods give
    10-12 digits.  Coarse or uneven samples lose accuracy; sample densely (``samples=``).

    Raises SimulationInputError when the trajectory's coordinates are not the system's or it
    has fewer than 2 samples.

    >>> import lagrangian as lg
    >>> from lagrangian.simulation import simulate
    >>> pendulum = lg.examples.simple_pendulum()
    >>> trajectory = simulate(pendulum, {"theta": 0.0}, 1.0, samples=101)
    >>> round(action(pendulum, trajectory), 6)  # at rest: L = m g l for one second
    9.81
    """
    functions, p = _along(system_or_eom, trajectory, "Cannot compute the action")
    return _integral(functions, trajectory.t, trajectory.q, trajectory.q_dot, p)


def stationary_path(
    system_or_eom: System | EquationsOfMotion,
    q_start: Mapping[Any, float] | ArrayLike,
    q_end: Mapping[Any, float] | ArrayLike,
    t_span: float | tuple[float, float],
    nodes: int = 50,
    parameters: Mapping[Any, float] | None = None,
) -> Trajectory:
    """The path from q(t0) = q_start to q(t1) = q_end that makes the discrete action stationary.

    With N = ``nodes`` intervals of length h = (t1 - t0)/N and the midpoint discrete Lagrangian

        L_d(q_k, q_{k+1}) = h L((q_k + q_{k+1})/2, (q_{k+1} - q_k)/h, t_k + h/2),

    the unknowns q_1 .. q_{N-1} solve the discrete Euler-Lagrange equations

        D2 L_d(q_{k-1}, q_k) + D1 L_d(q_k, q_{k+1}) = 0,
        D1 L_d = h/2 dL/dq - dL/dq_dot,   D2 L_d = h/2 dL/dq + dL/dq_dot   (at the midpoint),

    by ``scipy.optimize.root`` (hybr) from the straight line.  The nodes are second-order
    accurate in h (exact for L quadratic in q_dot with V linear in q); q_dot comes from
    second-order finite differences.  Where the boundary problem has several solutions (spans
    beyond a conjugate point), the one found is the one nearest the straight line.

    Parameters
    ----------
    q_start, q_end:
        Coordinates at t0 and t1, by name or in the order of the coordinates.
    t_span:
        T or (t0, T).
    nodes:
        Number of intervals N (the path has N + 1 samples, both ends included).
    parameters:
        Parameter values by name, over the defaults.

    Returns a Trajectory (method ``"discrete action (midpoint rule)"``) whose message gives the
    largest residual.  Raises SimulationInputError on bad input, SimulationError when the
    solver fails.
    """
    compiled, functions = prepare(system_or_eom)
    problems: list[Problem] = []
    values = parameter_values(compiled, parameters or {}, problems)
    t0, t1 = time_span(t_span, None, problems)
    start = _coordinates(compiled, q_start, "q_start", problems)
    end = _coordinates(compiled, q_end, "q_end", problems)
    if isinstance(nodes, bool) or not isinstance(nodes, int) or nodes < 2:
        problems.append(Problem("nodes", f"{nodes!r} is not an integer >= 2"))
    raise_if_problems(problems, "Cannot find the stationary path", SimulationInputError)
    p = _parameter_vector(compiled, values)
    t = np.linspace(t0, t1, nodes + 1)
    terms = _discrete_euler_lagrange(functions, t, start, end, p)
    guess = start + np.outer((t[1:-1] - t0) / (t1 - t0), end - start)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        solution = root(lambda x: np.add(*terms(x)), guess.ravel(), method="hybr")
        converged, worst = residual_converged(terms(solution.x))
    if not (converged or (solution.success and np.isfinite(worst))):
        raise SimulationError(
            f"No stationary path found: {solution.message} (largest residual of the discrete "
            f"Euler-Lagrange equations {worst:.3g}). Try more nodes, a shorter t_span, or end "
            "points closer together."
        )
    q = np.vstack((start, solution.x.reshape(guess.shape), end))
    return _path_trajectory(compiled, t, q, p, values, worst)


def action_variation(
    system_or_eom: System | EquationsOfMotion,
    trajectory: Trajectory,
    amplitudes: ArrayLike,
    shape: Callable[[float], ArrayLike] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Actions A[q + eps eta] of the varied paths, for each eps in ``amplitudes``.

        q_eps(t) = q(t) + eps eta(t),   q_dot_eps(t) = q_dot(t) + eps eta'(t),
        eta(t0) = eta(t1) = 0

    On the true path A is stationary, dA/deps = 0 at eps = 0, and quadratic near 0.
    ``shape`` is eta, a function t -> array of one value per coordinate vanishing at both ends
    (default sin(pi (t - t0)/(t1 - t0)) for every coordinate); its derivative is a central
    difference with step 1e-6 (t1 - t0).  Each action is :func:`action` (Simpson's rule).

    Returns (amplitudes, actions), two arrays of the same length.
    """
    functions, p = _along(system_or_eom, trajectory, "Cannot vary the action")
    eps = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    eta, eta_dot = _variation(trajectory, shape)
    actions = np.array(
        [
            _integral(
                functions, trajectory.t, trajectory.q + e * eta, trajectory.q_dot + e * eta_dot, p
            )
            for e in eps
        ]
    )
    return eps, actions


def _along(
    system_or_eom: System | EquationsOfMotion, trajectory: Trajectory, refusal: str
) -> tuple[LagrangianFunctions, np.ndarray]:
    """The compiled L of the system and the parameter vector of ``trajectory`` (its values
    over the defaults); SimulationInputError, headed ``refusal``, when the trajectory does not
    fit."""
    compiled, functions = prepare(system_or_eom)
    problems: list[Problem] = []
    values = parameter_values(compiled, trajectory.parameters, problems)
    _check_trajectory(compiled, trajectory, problems)
    raise_if_problems(problems, refusal, SimulationInputError)
    return functions, _parameter_vector(compiled, values)


def _parameter_vector(compiled: CompiledEquations, values: Mapping[str, float]) -> np.ndarray:
    """p in the order of the compiled parameters."""
    return np.array([values[name] for name in compiled.parameters], dtype=float)


def _integral(
    functions: LagrangianFunctions, t: np.ndarray, q: np.ndarray, qd: np.ndarray, p: np.ndarray
) -> float:
    """Simpson's rule for integral L dt over the samples."""
    return float(simpson(functions.lagrangian(q, qd, t, p), x=t))


def _discrete_euler_lagrange(
    functions: LagrangianFunctions,
    t: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    p: np.ndarray,
) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """The two terms of (D2 L_d(q_{k-1}, q_k) + D1 L_d(q_k, q_{k+1})) / h at the interior nodes.

    Divided by h the sum approximates dL/dq - d/dt dL/dq_dot at the node (units of a force):
    the terms are the mean dL/dq of the two neighbouring intervals and minus the change of
    dL/dq_dot across the node over h.
    """
    h = t[1] - t[0]
    midpoint_times = t[:-1] + h / 2

    def terms(interior: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        q = np.vstack((start, interior.reshape(-1, len(start)), end))
        midpoints, slopes = (q[1:] + q[:-1]) / 2, (q[1:] - q[:-1]) / h
        dq = functions.dL_dq(midpoints, slopes, midpoint_times, p)
        dv = functions.dL_dq_dot(midpoints, slopes, midpoint_times, p)
        return ((dq[:-1] + dq[1:]) / 2).ravel(), ((dv[:-1] - dv[1:]) / h).ravel()

    return terms


def _path_trajectory(
    compiled: CompiledEquations,
    t: np.ndarray,
    q: np.ndarray,
    p: np.ndarray,
    parameters: Mapping[str, float],
    worst: float,
) -> Trajectory:
    q_dot = np.gradient(q, t, axis=0, edge_order=2)
    return trajectory_of_rows(
        compiled.coordinates,
        rows_with_energies(compiled, p, t, q, q_dot),
        message=(
            f"The discrete action is stationary: largest residual of the discrete "
            f"Euler-Lagrange equations {worst:.3g}."
        ),
        method=METHOD,
        parameters=parameters,
    )


def _coordinates(
    compiled: CompiledEquations,
    given: Mapping[Any, float] | ArrayLike,
    field: str,
    problems: list[Problem],
) -> np.ndarray:
    """Coordinate values by name (a mapping) or in the order of the coordinates."""
    names = compiled.coordinates
    if isinstance(given, Mapping):
        by_name = {name_of(k): v for k, v in given.items()}
        unknown = sorted(set(by_name) - set(names))
        missing = [name for name in names if name not in by_name]
        if unknown or missing:
            problems.append(
                Problem(field, f"needs exactly the coordinates {names}", f"got {sorted(by_name)}")
            )
            return np.zeros(len(names))
        given = [by_name[name] for name in names]
    try:
        values = np.asarray(given, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        problems.append(Problem(field, f"{given!r} is not a list of numbers"))
        return np.zeros(len(names))
    if values.shape != (len(names),) or not np.all(np.isfinite(values)):
        problems.append(
            Problem(field, f"needs {len(names)} finite values, one per coordinate {names}")
        )
        return np.zeros(len(names))
    return values


def _check_trajectory(
    compiled: CompiledEquations, trajectory: Trajectory, problems: list[Problem]
) -> None:
    if tuple(trajectory.coordinates) != compiled.coordinates:
        problems.append(
            Problem(
                "trajectory",
                f"its coordinates {trajectory.coordinates} are not the system's "
                f"{compiled.coordinates}",
                "pass the trajectory of this system",
            )
        )
    if len(trajectory.t) < 2:
        problems.append(Problem("trajectory", "fewer than 2 samples", "simulate with samples="))


def _variation(
    trajectory: Trajectory, shape: Callable[[float], ArrayLike] | None
) -> tuple[np.ndarray, np.ndarray]:
    """eta and eta' at the samples, shape (N, n); eta must vanish at both ends."""
    t = trajectory.t
    t0, t1, n = float(t[0]), float(t[-1]), len(trajectory.coordinates)
    if shape is None:
        phase = np.pi * (t - t0) / (t1 - t0)
        eta = np.repeat(np.sin(phase)[:, None], n, axis=1)
        eta[[0, -1]] = 0.0  # sin(pi) is 1.2e-16, not 0
        return eta, np.repeat((np.pi / (t1 - t0) * np.cos(phase))[:, None], n, axis=1)

    def values(times: np.ndarray) -> np.ndarray:
        return np.array([np.broadcast_to(np.asarray(shape(s), dtype=float), (n,)) for s in times])

    step = 1e-6 * (t1 - t0)
    eta = values(t)
    ends = np.abs(eta[[0, -1]]).max()
    if ends > 1e-9 * max(np.abs(eta).max(), 1.0):
        raise SimulationInputError(
            f"The variation shape is {ends:.3g} at an end of the time span: Hamilton's "
            "principle varies the path with its ends fixed, so shape(t0) = shape(t1) = 0."
        )
    eta_dot = (values(t + step) - values(t - step)) / (2 * step)
    return eta, eta_dot
