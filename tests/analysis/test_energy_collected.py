"""The energy function written as T + V + U(q, 0, t), nothing expanded, when T is a quadratic
form in the velocities: against h = sum q_dot dL/dq_dot - L taken by SymPy from L, on every
built-in example, and against a hand derivation of the n-link pendulum; written once in the
text and JSON reports."""

from __future__ import annotations

import json
import random
import sys
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.energy import collected_energy_function, energy_conservation
from lagrangian.cli.main import main

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "derivation"))
from test_energies import hand_energy


def numerically_zero(expr: sp.Expr, points: int = 3) -> bool:
    """``expr`` below 1e-9 at random points in (0.3, 1.3) (not the probe's own points)."""
    rng = random.Random(7)
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    for _ in range(points):
        value = complex(expr.xreplace({s: sp.Float(rng.uniform(0.3, 1.3)) for s in symbols}))
        if abs(value) > 1e-9:
            return False
    return True


def legendre_energy(eom: lg.EquationsOfMotion) -> sp.Expr:
    """h = sum_j q_dot_j dL/dq_dot_j - L, by SymPy from L as derived."""
    lagrangian = eom.lagrangian
    return sum((v * lagrangian.diff(v) for v in eom.velocities), sp.Integer(0)) - lagrangian


EXAMPLES = [name for name in lg.examples.names() if name not in {"whipple_bicycle"}]


@pytest.mark.parametrize("name", EXAMPLES)
def test_collected_energy_function_is_the_legendre_sum(name: str) -> None:
    eom = lg.derive(lg.examples.get(name)())
    collected = collected_energy_function(eom)
    if collected is None:  # T with terms of degree 0 or 1, or not polynomial: expanded h
        return
    assert numerically_zero(collected - legendre_energy(eom))


def test_most_examples_are_collected_and_a_rheonomic_one_is_not() -> None:
    collected = [
        name
        for name in EXAMPLES
        if collected_energy_function(lg.derive(lg.examples.get(name)())) is not None
    ]
    assert {"simple_pendulum", "double_pendulum", "planet", "charged_particle_em"} <= set(collected)
    # the pivot moves with time: T has parts of degree 0 and 1, h = T2 - T0 + V is not T + V
    assert "moving_pivot_pendulum" not in collected
    energy = energy_conservation(lg.examples.moving_pivot_pendulum())
    assert not energy.equals_total_energy


@pytest.mark.parametrize("n", [2, 5])
def test_chain_energy_function_is_the_hand_derived_total_energy(n: int) -> None:
    energy = energy_conservation(lg.examples.n_link_pendulum(n))
    assert energy.conserved and energy.equals_total_energy
    assert energy.total_energy is energy.energy_function
    assert numerically_zero(energy.energy_function - hand_energy(n))
    # written as the equations write T: the sums of masses not multiplied out
    masses = sp.Add(*sp.symbols(f"m1:{n + 1}"))
    assert energy.energy_function.has(masses)


def test_charged_particle_energy_keeps_the_scalar_potential() -> None:
    # U = q (phi - v.A): h = T + q phi, the part of U at rest (Goldstein §1.5, §8.1)
    eom = lg.derive(lg.examples.charged_particle_em())
    energy = energy_conservation(eom)
    scalar = eom.velocity_potential.xreplace({v: 0 for v in eom.velocities})
    assert scalar != 0
    assert numerically_zero(
        energy.energy_function - (eom.kinetic_energy + eom.potential_energy + scalar)
    )
    assert numerically_zero(energy.energy_function - legendre_energy(eom))


def test_text_report_writes_the_energy_function_once(capsys) -> None:
    args = ["analyze", "examples/n_link_pendulum:4", "--format", "text", "--search-degree", "0"]
    assert main(args) == 0
    out = capsys.readouterr().out
    conserved = out.split("Conserved:\n", 1)[1].split("\n\n", 1)[0]
    assert "h: the energy function (below)  [energy]" in conserved
    energy = out.split("Energy function:\n", 1)[1].split("\n\n", 1)[0].splitlines()
    assert energy[0].startswith("  h = ") and energy[-1] == "  h = T + V"
    written = sp.sympify(energy[0].split(" = ", 1)[1])
    assert numerically_zero(written - hand_energy(4))


def test_json_report_gives_the_energy_function_in_every_key(capsys) -> None:
    args = ["analyze", "examples/n_link_pendulum:3", "--format", "json", "--search-degree", "0"]
    assert main(args) == 0
    document = json.loads(capsys.readouterr().out)
    h = document["energy_function"]
    [entry] = [q for q in document["conserved_quantities"] if q["origin"] == "energy"]
    assert entry["expression"] == h and h in document["conserved"]
    assert document["energy"]["total_energy"] == h and document["energy"]["equals_total_energy"]
    assert numerically_zero(sp.sympify(h) - hand_energy(3))
