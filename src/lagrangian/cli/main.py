"""The ``lagrangian`` command.  Exit codes are decided here only: 0 ok, 1 failure, 2 bad input.

lagrangian examples                       list the built-in examples
lagrangian examples NAME                  describe one
lagrangian derive examples/NAME --steps   derive with every step
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Sequence
from typing import Any, NoReturn

from lagrangian.cli.commands import (
    analyze_command,
    derive_command,
    examples_command,
    export_command,
    simulate_command,
)
from lagrangian.errors import ExpressionError, LagrangianError, ModelError

OK, FAILURE, BAD_INPUT = 0, 1, 2

EPILOG = """examples:
  lagrangian examples
  lagrangian derive examples/double_pendulum --steps
  lagrangian derive examples/robot_arm --format json
  lagrangian derive examples/simple_pendulum --format latex --set m=2
  lagrangian export examples/double_pendulum --language c --out build/
  lagrangian simulate examples/double_pendulum --t-end 10 --out traj.csv --plot traj.png
  lagrangian derive my_model.yaml --steps
  lagrangian analyze examples/double_pendulum
  lagrangian analyze examples/spherical_pendulum --about theta=0.5,phi_dot=2
"""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # argparse exits 2 on bad usage, as we do
        self.print_usage(sys.stderr)
        self.exit(BAD_INPUT, f"{self.prog}: error: {message}\n")


def _command(sub: Any, name: str, summary: str, example: str) -> argparse.ArgumentParser:
    """A subcommand taking a model, ``--set`` overrides and ``--debug``, with an example."""
    command: argparse.ArgumentParser = sub.add_parser(
        name,
        help=summary,
        description=summary,
        epilog=f"example: {example}",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    command.add_argument("model", help="examples/NAME, a model file, or - for stdin")
    command.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="override a parameter or an initial value (repeatable)",
    )
    command.add_argument("--debug", action="store_true", help="show tracebacks")
    return command


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="lagrangian",
        description="Analytical mechanics, from energies to motion.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--debug", action="store_true", help="show tracebacks")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    derive = _command(
        sub,
        "derive",
        "Euler–Lagrange equations of a system",
        "lagrangian derive examples/double_pendulum --steps",
    )
    derive.add_argument("--format", choices=["text", "latex", "mathml", "json"], default="text")
    derive.add_argument("--steps", action="store_true", help="show every step of the derivation")
    derive.add_argument("--matrix", action="store_true", help="also show M, C q_dot, G, Q")

    export = _command(
        sub,
        "export",
        "generate code: NumPy, C, MATLAB/Octave, Julia",
        "lagrangian export examples/double_pendulum --language c --out build/",
    )
    export.add_argument("--language", choices=["numpy", "c", "matlab", "julia"], default="numpy")
    export.add_argument("--out", default="-", help="a folder for the files, or - for stdout")

    analyze = _command(
        sub,
        "analyze",
        "momenta, conservation laws, Hamiltonian, equilibria, modes (JSON)",
        "lagrangian analyze examples/spherical_pendulum --about theta=0.5,phi_dot=2",
    )
    analyze.add_argument(
        "--about",
        metavar="NAME=VALUE[,NAME=VALUE...]",
        help="linearize about this state (unlisted coordinates and velocities are 0)",
    )
    analyze.add_argument(
        "--input",
        action="append",
        default=[],
        metavar="PARAMETER",
        help="a parameter taken as an input u of the linearization",
    )

    simulate = _command(
        sub,
        "simulate",
        "integrate the motion; CSV of t, coordinates, velocities, energy",
        "lagrangian simulate examples/double_pendulum --t-end 10 --out traj.csv --plot traj.png",
    )
    simulate.add_argument("--t-end", type=float, help="end time (default: the model's)")
    simulate.add_argument("--method", help="RK45, RK23, DOP853, Radau, BDF, LSODA or RK4")
    simulate.add_argument("--rtol", type=float, help="relative tolerance")
    simulate.add_argument("--atol", type=float, help="absolute tolerance")
    simulate.add_argument("--samples", type=int, help="number of evenly spaced output times")
    simulate.add_argument("--out", default="-", help="CSV file, or - for standard output")
    simulate.add_argument("--plot", help="write time series, phase portrait and energy (PNG)")
    simulate.add_argument(
        "--animate", metavar="FILE", help="write an animation: .gif, .html, or .mp4 (needs ffmpeg)"
    )
    simulate.add_argument(
        "--progress",
        action="store_true",
        help="show a progress bar even when stderr is not a terminal",
    )

    examples = sub.add_parser(
        "examples",
        help="list or describe the built-in examples",
        epilog="example: lagrangian examples double_pendulum",
    )
    examples.add_argument("name", nargs="?", help="an example to describe")
    examples.add_argument("--debug", action="store_true", help="show tracebacks")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    args = build_parser().parse_args(argv)
    try:
        if args.command == "derive":
            output = derive_command(
                args.model, fmt=args.format, steps=args.steps, matrix=args.matrix, settings=args.set
            )
        elif args.command == "analyze":
            output = analyze_command(
                args.model, about=args.about, inputs=args.input, settings=args.set
            )
        elif args.command == "simulate":
            options = {
                "t_end": args.t_end,
                "method": args.method,
                "rtol": args.rtol,
                "atol": args.atol,
                "samples": args.samples,
            }
            output = simulate_command(
                args.model,
                options=options,
                out=args.out,
                plot=args.plot,
                settings=args.set,
                animate=args.animate,
                progress=args.progress,
            )
        elif args.command == "export":
            output = export_command(
                args.model, language=args.language, out=args.out, settings=args.set
            )
        else:
            output = examples_command(args.name)
        sys.stdout.write(output if output.endswith("\n") else output + "\n")
        return OK
    except (ModelError, ExpressionError, FileNotFoundError, IsADirectoryError) as error:
        return _report(error, BAD_INPUT, args.debug)
    except LagrangianError as error:  # listed problems are the input's; otherwise it failed
        return _report(error, BAD_INPUT if error.problems else FAILURE, args.debug)
    except OSError as error:
        return _report(error, FAILURE, args.debug)
    except Exception as error:  # a bug: say so plainly, traceback only with --debug
        return _report(error, FAILURE, args.debug, prefix="internal error: ")


def _report(error: BaseException, code: int, debug: bool, prefix: str = "") -> int:
    if debug:
        traceback.print_exception(error)
    sys.stderr.write(f"lagrangian: {prefix}{error}\n")
    return code


if __name__ == "__main__":
    raise SystemExit(main())
