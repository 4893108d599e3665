"""Code generation: the equations of motion as NumPy, C, MATLAB/Octave or Julia source.

Every language gets the same functions, with ``p`` the parameter vector in the order of
``eom.parameters`` (each file lists the order of q and p, and the defaults)::

    mass_matrix(q, t, p)              M
    coriolis(q, qd, t, p)             the vector C(q, qd) qd
    time_terms(q, qd, t, p)           explicit time terms (moving supports, driven frames)
    gravity(q, t, p)                  G = dV/dq
    generalized_forces(q, qd, t, p)   Q
    forcing(q, qd, t, p)              M q_ddot = forcing
    rhs(t, x, p)                      x = [q; qd] -> [qd; q_ddot]   (regular M only)

and for a system with holonomic or velocity constraints the multiplier form
(:mod:`lagrangian.numerics.export.multiplier_form`): ``constraint_jacobian``,
``constraint_rhs``, ``augmented_matrix``, ``augmented_forcing``, an ``rhs`` that solves the
augmented system, and ``multipliers(t, x, p)``; Baumgarte's gains are the last two parameters.

>>> import lagrangian as lg
>>> from lagrangian.numerics.export import export
>>> sorted(export(lg.derive(lg.examples.simple_pendulum()), "c"))
['simple_pendulum.c', 'simple_pendulum.h']
"""

from __future__ import annotations

from collections.abc import Callable

from lagrangian.derivation import equations_of
from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import ModelError, require
from lagrangian.limits import bounded
from lagrangian.model import System
from lagrangian.numerics.export.c_code import export_c
from lagrangian.numerics.export.common import sanitize
from lagrangian.numerics.export.julia import export_julia
from lagrangian.numerics.export.matlab import export_matlab
from lagrangian.numerics.export.numpy_module import export_numpy


def _numpy_files(eom: EquationsOfMotion, base: str) -> dict[str, str]:
    return {f"{base}.py": export_numpy(eom)}


def _c_files(eom: EquationsOfMotion, base: str) -> dict[str, str]:
    source, header = export_c(eom)
    return {f"{base}.c": source, f"{base}.h": header}


def _julia_files(eom: EquationsOfMotion, base: str) -> dict[str, str]:
    return {f"{base}.jl": export_julia(eom)}


def _matlab_files(eom: EquationsOfMotion, base: str) -> dict[str, str]:
    return export_matlab(eom)


#: Language name -> (eom, base file name) -> {file name: content}.
LANGUAGES: dict[str, Callable[[EquationsOfMotion, str], dict[str, str]]] = {
    "numpy": _numpy_files,
    "c": _c_files,
    "matlab": _matlab_files,
    "julia": _julia_files,
}


@bounded("export")
def export(
    subject: System | EquationsOfMotion, language: str, *, time_limit: float | None = None
) -> dict[str, str]:
    """The generated files for ``language`` ("numpy", "c", "matlab" or "julia") of a System
    or its equations of motion, as file name -> content; file names come from the system's
    name (or "model").  ``time_limit`` bounds the work in seconds (TimeLimitError; default
    ``$LAGRANGIAN_TIME_LIMIT`` or :data:`lagrangian.limits.DEFAULT_SECONDS`).

    Raises ModelError for any other language.
    """
    eom = equations_of(subject, "export(subject, language)")
    require(language, str, "export(subject, language)", f"name one of {', '.join(LANGUAGES)}")
    writer = LANGUAGES.get(language.strip().lower())
    if writer is None:
        raise ModelError(f"Cannot export to {language!r}: choose one of {', '.join(LANGUAGES)}.")
    if eom.system.transitions:
        names = ", ".join(item.name for item in eom.system.transitions)
        raise ModelError(
            f"Cannot export {eom.name or 'this system'}: its transitions ({names}) reset the "
            "state where a guard crosses zero, so no one right-hand side describes the "
            "motion; simulate it with lagrangian itself."
        )
    return writer(eom, sanitize(eom.name))


__all__ = ["LANGUAGES", "export", "export_c", "export_julia", "export_matlab", "export_numpy"]
