"""Benchmark: the parts of a gas run whose cost grows with the number of contacts, timed one
by one (best of several calls), to compare two versions of the code on one machine.

What is measured, for ``--disks`` hard disks of radius 0.02 (``hard_disk_gas(n, radius=0.02)``)
    conserved   ``conserved_expressions`` and ``momentum_obstructions`` of the gas without a
                field (every coordinate absent from L, every one met by a wall): which
                momenta a simulation reports, first call and again;
    columns     a run's ``Trajectory.columns()``, ``to_csv`` and ``from_csv`` (one multiplier
                column per contact);
    flight      ``quadratic_gaps`` of every contact (once per run's setup), then
                ``QuadraticGaps.along`` on 1 gap (an impact's bounce check) and on the ~4 n
                gaps of two disks (the calendar after a collision), their
                ``first_crossings``, and ``resolve`` of a lone contact (its closed form);
    compiled    the compiled step alone (``numerics/fast/c_flight.py``'s ``fly``): flights,
                lone impacts and calendar updates of the gas from its start over ``--t-end``,
                per impact (where there is a C compiler).

Usage
    python benchmarks/impacts_parts.py --disks 40
"""

from __future__ import annotations

import argparse
import io
import time
from collections.abc import Callable

import numpy as np
import sympy as sp

import lagrangian as lg
from lagrangian.examples.gas import hard_disk_gas
from lagrangian.numerics.fast import c_flight
from lagrangian.simulation.conserved import conserved_expressions, momentum_obstructions
from lagrangian.simulation.flight import Calendar, first_crossings, quadratic_gaps
from lagrangian.simulation.impacts import resolve


def best(
    work: Callable[[], object], repeat: int = 5, clock: Callable[[], float] = time.perf_counter
) -> float:
    """The least time of ``repeat`` calls of ``work`` on ``clock``."""
    times = []
    for _ in range(repeat):
        started = clock()
        work()
        times.append(clock() - started)
    return min(times)


def conserved_part(disks: int) -> tuple[float, float]:
    gas = hard_disk_gas(disks, radius=0.02)
    speeds = [sp.Symbol(f"{q.name}_dot") for q in gas.coordinates]
    flying = gas.replace(
        particles=(), gravity=None, potential=0, kinetic=sum(v**2 for v in speeds) / 2
    )
    eom = lg.derive(flying)

    def ask() -> None:
        conserved_expressions(eom, flying, {})
        momentum_obstructions(eom, flying, {})

    first = best(ask, 1)
    return first, best(ask)


def columns_part(disks: int) -> tuple[float, float, float]:
    gas = hard_disk_gas(disks, radius=0.02)
    run = lg.simulate(lg.derive(gas), dict(gas.initial), 0.2, samples=11)
    buffer = io.StringIO()
    run.to_csv(buffer)
    text = buffer.getvalue()
    return (
        best(run.columns),
        best(lambda: run.to_csv(io.StringIO())),
        best(lambda: lg.Trajectory.from_csv(io.StringIO(text))),
    )


def flight_part(disks: int) -> tuple[float, float, float, float, float]:
    """Reading every contact's polynomial (once per run's setup), a flight's gap polynomials
    on 1 gap and on the gaps of two disks, their first crossings, and a lone contact's
    impulse (``resolve`` of one disk pair)."""
    gas = hard_disk_gas(disks, radius=0.02)
    values = {s: sp.Float(v) for s, v in gas.parameters.items()}
    expressions = [c.expression for c in gas.constraints]
    started = time.perf_counter()
    gaps = quadratic_gaps(expressions, range(len(expressions)), gas.coordinates, values)
    read = time.perf_counter() - started
    assert gaps is not None
    rng = np.random.default_rng(1)
    n = len(gas.coordinates)
    q, v, a = rng.uniform(0, 1, n), rng.normal(size=n), np.zeros(n)
    pair = np.unique(np.concatenate([gaps.incidence[0], gaps.incidence[1]]))
    one = np.array([0])
    coefficients = gaps.along(pair, q, v, a)
    contact = np.array([len(expressions) - 1])
    jacobian = gaps.gradients(contact, q)
    inverse = np.eye(n)

    def impulse() -> object:
        return resolve(inverse, jacobian, -np.abs(jacobian @ v), [], [0], [1.0], v, inverse)

    return (
        read,
        best(lambda: gaps.along(one, q, v, a), 200),
        best(lambda: gaps.along(pair, q, v, a), 200),
        best(lambda: first_crossings(*coefficients), 200),
        best(impulse, 200),
    )


