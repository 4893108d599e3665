"""No text from a user is ever run as Python: the source has no call of sympify (but the one
safe converter), parse_expr, eval or exec, except the generated code listed here with why."""

import ast
import pathlib

import pytest
import sympy as sp

from lagrangian.model import inertia

SOURCE = pathlib.Path(__file__).resolve().parents[1] / "src" / "lagrangian"

#: (file, function called): why it is safe.
ALLOWED = {
    ("symbolic/objects.py", "sympify"): "strict=True (refuses text) and numeric arrays only",
    ("numerics/fast/native.py", "exec"): "runs source lagrangian generates from SymEngine's "
    "printer, whose names are its own array elements",
}
FORBIDDEN = {"sympify", "parse_expr", "eval", "exec", "S"}


def _called(node: ast.Call) -> str | None:
    function = node.func
    if isinstance(function, ast.Name):
        return function.id
    if isinstance(function, ast.Attribute):
        owner = function.value
        if isinstance(owner, ast.Name) and owner.id in ("se", "symengine"):
            return None  # SymEngine's sympify does not evaluate text as Python
        return function.attr
    return None


def test_no_call_evaluates_text():
    found = []
    for path in SOURCE.rglob("*.py"):
        relative = path.relative_to(SOURCE).as_posix()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            name = _called(node) if isinstance(node, ast.Call) else None
            if name in FORBIDDEN and (relative, name) not in ALLOWED:
                found.append(f"{relative}:{node.lineno} {name}")
    assert found == []


def test_text_in_the_inertia_api_is_parsed_not_run(tmp_path):
    sentinel = tmp_path / "ran"
    code = f"__import__('os').system('touch {sentinel}')"
    for call in (
        lambda: inertia.parallel_axis(sp.eye(3), code, (1, 0, 0)),
        lambda: inertia.rotated([[code, 0, 0], [0, 1, 0], [0, 0, 1]], sp.eye(3)),
        lambda: inertia.parallel_axis([[code, 0, 0], [0, 1, 0], [0, 0, 1]], 1, (1, 0, 0)),
    ):
        with pytest.raises(ValueError, match="listed functions"):  # refused as bad input
            call()
    assert not sentinel.exists()
    # and text that is an expression still works
    assert (
        inertia.parallel_axis(sp.zeros(3), "m", ("a", 0, 0))[1, 1]
        == sp.Symbol("m") * sp.Symbol("a") ** 2
    )
