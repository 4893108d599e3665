"""The momenta dL/dq_dot and slopes dL/dq that the analysis reads are the steps' own, found
without the rest of the steps (d/dt dL/dq_dot and the tidied equations, n^2 terms each for a
chain): the same expressions whichever comes first."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian import examples
from lagrangian.derivation import steps

NAMES = [name for name in examples.names() if name not in ("n_link_pendulum", "hard_disk_gas")]


def fresh(name: str) -> lg.System:
    base, *size = name.split(":")
    # a System of its own, not the one examples.get keeps: nothing derived for it yet
    return examples.loads(examples.model_text(base, *[int(n) for n in size]))


@pytest.mark.parametrize("name", [*NAMES, "n_link_pendulum:7"])
def test_momenta_and_slopes_alone_are_the_steps_own(name):
    alone, whole = fresh(name), fresh(name)
    assert alone is not whole
    momenta, slopes = steps.step_momenta(alone), steps.step_slopes(alone)
    shown = steps.coordinate_steps(whole)
    assert [sp.srepr(p) for p in momenta] == [sp.srepr(s.dL_dvelocity) for s in shown]
    assert [sp.srepr(p) for p in slopes] == [sp.srepr(s.dL_dcoordinate) for s in shown]


def test_the_momenta_alone_take_no_time_derivative():
    system = fresh("n_link_pendulum:5")
    steps.step_momenta(system)
    steps.step_slopes(system)
    assert steps._DERIVATIVES.peek(system) is None
    # and the steps derived afterwards show the same momenta (the hand derivation:
    # p_1 = l1^2 (m1 + ... + m5) theta1_dot + ..., checked in test_steps_own_symbols)
    assert steps.coordinate_steps(system)[0].dL_dvelocity == steps.step_momenta(system)[0]
