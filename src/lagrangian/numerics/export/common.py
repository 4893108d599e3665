"""What every export language shares: the argument layout, CSE, and the header text.

Every language gets the same functions (p in the order of ``eom.parameters``)::

    mass_matrix(q, t, p)              M                   (n x n)
    coriolis(q, qd, t, p)             C(q, qd) qd         (n)
    time_terms(q, qd, t, p)           explicit time terms (n)
    gravity(q, t, p)                  G = dV/dq           (n)
    generalized_forces(q, qd, t, p)   Q                   (n)
    forcing(q, qd, t, p)              M q_ddot = forcing  (n)
    rhs(t, x, p)                      x = [q; qd] -> [qd; q_ddot]   (regular M only)

A mass matrix (or G) that depends on the velocities takes ``qd`` too:
``mass_matrix(q, qd, t, p)``.  The model's symbols become array elements (``q[0]`` or ``q(1)``)
after a common-subexpression elimination over all outputs of one function.
"""

from __future__ import annotations

import keyword
import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType

import symengine as se
import sympy as sp
from sympy.printing.codeprinter import CodePrinter, PrintMethodNotImplementedError

from lagrangian.derivation.backend import SympyView, backend_entries, to_backend
from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import ModelError
from lagrangian.numerics.export.multiplier_form import HEADER as MULTIPLIER_HEADER
from lagrangian.numerics.export.multiplier_form import multiplier_pieces

#: Formats an array element for the header comments: (array name, 0-based position) -> text.
IndexFormat = Callable[[str, int], str]

#: Generated function -> (output variable, one-line summary).
OUTPUTS: dict[str, tuple[str, str]] = {
    "mass_matrix": ("M", "Mass matrix M ({n} x {n}), M q_ddot = forcing."),
    "coriolis": ("Cqd", "Coriolis and centrifugal terms, the vector C(q, qd) qd."),
    "time_terms": (
        "h",
        "Explicit time terms: d/dt dT/dqd - dT/dq besides M q_ddot + C qd (moving supports).",
    ),
    "gravity": ("G", "Potential forces G = dV/dq."),
    "generalized_forces": ("Q", "Applied generalized forces Q."),
    "forcing": ("f", "Right-hand side of M q_ddot = forcing."),
    "constraint_jacobian": ("A", "Constraint Jacobian A ({n} x n): A q_ddot = gamma."),
    "constraint_rhs": ("gamma", "gamma - 2 alpha c - beta^2 h, the right side of A q_ddot."),
    "augmented_matrix": ("K", "Augmented matrix [M, -A^T; A, 0] ({n} x {n})."),
    "augmented_forcing": ("r", "Augmented right side [forcing; gamma - 2 alpha c - beta^2 h]."),
}
#: The functions whose output is a matrix (the others return vectors).
MATRICES = ("mass_matrix", "constraint_jacobian", "augmented_matrix")
RHS_SUMMARY = "State derivative [qd; q_ddot] of x = [q; qd], with M q_ddot = forcing solved."


@dataclass(frozen=True)
class Routine:
    """One generated function: arguments, CSE temporaries and the outputs to assign."""

    name: str
    arguments: tuple[str, ...]
    temporaries: tuple[tuple[sp.Symbol, sp.Expr], ...]
    outputs: sp.ImmutableMatrix

    @property
    def output(self) -> str:
        return OUTPUTS[self.name][0]

    @property
    def summary(self) -> str:
        return OUTPUTS[self.name][1].format(n=self.outputs.rows)

    @property
    def is_matrix(self) -> bool:
        return self.name in MATRICES

    def uses(self, argument: str) -> bool:
        """Whether the generated body reads ``argument`` (``"q"``, ``"qd"``, ``"t"``, ``"p"``)."""
        exprs = [*self.outputs, *(e for _, e in self.temporaries)]
        names = {i.base.label.name for e in exprs for i in e.atoms(sp.Indexed)}
        names |= {s.name for e in exprs for s in e.atoms(sp.Symbol)}
        return argument in names

    def entries(self) -> list[tuple[int, int, sp.Expr]]:
        """(row, column, expression) of every output element, row-major."""
        rows, cols = self.outputs.shape
        return [(i, j, self.outputs[i, j]) for i in range(rows) for j in range(cols)]


