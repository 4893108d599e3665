"""``lagrangian sweep``: a grid of parameters and initial values simulated on Dask into Zarr.

The parser part needs neither NumPy nor Dask (``lagrangian --help`` stays fast); the sweep
itself (:func:`lagrangian.sweeps.sweep`) loads when the command runs.  Bad flags exit 2 with
a message naming the flag; Ctrl-C keeps the blocks written, and ``--resume`` finishes them.

>>> parse_vary(["theta=0:1:3", "l=1,2"])
({'theta': [0.0, 0.5, 1.0], 'l': [1.0, 2.0]}, {'theta': '--vary theta=0:1:3', 'l': '--vary l=1,2'})
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from types import MappingProxyType

from lagrangian.cli.wording import FLAGS, CommandLineWording
from lagrangian.errors import Problem, SimulationInputError, raise_if_problems

SUMMARY = "simulate a grid of parameters and initial values on Dask, into a Zarr store"
EXAMPLE = (
    "lagrangian sweep examples/double_pendulum --vary theta=-3:3:200 --vary phi=-3:3:200 "
    "--set theta_dot=0 --set phi_dot=0 --t-end 30 --stop-when '(pi - Abs(theta))*(pi - Abs(phi))' "
    "--out flips.zarr"
)


def add_sweep_options(command: argparse.ArgumentParser) -> None:
    """The flags of ``lagrangian sweep`` (the model, --set and --debug are the caller's)."""
    command.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="NAME=START:STOP:COUNT|NAME=v1,v2,...",
        help="an axis of the grid: a parameter or an initial value (repeatable)",
    )
    command.add_argument(
        "--random",
        action="append",
        default=[],
        metavar="NAME=LOW:HIGH:N",
        help="N values drawn uniformly, along the dimension sample (repeatable, same N)",
    )
    command.add_argument("--seed", type=int, default=0, help="seed of --random (0)")
    command.add_argument("--t-end", type=float, help="end time (default: the model's)")
    command.add_argument("--samples", type=int, help="output times (default: the ends only)")
    command.add_argument(
        "--method",
        help="RK45 (default), DOP853 or RK4; with constraints any method of lagrangian simulate",
    )
    command.add_argument("--dt", type=float, help="the step of RK4 (or give --samples)")
    command.add_argument("--rtol", type=float, help="relative tolerance")
    command.add_argument("--atol", type=float, help="absolute tolerance")
    command.add_argument(
        "--max-steps", type=int, help="accepted steps a member may take (one million)"
    )
    command.add_argument("--backend", choices=["numpy", "numba"], default="numpy")
    command.add_argument(
        "--stop-when",
        metavar="EXPR",
        help="a member stops where EXPR (of t, coordinates, NAME_dot) turns negative",
    )
    command.add_argument("--out", required=True, help="the Zarr store to write (RESULT.zarr)")
    command.add_argument("--scheduler", metavar="ADDRESS", help="a running Dask scheduler")
    # Dask's own names for the files of a TLS scheduler (dask scheduler --help)
    command.add_argument("--tls-ca-file", metavar="PEM", help="--scheduler's certificate authority")
    command.add_argument("--tls-cert", metavar="PEM", help="this client's certificate for it")
    command.add_argument("--tls-key", metavar="PEM", help="this client's private key for it")
    command.add_argument("--workers", type=int, help="local worker processes (one per core)")
    command.add_argument(
        "--chunk-size", type=int, help="members per task (512; 32 with constraints)"
    )
    command.add_argument(
        "--project-initial",
        action="store_true",
        help="constrained systems: move each member's start onto the constraints",
    )
    command.add_argument("--resume", action="store_true", help="continue the sweep in --out")
    command.add_argument(
        "--progress", action="store_true", help="show progress even when not on a terminal"
    )


def sweep_wording() -> CommandLineWording:
    """The sweep's options as its flags: the keywords :func:`add_sweep_options` defines (and
    the caller's ``--set``, which gives initial values too: a sweep has no ``--initial``),
    the values of ``--vary`` and ``--random`` in their own forms."""
    parser = argparse.ArgumentParser(add_help=False)
    add_sweep_options(parser)
    keywords = frozenset(vars(parser.parse_args(["--out", "-"]))) | {"set"}
    flags = MappingProxyType({**FLAGS, "initial": "--set"})
    placeholders = MappingProxyType({"vary": "START:STOP:COUNT", "random": "LOW:HIGH:N"})
    return CommandLineWording(keywords, flags, placeholders)


