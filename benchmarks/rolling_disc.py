"""Benchmark: the rolling disc in every formulation, from nothing to its constrained equations.

The disc
    A thin disc (mass m, radius r) rolling without slip on z = 0: 5 coordinates (a point's
    x, y, heading psi, lean theta, spin phi), 2 no-slip constraints, 3 independent velocities.

What is measured
    The wall time from nothing to the multiplier form (``lg.derive``, then
    ``lg.constrained_equations`` and its M, forcing, A and gamma), in a fresh process per run:

    element     the RollingDisc element (heading and lean frames, the wheel spinning in the
                lean frame by ``rotations``: the no-slip constraints generated);
    example     the built-in ``rolling_disc`` example (Euler angles ZXY, the constraints
                written in its model file);
    product     written by hand (``multibody.hand_rolling_disc``): the orientation the
                product Rz(psi) Rx(theta) Ry(phi) of rotation matrices, the contact's
                material velocity written out as two VelocityConstraints;
    expanded    the same with every entry of the matrix multiplied out;
    quaternion  the same with the orientation the product of the three half-angle
                quaternions;
    kane        sympy.physics.mechanics KanesMethod on the same disc (the contact point's
                velocity as its nonholonomic constraints), ``kanes_equations`` and its
                ``mass_matrix`` and ``forcing``.

    Untimed, the first run of each solves its equations for psi'', theta'' and phi'' at one
    rolling state (the dependent rates from its own constraints); the report compares them
    with KanesMethod's.

Usage
    python benchmarks/rolling_disc.py               # 3 runs of each
    python benchmarks/rolling_disc.py --record      # also write the section in RESULTS.md
"""

from __future__ import annotations

import json
import math
import statistics
import sys
from pathlib import Path

import multibody

HERE = Path(__file__).resolve()
BEGIN, END = "<!-- rolling_disc.py: begin -->", "<!-- rolling_disc.py: end -->"
METHODS = ("element", "example", "product", "expanded", "quaternion", "kane")
#: The state of the check (the other coordinates 0, x_dot and y_dot from the constraints).
STATE = {"psi": 0.4, "theta": -0.3, "phi": 0.7, "psi_dot": 1.0, "theta_dot": 0.5, "phi_dot": 5.0}
PARAMETERS = {"m": 1.0, "g": 9.81, "r": 0.3}
AGREE = 1e-9


def element_disc():
    """The disc of RollingDisc: the wheel turned in a lean frame, its centre (x, y,
    r cos(theta)), the no-slip constraints generated."""
    import sympy as sp

    import lagrangian as lg

    x, y, psi, theta, phi, m, g, r = sp.symbols("x y psi theta phi m g r")
    frames = [
        lg.Frame("heading", [("z", psi)]),
        lg.Frame("lean", [("x", theta)], parent="heading"),
    ]
    wheel = lg.RigidBody(
        "wheel",
        m,
        sp.diag(m * r**2 / 4, m * r**2 / 2, m * r**2 / 4),
        (x, y, r * sp.cos(theta)),
        parent="lean",
        rotations=[("y", phi)],
    )
    return lg.System(
        coordinates=[x, y, psi, theta, phi],
        parameters={m: 1.0, g: 9.81, r: 0.3},
        gravity=(0, 0, -g),
        frames=frames,
        rigid_bodies=[wheel],
        rolling=[lg.RollingDisc("wheel", r, axis="y")],
    )


def build(method: str):
    import lagrangian as lg

    if method == "element":
        return element_disc()
    if method == "example":
        return lg.examples.get("rolling_disc")()
    return multibody.hand_rolling_disc(method)


def derive(method: str):
    """The method's result: the System (lagrangian) or KanesMethod's pieces."""
    if method == "kane":
        found = multibody.kane_rolling_disc()
        found["method"].mass_matrix  # noqa: B018
        found["method"].forcing  # noqa: B018
        return found
    import lagrangian as lg

    system = build(method)
    lg.derive(system)
    equations = lg.constrained_equations(system)
    for matrix in ("mass_matrix", "forcing", "constraint_jacobian", "gamma"):
        getattr(equations, matrix)
    return system


