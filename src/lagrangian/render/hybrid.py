"""The jumps of a hybrid model, as derive writes them beside its equations: the impacts on
unilateral constraints (where g reaches 0 approaching, the velocities jump by the impulsive
Lagrange equations M (q_dot+ - q_dot-) = J^T Lambda with Newton's law dg/dt+ = -e dg/dt-) and
the transitions (where a guard crosses 0, the state is reset; the right-hand sides are read at
the state just before).  The equations of motion hold between the jumps; without these lines
a reader of the derivation could not tell a walker from a double pendulum.

>>> import lagrangian as lg
>>> print(hybrid_text(lg.examples.bouncing_ball()))
Impacts (M (q_dot+ - q_dot-) = J^T Lambda, dg/dt+ = -e dg/dt- where g reaches 0 approaching):
  floor: y >= 0, e = e
>>> hybrid_document(lg.examples.simplest_walker())["transitions"][0]["reset"]["theta"]
'-theta'
"""

from __future__ import annotations

from typing import Any

from lagrangian.model import System
from lagrangian.model.constraints import Unilateral
from lagrangian.model.transitions import Transition
from lagrangian.render.latex import KeptLatexPrinter, symbol_names
from lagrangian.render.mathml import Dotted, TableRow

IMPACTS = (
    "Impacts (M (q_dot+ - q_dot-) = J^T Lambda, dg/dt+ = -e dg/dt- where g reaches 0 approaching):"
)
TRANSITIONS = "Transitions (where a guard crosses 0; right-hand sides at the state before):"
#: A unilateral constraint without a coefficient of restitution.
NO_IMPACT = "no impact allowed (a run reaching one stops there)"


def has_jumps(system: System) -> bool:
    """Whether the model has impacts or transitions to write."""
    return bool(_unilateral(system) or system.transitions)


def _unilateral(system: System) -> list[tuple[int, Unilateral]]:
    return [(i, c) for i, c in enumerate(system.constraints) if isinstance(c, Unilateral)]


def _name(index: int, constraint: Unilateral) -> str:
    return constraint.name or f"constraints[{index}]"


def _crossing(transition: Transition) -> str:
    """``rising`` -> ``crosses 0 rising``; ``both`` -> ``crosses 0``."""
    return "crosses 0" + ("" if transition.direction == "both" else f" {transition.direction}")


def hybrid_text(system: System) -> str:
    """The impacts and transitions in plain text ('' when the model has neither)."""
    lines = []
    unilateral = _unilateral(system)
    if unilateral:
        lines.append(IMPACTS)
        for i, c in unilateral:
            law = NO_IMPACT if c.restitution is None else f"e = {c.restitution}"
            lines.append(f"  {_name(i, c)}: {c.expression} >= 0, {law}")
    if system.transitions:
        lines.append(TRANSITIONS)
        for item in system.transitions:
            condition = "" if item.when is None else f", if {item.when}"
            lines.append(f"  {item.name}: {item.guard} {_crossing(item)}{condition}:")
            lines += [f"    {key}+ = {value}" for key, value in item.reset]
    return "\n".join(lines)


def hybrid_document(system: System) -> dict[str, Any]:
    """What the jumps add to the derive JSON: ``restitution`` (constraint name -> e, None
    where no impact is allowed) and ``transitions`` (each with ``name``, ``guard``,
    ``direction``, ``when`` and ``reset``: name -> the value after the jump, an expression
    of the state before)."""
    document: dict[str, Any] = {}
    unilateral = _unilateral(system)
    if unilateral:
        document["restitution"] = {
            _name(i, c): None if c.restitution is None else str(c.restitution)
            for i, c in unilateral
        }
    if system.transitions:
        document["transitions"] = [
            {
                "name": item.name,
                "guard": str(item.guard),
                "direction": item.direction,
                "when": None if item.when is None else str(item.when),
                "reset": {str(key): str(value) for key, value in item.reset},
            }
            for item in system.transitions
        ]
    return document


def _text_latex(text: str) -> str:
    return r"\text{" + text.replace("_", r"\_") + "}"


def hybrid_latex_lines(system: System) -> list[str]:
    """The aligned lines of the impacts and transitions (none without them)."""
    tex = KeptLatexPrinter({"symbol_names": symbol_names(system.coordinates)}).doprint
    lines = []
    unilateral = _unilateral(system)
    if unilateral:
        lines.append(
            r"&\text{impacts: } M(\dot q^{+} - \dot q^{-}) = J^{T}\Lambda,\ "
            r"\dot g^{+} = -e\,\dot g^{-}"
        )
        for i, c in unilateral:
            law = _text_latex(NO_IMPACT) if c.restitution is None else f"e = {tex(c.restitution)}"
            lines.append(rf"{_text_latex(_name(i, c) + ': ')}{tex(c.expression)} &\geq 0,\ {law}")
    if system.transitions:
        lines.append(r"&\text{transitions: where a guard crosses 0}")
        for item in system.transitions:
            condition = "" if item.when is None else rf"\text{{, if }}{tex(item.when)}"
            lines.append(
                f"&{_text_latex(item.name + ': ')}{tex(item.guard)}"
                f"{_text_latex(' ' + _crossing(item))}{condition}"
            )
            lines += [f"{_after(tex(key))} &= {tex(value)}" for key, value in item.reset]
    return lines


def _after(name: str) -> str:
    """``\\dot{\\theta}`` -> ``\\dot{\\theta}^{+}`` (the value after the jump)."""
    return f"{{{name}}}^{{+}}"


def hybrid_mathml_rows(system: System, dotted: Dotted) -> list[TableRow]:
    """The rows of the impacts and transitions in derive's MathML table."""
    rows: list[TableRow] = []
    unilateral = _unilateral(system)
    if unilateral:
        rows.append((f"<mtext>{_escaped(IMPACTS)}</mtext>", "", ""))
        for i, c in unilateral:
            right = "<mn>0</mn>" + (
                f"<mtext>, {NO_IMPACT}</mtext>"
                if c.restitution is None
                else f"<mtext>, e = </mtext>{dotted(c.restitution)}"
            )
            rows.append((f"<mtext>{_name(i, c)}: </mtext>{dotted(c.expression)}", "&#8805;", right))
    if system.transitions:
        rows.append((f"<mtext>{_escaped(TRANSITIONS)}</mtext>", "", ""))
        for item in system.transitions:
            condition = "" if item.when is None else f"<mtext>, if </mtext>{dotted(item.when)}"
            rows.append(
                (
                    f"<mtext>{item.name}: </mtext>{dotted(item.guard)}"
                    f"<mtext> {_crossing(item)}</mtext>{condition}",
                    "",
                    "",
                )
            )
            rows += [
                (f"<msup>{dotted(key)}<mo>+</mo></msup>", dotted(value))
                for key, value in item.reset
            ]
    return rows


def _escaped(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
