"""sweep(system, vary, t_span, out=...) -> SweepReport: many members on a Dask cluster,
written to Zarr block by block, resumable.

The members (the product of the ``vary`` axes, times the ``random`` samples,
:mod:`lagrangian.sweeps.grid`) are cut into blocks (:mod:`lagrangian.sweeps.blocks`); each block
is one task integrating its members on a worker, as one compiled batch
(:func:`lagrangian.simulate_batch`; a constrained system's in the multiplier form, whose
multipliers are stored too), or member by member with :func:`lagrangian.simulate` where the
batch refuses the block (:mod:`lagrangian.sweeps.chunk_run`).  The System is scattered to
every worker once.  The client writes each block into the store as it finishes
(:mod:`lagrangian.sweeps.store`), its ``done`` flags last; with ``resume=True`` the blocks
already done are skipped.  A task that raises is retried (``retries``) and a task whose
worker dies is run again on another by Dask.

>>> import tempfile, pathlib, lagrangian as lg  # doctest: +SKIP
>>> out = pathlib.Path(tempfile.mkdtemp()) / "map.zarr"  # doctest: +SKIP
>>> report = sweep(lg.examples.simple_pendulum(), {"theta": [0.1, 0.2], "l": [1, 2]}, 2.0,
...                out=out, samples=5, workers=2)  # doctest: +SKIP
>>> report.dataset()["theta"].dims  # doctest: +SKIP
('theta_0', 'l', 't')
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import os
import shutil
import time
import uuid
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from lagrangian.errors import (
    Fix,
    Problem,
    Setting,
    SimulationError,
    SimulationInputError,
    raise_if_problems,
)
from lagrangian.model import System
from lagrangian.model.system import require_system
from lagrangian.simulation.batch.run import StopCondition
from lagrangian.simulation.options import StepKeywords
from lagrangian.sweeps.blocks import (
    DEFAULT_CHUNK_SIZE,
    MEMBER_CHUNK_SIZE,
    block_shape,
    region_size,
    regions,
)
from lagrangian.sweeps.chunk_run import ChunkSettings, run_chunk
from lagrangian.sweeps.cluster import cluster_problems, dask_client
from lagrangian.sweeps.dependencies import require_sweep_packages
from lagrangian.sweeps.grid import Grid, Region, build_grid
from lagrangian.sweeps.inputs import checked_member_times, checked_times
from lagrangian.sweeps.progress import ProgressLine
from lagrangian.sweeps.stop_condition import StopExpression, stop_expression
from lagrangian.sweeps.store import SweepWriter, check_resumable, create_store
from lagrangian.sweeps.variables import SweepVariables, sweep_variables

if TYPE_CHECKING:
    from typing_extensions import Unpack

#: Times Dask runs a block again after it raised.
RETRIES = 2
#: The version of the store's layout (a resume into a store of another layout is refused).
LAYOUT = 2


@dataclass(frozen=True)
class SweepReport:
    """What a sweep did: the store, its members by status, and how this run went."""

    out: Path
    members: int
    computed: int
    skipped: int
    status: Mapping[str, int]
    seconds: float
    dashboard: str | None = None

    def dataset(self) -> Any:
        """The result as an xarray Dataset (``xarray.open_zarr(out)``)."""
        import xarray as xr

        return xr.open_zarr(self.out)

    def summary(self) -> str:
        """One line for people."""
        counts = ", ".join(f"{n} {s}" for s, n in self.status.items() if n)
        rate = f", {self.computed / self.seconds:.4g} members/s" if self.seconds > 0 else ""
        resumed = f" ({self.skipped} already written)" if self.skipped else ""
        return (
            f"{self.members} members{resumed}: {counts or 'none'}; {self.computed} computed in "
            f"{self.seconds:.3g} s{rate}; written to {self.out}"
        )


def sweep(
    system: System,
    vary: Mapping[Any, ArrayLike] | None = None,
    t_span: float | tuple[float, float] | None = None,
    *,
    out: str | os.PathLike[str],
    random: Mapping[Any, tuple[float, float, int]] | None = None,
    seed: int = 0,
    scheduler: str | None = None,
    workers: int | None = None,
    security: Any | None = None,
    resume: bool = False,
    stop_when: str | StopCondition | None = None,
    chunk_size: int | None = None,
    backend: str = "numpy",
    project_initial: bool = False,
    progress: bool | None = None,
    messages: Callable[[str], None] | None = None,
    retries: int = RETRIES,
    **stepping: Unpack[StepKeywords],
) -> SweepReport:
    """Simulate every member of a grid on a Dask cluster into the Zarr store ``out``.

    Parameters
    ----------
    vary:
        NAME -> values: a parameter, or an initial value (a coordinate or ``NAME_dot``).  The
        members are the product of the axes; each is a dimension of the result, the
        parameter's own name or ``NAME_0`` for an initial value.
    t_span, method, rtol, atol, samples, ...:
        As for :func:`lagrangian.simulate_batch` (without ``samples``: the ends only).  A
        system with constraints runs in the multiplier form (backend "numpy"), and its
        multipliers ``lambda_j`` are stored as well.
    random, seed:
        NAME -> (low, high, N): N members drawn uniformly, along the dimension ``sample``
        (every random name the same N), seeded.
    scheduler, workers:
        A running cluster's address ``tls://HOST:PORT`` (or ``tcp://``, which anyone who
        reaches it can use to run code as its workers' user), or else a local cluster of
        ``workers`` processes (default one per core) on 127.0.0.1, which speaks TLS with
        temporary credentials of its own.
    security:
        The running cluster's TLS credentials, a ``distributed.security.Security``
        (:func:`lagrangian.sweeps.cluster.tls_security` makes one from the files); None: Dask's
        configuration (``distributed.comm.tls``).
    resume:
        Continue the sweep already in ``out`` (same model and options), skipping the blocks
        written; without it an existing ``out`` is refused.
    stop_when:
        g(t, q, q_dot) or its text (``"pi - Abs(theta)"``): a member stops where g turns
        negative; its time is the variable ``stop_time``.  The text works with every backend;
        a function must suit the backend's (:func:`lagrangian.simulate_batch`).
    chunk_size:
        Members per block (one task, one chunk of the store); default 512, or 32 for a
        constrained system.
    project_initial:
        Constrained systems: move each member's initial state onto the constraints (as
        :func:`lagrangian.simulate` does) instead of recording it as failed.
    progress, messages:
        The progress line on standard error (None: when it is a terminal), and a function
        told the dashboard address and other news.

    Raises
    ------
    SimulationInputError
        Bad input, every problem naming its field, before any cluster starts.
    SimulationError
        The sweep packages are missing (``pip install lagrangian[sweep]``) or the scheduler
        cannot be reached.
    """
    require_sweep_packages()
    system = require_system(system, "sweep(system)")
    path = Path(out)
    grid = build_grid(system, vary, random, seed)
    stored = sweep_variables(system)
    if chunk_size is None:
        chunk_size = MEMBER_CHUNK_SIZE if stored.per_member else DEFAULT_CHUNK_SIZE
    problems = cluster_problems(scheduler, workers, security)
    _check_options(path, resume, chunk_size, retries, project_initial, stored, problems)
    condition = _stop_condition(system, grid, stop_when)
    block = block_shape(grid.shape, chunk_size)
    parts = list(regions(grid.shape, block))
    settings = ChunkSettings(
        t_span, stored, (), dict(stepping), condition, backend, bool(project_initial)
    )
    t = _checked_times(system, grid, parts[0], settings)
    settings = dataclasses.replace(settings, t=tuple(t.tolist()))
    description = _description(system, grid, t, settings)
    created = not path.exists()
    if created:
        create_store(path, grid, stored, t, block, description, condition is not None)
    else:
        check_resumable(path, description)
    writer = SweepWriter(path)
    todo = [part for part, done in zip(parts, writer.done(parts)) if not done]
    skipped = grid.size - sum(region_size(part) for part in todo)
    start = time.perf_counter()
    dashboard = None
    if todo:
        line = ProgressLine(sum(region_size(part) for part in todo), force=bool(progress))
        line.shown = line.shown if progress is None else bool(progress)
        with contextlib.ExitStack() as stack:
            try:
                client = stack.enter_context(dask_client(scheduler, workers, security))
            except SimulationError:  # no cluster: leave no empty store behind to resume
                if created:
                    shutil.rmtree(path, ignore_errors=True)
                raise
            dashboard = client.dashboard_link
            if messages:
                messages(f"Dask dashboard: {dashboard}")
            try:
                _run_blocks(client, system, grid, todo, settings, writer, line, retries)
            finally:
                line.close()
    return SweepReport(
        out=path,
        members=grid.size,
        computed=grid.size - skipped,
        skipped=skipped,
        status=writer.status_counts(),
        seconds=time.perf_counter() - start,
        dashboard=dashboard,
    )


def _run_blocks(
    client: Any,
    system: System,
    grid: Grid,
    todo: list[Any],
    settings: ChunkSettings,
    writer: SweepWriter,
    line: ProgressLine,
    retries: int,
) -> None:
    """Submit every block, write each as it finishes; on an error, cancel the rest."""
    from dask.distributed import as_completed

    run = uuid.uuid4().hex[:12]
    # The System reaches each worker once, as the result of a task rather than scattered
    # data: a worker lost with its copy makes the scheduler compute it again, where
    # scattered data would be gone for good and every block waiting on it would fail.
    model = client.submit(_the_system, system, key=f"lagrangian-sweep-model-{run}", pure=False)
    futures = {}
    for index, part in enumerate(todo):
        initial, parameters = grid.columns(part)
        future = client.submit(
            run_chunk,
            model,
            initial,
            parameters,
            settings,
            key=f"lagrangian-sweep-{run}-{index}",
            retries=retries,
            pure=False,
        )
        futures[future.key] = (future, part)
    try:
        for future in as_completed([f for f, _ in futures.values()]):
            result = future.result()
            part = futures.pop(future.key)[1]
            writer.write(part, result)
            line.advance(region_size(part))
            future.release()
    finally:
        client.cancel([f for f, _ in futures.values()])


def _the_system(system: System) -> System:
    """The System a worker keeps for every block it runs (a task, so it can be recomputed)."""
    return system


def _checked_times(
    system: System, grid: Grid, first: Region, settings: ChunkSettings
) -> np.ndarray:
    """The output times, after the checks of the integrator the workers will use: on the
    first block for a batch, on its first member for members run one by one (the start on
    the constraints included)."""
    initial, parameters = grid.columns(first)
    t_span, stepping, backend = settings.t_span, settings.stepping, settings.backend
    if settings.variables.per_member:
        one = {name: float(values[0]) for name, values in initial.items()}
        given = {name: float(values[0]) for name, values in parameters.items()}
        return checked_member_times(
            system,
            one,
            given,
            t_span,
            stepping,
            backend,
            settings.stop_when,
            settings.project_initial,
        )
    return checked_times(system, initial, parameters, t_span, stepping, backend)


def _check_options(
    path: Path,
    resume: bool,
    chunk_size: Any,
    retries: Any,
    project_initial: bool,
    stored: SweepVariables,
    problems: list[Problem],
) -> None:
    """Raise every problem of the sweep's own options, with ``problems`` found before."""
    if project_initial and not stored.per_member:
        message = "project_initial moves states onto the constraints, and this system has none"
        remove = Fix("remove {}", (Setting("project_initial", True),))
        problems.append(Problem("project_initial", message, remove))
    if path.exists() and not resume:
        again = Fix("pass {} to continue it, or choose another path", (Setting("resume", True),))
        problems.append(Problem("out", f"{path} already exists", again))
    if not path.parent.is_dir():
        fix = "create the folder first, or choose a path in an existing one"
        problems.append(Problem("out", f"the folder {path.parent} does not exist", fix))
    for name, value, least in (("chunk_size", chunk_size, 1), ("retries", retries, 0)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
            fix = f"give a whole number >= {least}"
            problems.append(Problem(name, f"{value!r} is not a whole number >= {least}", fix))
    raise_if_problems(problems, "Cannot sweep", SimulationInputError)


def _stop_condition(
    system: System, grid: Grid, stop_when: str | StopCondition | None
) -> StopCondition | None:
    if isinstance(stop_when, str):
        varied = {a.name for a in (*grid.axes, *grid.random) if a.kind == "parameter"}
        return stop_expression(system, stop_when, varied)
    if stop_when is not None and not callable(stop_when):
        fix = "give g(t, q, q_dot) or its text, e.g. 'pi - Abs(theta)'"
        raise SimulationInputError(
            "Cannot sweep:", [Problem("stop_when", f"{stop_when!r} is not callable", fix)]
        )
    return stop_when


def _description(
    system: System, grid: Grid, t: np.ndarray, settings: ChunkSettings
) -> dict[str, Any]:
    """What identifies a sweep, as JSON values: a resume must match it."""
    model = repr(system)  # every field of the value, printed the same in every process
    condition, stepping = settings.stop_when, settings.stepping
    stop: str | None = None
    if isinstance(condition, StopExpression):
        stop = condition.text
    else:
        stop = getattr(condition, "__qualname__", repr(condition)) if condition else None
    return {
        "layout": LAYOUT,
        "model": system.name,
        "model_digest": hashlib.sha256(model.encode()).hexdigest(),
        "dims": list(grid.dims),
        "shape": list(grid.shape),
        "grid_digest": _grid_digest(grid),
        "t": [float(t[0]), float(t[-1]), len(t)],
        "stepping": {key: _plain(value) for key, value in sorted(stepping.items())},
        "stop_when": stop,
        "backend": settings.backend,
        "project_initial": settings.project_initial,
    }


def _grid_digest(grid: Grid) -> str:
    digest = hashlib.sha256()
    for axis in (*grid.axes, *grid.random):
        digest.update(axis.name.encode() + b"\0" + np.ascontiguousarray(axis.values).tobytes())
    return digest.hexdigest()


def _plain(value: Any) -> Any:
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    return np.asarray(value, dtype=float).tolist()
