"""The ``lagrangian`` command: parse the arguments, run the command, print what it returns.

Exit codes: 0 ok, 1 failure, 2 bad input.  Each error knows its own
(:attr:`lagrangian.errors.LagrangianError.exit_code`); this module prints the message and
returns that code, with the traceback only under ``--debug``.  The parser needs neither SymPy
nor NumPy, so ``lagrangian --help`` and ``--version`` answer at once; the commands
(:mod:`lagrangian.cli.commands`) load after the arguments are parsed.

lagrangian examples                       list the built-in examples
lagrangian examples NAME                  describe one
lagrangian derive examples/NAME --steps   derive with every step
"""

from __future__ import annotations

import argparse
import codecs
import contextlib
import difflib
import io
import math
import os
import signal
import sys
import threading
import traceback
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from lagrangian.cli import serve_command, sweep_command
from lagrangian.cli.wording import COMMAND_LINE
from lagrangian.errors import BAD_INPUT, FAILURE, ArgumentError, LagrangianError
from lagrangian.limits import time_limit as library_limit

if TYPE_CHECKING:
    from lagrangian.cli.commands import JsonDocument

OK = 0

EPILOG = """examples:
  lagrangian examples
  lagrangian derive examples/double_pendulum --steps
  lagrangian derive examples/robot_arm --format json
  lagrangian derive examples/simple_pendulum --format latex --set m=2
  lagrangian export examples/double_pendulum --language c --out build/
  lagrangian simulate examples/double_pendulum --t-end 10 --out traj.csv --plot traj.png
  lagrangian derive my_model.yaml --steps
  lagrangian analyze examples/double_pendulum
  lagrangian analyze examples/double_pendulum --format json > analysis.json
  lagrangian analyze examples/spherical_pendulum --about theta=0.5,phi_dot=2
"""


class _Parser(argparse.ArgumentParser):
    def parse_args(self, args: Any = None, namespace: Any = None) -> Any:
        # kept for the suggestion: the words say which command an unknown option was given to
        self._words = list(sys.argv[1:] if args is None else args)
        return super().parse_args(args, namespace)

    def error(self, message: str) -> NoReturn:  # argparse exits 2 on bad usage, as we do
        self.print_usage(sys.stderr)
        self.exit(BAD_INPUT, f"{self.prog}: error: {message}{self._suggestion(message)}\n")

    def _suggestion(self, message: str) -> str:
        """`` — did you mean --t-end?`` for a mistyped option (argparse names none), or
        `` — simulate has no --format (derive, export, analyze do)`` for another command's."""
        if not message.startswith("unrecognized arguments:"):
            return ""
        commands = _subcommands(self)
        command = next((w for w in getattr(self, "_words", []) if w in commands), None)
        known = _option_strings(commands[command] if command else self)
        hints = []
        for token in message.split(":", 1)[1].split():
            if not token.startswith("--"):
                continue
            name = token.split("=", 1)[0]
            owners = [c for c, sub in commands.items() if name in _option_strings(sub)]
            if command in owners:  # given before the command's name
                hints.append(f"give {name} after {command}")
                continue
            if command and owners:
                verb = "does" if len(owners) == 1 else "do"
                hints.append(f"{command} has no {name} ({', '.join(owners)} {verb})")
                continue
            hints += [f"did you mean {g}?" for g in difflib.get_close_matches(name, known, n=1)]
        return f" — {'; '.join(dict.fromkeys(hints))}" if hints else ""


