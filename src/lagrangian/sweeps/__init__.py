"""Sweeps: many members of one System (a grid of parameters and initial values, random
samples) integrated on a Dask cluster into a Zarr store, resumable (docs/architecture.md).

Needs ``pip install lagrangian[sweep]`` (Dask, xarray, Zarr), imported only when a sweep runs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from lagrangian.lazy_names import lazy_attribute

if TYPE_CHECKING:
    from lagrangian.sweeps.grid import Grid, build_grid
    from lagrangian.sweeps.run import SweepReport, sweep
    from lagrangian.sweeps.stop_condition import StopExpression, stop_expression

#: Public name -> the module defining it, imported when the name is first used.
_HOMES = {
    **dict.fromkeys(("Grid", "build_grid"), "lagrangian.sweeps.grid"),
    **dict.fromkeys(("SweepReport", "sweep"), "lagrangian.sweeps.run"),
    **dict.fromkeys(("StopExpression", "stop_expression"), "lagrangian.sweeps.stop_condition"),
}


def __getattr__(name: str) -> Any:
    return lazy_attribute(globals(), _HOMES, __name__, name)


__all__ = ["Grid", "StopExpression", "SweepReport", "build_grid", "stop_expression", "sweep"]