@dataclass(frozen=True)
class ExportPlan:
    """The language-neutral content of an export: names, layout and the routines."""

    title: str
    base: str
    coordinates: tuple[str, ...]
    parameters: tuple[tuple[str, float | None], ...]
    routines: tuple[Routine, ...]
    singular_reason: str
    multipliers: tuple[str, ...] = ()

    @property
    def n(self) -> int:
        return len(self.coordinates)

    @property
    def m(self) -> int:
        """The number of constraints (0: the free equations)."""
        return len(self.multipliers)

    @property
    def solved(self) -> tuple[str, str]:
        """The functions rhs solves: (matrix, vector) of M q_ddot = forcing, or of the
        augmented system with constraints."""
        if self.m:
            return "augmented_matrix", "augmented_forcing"
        return "mass_matrix", "forcing"

    @property
    def solved_name(self) -> str:
        """The generated code's name for the matrix rhs solves: M, or K when augmented."""
        return "K" if self.m else "M"

    @property
    def solved_call(self) -> str:
        """The arguments rhs passes to the matrix it solves."""
        return ", ".join(self.routine(self.solved[0]).arguments)

    @property
    def has_rhs(self) -> bool:
        return not self.singular_reason

    def routine(self, name: str) -> Routine:
        return next(r for r in self.routines if r.name == name)

    def header(self, index: IndexFormat) -> list[str]:
        """The documentation every file starts with (lines without comment markers)."""
        lines = [
            f"{one_line(self.title)}: equations of motion exported by lagrangian.",
            "",
            "    M(q, t) q_ddot = forcing(q, qd, t)",
            "    forcing = generalized_forces + dissipation and velocity-potential forces",
            "              - coriolis - time_terms - gravity",
            "",
        ]
        if self.m:
            lines += [*MULTIPLIER_HEADER, ""]
        if self.has_rhs:
            lines.append("State x = [q; qd]; rhs(t, x, p) returns dx/dt = [qd; q_ddot].")
            if self.m:
                lines.append(
                    "multipliers(t, x, p) returns lambda (in the order of the constraints)."
                )
        else:
            lines.extend(["NO rhs IS GENERATED.", *wrap(self.singular_reason)])
        for routine in self.routines:
            if "qd" in routine.arguments and routine.name in ("mass_matrix", "gravity"):
                lines.append(f"{routine.name} depends on the velocities, so it takes qd too.")
        lines += ["", "Coordinates q (velocities qd in the same order):"]
        lines += [
            f"    {index('q', i)}  {one_line(name)}" for i, name in enumerate(self.coordinates)
        ]
        lines.append("Parameters p (default):" if self.parameters else "Parameters p: none.")
        for i, (name, default) in enumerate(self.parameters):
            value = "no default" if default is None else repr(default)
            lines.append(f"    {index('p', i)}  {one_line(name)} = {value}")
        return lines


def one_line(name: str) -> str:
    """``name`` as printable ASCII on one line (escapes for anything else), so that a name
    written into a comment can never end the comment and start code."""
    return name.encode("unicode_escape").decode("ascii")


