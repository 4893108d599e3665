"""The names the analysis introduces, chosen so that none is a name of the model.

An analysis writes symbols of its own beside the model's: the energy function h, the
Hamiltonian H, the momenta p_q, the frequencies omega, the effective potential V_eff, the
first integrals I_k.  A model may use any of them already (a hoop spinning at ``omega``, a
height ``h``), and then "omega = sqrt(...omega...)" says something false.  Each introduced
name is the textbook's unless the model has it; then the next of its alternatives (the
capital letter, as Omega for a frequency), else the name with the first free index.

>>> import sympy as sp
>>> names = OutputNames.avoiding({"omega", "h", "p_x"})
>>> names.frequency, names.energy, names.hamiltonian, names.momentum(sp.Symbol("x"))
('Omega', 'h_1', 'H', 'P_x')
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from itertools import count

import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.symbolic.caches import IdentityCache


@dataclass(frozen=True)
class OutputNames:
    """The names an analysis writes, none of them in ``taken`` (the model's names)."""

    taken: frozenset[str] = frozenset()

    @classmethod
    def avoiding(cls, taken: Iterable[str]) -> OutputNames:
        return cls(frozenset(taken))

    @classmethod
    def of(cls, eom: EquationsOfMotion) -> OutputNames:
        """The names free in the model of ``eom``: its coordinates and their derivatives,
        its parameters and every other symbol of its equations and energies (inputs);
        found once per equations object (several parts of one analysis ask)."""
        return _NAMES.get(eom, _model_names)

    def fresh(self, preferred: str, *alternatives: str) -> str:
        """``preferred`` unless the model has it, else the first free alternative, else
        ``preferred`` with the first free index (``h_1``)."""
        for name in (preferred, *alternatives):
            if name not in self.taken:
                return name
        return next(f"{preferred}_{k}" for k in count(1) if f"{preferred}_{k}" not in self.taken)

    @property
    def energy(self) -> str:
        """The energy function h (Jacobi's integral)."""
        return self.fresh("h")

    @property
    def hamiltonian(self) -> str:
        return self.fresh("H")

    @property
    def frequency(self) -> str:
        """A normal mode's angular frequency."""
        return self.fresh("omega", "Omega")

    @property
    def effective_potential(self) -> str:
        return self.fresh("V_eff", "U_eff")

    def momentum(self, coordinate: sp.Symbol) -> str:
        """The momentum conjugate to ``coordinate``: p_theta, else P_theta."""
        return self.fresh(f"p_{coordinate.name}", f"P_{coordinate.name}")

    def integral(self, index: int) -> str:
        """The ``index``-th first integral found by the search: I_1, else J_1."""
        return self.fresh(f"I_{index}", f"J_{index}")


def _model_names(eom: EquationsOfMotion) -> OutputNames:
    symbols = {*eom.coordinates, *eom.velocities, *eom.accelerations, *eom.parameters}
    for matrix in (eom.mass_matrix, eom.forcing):
        symbols |= matrix.free_symbols
    symbols |= eom.potential_energy.free_symbols
    return OutputNames.avoiding(s.name for s in symbols)


_NAMES: IdentityCache[EquationsOfMotion, OutputNames] = IdentityCache()

#: The textbook's names, for a model that uses none of them.
TEXTBOOK_NAMES = OutputNames()
