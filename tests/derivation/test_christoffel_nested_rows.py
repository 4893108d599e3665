"""C q_dot's rows written as sum over velocity pairs of the pair times its Christoffel
symbol (:meth:`TrigAlgebra.products_expression`): expanded, each is the flat row the
algebra writes from the row's polynomial, and converting it back gives that polynomial
(remembered, and the same as converting a copy of the expression afresh)."""

from __future__ import annotations

import symengine as se

from lagrangian.derivation.assemble import assemble
from lagrangian.derivation.kinetic import _christoffel, _christoffel_symbols, kinetic_form
from lagrangian.derivation.trig_polynomial import TrigAlgebra, algebra_for, forget_algebras
from lagrangian.examples import BENCHMARKS


def test_nested_rows_are_the_flat_rows() -> None:
    forget_algebras()
    asm = assemble(BENCHMARKS["whipple_bicycle"]())
    algebra = algebra_for([*asm.q, *asm.q_dot, *asm.q_ddot, asm.t])
    state = [*asm.q, *asm.q_dot, *asm.q_ddot, asm.t]
    entries = kinetic_form(asm).mass_matrix
    mass = [[algebra.finish(algebra.convert(se.expand(e))) for e in row] for row in entries]
    flat = _christoffel(algebra, mass, asm)
    for symbols, row in zip(_christoffel_symbols(algebra, mass, asm), flat):
        nested = algebra.products_expression(symbols)
        assert se.expand(nested - algebra.expression(row)) == 0
        assert algebra.convert(nested) == row
        fresh = TrigAlgebra(state)
        assert fresh.finish(fresh.convert(se.expand(nested))) == fresh.finish(
            fresh.convert(algebra.expression(row))
        )
