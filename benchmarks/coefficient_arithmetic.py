"""Measurement: the bicycle's trigonometric-polynomial coefficients expanded by SymEngine and
as numbers (the groundwork of a coefficient algebra without SymEngine objects).

What is measured
    ``lg.derive`` of the built-in Whipple bicycle is run with every coefficient that
    :meth:`lagrangian.derivation.trig_polynomial.TrigAlgebra.finish` expands recorded (the
    unexpanded sums of products of parameters that the kinetic form and the forcing's
    tidying build).  Each is then expanded twice, in one process, timed apart (CPU):

    symengine   ``se.expand`` of each, as ``finish`` does;
    numbers     each as a dict from a parameter monomial, packed into one Python integer
                (4 bits per parameter's exponent), to an integer or Fraction coefficient:
                sums merge dicts, products add the packed keys and multiply the numbers,
                each distinct subexpression once.

    The check: every coefficient is a polynomial in the parameters (nothing else to keep
    whole), and both give the same number of terms for each.

Usage
    python benchmarks/coefficient_arithmetic.py
"""

from __future__ import annotations

import sys
import time
from fractions import Fraction
from typing import Any

import multibody

BITS = 4  # bits per parameter exponent in a packed monomial

Numbers = dict[int, Any]  # packed parameter monomial -> int or Fraction


def recorded_coefficients() -> tuple[list[Any], list[Any]]:
    """The coefficients ``finish`` expanded while deriving the built-in bicycle, and the
    bicycle's parameters (SymEngine)."""
    import symengine as se

    import lagrangian as lg
    from lagrangian.derivation import trig_polynomial
    from lagrangian.examples import BENCHMARKS

    seen: list[Any] = []
    finish = trig_polynomial.TrigAlgebra.finish

    def recording(p: dict) -> dict:
        seen.extend(p.values())
        return finish(p)

    trig_polynomial.TrigAlgebra.finish = staticmethod(recording)  # type: ignore[method-assign]
    try:
        system = BENCHMARKS["whipple_bicycle"]()
        lg.derive(system)
    finally:
        trig_polynomial.TrigAlgebra.finish = staticmethod(finish)  # type: ignore[method-assign]
    return seen, [se.sympify(p) for p in system.parameters]


def _merge(target: Numbers, key: int, value: Any) -> None:
    total = target.get(key, 0) + value
    if total:
        target[key] = total
    else:
        target.pop(key, None)


def _times(a: Numbers, b: Numbers) -> Numbers:
    out: Numbers = {}
    for ka, ca in a.items():
        for kb, cb in b.items():
            _merge(out, ka + kb, ca * cb)
    return out


def as_numbers(expr: Any, index: dict[Any, int], memo: dict[Any, Numbers | None]) -> Numbers | None:
    """``expr`` as a dict of packed parameter monomials; None when it is not a polynomial in
    the parameters."""
    if expr in memo:
        return memo[expr]
    result: Numbers | None
    if expr.is_Number:
        value = int(expr) if expr.is_Integer else Fraction(str(expr))
        result = {0: value} if value else {}
    elif expr.is_Symbol:
        result = {1 << (BITS * index[expr]): 1} if expr in index else None
    elif expr.is_Add or expr.is_Mul:
        parts = [as_numbers(a, index, memo) for a in expr.args]
        if any(p is None for p in parts):
            result = None
        elif expr.is_Add:
            result = {}
            for p in parts:
                for k, c in p.items():  # type: ignore[union-attr]
                    _merge(result, k, c)
        else:
            result = {0: 1}
            for p in parts:
                result = _times(result, p)  # type: ignore[arg-type]
    elif expr.is_Pow and expr.args[1].is_Integer and int(expr.args[1]) > 0:
        base = as_numbers(expr.args[0], index, memo)
        result = None if base is None else {0: 1}
        for _ in range(int(expr.args[1]) if base is not None else 0):
            result = _times(result, base)  # type: ignore[arg-type]
    else:
        result = None
    memo[expr] = result
    return result


def main() -> int:
    import symengine as se

    multibody.warm_up()
    coefficients, parameters = recorded_coefficients()
    index = {p: i for i, p in enumerate(parameters)}
    for _ in range(2):  # the second round is the one reported: both sides warm
        start = time.process_time()
        expanded = [se.expand(c) for c in coefficients]
        middle = time.process_time()
        memo: dict[Any, Numbers | None] = {}
        numbers = [as_numbers(c, index, memo) for c in coefficients]
        done = time.process_time()
    whole = sum(1 for n in numbers if n is None)
    counts = [len(e.args) if e.is_Add else int(e != 0) for e in expanded]
    same = sum(1 for c, n in zip(counts, numbers) if n is not None and c == len(n))
    print(
        f"{len(coefficients)} coefficients over {len(parameters)} parameters, {sum(counts)} terms"
    )
    print(f"symengine  se.expand       {middle - start:.3f} s CPU")
    print(f"numbers    packed dicts    {done - middle:.3f} s CPU")
    checked = same == len(coefficients) - whole and whole == 0
    print(
        f"{'PASS' if checked else 'FAIL'}  every coefficient a polynomial in the parameters, "
        f"the same number of terms both ways ({same} of {len(coefficients)})"
    )
    return 0 if checked else 1


if __name__ == "__main__":
    sys.exit(main())
