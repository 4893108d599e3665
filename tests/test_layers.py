"""The folders are the architecture (docs/architecture.md): imports point down the layers
only, and no module reaches into another's private names."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "lagrangian"

# Layer ranks, top to bottom: a module may import its own layer or lower ranks only.
# The command line may start the playground (``lagrangian serve``); the playground never
# imports the command line: what both print is in ``documents`` below them.
RANKS = {
    "cli": 11,
    "web": 10,
    "sweeps": 10,
    "documents": 9,
    "simulation": 8,
    "numerics": 7,
    "analysis": 6,
    "constraints": 6,
    "derivation": 5,
    "model": 4,
    "symbolic": 3,
    "limits": 0,
    "lazy_names": 0,
    "compiled": 0,
    "size_limits": 0,
    "errors": 0,
}
# Side layers: io imports only model (with its symbolic tools, and errors); render imports
# what it draws; examples build Systems (model) and may read model files (io).
ALLOWED_SIDE = {
    "io": {"io", "model", "symbolic", "errors"},
    "examples": {"examples", "model", "symbolic", "io", "errors"},
    "render": {
        "render",
        "symbolic",
        "model",
        "derivation",
        "constraints",
        "analysis",
        "numerics",
        "simulation",
        "errors",
    },
}


#: The layers that may use every side layer (io, examples, render): the front ends and what
#: they print.
FRONT_ENDS = {"cli", "web", "sweeps", "documents"}


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
            # ``from lagrangian import simulation`` imports lagrangian.simulation: name the
            # package the import reaches, not only the one it is written from
            if node.module == "lagrangian":
                found.extend(f"lagrangian.{alias.name}" for alias in node.names)
            else:
                found.append(node.module)
    return found


def _violations() -> list[str]:
    problems = []
    for path in PACKAGE.rglob("*.py"):
        relative = path.relative_to(PACKAGE)
        if relative.name in {"__init__.py", "__main__.py"} and len(relative.parts) == 1:
            continue  # lagrangian/__init__.py re-exports every layer's verbs
        own = relative.parts[0] if len(relative.parts) > 1 else relative.stem
        for module in _imports(path):
            target = _layer(module)
            if target is None or target == own:
                continue
            if own in ALLOWED_SIDE:
                ok = target in ALLOWED_SIDE[own]
            elif target in ALLOWED_SIDE:
                ok = target in {"io", "examples", "render"} and own in FRONT_ENDS
            else:
                ok = RANKS.get(target, 99) <= RANKS.get(own, -1)
            if not ok:
                problems.append(f"{relative}: imports {module} ({own} -> {target})")
    return problems


def _private_imports(package: Path) -> list[str]:
    """Private names (``_name``, not dunders) one module takes from another: ``from
    lagrangian.a import _b``, or ``m._b`` after ``import lagrangian.a as m``."""
    problems = []
    for path in package.rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        aliases = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("lagrangian"):
                problems.extend(
                    f"{path.relative_to(package)}: imports {node.module}.{alias.name}"
                    for alias in node.names
                    if _private(alias.name)
                )
            elif isinstance(node, ast.Import):
                aliases.update(
                    alias.asname or alias.name
                    for alias in node.names
                    if alias.name.startswith("lagrangian")
                )
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and _private(node.attr)
                and ast.unparse(node.value) in aliases
            ):
                problems.append(f"{path.relative_to(package)}: uses {ast.unparse(node)}")
    return problems


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def test_every_import_points_down_the_layers() -> None:
    assert _violations() == []


def test_no_module_imports_a_private_name_of_another() -> None:
    assert _private_imports(PACKAGE) == []


def test_the_private_name_check_sees_a_violation(tmp_path: Path) -> None:
    fake = tmp_path / "lagrangian"
    (fake / "model").mkdir(parents=True)
    (fake / "model" / "bad.py").write_text(
        "import lagrangian.symbolic.symbols as symbols\n"
        "from lagrangian.model.elements import _vector, as_expression\n"
        "symbols._time_function_name\n"
    )
    assert _private_imports(fake) == [
        "model/bad.py: imports lagrangian.model.elements._vector",
        "model/bad.py: uses symbols._time_function_name",
    ]


def test_the_checker_sees_a_violation(tmp_path: Path, monkeypatch) -> None:
    # The check must be able to fail: a model module importing derive is flagged.
    fake = tmp_path / "lagrangian"
    (fake / "model").mkdir(parents=True)
    (fake / "model" / "bad.py").write_text("from lagrangian.derivation import derive\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", fake)
    assert _violations() == ["model/bad.py: imports lagrangian.derivation (model -> derivation)"]


def test_the_checker_sees_an_import_from_the_package_root(tmp_path: Path, monkeypatch) -> None:
    # ``from lagrangian import simulation`` in model/ reaches up three layers.
    fake = tmp_path / "lagrangian"
    (fake / "model").mkdir(parents=True)
    (fake / "model" / "bad.py").write_text("from lagrangian import simulation\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", fake)
    assert _violations() == ["model/bad.py: imports lagrangian.simulation (model -> simulation)"]


def test_the_checker_refuses_the_playground_importing_the_command_line(
    tmp_path: Path, monkeypatch
) -> None:
    fake = tmp_path / "lagrangian"
    (fake / "web").mkdir(parents=True)
    (fake / "web" / "bad.py").write_text("from lagrangian.cli.commands import analysis_of\n")
    (fake / "cli").mkdir(parents=True)
    (fake / "cli" / "fine.py").write_text("from lagrangian.web.server import serve\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", fake)
    assert _violations() == ["web/bad.py: imports lagrangian.cli.commands (web -> cli)"]


def test_the_checker_refuses_the_symbolic_tools_importing_the_model(
    tmp_path: Path, monkeypatch
) -> None:
    fake = tmp_path / "lagrangian"
    (fake / "symbolic").mkdir(parents=True)
    (fake / "symbolic" / "bad.py").write_text("from lagrangian.model.system import System\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", fake)
    assert _violations() == ["symbolic/bad.py: imports lagrangian.model.system (symbolic -> model)"]