def accelerations(method: str, found) -> list[float]:
    """psi'', theta'', phi'' at :data:`STATE`."""
    import numpy as np
    import sympy as sp

    import lagrangian as lg

    def numbers(matrix, values):
        return np.array(sp.Matrix(matrix).xreplace(values).evalf(30), dtype=float)

    names = ("psi", "theta", "phi")
    if method == "kane":
        kane = found["method"]
        plain = {qi: sp.Symbol(qi.func.__name__) for qi in found["q"]}
        plain.update({ui: sp.Symbol(ui.func.__name__) for ui in found["u"]})
        values = {sp.Symbol(k): v for k, v in {**PARAMETERS, **STATE}.items()}
        values.update({sp.Symbol(k): 0.0 for k in ("x", "y", "x_dot", "y_dot")})
        for rate, slip in zip(("x_dot", "y_dot"), found["slip"]):
            values[sp.Symbol(rate)] = -float(slip.xreplace(plain).xreplace(values))
        solved = np.linalg.solve(
            numbers(kane.mass_matrix.xreplace(plain), values),
            numbers(kane.forcing.xreplace(plain), values).ravel(),
        )
        return [float(a) for a in solved[:3]]  # the independent speeds first: psi, theta, phi
    equations = lg.constrained_equations(found)
    coordinates = [q.name for q in equations.coordinates]
    values = {s: PARAMETERS.get(s.name, 0.0) for s in found.parameters}
    values.update({q: STATE.get(q.name, 0.0) for q in equations.coordinates})
    values[lg.t] = 0.0
    rates = {sp.Symbol(f"{name}_dot"): STATE.get(f"{name}_dot", 0.0) for name in coordinates}
    jacobian = numbers(equations.constraint_jacobian, {**values, **rates})
    dependent = [coordinates.index("x"), coordinates.index("y")]
    given = [j for j in range(len(coordinates)) if j not in dependent]
    vector = np.array([rates[sp.Symbol(f"{name}_dot")] for name in coordinates])
    vector[dependent] = np.linalg.solve(jacobian[:, dependent], -jacobian[:, given] @ vector[given])
    rates = {sp.Symbol(f"{name}_dot"): v for name, v in zip(coordinates, vector)}
    values.update(rates)
    solved = np.linalg.solve(
        numbers(equations.augmented_matrix, values), numbers(equations.augmented_rhs, values)
    ).ravel()
    return [float(solved[coordinates.index(name)]) for name in names]


def worker(method: str, verify: bool) -> int:
    multibody.warm_up()
    clock = multibody.Stopwatch()
    found = derive(method)
    outcome: dict = clock.read()
    if verify:
        outcome["accelerations"] = accelerations(method, found)
    print(json.dumps(outcome), flush=True)
    return 0


def measure(repeat: int, cap: float) -> dict:
    times: dict = {m: [] for m in METHODS}
    found: dict = {}
    notes: list[str] = []
    for r in range(repeat):
        for method in METHODS:
            outcome = multibody.run_worker(HERE, [method], cap, verify=(r == 0))
            times[method].append(outcome["seconds"])
            if "error" in outcome:
                notes.append(f"{method}: error: {outcome['error']}")
            if "accelerations" in outcome:
                found[method] = outcome["accelerations"]
            print(f"  {method:<10} run {r + 1}: {outcome['seconds']:.3g} s", file=sys.stderr)
    theirs = found.get("kane")
    for method in METHODS[:-1]:
        if theirs is None or method not in found:
            notes.append(f"WARNING {method}: not checked")
            continue
        between = max(abs(a - b) / (1 + abs(b)) for a, b in zip(found[method], theirs))
        verdict = "agree" if between < AGREE else "WARNING differ"
        notes.append(
            f"{method}: psi'', theta'', phi'' = "
            + ", ".join(f"{a:.10g}" for a in found[method])
            + f"; with KanesMethod they {verdict} (max relative difference {between:.2g})."
        )
    return {"medians": {m: statistics.median(v) for m, v in times.items()}, "notes": notes}


def report(measured: dict, repeat: int, cap: float) -> str:
    medians = measured["medians"]
    kane = medians["kane"]
    lines = [
        f"Median of {repeat} run(s), seconds; cap {cap:g} s per run.",
        "",
        "| formulation | lagrangian s | KanesMethod s | Kane/lagrangian |",
        "|---|---:|---:|---:|",
    ]
    for method in METHODS[:-1]:
        ours = medians[method]
        ratio = kane / ours if math.isfinite(ours) and math.isfinite(kane) else math.nan
        lines.append(f"| {method} | {ours:.3g} | {kane:.3g} | {ratio:.3g} |")
    return "\n".join([*lines, "", *(f"- {note}" for note in measured["notes"])])


def main(argv: list[str] | None = None) -> int:
    args = multibody.benchmark_parser(__doc__, METHODS).parse_args(argv)
    if args.worker:
        return worker(args.worker, args.verify)
    text = report(measure(args.repeat, args.cap), args.repeat, args.cap)
    title = "The rolling disc in every formulation against KanesMethod (benchmarks/rolling_disc.py)"
    multibody.publish(text, "rolling_disc.py", argv, title, (BEGIN, END), args.record)
    return 0


if __name__ == "__main__":
    sys.exit(main())
