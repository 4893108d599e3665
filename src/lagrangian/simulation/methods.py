"""The integration methods of :func:`lagrangian.simulate`: one table, read by every check and
every driver (which options apply, which backend runs a method, which may be projected).

* adaptive: SciPy's ``solve_ivp`` methods, the step chosen from ``rtol``, ``atol`` and
  bounded by ``max_step``;
* fixed: the classical RK4 (:mod:`lagrangian.simulation.integrators.rk4`), step ``dt``;
* variational: the variational integrators, step ``dt``: the midpoint rule
  (``variational``, :mod:`lagrangian.simulation.variational.midpoint`) and the symplectic
  collocation
  methods of order 4 and 6 (``gauss4``, ``gauss6``,
  :mod:`lagrangian.simulation.variational.collocation`).

>>> method_named("DOP853").stepping, method_named("RK4").takes_tolerances
('adaptive', False)
>>> METHODS
('RK45', 'RK23', 'DOP853', 'Radau', 'BDF', 'LSODA', 'RK4')
>>> names_where("variational")
('variational', 'gauss4', 'gauss6')
"""

from __future__ import annotations

import difflib
import importlib
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from scipy.integrate import OdeSolver


@dataclass(frozen=True)
class Method:
    """One integration method and what it can do.

    ``stepping`` is ``"adaptive"`` (tolerances), ``"fixed"`` (``dt``) or ``"variational"``
    (``dt``, a discrete Lagrangian instead of a vector field); ``solver`` the
    ``module:Class`` of its SciPy ``OdeSolver`` (empty for the variational ones);
    ``explicit`` whether it is an explicit Runge–Kutta method, which carries nothing but its
    last state from step to step, so that state may be projected onto constraints;
    ``compiled`` whether the numba backend runs it.
    """

    name: str
    stepping: str
    solver: str
    explicit: bool
    compiled: bool

    @property
    def takes_tolerances(self) -> bool:
        """Whether rtol, atol and max_step steer it (the adaptive methods)."""
        return self.stepping == "adaptive"

    @property
    def takes_step(self) -> bool:
        """Whether it steps by ``dt`` (the fixed-step and variational methods)."""
        return self.stepping != "adaptive"

    @property
    def variational(self) -> bool:
        """Whether it is a variational integrator (the discrete equations of motion of
        :mod:`lagrangian.simulation.variational.midpoint`, not a vector field)."""
        return self.stepping == "variational"

    @property
    def takes_events(self) -> bool:
        """Whether it locates events (on the dense output of a SciPy solver)."""
        return bool(self.solver)

    def solver_class(self) -> type[OdeSolver]:
        """The OdeSolver class (imported on first use: SciPy's integrators load late)."""
        module, name = self.solver.split(":")
        solver: type[OdeSolver] = getattr(importlib.import_module(module), name)
        return solver


_SCIPY = "scipy.integrate"

#: Every method, by name, in the order the documentation lists them.
TABLE = MappingProxyType(
    {
        method.name: method
        for method in (
            Method("RK45", "adaptive", f"{_SCIPY}:RK45", explicit=True, compiled=True),
            Method("RK23", "adaptive", f"{_SCIPY}:RK23", explicit=True, compiled=False),
            Method("DOP853", "adaptive", f"{_SCIPY}:DOP853", explicit=True, compiled=True),
            Method("Radau", "adaptive", f"{_SCIPY}:Radau", explicit=False, compiled=False),
            Method("BDF", "adaptive", f"{_SCIPY}:BDF", explicit=False, compiled=False),
            Method("LSODA", "adaptive", f"{_SCIPY}:LSODA", explicit=False, compiled=False),
            Method(
                "RK4",
                "fixed",
                "lagrangian.simulation.integrators.rk4:RK4",
                explicit=True,
                compiled=True,
            ),
            Method("variational", "variational", "", explicit=False, compiled=False),
            Method("gauss4", "variational", "", explicit=False, compiled=False),
            Method("gauss6", "variational", "", explicit=False, compiled=False),
        )
    }
)
#: The method used when neither the call nor the System names one.
DEFAULT_METHOD = "RK45"
#: The methods that integrate the state equations dx/dt = f(t, x) (all but the variational).
METHODS = tuple(name for name, method in TABLE.items() if method.solver)
#: The midpoint-rule variational integrator's name.
VARIATIONAL = "variational"


def method_named(name: str) -> Method:
    """The method called ``name``; KeyError when there is none (see :func:`suggest_method`)."""
    return TABLE[name]


def names_where(condition: str) -> tuple[str, ...]:
    """The names of the methods with the true attribute ``condition`` (``"explicit"``,
    ``"compiled"``, ``"takes_tolerances"``, ``"takes_step"``, ``"variational"``), as the
    messages list them."""
    return tuple(name for name, method in TABLE.items() if getattr(method, condition))


def suggest_method(name: object) -> str:
    """The fix for an unknown method name: the closest known one, and the list."""
    lowered = {known.lower(): known for known in TABLE}
    close = difflib.get_close_matches(str(name).lower(), list(lowered), n=1, cutoff=0.4)
    hint = f"did you mean {lowered[close[0]]!r}? " if close else ""
    return f"{hint}methods: {tuple(TABLE)}"