def run_sweep(args: argparse.Namespace) -> str:
    """Run the parsed ``sweep`` command; its one-line summary."""
    from lagrangian.cli.commands import load_system
    from lagrangian.cli.simulate_command import interrupted
    from lagrangian.documents import apply_settings
    from lagrangian.sweeps import build_grid, sweep
    from lagrangian.sweeps.cluster import tls_security

    system = apply_settings(load_system(args.model), args.set, SWEEP)
    problems: list[Problem] = []
    vary, vary_labels = parse_vary(args.vary, problems)
    random, random_labels = parse_random(args.random, problems)
    raise_if_problems(problems, "Bad --vary or --random option", SimulationInputError)
    stepping = {
        key: value
        for key, value in (
            ("samples", args.samples),
            ("method", args.method),
            ("rtol", args.rtol),
            ("atol", args.atol),
            ("dt", args.dt),
            ("max_steps", args.max_steps),
        )
        if value is not None
    }
    try:
        build_grid(system, vary, random, args.seed, {**vary_labels, **random_labels})
        report = sweep(
            system,
            vary,
            args.t_end,
            out=args.out,
            random=random,
            seed=args.seed,
            scheduler=args.scheduler,
            workers=args.workers,
            security=tls_security(args.scheduler, args.tls_ca_file, args.tls_cert, args.tls_key),
            resume=args.resume,
            stop_when=args.stop_when,
            chunk_size=args.chunk_size,
            backend=args.backend,
            project_initial=args.project_initial,
            progress=True if args.progress else None,
            messages=lambda text: print(f"lagrangian: {text}", file=sys.stderr, flush=True),
            **stepping,
        )
    except KeyboardInterrupt:
        interrupted(
            f"Interrupted (Ctrl-C); the blocks finished are in {args.out}: run the same "
            "command with --resume to compute the rest."
        )
    return report.summary()


def parse_vary(
    items: Sequence[str], problems: list[Problem] | None = None
) -> tuple[dict[str, list[float]], dict[str, str]]:
    """``NAME=START:STOP:COUNT`` (COUNT evenly spaced values) or ``NAME=v1,v2,...`` -> values
    by name, and the flag that gave each (for messages).  Bad items are added to
    ``problems``, or raised as SimulationInputError when it is None."""
    values: dict[str, list[float]] = {}
    labels: dict[str, str] = {}
    found: list[Problem] = []
    for item in items:
        field = f"--vary {item}"
        name, sep, text = (part.strip() for part in item.partition("="))
        axis = _axis_values(text) if sep and name else None
        if axis is None:
            fix = "e.g. --vary theta=0:1:11 (START:STOP:COUNT) or --vary m=1,2,5"
            found.append(Problem(field, "expected NAME=START:STOP:COUNT or NAME=v1,v2,...", fix))
            continue
        values[name], labels[name] = axis, field
    _report(found, problems, "Bad --vary option")
    return values, labels


def parse_random(
    items: Sequence[str], problems: list[Problem] | None = None
) -> tuple[dict[str, tuple[float, float, int]], dict[str, str]]:
    """``NAME=LOW:HIGH:N`` -> (low, high, N) by name, and the flag that gave each (bad items
    as for :func:`parse_vary`)."""
    ranges: dict[str, tuple[float, float, int]] = {}
    labels: dict[str, str] = {}
    found: list[Problem] = []
    for item in items:
        field = f"--random {item}"
        name, sep, text = (part.strip() for part in item.partition("="))
        parts = text.split(":")
        try:
            low, high, count = float(parts[0]), float(parts[1]), int(parts[2])
            if not sep or not name or len(parts) != 3 or not low < high or count < 1:
                raise ValueError(item)
        except (ValueError, IndexError):
            fix = "e.g. --random theta=-1:1:1000 (LOW < HIGH, N >= 1)"
            found.append(Problem(field, "expected NAME=LOW:HIGH:N", fix))
            continue
        ranges[name], labels[name] = (low, high, count), field
    _report(found, problems, "Bad --random option")
    return ranges, labels


def _report(found: list[Problem], problems: list[Problem] | None, summary: str) -> None:
    if problems is None:
        raise_if_problems(found, summary, SimulationInputError)
    else:
        problems.extend(found)


def _axis_values(text: str) -> list[float] | None:
    """The values of START:STOP:COUNT or v1,v2,...; None when the text is neither."""
    import math

    try:
        if ":" in text:
            start_text, stop_text, count_text = text.split(":")
            start, stop, count = float(start_text), float(stop_text), int(count_text)
            if count < 1 or not (math.isfinite(start) and math.isfinite(stop)):
                return None
            if count == 1:
                return [start]
            values = [start + (stop - start) * i / (count - 1) for i in range(count)]
            return [*values[:-1], stop]
        values = [float(v) for v in text.split(",")]
    except ValueError:
        return None
    return values if values and all(math.isfinite(v) for v in values) else None


#: The sweep's flags in its fixes (``lagrangian.cli.main`` words its errors with it).
SWEEP = sweep_wording()
