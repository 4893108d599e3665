"""One lazy_attribute loads the public names of ``lagrangian``, ``lagrangian.simulation`` and
``lagrangian.sweeps`` on first use: each package refuses an unknown name in its own name, gives
the object its home module defines, loads that home and nothing more, and binds the names the
home holds so that later uses are plain attribute reads."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

from lagrangian.lazy_names import lazy_attribute


def fresh(code: str) -> object:
    """What ``code`` prints last, as JSON, in a new interpreter (nothing loaded yet)."""
    done = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, check=True
    )
    return json.loads(done.stdout.splitlines()[-1])


@pytest.mark.parametrize("package", ["lagrangian", "lagrangian.simulation", "lagrangian.sweeps"])
def test_each_package_refuses_an_unknown_name_in_its_own_name(package):
    module = __import__(package, fromlist=["_"])
    with pytest.raises(AttributeError, match=f"^module '{package}' has no attribute 'nope'$"):
        module.nope  # noqa: B018


@pytest.mark.parametrize(
    ("package", "name", "home"),
    [
        ("lagrangian", "simulate", "lagrangian.simulation.run"),
        ("lagrangian", "time_limit", "lagrangian.limits"),
        ("lagrangian.simulation", "action", "lagrangian.simulation.variational.action"),
        ("lagrangian.simulation", "Trajectory", "lagrangian.simulation.trajectory"),
        ("lagrangian.sweeps", "sweep", "lagrangian.sweeps.run"),
        ("lagrangian.sweeps", "stop_expression", "lagrangian.sweeps.stop_condition"),
    ],
)
def test_each_package_gives_the_object_its_home_defines(package, name, home):
    found = fresh(
        f"""
        import importlib, json, sys
        package = importlib.import_module({package!r})
        value = getattr(package, {name!r})
        home = importlib.import_module({home!r})
        print(json.dumps([value is getattr(home, {name!r}), {name!r} in vars(package)]))
        """
    )
    assert found == [True, True]  # the defined object, bound in the package after first use


def test_a_name_loads_its_home_and_binds_that_homes_names_only():
    found = fresh(
        """
        import json, sys
        import lagrangian as lg
        import lagrangian.simulation as simulation
        import lagrangian.sweeps as sweeps
        lg.Trajectory
        sweeps.Grid
        loaded = [m for m in ("scipy", "dask", "lagrangian.simulation.run",
                              "lagrangian.simulation.batch.run", "lagrangian.sweeps.run")
                  if m in sys.modules]
        simulation.stationary_path  # the home of action and action_variation too
        print(json.dumps([
            loaded,
            sorted(n for n in ("Trajectory", "Event", "simulate", "Batch") if n in vars(lg)),
            sorted(n for n in ("Grid", "build_grid", "sweep") if n in vars(sweeps)),
            [type(simulation.action).__name__, "simulate" in vars(simulation)],
        ]))
        """
    )
    loaded, top, sweep_names, action = found
    assert loaded == []  # neither SciPy's integrators nor Dask, nor the modules that use them
    # lagrangian's home of Trajectory is lagrangian.simulation, which loads its own names
    # lazily: only what it holds is bound (Trajectory and Event, both of trajectory.py), not
    # simulate or Batch, whose modules stay unloaded
    assert top == ["Event", "Trajectory"]
    assert sweep_names == ["Grid", "build_grid"]  # the names of sweeps.grid, not sweeps.run's
    assert action == ["function", False]  # the function action(), not its module action.py


def test_a_bound_name_is_what_a_later_import_of_its_home_would_give():
    namespace: dict[str, object] = {"sqrt": "stale"}
    homes = {"sqrt": "math", "floor": "math"}
    import math

    assert lazy_attribute(namespace, homes, "example", "floor") is math.floor
    assert namespace == {"sqrt": math.sqrt, "floor": math.floor}  # the stale value replaced
