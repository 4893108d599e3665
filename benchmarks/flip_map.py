"""The double pendulum's flip-time map: time until either arm flips, over a grid of starts.

Both masses and lengths equal (l = 1, g = 9.81), starting at rest at angles (theta, phi) in
[-3, 3]^2; each start is integrated (DOP853, rtol = atol = 1e-9) until |theta| or |phi| passes
pi or t_end = T sqrt(l/g) (default T = 100: the classic picture integrates to 1000 sqrt(l/g),
ten times longer, for finer structure at the boundary of the regions that never flip). The
flip times, in units of sqrt(l/g) and on a log scale, are drawn as an image; white cells do not
flip within t_end, including every start with 2 cos theta + cos phi > 1, which energy forbids.

Usage
    python benchmarks/flip_map.py                   # 200 x 200, T = 100 -> benchmarks/flip_map.png
    python benchmarks/flip_map.py --grid 50 --t-end 10 --backend numpy --out /tmp/map.png
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from matplotlib.figure import Figure

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[1] / "src"))  # the checkout, installed or not

import lagrangian as lg  # noqa: E402
from lagrangian.derivation import EquationsOfMotion  # noqa: E402
from lagrangian.model import System  # noqa: E402

LENGTH, GRAVITY = 1.0, 9.81


def flipped(t: float, q: np.ndarray, q_dot: np.ndarray) -> np.ndarray:
    """pi - max(|theta|, |phi|): negative once either arm has flipped over."""
    return np.pi - np.maximum(np.abs(q[..., 0]), np.abs(q[..., 1]))


def flip_times(
    double_pendulum: System | EquationsOfMotion,
    theta: ArrayLike,
    phi: ArrayLike,
    t_end: float,
    *,
    length: float = 1.0,
    gravity: float = 9.81,
    rtol: float = 1e-9,
    atol: float = 1e-9,
    backend: str = "numpy",
    progress: bool | Callable[[float], None] = False,
    workers: int = 1,
) -> np.ndarray:
    """Flip times of starts at rest on the grid ``theta`` x ``phi``, shape (len(phi),
    len(theta)) (rows: phi, as an image), NaN where no arm flips before ``t_end``.

    ``double_pendulum``: ``lagrangian.examples.double_pendulum()`` or its equations (angles
    theta, phi; parameters m1, m2, l1, l2, g).  DOP853 with rtol and atol; both masses 1 (the
    times do not depend on them when equal).
    """
    grid_theta, grid_phi = np.meshgrid(np.asarray(theta, float), np.asarray(phi, float))
    at_rest = {"theta_dot": 0.0, "phi_dot": 0.0}
    batch = lg.simulate_batch(
        double_pendulum,
        {"theta": grid_theta.ravel(), "phi": grid_phi.ravel(), **at_rest},
        t_end,
        parameters={"l1": length, "l2": length, "g": gravity, "m1": 1.0, "m2": 1.0},
        method="DOP853",
        rtol=rtol,
        atol=atol,
        stop_when=flipped,
        samples=2,  # the flip time is all the map needs: keep only the ends
        backend=backend,
        progress=progress,
        workers=workers,
    )
    return batch.stop_time.reshape(grid_theta.shape)


def flip_map_figure(
    times: np.ndarray,
    theta_range: tuple[float, float],
    phi_range: tuple[float, float],
    t_end: float,
    unit: float = 1.0,
) -> Figure:
    """The map ``times`` (rows: phi, columns: theta; NaN: no flip) as a figure; times are
    shown divided by ``unit`` (sqrt(l/g) for dimensionless times)."""
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

    scaled = np.asarray(times, dtype=float) / unit
    finite = scaled[np.isfinite(scaled)]
    low = float(np.min(finite)) if finite.size else 1e-3
    figure = Figure(figsize=(6.4, 5.4), layout="constrained")
    ax = figure.add_subplot()
    image = ax.imshow(
        np.ma.masked_invalid(scaled),
        origin="lower",
        extent=(*theta_range, *phi_range),
        cmap="viridis",
        norm=LogNorm(vmin=max(low, 1e-3), vmax=t_end / unit),
        interpolation="nearest",
    )
    ax.set_facecolor("white")
    ax.set_xlabel("theta (rad)")
    ax.set_ylabel("phi (rad)")
    ax.set_title(f"Double pendulum: time until an arm flips (white: none by {t_end / unit:g})")
    label = "flip time" if unit == 1.0 else "flip time / sqrt(l/g)"
    figure.colorbar(image, ax=ax, label=label)
    return figure


def save_flip_map(path: str | Path, figure: Figure, dpi: int = 100) -> None:
    """Write the figure as a PNG."""
    figure.savefig(path, dpi=dpi)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grid", type=int, default=200, help="cells per side (200)")
    parser.add_argument("--t-end", type=float, default=100.0, help="end time / sqrt(l/g) (100)")
    default = "numba" if importlib.util.find_spec("numba") else "numpy"
    parser.add_argument("--backend", choices=("numpy", "numba"), default=default)
    parser.add_argument("--workers", type=int, default=2, help="numba threads (2)")
    parser.add_argument("--out", type=Path, default=HERE.parent / "flip_map.png")
    args = parser.parse_args(argv)
    unit = math.sqrt(LENGTH / GRAVITY)
    angles = np.linspace(-3.0, 3.0, args.grid)
    start = time.perf_counter()
    times = flip_times(
        lg.examples.double_pendulum(),
        angles,
        angles,
        args.t_end * unit,
        length=LENGTH,
        gravity=GRAVITY,
        backend=args.backend,
        progress=True,
        workers=args.workers,
    )
    seconds = time.perf_counter() - start
    figure = flip_map_figure(times, (-3.0, 3.0), (-3.0, 3.0), args.t_end * unit, unit=unit)
    save_flip_map(args.out, figure)
    flipped = int(np.sum(np.isfinite(times)))
    print(
        f"{args.grid}x{args.grid} starts, t_end = {args.t_end:g} sqrt(l/g), {args.backend}: "
        f"{seconds:.1f} s, {flipped} flipped; wrote {args.out} ({args.out.stat().st_size} bytes)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
