"""The progress bar of long simulations (one implementation, in the simulate layer)."""

from __future__ import annotations

from lagrangian.simulation.progress_bar import WIDTH, progress_bar

__all__ = ["WIDTH", "progress_bar"]
