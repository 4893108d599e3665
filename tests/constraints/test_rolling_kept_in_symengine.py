"""Each rolling contact's constraint is kept in SymEngine as it was made
(lagrangian.model.contact.MADE), and the constraints' forms start from it instead
of converting the SymPy constraint back: it is the expression that conversion gives (equal,
printed alike) for the built-in models with rolling contacts and for wheels of other shapes
and positions, and the forms made from it are those made from the conversion (srepr-equal)."""

from __future__ import annotations

import pytest
import sympy as sp

from lagrangian.constraints import pfaffian
from lagrangian.constraints.pfaffian import backend, pfaffian_form
from lagrangian.examples import BENCHMARKS, CATALOG
from lagrangian.model import Frame, RigidBody, RollingDisc, System, shape
from lagrangian.model.contact import MADE, rolling_sphere
from lagrangian.symbolic.caches import forget_all
from lagrangian.symbolic.native import to_symengine_sharing

x, y, z, a, b, c, psi, theta, phi = sp.symbols("x y z a b c psi theta phi")
m, r, R, rt, k = sp.symbols("m r R r_t k")


def _torus_wheel() -> System:
    wheel = RigidBody(
        "wheel",
        m,
        sp.diag(1, 2, 1),
        (x, y, R * sp.cos(theta) + rt),
        parent="lean",
        rotations=[("y", phi)],
    )
    return System(
        coordinates=[x, y, psi, theta, phi],
        parameters={m: 1.3, R: 0.3, rt: 0.05},
        frames=[
            Frame("heading", [("z", psi)]),
            Frame("lean", [("x", theta)], parent="heading"),
        ],
        rigid_bodies=[wheel],
        rolling=[RollingDisc("wheel", R, "y", tyre_radius=rt)],
    )


def _ball() -> System:
    body = RigidBody(
        "ball", m, shape("solid_sphere", radius=r), (x, y, r), rotations=[("z", a), ("y", b)]
    )
    return System(
        coordinates=[x, y, a, b],
        parameters={m: 2.0, r: 0.1},
        rigid_bodies=[body],
        rolling=[rolling_sphere("ball", r)],
    )


def _wheel_with_exp() -> System:
    """A wheel whose centre holds exp: its coefficients are tidied by the walk."""
    wheel = RigidBody(
        "wheel",
        m,
        shape("disc", radius=r, axis="y"),
        (x + sp.exp(k * theta), y, z),
        rotations=[("z", psi), ("x", theta)],
    )
    return System(
        coordinates=[x, y, z, psi, theta],
        parameters={m: 1.0, r: 0.3, k: 0.5},
        rigid_bodies=[wheel],
        rolling=[RollingDisc("wheel", r)],
    )


def _built(name: str) -> System:
    build = BENCHMARKS[name] if name in BENCHMARKS else CATALOG[name]
    return build.__wrapped__()  # type: ignore[attr-defined]


SYSTEMS = {
    "whipple_bicycle": lambda: _built("whipple_bicycle"),
    "rolling_coin": lambda: _built("rolling_coin"),
    "torus": _torus_wheel,
    "ball": _ball,
    "exp": _wheel_with_exp,
}


def _kept(constraint: object, table: object = MADE) -> object:
    made = table.peek(constraint)  # type: ignore[attr-defined]
    return None if made is None else made.expression


@pytest.mark.parametrize("name", SYSTEMS)
def test_a_rolling_constraint_kept_in_symengine_is_its_conversion(name: str) -> None:
    system = SYSTEMS[name]()
    kept = [_kept(constraint) for constraint in system.constraints]
    assert any(fast is not None for fast in kept)
    for constraint, fast in zip(system.constraints, kept):
        if fast is None:
            continue
        converted = to_symengine_sharing(constraint.expression, {})
        assert fast == converted
        assert str(fast) == str(converted)


@pytest.mark.parametrize("name", ["whipple_bicycle", "torus", "exp"])
def test_the_forms_from_the_kept_expressions_are_those_from_the_conversion(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    def forms() -> list[str]:
        forget_all()  # no form or conversion remembered from before
        system = SYSTEMS[name]()
        made = [pfaffian_form(c, system.coordinates) for c in system.constraints]
        for constraint in system.constraints:
            fast = backend(constraint.expression)
            assert fast == to_symengine_sharing(constraint.expression, {})
            kept = _kept(constraint, pfaffian.MADE)
            assert kept is None or fast is kept  # not converted again
        return [sp.srepr((f.coefficients, f.time_coefficient, f.velocity_expression)) for f in made]

    kept = forms()
    monkeypatch.setattr(pfaffian, "MADE", type(MADE)())
    assert forms() == kept
