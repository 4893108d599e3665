"""The public surface: what ``lagrangian`` lists is there, loads on first use only, and importing
it changes nothing in IPython until asked."""

from __future__ import annotations

import ast
import importlib
import importlib.metadata
import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import lagrangian as lg

INIT = Path(lg.__file__)
HEAVY = ("sympy", "numpy", "scipy", "matplotlib", "numba")


def run_fresh(code: str) -> object:
    """What ``code`` prints last, as JSON, run in a new interpreter (a clean sys.modules)."""
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(done.stdout.splitlines()[-1])


def test_every_listed_name_is_there() -> None:
    missing = [name for name in lg.__all__ if not hasattr(lg, name)]
    assert missing == []
    assert len(set(lg.__all__)) == len(lg.__all__)
    assert set(lg.__all__) <= set(dir(lg))


def test_the_verbs_results_and_constraint_verbs_are_listed() -> None:
    wanted = {
        "derive",
        "analyze",
        "simulate",
        "simulate_batch",
        "load",
        "newton_euler",
        "classify",
        "constrained_equations",
        "eliminate",
        "particle_constraint_forces",
        "reaction_wrenches",
        "project_state",
        "EquationsOfMotion",
        "CoordinateSteps",
        "AnalysisReport",
        "ConstraintReport",
        "Trajectory",
        "Batch",
        "Event",
        "System",
        "LagrangianError",
        "SimulationInputError",
    }
    assert wanted <= set(lg.__all__)
    assert lg.classify is importlib.import_module("lagrangian.constraints").classify


def test_check_newton_euler_lives_in_derivation() -> None:
    assert "check_newton_euler" not in lg.__all__
    with pytest.raises(AttributeError, match="has no attribute 'check_newton_euler'"):
        lg.check_newton_euler  # noqa: B018
    from lagrangian.derivation import check_newton_euler

    assert check_newton_euler(lg.examples.simple_pendulum()).agree


def _type_checking_imports() -> dict[str, str]:
    """Name -> module of every import under ``if TYPE_CHECKING:`` in lagrangian/__init__.py."""
    tree = ast.parse(INIT.read_text(encoding="utf-8"))
    found = {}
    for node in tree.body:
        if isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING":
            for statement in node.body:
                if isinstance(statement, ast.ImportFrom):
                    found.update({alias.name: str(statement.module) for alias in statement.names})
    return found


def test_the_names_type_checkers_see_are_the_names_loaded() -> None:
    # mypy reads the TYPE_CHECKING imports; users get what __getattr__ loads: the same objects.
    declared = _type_checking_imports()
    for name, module in declared.items():
        assert getattr(lg, name) is getattr(importlib.import_module(module), name), name
    errors = {name for name in lg.__all__ if name.endswith("Error") or name == "Problem"}
    assert set(lg.__all__) == (set(declared) | errors)


def test_unknown_names_are_attribute_errors() -> None:
    with pytest.raises(AttributeError, match="module 'lagrangian' has no attribute 'nope'"):
        lg.nope  # noqa: B018


def test_the_version_comes_from_the_package_metadata(monkeypatch: pytest.MonkeyPatch) -> None:
    assert lg.__version__ == importlib.metadata.version("lagrangian")

    def not_installed(name: str) -> str:
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "version", not_installed)
    assert lg.__version__ == "0+unknown"


def test_import_loads_nothing_heavy_and_derive_loads_no_scipy() -> None:
    loaded = run_fresh(
        f"""
        import json, sys
        heavy = {HEAVY!r}
        import lagrangian as lg
        at_import = [m for m in heavy if m in sys.modules]
        eom = lg.derive(lg.examples.simple_pendulum())
        lg.render.steps_text(eom)
        lg.classify(lg.examples.spherical_pendulum())
        after_derive = [m for m in heavy if m in sys.modules]
        lg.simulate(lg.examples.simple_pendulum(), t_span=0.1)
        after_simulate = [m for m in heavy if m in sys.modules]
        print(json.dumps([at_import, after_derive, after_simulate]))
        """
    )
    assert loaded == [[], ["sympy", "numpy"], ["sympy", "numpy", "scipy"]]


def test_a_function_is_not_shadowed_by_its_module() -> None:
    # simulation/variational/action.py defines action(): importing the module first must not hide
    # it.
    kinds = run_fresh(
        """
        import json
        from lagrangian.simulation import stationary_path
        from lagrangian.simulation import action
        import lagrangian.simulation as simulation
        print(json.dumps([callable(action), type(simulation.action).__name__]))
        """
    )
    assert kinds == [True, "function"]


FAKE_IPYTHON = """
import json, sys, types

class Formatter:
    def __init__(self):
        self.types = []

    def for_type(self, kind, printer):
        self.types.append(kind.__name__)

latex, png, page = Formatter(), Formatter(), Formatter()
shell = types.SimpleNamespace(
    display_formatter=types.SimpleNamespace(
        formatters={"text/latex": latex, "image/png": png, "text/html": page}
    )
)
fake = types.ModuleType("IPython")
fake.get_ipython = lambda: shell
sys.modules["IPython"] = fake  # as inside a running IPython
"""


def test_importing_inside_ipython_registers_nothing() -> None:
    registered = run_fresh(
        FAKE_IPYTHON
        + """
import lagrangian as lg
eom = lg.derive(lg.examples.simple_pendulum())
lg.render.steps_text(eom)
print(json.dumps(latex.types + png.types + page.types))
"""
    )
    assert registered == []


def test_load_ext_registers_the_formatters() -> None:
    registered = run_fresh(
        FAKE_IPYTHON
        + """
import lagrangian
lagrangian.load_ipython_extension(shell)  # what %load_ext lagrangian calls
print(json.dumps([latex.types, png.types, page.types]))
"""
    )
    latex, png, page = registered  # type: ignore[misc]
    assert {"EquationsOfMotion", "CoordinateSteps", "Steps", "System", "AnalysisReport"} <= set(
        latex
    )
    assert png == ["Trajectory"]
    assert page == ["Drift"]
