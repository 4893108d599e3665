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
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[1] / "src"))  # the checkout, installed or not

import lagrangian as lg  # noqa: E402
from lagrangian.render.flip_map_plot import flip_map_figure, save_flip_map  # noqa: E402
from lagrangian.simulation.flip_map import flip_times  # noqa: E402

LENGTH, GRAVITY = 1.0, 9.81


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
