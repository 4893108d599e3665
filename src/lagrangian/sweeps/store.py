"""The Zarr store of a sweep: laid out whole before any work, then filled block by block.

The store is an xarray Dataset (Zarr format 2, read by ``xarray.open_zarr``) with one
dimension per varied name and ``t``.  Over (dims..., t): every coordinate and ``NAME_dot``,
with constraints the multipliers ``lambda_j``, and ``energy`` — the energy function h where it
differs from T + V, else T + V, as its attribute ``quantity`` says
(:mod:`lagrangian.sweeps.variables`).  Per member: ``status`` (``success``, ``stopped``,
``failed``; empty while not computed), ``message``, the drift of each conserved quantity
(``energy_drift`` = max |energy - energy(t0)|, ``p_NAME_drift`` for the momentum of a cyclic
coordinate; NaN where the member does not conserve it, ``not_conserved`` saying why), with
constraints ``constraint_drift`` (the largest constraint residual), ``stop_time`` with a stop
condition, with impacts (unilateral constraints with a coefficient of restitution)
``impacts``, how many the member met (-1 while not computed or when it failed), and
``rest_time``, when a contact came to rest (NaN: none did), and ``done``.  Each block is one
chunk of every array; its ``done`` flags are written after its data, so a block interrupted
mid-write reads as not done and is computed again by a resumed sweep.  The attribute
``lagrangian_sweep`` describes the sweep (model, grid, time span, method...) so that a resume
can check it continues the same one.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from lagrangian.errors import Problem, SimulationInputError
from lagrangian.sweeps.chunk_run import ChunkResult
from lagrangian.sweeps.grid import SAMPLE, Grid, Region
from lagrangian.sweeps.variables import ENERGY_LABELS, SweepVariables

#: The attribute describing the sweep that wrote a store.
DESCRIPTION = "lagrangian_sweep"
#: Per-member text lengths (Zarr stores fixed-width text): longer messages are cut.
STATUS_DTYPE, MESSAGE_LENGTH, REASONS_LENGTH = "<U7", 200, 100
#: What each per-member drift variable measures.
DRIFT_NAMES = {"energy_drift": "max |energy - energy(t0)|", "constraint_drift": "max residual"}
#: What ``impacts`` and ``rest_time`` hold.
IMPACTS_NAME = "number of impacts on the unilateral constraints"
REST_NAME = "time (as t) a contact came to rest: its bounces accumulated; NaN: none did"


def create_store(
    path: str | os.PathLike[str],
    grid: Grid,
    stored: SweepVariables,
    t: np.ndarray,
    block: tuple[int, ...],
    description: Mapping[str, Any],
    stop_time: bool,
) -> None:
    """Write the layout of the whole result (metadata and coordinates, no data) at ``path``."""
    import dask.array as da
    import xarray as xr

    dims, shape = grid.dims, grid.shape
    series = (*dims, "t")

    def empty(extra: tuple[int, ...], dtype: Any, fill: Any) -> Any:
        return da.full(shape + extra, fill, dtype=dtype, chunks=block + extra)

    variables: dict[str, Any] = {}
    for name in stored.series:
        variables[name] = (series, empty((len(t),), float, np.nan))
    quantity, long_name = ENERGY_LABELS[stored.energy_function]
    energy_attrs = {"quantity": quantity, "long_name": long_name}
    variables["energy"] = (series, empty((len(t),), float, np.nan), energy_attrs)
    variables["status"] = (dims, empty((), STATUS_DTYPE, ""))
    variables["message"] = (dims, empty((), f"<U{MESSAGE_LENGTH}", ""))
    for name in stored.drifts:
        measured = DRIFT_NAMES.get(name, f"max |{name[: -len('_drift')]} - its value at t0|")
        variables[name] = (dims, empty((), float, np.nan), {"long_name": measured})
    variables["not_conserved"] = (dims, empty((), f"<U{REASONS_LENGTH}", ""))
    if stop_time:
        variables["stop_time"] = (dims, empty((), float, np.nan))
    if stored.impacts:
        counted = {"long_name": IMPACTS_NAME, "comment": "-1: not computed (yet, or failed)"}
        variables["impacts"] = (dims, empty((), np.int64, -1), counted)
        variables["rest_time"] = (dims, empty((), float, np.nan), {"long_name": REST_NAME})
    variables["done"] = (dims, empty((), bool, False))
    coords: dict[str, Any] = {axis.dimension: axis.values for axis in grid.axes}
    if grid.random:
        coords[SAMPLE] = np.arange(len(grid.random[0].values))
        coords.update((axis.dimension, (SAMPLE, axis.values)) for axis in grid.random)
    coords["t"] = t
    attrs = {DESCRIPTION: json.dumps(description, sort_keys=True)}
    dataset = xr.Dataset(variables, coords=coords, attrs=attrs)
    dataset.to_zarr(os.fspath(path), mode="w-", compute=False, zarr_format=2)


def stored_description(path: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The description of the sweep that wrote ``path``; None when it is not a sweep."""
    import zarr

    try:
        group = zarr.open_group(os.fspath(path), mode="r")
        return dict(json.loads(str(group.attrs[DESCRIPTION])))
    except Exception:  # any store zarr cannot read, or another kind of store: not a sweep
        return None