def plan_export(
    eom: EquationsOfMotion, first_index: int = 0, name: str | None = None
) -> ExportPlan:
    """Map the model's symbols to array elements (counting from ``first_index``) and CSE
    every function's outputs together."""
    _check_symbols(eom)
    n = len(eom.coordinates)
    pieces: dict[str, sp.MatrixBase] = {
        "mass_matrix": eom.mass_matrix,
        "coriolis": eom.coriolis,
        "time_terms": eom.time_terms,
        "gravity": eom.gravity,
        "generalized_forces": eom.generalized_forces,
        "forcing": eom.forcing,
    }
    parameters = tuple((s, eom.parameters[s]) for s in eom.parameters)
    multipliers: tuple[str, ...] = ()
    if eom.system.constraints:
        extra, gains, multipliers = multiplier_pieces(eom)
        pieces.update(extra)
        parameters += tuple((gain, 0.0) for gain in gains)
    mapping: dict[sp.Basic, sp.Basic] = {eom.time: sp.Symbol("t")}
    for base, symbols in (
        ("q", eom.coordinates),
        ("qd", eom.velocities),
        ("p", tuple(s for s, _ in parameters)),
    ):
        array = sp.IndexedBase(base, shape=(len(symbols) + first_index,))
        mapping.update({s: array[i + first_index] for i, s in enumerate(symbols)})
    velocities = set(eom.velocities)
    routines = []
    for routine_name, matrix in pieces.items():
        positional = ("mass_matrix", "gravity", "constraint_jacobian", "augmented_matrix")
        with_qd = routine_name not in positional or bool(matrix.free_symbols & velocities)
        arguments = ("q", "qd", "t", "p") if with_qd else ("q", "t", "p")
        routines.append(_routine(routine_name, arguments, matrix, mapping))
    title = " ".join(eom.name.split()) or "model"
    return ExportPlan(
        title=title,
        base=sanitize(name if name is not None else eom.name),
        coordinates=tuple(q.name for q in eom.coordinates),
        parameters=tuple((s.name, None if v is None else float(v)) for s, v in parameters),
        routines=tuple(routines),
        singular_reason="" if eom.mass_matrix_is_regular else _singular_reason(eom, n),
        multipliers=multipliers,
    )


def _routine(
    name: str,
    arguments: tuple[str, ...],
    matrix: sp.MatrixBase,
    mapping: dict[sp.Basic, sp.Basic],
) -> Routine:
    # Constants other than pi and E have no spelling in every language: use their value.
    constants = {
        c: sp.Float(c.evalf(20), 20)
        for c in matrix.atoms(sp.NumberSymbol)
        if c not in (sp.pi, sp.E)
    }
    if constants:
        exprs = [e.xreplace(constants) for e in matrix]
        replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("s"), order="canonical")
        temporaries = tuple((s, e.xreplace(mapping)) for s, e in replacements)
        reduced = [e.xreplace(mapping) for e in reduced]
    else:
        temporaries, reduced = _backend_cse(matrix, mapping)
    outputs = sp.ImmutableMatrix(matrix.rows, matrix.cols, reduced)
    return Routine(name, arguments, temporaries, outputs)


def _backend_cse(
    matrix: sp.MatrixBase, mapping: dict[sp.Basic, sp.Basic]
) -> tuple[tuple[tuple[sp.Symbol, sp.Expr], ...], list[sp.Expr]]:
    """The common subexpressions of ``matrix``'s entries found by SymEngine's cse (in C++:
    SymPy's takes seconds per thousand entries, a 50-link chain's export 10 s of its 13),
    as (temporary s_k, its expression) pairs and the reduced entries, with ``mapping``
    (the model's symbols -> array elements) applied.

    The model's symbols are renamed first (``_a0``, ``_a1``, ...), so SymEngine's temporaries
    (``x0``, ``x1``, ...) cannot meet a model symbol of the same name; both are given their
    final form (array elements, ``s0``, ``s1``, ...) as they are converted back."""
    # the entries the derivation converted the matrix from, when it did (most pieces)
    known = backend_entries(matrix)
    entries = list(known) if known is not None else [to_backend(e) for e in matrix]
    originals = list(mapping)
    renamed = [se.Symbol(f"_a{i}") for i in range(len(originals))]
    # by name: a model symbol with assumptions converts to SymEngine by its name alone
    rename = {se.Symbol(s.name): r for s, r in zip(originals, renamed) if isinstance(s, sp.Symbol)}
    replacements, reduced = se.cse([e.xreplace(rename) if rename else e for e in entries])
    numbered = sp.numbered_symbols("s")
    names = {r.name: mapping[s] for s, r in zip(originals, renamed)}
    names.update({str(temporary): next(numbered) for temporary, _ in replacements})
    # one view: a subexpression that several entries share is built once
    view = SympyView((), names)
    temporaries = tuple((view(temporary), view(value)) for temporary, value in replacements)
    return temporaries, [view(e) for e in reduced]