def compiled_part(disks: int, t_end: float) -> tuple[int, float, float] | None:
    """(impacts, seconds per impact, CPU seconds per impact) of the compiled step flying the
    gas from its start (every disk of mass 1, e = 1, no field), None without a C compiler
    (CPU time: on a shared machine the wall time carries the waits for a core)."""
    if not c_flight.available():
        return None
    gas = hard_disk_gas(disks, radius=0.02)
    values = {s: sp.Float(v) for s, v in gas.parameters.items()}
    expressions = [c.expression for c in gas.constraints]
    gaps = quadratic_gaps(expressions, range(len(expressions)), gas.coordinates, values)
    assert gaps is not None
    n = len(gas.coordinates)
    by_name = {str(key): value for key, value in gas.initial.items()}
    x0 = np.array([by_name[q.name] for q in gas.coordinates]
                  + [by_name[f"{q.name}_dot"] for q in gas.coordinates])  # fmt: skip
    a = np.zeros(n)
    model = c_flight.FlightModel(gaps.augmented_index, gaps.forms, gaps.incidence, np.eye(n),
                                 np.ones(len(expressions)), a)  # fmt: skip
    calendar = Calendar(gaps)
    calendar.next(0.0, x0[:n], x0[n:], a, np.zeros(len(expressions), dtype=bool))
    impacts = []

    def flights() -> None:
        times = calendar.times.copy()
        flown = c_flight.fly(model, times, 0.0, x0, t_end, np.zeros(0), 4096,
                             (1e-12, 1e-10, 1e-8))  # fmt: skip
        impacts.append(len(flown.impact_t))

    seconds, cpu = best(flights), best(flights, clock=time.process_time)
    return impacts[-1], seconds / max(impacts[-1], 1), cpu / max(impacts[-1], 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--disks", type=int, default=40)
    parser.add_argument("--t-end", type=float, default=2.0, help="of the compiled step")
    args = parser.parse_args()
    compiled = compiled_part(args.disks, args.t_end)
    if compiled is not None:
        print(
            f"the compiled step alone: {compiled[0]} impacts over t_end = {args.t_end:g}, "
            f"{compiled[1] * 1e6:.3g} us per impact ({compiled[2] * 1e6:.3g} us of CPU)"
        )
    first, again = conserved_part(args.disks)
    print(f"conserved momenta, {args.disks} disks without a field: first {first:.3g} s, "
          f"again {again:.3g} s")  # fmt: skip
    columns, written, read = columns_part(args.disks)
    print(f"Trajectory with a column per contact: columns() {columns * 1e3:.3g} ms, to_csv "
          f"{written * 1e3:.3g} ms, from_csv {read * 1e3:.3g} ms")  # fmt: skip
    read, single, pair, crossings, impulse = flight_part(args.disks)
    print(f"every contact's polynomial read: {read:.3g} s; a flight's gap polynomials: 1 gap "
          f"{single * 1e6:.3g} us, the gaps of two disks {pair * 1e6:.3g} us, their first "
          f"crossings {crossings * 1e6:.3g} us; a lone contact's impulse "
          f"{impulse * 1e6:.3g} us")  # fmt: skip


if __name__ == "__main__":
    main()