def _subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    """The subcommands of ``parser`` by name (none for a subcommand's own parser)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _option_strings(parser: argparse.ArgumentParser) -> list[str]:
    """Every long option of ``parser`` and of its subcommands."""
    found = []
    for action in parser._actions:
        found += [o for o in action.option_strings if o.startswith("--")]
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found += _option_strings(sub)
    return sorted(set(found))


class _Version(argparse.Action):
    """``--version``: the installed version, read from the package metadata when asked."""

    def __init__(self, option_strings: Sequence[str], dest: str, **kwargs: Any) -> None:
        super().__init__(
            option_strings,
            dest,
            nargs=0,
            default=argparse.SUPPRESS,
            help="show the version and exit",
        )

    def __call__(self, parser: argparse.ArgumentParser, *args: Any) -> NoReturn:
        import lagrangian

        sys.stdout.write(f"{parser.prog} {lagrangian.__version__}\n")
        parser.exit(OK)


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
        "--input-format",
        choices=["yaml", "toml", "json"],
        help="the format of the model read from standard input (default: JSON when it starts "
        "with {, else YAML)",
    )
    command.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="override a parameter or an initial value (repeatable)",
    )
    _debug_option(command)
    return command


def _debug_option(command: argparse.ArgumentParser) -> None:
    """``--debug`` and ``--timeout`` after the subcommand; absent, they leave the ones before
    it (``lagrangian --debug derive ...``) as they were instead of resetting them."""
    command.add_argument(
        "--debug", action="store_true", default=argparse.SUPPRESS, help="show tracebacks"
    )
    command.add_argument(
        "--timeout", type=float, default=argparse.SUPPRESS, metavar="SECONDS", help=TIMEOUT_HELP
    )
    command.add_argument(
        "--size-limit",
        type=operations_option,
        default=argparse.SUPPRESS,
        metavar="OPERATIONS",
        help=SIZE_LIMIT_HELP,
    )


TIMEOUT_HELP = "stop the command after this many seconds of wall time (exit 1, with a message)"
TIMEOUT_FIX = (
    "give more time with --timeout SECONDS (or the environment variable "
    "LAGRANGIAN_TIME_LIMIT, none for no limit), or simplify the model"
)
SIZE_LIMIT_HELP = (
    "stop the command when a derived expression grows past this many operations (exit 1, "
    "naming it; default $LAGRANGIAN_SIZE_LIMIT or 5000000; none for no limit)"
)


def operations_option(text: str) -> float:
    """``--size-limit``: a positive whole number of operations, or none (no limit)."""
    if text.strip().lower() in ("none", "off", "inf"):
        return math.inf
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(
            f"{text[:40]!r}: give a positive whole number of operations, or none for no limit"
        )
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="lagrangian",
        description="Analytical mechanics, from energies to motion.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action=_Version)
    parser.add_argument("--debug", action="store_true", help="show tracebacks")
    parser.add_argument("--timeout", type=float, metavar="SECONDS", help=TIMEOUT_HELP)
    parser.add_argument(
        "--size-limit", type=operations_option, metavar="OPERATIONS", help=SIZE_LIMIT_HELP
    )
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
    derive.add_argument(
        "--substitute",
        action="store_true",
        help="put the parameters' values (with --set) into the equations",
    )

    export = _command(
        sub,
        "export",
        "generate code: NumPy, C, MATLAB/Octave, Julia",
        "lagrangian export examples/double_pendulum --language c --out build/",
    )
    export.add_argument("--language", choices=["numpy", "c", "matlab", "julia"], default="numpy")
    export.add_argument("--out", default="-", help="a folder for the files, or - for stdout")
    export.add_argument(
        "--independent",
        metavar="NAMES",
        help="export the minimal form in these coordinates (comma-separated), the holonomic "
        "constraints eliminated; default with constraints: the multiplier form",
    )

    analyze = _command(
        sub,
        "analyze",
        "momenta, conservation laws, Hamiltonian, equilibria, modes (on the constraints)",
        "lagrangian analyze examples/spherical_pendulum --about theta=0.5,phi_dot=2",
    )
    analyze.add_argument(
        "--format",
        choices=["json", "text", "latex"],
        help="text for people (the default on a terminal), json for scripts (the default when "
        "the output goes to a pipe or a file), latex",
    )
    analyze.add_argument(
        "--project",
        action="store_true",
        help="move the --about state onto the constraints before linearizing",
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
    analyze.add_argument(
        "--limit-cycle",
        metavar="TRANSITION|EXPR",
        help="find the period-one cycle through this transition (a walker's heel strike), or "
        "through the section EXPR = 0 crossed rising (theta: a pendulum's swing through the "
        "vertical), near the motion from the initial state, with its period and Floquet "
        "multipliers",
    )
    analyze.add_argument(
        "--initial",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="an initial value for --limit-cycle (theta=0.2; repeatable)",
    )
    analyze.add_argument(
        "--search-degree",
        type=int,
        default=2,
        metavar="N",
        help="degree of the functions in which further first integrals are sought "
        "(Lie point symmetries, integrals quadratic in the velocities; 3 or more also "
        "cubic ones); 0: no search",
    )

    simulate = _command(
        sub,
        "simulate",
        "integrate the motion; CSV of t, coordinates, velocities, energy",
        "lagrangian simulate examples/double_pendulum --t-end 10 --out traj.csv --plot traj.png",
    )
    simulate.add_argument("--t-end", type=float, help="end time (default: the model's)")
    simulate.add_argument("--method", help=f"one of {method_names()} (default RK45)")
    simulate.add_argument("--rtol", type=float, help="relative tolerance")
    simulate.add_argument("--atol", type=float, help="absolute tolerance")
    simulate.add_argument("--dt", type=float, help="the step of a fixed-step method")
    simulate.add_argument("--samples", type=int, help="number of evenly spaced output times")
    simulate.add_argument(
        "--max-steps", type=int, help="stop after this many steps (default 1,000,000)"
    )
    simulate.add_argument(
        "--max-wall-time", type=float, metavar="SECONDS", help="stop after this many seconds"
    )
    simulate.add_argument(
        "--initial",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set the initial value of a coordinate or a velocity (theta=0.5, theta_dot=0; "
        "repeatable)",
    )
    simulate.add_argument(
        "--keep-failed",
        action="store_true",
        help="a run that fails also writes the plot and the animation of the rows computed up "
        "to the failure (the CSV of them is always written; the exit code stays 1)",
    )
    simulate.add_argument(
        "--project-initial",
        action="store_true",
        help="move an initial state that violates the constraints onto them",
    )
    simulate.add_argument(
        "--phase", metavar="NAME", help="the coordinate of the plot's phase portrait"
    )
    simulate.add_argument(
        "--poincare",
        metavar="EXPR",
        help="record the crossings of the section EXPR = 0 (an expression of the state, e.g. x): "
        "written to NAME.poincare.csv beside --out, plotted to NAME.poincare.png beside --plot",
    )
    simulate.add_argument(
        "--poincare-direction",
        choices=("rising", "falling", "both"),
        default="rising",
        help="the crossings counted: EXPR from negative to positive (default), the reverse, both",
    )
    simulate.add_argument(
        "--poincare-axes",
        metavar="A,B",
        help="the two columns of the section plot (default: the first coordinate the section "
        "does not involve and its velocity, y,y_dot for --poincare x)",
    )
    simulate.add_argument(
        "--out",
        default="-",
        help="CSV file (FILE.json: the columns and the run's summary as JSON), or - for "
        "standard output",
    )
    simulate.add_argument(
        "--plot", help="write time series, phase portrait and energy (.png, .pdf or .svg)"
    )
    simulate.add_argument(
        "--animate", metavar="FILE", help="write an animation: .gif, .html, or .mp4 (needs ffmpeg)"
    )
    simulate.add_argument(
        "--frames",
        type=int,
        metavar="N",
        help="frames of the --animate animation (default: from the motion's time scale, "
        "10 per swing of its fastest coordinate, 40 to 300)",
    )
    simulate.add_argument(
        "--fps",
        type=float,
        metavar="F",
        help="frames per second of the --animate animation's playback (default 25)",
    )
    simulate.add_argument(
        "--projection",
        metavar="VIEW",
        # the names of lagrangian.render.projection.PROJECTIONS (a test keeps them equal;
        # importing the render layer here would slow every command's start)
        help="the view of a 3-D system in the --animate animation: auto (default: the plane "
        "the motion spreads over most), xy, xz, yz or isometric",
    )
    simulate.add_argument(
        "--progress",
        action="store_true",
        help="show the progress bars (the run, the frames of --animate) even when stderr is "
        "not a terminal",
    )

    sweep_command.add_sweep_options(
        _command(sub, "sweep", sweep_command.SUMMARY, sweep_command.EXAMPLE)
    )

    serve_command.add_serve_parser(sub)

    examples = sub.add_parser(
        "examples",
        help="list or describe the built-in examples",
        epilog="example: lagrangian examples double_pendulum",
    )
    examples.add_argument("name", nargs="?", help="an example to describe")
    _debug_option(examples)
    return parser


#: What an internal error (a bug, not bad input) adds.
BUG_HINT = (
    "this is a bug in lagrangian, not a problem with your input: please report it with the "
    "output of the same command run with --debug"
)


def method_names() -> str:
    """The simulation methods, from the one table of them (imports no SciPy)."""
    from lagrangian.simulation.methods import TABLE

    return ", ".join(TABLE)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    if sys.stderr is None:  # closed (2>&-): the messages go nowhere, as asked
        sys.stderr = Discarded()
    args = build_parser().parse_args(argv)
    try:
        with (
            terminated_in_order(args.command),
            time_limit(args.timeout, args.command),
            size_limit(args.size_limit),
        ):
            output = run(args)
    except Exception as raised:
        code = exit_code(raised, given_paths(args))
        error = in_command_line_words(raised, args.command)
        if args.debug:
            traceback.print_exception(error)
        internal = not isinstance(error, (LagrangianError, OSError))
        prefix = "internal error: " if internal else ""  # a bug: say so plainly
        sys.stderr.write(f"lagrangian: {prefix}{error}\n")
        if internal and not args.debug:
            sys.stderr.write(f"lagrangian: {BUG_HINT}\n")
        return code
    return write_output(output)


class Discarded(io.TextIOBase):
    """A text stream that keeps nothing: standard error when it was closed."""

    def write(self, text: str) -> int:
        return len(text)


#: The exit code of a command ended by SIGTERM: 128 + 15, as shells report it.
TERMINATED = 128 + signal.SIGTERM


@contextlib.contextmanager
def terminated_in_order(command: str = "") -> Iterator[None]:
    """SIGTERM (``kill``, a batch system's time limit) ends the command in order: SystemExit
    unwinds it, so a file being written removes its temporary file
    (:mod:`lagrangian.simulation.files`) instead of leaving it beside the target; exit code
    :data:`TERMINATED`.  Not for :data:`LONG_RUNNING` commands (their servers handle the
    signal) nor off the main thread (where no handler can be set)."""
    if command in LONG_RUNNING or threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, frame: Any) -> NoReturn:
        sys.stderr.write("lagrangian: stopped by SIGTERM; files not finished were not written\n")
        raise SystemExit(TERMINATED)

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


#: The commands that run until they are stopped: the command as a whole has no time limit
#: unless --timeout gives one (each playground request and each sweep member keeps its own
#: bound), so the playground does not stop itself after the default ten minutes.
LONG_RUNNING = ("serve", "sweep")


@contextlib.contextmanager
def time_limit(seconds: float | None, command: str = "") -> Iterator[None]:
    """The command's time limit (:func:`lagrangian.limits.time_limit`, the one timer):
    TimeLimitError when ``seconds`` of wall time have passed (a symbolic computation that
    grows without end, a run asked for too long).  None: the library's own limit
    ($LAGRANGIAN_TIME_LIMIT, else ten minutes), its message speaking of ``--timeout``; none
    at all for a :data:`LONG_RUNNING` command."""
    if seconds is None:
        if command in LONG_RUNNING:
            yield
            return
        with library_limit(what="the command", fix=TIMEOUT_FIX):
            yield
        return
    if not seconds > 0:
        raise ArgumentError(f"--timeout {seconds:g}: give a positive number of seconds")
    message = (
        f"stopped after --timeout {seconds:g} s: the work on this model is larger than the "
        "time given (a long expression, a long run); give more time, or simplify the model"
    )
    with library_limit(seconds, message=message):
        yield


@contextlib.contextmanager
def size_limit(operations: float | None) -> Iterator[None]:
    """The size limit of derived expressions in the command (:mod:`lagrangian.size_limits`:
    ``operations``, else the configured one), its message speaking of ``--size-limit``."""
    from lagrangian.size_limits import size_limit as sized_to

    with sized_to(operations, where="--size-limit"):
        yield


def in_command_line_words(error: Exception, command: str | None = None) -> Exception:
    """``error`` with the options its fixes name said as the ``command``'s flags
    (``--max-steps``, not ``max_steps=...``: :data:`lagrangian.cli.wording.COMMAND_LINE`;
    a sweep's own, :data:`lagrangian.cli.sweep_command.SWEEP`)."""
    if not isinstance(error, LagrangianError):
        return error
    return error.worded(sweep_command.SWEEP if command == "sweep" else COMMAND_LINE)


#: Bytes written to standard output at a time (a closed pipe is noticed within one chunk).
CHUNK = 1 << 16


def write_output(output: str | JsonDocument) -> int:
    """Write ``output`` (text, or a JSON document encoded as it goes) to standard output,
    encoded a chunk at a time (a large output is never held twice); a reader that closes the
    pipe early (``| head``) is an error, said in one line: exit 1, never a success with the
    data silently lost; so is a closed standard output (``>&-``)."""
    if sys.stdout is None:
        sys.stderr.write(
            "lagrangian: standard output is closed, so the output was not written; give the "
            "command an open standard output (a file, a pipe), or --out FILE where it has one\n"
        )
        return FAILURE
    encoding = sys.stdout.encoding or "utf-8"
    encoder = codecs.getincrementalencoder(encoding)(errors="replace")
    written = 0
    try:
        sys.stdout.flush()
        for piece in _pieces(output):
            data = encoder.encode(piece)
            sys.stdout.buffer.write(data)
            sys.stdout.buffer.flush()
            written += len(data)
        sys.stdout.buffer.write(encoder.encode("", final=True))
    except BrokenPipeError:
        # nothing more can reach the reader; keep Python's own flush at exit quiet
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.stderr.write(
            f"lagrangian: the output pipe was closed by its reader after at most {written} "
            "bytes; write to a file with --out to keep all of it\n"
        )
        return FAILURE
    return OK


def _pieces(output: str | JsonDocument) -> Iterator[str]:
    """``output`` in pieces of about :data:`CHUNK` characters, ending with a newline."""
    if isinstance(output, str):
        text = output if output.endswith("\n") else output + "\n"
        for start in range(0, len(text), CHUNK):
            yield text[start : start + CHUNK]
        return
    buffered: list[str] = []
    size = 0
    for chunk in output.chunks():
        buffered.append(chunk)
        size += len(chunk)
        if size >= CHUNK:
            yield "".join(buffered)
            buffered, size = [], 0
    yield "".join(buffered)


def run(args: argparse.Namespace) -> str | JsonDocument:
    """What the parsed command prints (SymPy, NumPy and the rest load here: the simulation's
    integrators and SciPy only for ``simulate``)."""
    from lagrangian.cli import commands

    if getattr(args, "input_format", None) and args.model == "-":
        args.model = f"-:{args.input_format}"  # standard input in the format given
    if args.command == "derive" and args.format == "json":
        return commands.derive_json(
            args.model, steps=args.steps, settings=args.set, substitute=args.substitute
        )
    if args.command == "derive":
        return commands.derive_command(
            args.model,
            fmt=args.format,
            steps=args.steps,
            matrix=args.matrix,
            settings=args.set,
            substitute=args.substitute,
        )
    if args.command == "analyze":
        return commands.analyze_command(
            args.model,
            about=args.about,
            inputs=args.input,
            settings=args.set,
            fmt=args.format or analysis_format(sys.stdout),
            project=args.project,
            search_degree=args.search_degree,
            cycle=args.limit_cycle,
            initial=args.initial,
        )
    if args.command == "simulate":
        from lagrangian.cli import simulate_command

        options = {
            "t_end": args.t_end,
            "method": args.method,
            "rtol": args.rtol,
            "atol": args.atol,
            "samples": args.samples,
            "dt": args.dt,
            "max_steps": args.max_steps,
            "max_wall_time": args.max_wall_time,
            "project_initial": args.project_initial or None,
        }
        return simulate_command.run_simulate(
            args.model,
            options=options,
            out=args.out,
            plot=args.plot,
            settings=args.set,
            animate=args.animate,
            frames=args.frames,
            fps=args.fps,
            projection=args.projection,
            progress=args.progress,
            phase=args.phase,
            initial=args.initial,
            keep_failed=args.keep_failed,
            poincare=simulate_command.Poincare.of(
                args.poincare, args.poincare_direction, args.poincare_axes
            ),
        )
    if args.command == "export":
        return commands.export_command(
            args.model,
            language=args.language,
            out=args.out,
            settings=args.set,
            independent=args.independent,
        )
    if args.command == "sweep":
        return sweep_command.run_sweep(args)
    if args.command == "serve":
        return serve_command.run_serve(args)
    return commands.examples_command(args.name)


def analysis_format(stdout: Any) -> str:
    """``analyze``'s format without ``--format``: text for a person at a terminal, JSON for a
    script (a pipe or a file), so scripts keep reading JSON.

    >>> import io
    >>> analysis_format(io.StringIO())
    'json'
    """
    try:
        return "text" if stdout.isatty() else "json"
    except (AttributeError, ValueError):  # no stream, or a closed one
        return "json"


def given_paths(args: argparse.Namespace) -> tuple[str, ...]:
    """The files and folders named on the command line (the model, --out, --plot, --animate)."""
    names = (getattr(args, key, None) for key in ("model", "out", "plot", "animate"))
    return tuple(name for name in names if name and name != "-")


def exit_code(error: BaseException, paths: Sequence[str] = ()) -> int:
    """The exit code ``error`` means: a LagrangianError's own ``exit_code``; for an OSError,
    bad input (2) when it is about one of ``paths``, the files given on the command line (a
    model that is missing or unreadable, an output folder that does not exist), else a
    failure (1); any other exception is a bug, a failure.

    >>> exit_code(PermissionError(13, "Permission denied", "model.yaml"), ["model.yaml"])
    2
    >>> exit_code(OSError(28, "No space left on device")), exit_code(KeyError("x"))
    (1, 1)
    """
    if isinstance(error, LagrangianError):
        return error.exit_code
    if isinstance(error, OSError) and error.filename is not None:
        about = Path(os.fsdecode(error.filename))
        if any(about == Path(path) for path in paths):
            return BAD_INPUT
    return FAILURE


if __name__ == "__main__":
    raise SystemExit(main())
