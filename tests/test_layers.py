"""The folders are the architecture (DESIGN.md): imports point down the layers only."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "lagrangian"

# Layer ranks, top to bottom: a module may import its own layer or lower ranks only.
RANKS = {
    "cli": 9,
    "web": 9,
    "sweep": 9,
    "simulation": 8,
    "numerics": 7,
    "analysis": 6,
    "constraints": 6,
    "derivation": 5,
    "model": 4,
    "errors": 0,
}
# Side layers: io imports only model (and errors); render imports what it draws;
# examples build Systems (model) and may read model files (io).
ALLOWED_SIDE = {
    "io": {"io", "model", "errors"},
    "examples": {"examples", "model", "io", "errors"},
    "render": {
        "render",
        "model",
        "derivation",
        "constraints",
        "analysis",
        "numerics",
        "simulation",
        "errors",
    },
}


def _layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[0] == "lagrangian" else None


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.extend(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.append(node.module)
    return found


def _violations() -> list[str]:
    problems = []
    for path in PACKAGE.rglob("*.py"):
        relative = path.relative_to(PACKAGE)
        if len(relative.parts) == 1:
            continue  # lagrangian/__init__.py and errors.py sit at the top and bottom
        own = relative.parts[0]
        for module in _imports(path):
            target = _layer(module)
            if target is None or target == own:
                continue
            if own in ALLOWED_SIDE:
                ok = target in ALLOWED_SIDE[own]
            elif target in ALLOWED_SIDE:
                ok = (target == "io" and own in {"cli", "web", "sweep"}) or (
                    target in {"examples", "render"} and own in {"cli", "web", "sweep"}
                )
            else:
                ok = RANKS.get(target, 99) <= RANKS.get(own, -1)
            if not ok:
                problems.append(f"{relative}: imports {module} ({own} -> {target})")
    return problems


def test_every_import_points_down_the_layers() -> None:
    assert _violations() == []


def test_the_checker_sees_a_violation(tmp_path: Path, monkeypatch) -> None:
    # The check must be able to fail: a model module importing derive is flagged.
    fake = tmp_path / "lagrangian"
    (fake / "model").mkdir(parents=True)
    (fake / "model" / "bad.py").write_text("from lagrangian.derivation import derive\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", fake)
    assert _violations() == ["model/bad.py: imports lagrangian.derivation (model -> derivation)"]
