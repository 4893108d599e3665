"""The integration methods of :func:`lagrangian.simulate`: one table, read by every check and
every driver (which options apply, which engine runs a method, which may be projected).

* adaptive: SciPy's ``solve_ivp`` methods, the step chosen from ``rtol``, ``atol`` and
  bounded by ``max_step``;
* fixed: the classical RK4 (:mod:`lagrangian.simulation.integrators.rk4`), step ``dt``;
* variational: the variational integrators, step ``dt``: the midpoint rule
  (``variational``, :mod:`lagrangian.simulation.variational.midpoint`) and the symplectic
  collocation methods of order 4 and 6 (``gauss4``, ``gauss6``,
  :mod:`lagrangian.simulation.variational.collocation`).

Each method names the engines that run it, best first; the drivers take the first one that
can run here (nothing else decides which engine runs a method):

* ``"c"``: the C loop compiled once per machine (:mod:`lagrangian.numerics.fast.c_loop`), the
  one compiled engine of the explicit Runge–Kutta family (RK45, DOP853, RK4);
* ``"vectorized"``: a batch's members as the lanes of one Runge–Kutta stepper whose stages
  are computed for all members at once in NumPy
  (:mod:`lagrangian.simulation.batch.vectorized`), driven by the one Python loop: a batch's
  engine without a C compiler;
* ``"numba"``: the variational marches compiled by numba
  (:mod:`lagrangian.simulation.variational.compiled`) where it is installed;
* ``"python"``: the Python loop over a stepper (SciPy's solvers, RK4, the variational steps)
  as its one lane (:mod:`lagrangian.simulation.integrators.lanes`).

``backend="numba"`` is kept for one release as another name of the default: the C loop runs
RK45, DOP853 and RK4 (:func:`backend_note` says so in the run's note).

>>> method_named("DOP853").stepping, method_named("RK4").takes_tolerances
('adaptive', False)
>>> method_named("RK4").engines, runs_in("Radau", "c")
(('c', 'vectorized', 'python'), False)
>>> METHODS
('RK45', 'RK23', 'DOP853', 'Radau', 'BDF', 'LSODA', 'RK4')
>>> names_where("variational")
('variational', 'gauss4', 'gauss6')
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Mapping
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
    ``engines`` the engines that run it, best first (module docstring).
    """

    name: str
    stepping: str
    solver: str
    explicit: bool
    engines: tuple[str, ...] = ("python",)

    @property
    def compiled(self) -> bool:
        """Whether the compiled C loop runs it (the explicit Runge–Kutta family)."""
        return "c" in self.engines

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
_RK4 = "lagrangian.simulation.integrators.rk4"
#: The explicit Runge–Kutta methods with a tableau in the C loop and the batch's lanes stepper.
_RUNGE_KUTTA = ("c", "vectorized", "python")
#: The variational marches: compiled by numba where installed, else stepped in Python.
_MARCH = ("numba", "python")

#: Every method, by name, in the order the documentation lists them.
TABLE = MappingProxyType(
    {
        method.name: method
        for method in (
            Method("RK45", "adaptive", f"{_SCIPY}:RK45", explicit=True, engines=_RUNGE_KUTTA),
            Method("RK23", "adaptive", f"{_SCIPY}:RK23", explicit=True),
            Method("DOP853", "adaptive", f"{_SCIPY}:DOP853", explicit=True, engines=_RUNGE_KUTTA),
            Method("Radau", "adaptive", f"{_SCIPY}:Radau", explicit=False),
            Method("BDF", "adaptive", f"{_SCIPY}:BDF", explicit=False),
            Method("LSODA", "adaptive", f"{_SCIPY}:LSODA", explicit=False),
            Method("RK4", "fixed", f"{_RK4}:RK4", explicit=True, engines=_RUNGE_KUTTA),
            Method("variational", "variational", "", explicit=False, engines=_MARCH),
            Method("gauss4", "variational", "", explicit=False, engines=_MARCH),
            Method("gauss6", "variational", "", explicit=False, engines=_MARCH),
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
    ``"takes_tolerances"``, ``"takes_step"``, ``"variational"``), as the
    messages list them."""
    return tuple(name for name, method in TABLE.items() if getattr(method, condition))


def suggest_method(name: object) -> str:
    """The fix for an unknown method name: the closest known one, and the list."""
    lowered = {known.lower(): known for known in TABLE}
    close = difflib.get_close_matches(str(name).lower(), list(lowered), n=1, cutoff=0.4)
    hint = f"did you mean {lowered[close[0]]!r}? " if close else ""
    return f"{hint}methods: {tuple(TABLE)}"


def runs_in(name: str, engine: str) -> bool:
    """Whether the engine ``engine`` (module docstring) runs the method called ``name``."""
    method = TABLE.get(name)
    return method is not None and engine in method.engines


def engine_for(name: str, ready: Mapping[str, bool]) -> str:
    """The first engine of the method called ``name`` that is ``ready`` here (engine -> whether
    it can run: a compiler, numba installed); ``"python"`` runs every method.

    >>> engine_for("gauss4", {"numba": False})
    'python'
    """
    return next((e for e in TABLE[name].engines if ready.get(e, e == "python")), "python")


#: The backends of simulate and simulate_batch; "numba" another name of the default for one
#: release (the C loop replaced the numba loops of the Runge–Kutta methods).
BACKENDS = ("numpy", "numba")


def backend_note(backend: str) -> str:
    """What a run with ``backend`` says about it in its note (empty for the default)."""
    if backend == "numba":
        return (
            "backend='numba' is another name of the default backend for one release: RK45, "
            "DOP853 and RK4 run in the compiled C loop; drop backend='numba'."
        )
    return ""
