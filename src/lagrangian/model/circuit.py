"""Circuit elements on charge coordinates (the electromechanical analogy: inductor ~ mass,
capacitor ~ spring, resistor ~ damper; Crandall et al., Dynamics of Mechanical and
Electromechanical Systems).

Charges are generalized coordinates; a current is an expression in their velocities (for a
mesh current ``q1_dot``, for a shared branch ``q1_dot - q2_dot``).  Contributions:

- inductor:          T += 1/2 L i^2
- mutual inductance: T += M i_a i_b
- capacitor:         V += q^2 / (2 C)
- resistor:          F += 1/2 R i^2   (Rayleigh dissipation)
- voltage source:    Q_coordinate += u(t)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.model.elements import as_expression


@dataclass(frozen=True)
class Inductor:
    """Magnetic energy 1/2 L i^2 of a branch carrying ``current``."""

    inductance: sp.Expr
    current: sp.Expr
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "inductance", as_expression(self.inductance))
        object.__setattr__(self, "current", as_expression(self.current))


@dataclass(frozen=True)
class MutualInductance:
    """Magnetic coupling energy M i_a i_b between two branches (M may depend on q)."""

    inductance: sp.Expr
    currents: tuple[sp.Expr, sp.Expr]
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "inductance", as_expression(self.inductance))
        object.__setattr__(self, "currents", tuple(as_expression(c) for c in self.currents))


@dataclass(frozen=True)
class Capacitor:
    """Electric energy q^2 / (2 C) of a capacitor holding ``charge`` (C may depend on q)."""

    capacitance: sp.Expr
    charge: sp.Expr
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "capacitance", as_expression(self.capacitance))
        object.__setattr__(self, "charge", as_expression(self.charge))


@dataclass(frozen=True)
class Resistor:
    """Dissipation 1/2 R i^2 of a resistor carrying ``current``."""

    resistance: sp.Expr
    current: sp.Expr
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "resistance", as_expression(self.resistance))
        object.__setattr__(self, "current", as_expression(self.current))


@dataclass(frozen=True)
class VoltageSource:
    """An applied voltage u(t), the generalized force on the charge ``coordinate``."""

    voltage: sp.Expr
    coordinate: Any
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "voltage", as_expression(self.voltage))


CircuitElement = Inductor | MutualInductance | Capacitor | Resistor | VoltageSource
CIRCUIT_TYPES = (Inductor, MutualInductance, Capacitor, Resistor, VoltageSource)