def _check_symbols(eom: EquationsOfMotion) -> None:
    known = {*eom.coordinates, *eom.velocities, *eom.parameters, eom.time}
    found: set[sp.Basic] = set()
    pieces = (eom.mass_matrix, eom.coriolis, eom.time_terms, eom.gravity, eom.generalized_forces)
    for matrix in pieces:
        found |= matrix.free_symbols
    unknown = sorted(str(s) for s in (found | eom.forcing.free_symbols) - known)
    if unknown:
        raise ModelError(
            f"Cannot export: the equations use {', '.join(unknown)}, which are neither "
            "coordinates, velocities, parameters nor the time t. Declare them as parameters."
        )


def _singular_reason(eom: EquationsOfMotion, n: int) -> str:
    orders = ", ".join(f"{q}: {o}" for q, o in eom.orders_by_name().items())
    return (
        f"The mass matrix is singular (coordinate orders {orders}; 2 means inertia): "
        "coordinates without inertia give first-order or algebraic equations, so "
        "M q_ddot = forcing cannot be solved for q_ddot and there is no rhs(t, x, p) "
        f"for the {2 * n} states. Use mass_matrix and forcing with a DAE or "
        "mass-matrix solver, or lagrangian's own simulate."
    )


def sanitize(name: str | None) -> str:
    """A file and identifier name: ``"Double pendulum"`` -> ``"double_pendulum"``, or "model"."""
    base = re.sub(r"[^0-9a-zA-Z]+", "_", name or "").strip("_").lower()
    if not base:
        return "model"
    if base[0].isdigit():
        base = "model_" + base
    return base + "_model" if keyword.iskeyword(base) else base


def camel_case(base: str) -> str:
    """``"double_pendulum"`` -> ``"DoublePendulum"`` (a Julia module name)."""
    return "".join(part[:1].upper() + part[1:] for part in base.split("_") if part)


def wrap(text: str, width: int = 88) -> list[str]:
    """Split prose into comment lines of at most ``width`` characters."""
    lines: list[str] = []
    for word in text.split():
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += " " + word
        else:
            lines.append(word)
    return lines


def literal(value: float | None, nan: str, inf: str) -> str:
    """A float as a source literal; ``None`` (no default) becomes NaN."""
    if value is None or math.isnan(value):
        return nan
    if math.isinf(value):
        return inf if value > 0 else "-" + inf
    return repr(float(value))


#: The code printers' setting for the order of a sum's terms: as the expression holds them
#: (SymPy's canonical order), not sorted again for reading (sorting the terms of every sum is
#: a third of the time of printing a long chain's code, which is compiled, not read).
UNSORTED: Mapping[str, str] = MappingProxyType({"order": "none"})


def print_code(printer: CodePrinter, expr: sp.Basic, language: str) -> str:
    """``printer.doprint(expr)``, with unsupported functions reported as a ModelError."""
    try:
        return printer.doprint(expr)
    except PrintMethodNotImplementedError as error:
        raise ModelError(
            f"Cannot export to {language}: {error.args[0].splitlines()[0]}. "
            "Use the functions of the expression language (sin, cos, exp, sqrt, ...)."
        ) from None


def temporaries_code(
    routine: Routine, printer: CodePrinter, language: str
) -> list[tuple[sp.Symbol, str]]:
    """(name, code) of every common subexpression of ``routine``, in the order computed."""
    return [(s, print_code(printer, expr, language)) for s, expr in routine.temporaries]


def nonzero_entries_code(
    routine: Routine, printer: CodePrinter, language: str, first_index: int
) -> list[tuple[str, str]]:
    """(index, code) of every non-zero output element (the output starts as zeros), the index
    ``"i, j"`` of the mass matrix or ``"i"`` of a vector, counting from ``first_index``."""
    found = []
    for i, j, expr in routine.entries():
        if expr != 0:
            row, column = i + first_index, j + first_index
            index = f"{row}, {column}" if routine.is_matrix else f"{row}"
            found.append((index, print_code(printer, expr, language)))
    return found


def comment(lines: Sequence[str], marker: str) -> str:
    """Prefix each line with a comment marker (no trailing blanks on empty lines)."""
    return "\n".join(f"{marker} {line}".rstrip() for line in lines)