def check_resumable(path: str | os.PathLike[str], description: Mapping[str, Any]) -> None:
    """Refuse to resume into a store written by another sweep (or not by a sweep at all)."""
    stored = stored_description(path)
    if stored == json.loads(json.dumps(description, sort_keys=True)):
        return
    if stored is None:
        message = "is not the store of a sweep"
    else:
        changed = sorted(
            key for key in {*stored, *description} if stored.get(key) != description.get(key)
        )
        message = f"was written by a different sweep (it differs in {', '.join(changed)})"
    fix = "resume with the same model and options, or write to a new path"
    raise SimulationInputError(
        "Cannot resume the sweep:", [Problem("out", f"{path} {message}", fix)]
    )


class SweepWriter:
    """Writes blocks into a store made by :func:`create_store`, and reads which are done."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        import zarr

        self.group: Any = zarr.open_group(os.fspath(path), mode="r+")

    def done(self, regions: Iterable[Region]) -> list[bool]:
        """Whether each block is written (all its ``done`` flags set; unreadable: not done)."""
        flags = self.group["done"]
        found = []
        for region in regions:
            try:
                found.append(bool(np.all(flags[region])))
            except Exception:  # a chunk cut short by a crash: compute the block again
                found.append(False)
        return found

    def status_counts(self) -> dict[str, int]:
        """How many members have each status (``not computed``: not written yet)."""
        status = np.asarray(self.group["status"][...]).ravel()
        words, counts = np.unique(status, return_counts=True)
        found = {str(w) or "not computed": int(n) for w, n in zip(words, counts)}
        order = ("success", "stopped", "failed", "not computed")
        return {word: found[word] for word in order if word in found}

    def write(self, region: Region, result: ChunkResult) -> None:
        """The block's data, then its ``done`` flags."""
        shape = tuple(s.stop - s.start for s in region)
        for name, values in result.series.items():
            self._put(name, region, values, shape)
        self._put("status", region, np.array(result.status, dtype=STATUS_DTYPE), shape)
        self._put("message", region, _text(result.message, MESSAGE_LENGTH), shape)
        for name, values in result.drifts.items():
            self._put(name, region, values, shape)
        self._put("not_conserved", region, _text(result.not_conserved, REASONS_LENGTH), shape)
        for name in ("stop_time", "impacts", "rest_time"):
            if name in self.group:  # stored for the sweeps that have them
                self._put(name, region, getattr(result, name), shape)
        self._put("done", region, np.ones(len(result.status), dtype=bool), shape)

    def _put(self, name: str, region: Region, values: np.ndarray, shape: tuple[int, ...]) -> None:
        array = self.group[name]
        extra = values.shape[1:]
        array[region + (slice(None),) * len(extra)] = values.reshape(shape + extra)


def _text(values: Iterable[str], length: int) -> np.ndarray:
    """Fixed-width text, each value longer than ``length`` cut with an ellipsis."""
    cut = [v if len(v) <= length else v[: length - 1] + "…" for v in values]
    return np.array(cut, dtype=f"<U{length}")
