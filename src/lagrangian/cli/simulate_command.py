"""``lagrangian simulate``: the output files checked before any work, the integration with a
progress bar, then the data (CSV) first and the pictures after, each file written atomically;
a run that fails or is stopped by Ctrl-C keeps the rows it computed.  Beside the CSV go the
table of impacts (``run.impacts.csv``) and the points of a Poincaré section
(``--poincare EXPR``: ``run.poincare.csv``, and beside the plot ``run.poincare.png``)."""

from __future__ import annotations

import dataclasses
import io
import json
import math
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from lagrangian.cli.commands import load_system
from lagrangian.cli.outputs import file_problems
from lagrangian.cli.wording import COMMAND_LINE
from lagrangian.documents import apply_initial, apply_settings, run_document
from lagrangian.errors import (
    OutputError,
    Problem,
    SimulationError,
    SimulationInputError,
    raise_if_problems,
)
from lagrangian.model import System
from lagrangian.render.animation import animate as write_animation
from lagrangian.render.plots import save_plots
from lagrangian.render.projection import PROJECTIONS
from lagrangian.render.section_plot import save_section_plot
from lagrangian.simulation import Trajectory, simulate
from lagrangian.simulation.crossings import Crossing
from lagrangian.simulation.files import written_atomically, written_in_place
from lagrangian.simulation.impact_table import impacts_summary, write_impacts_csv
from lagrangian.simulation.poincare import PoincareSection, section_event, section_of
from lagrangian.simulation.progress_bar import progress_bar


def run_simulate(
    reference: str,
    *,
    options: dict[str, Any],
    out: str,
    plot: str | None,
    settings: Sequence[str],
    animate: str | None = None,
    frames: int | None = None,
    fps: float | None = None,
    projection: str | None = None,
    progress: bool = False,
    phase: str | None = None,
    initial: Sequence[str] = (),
    keep_failed: bool = False,
    poincare: Poincare | None = None,
) -> str:
    """Simulate; the CSV of docs/architecture.md goes to ``out`` (``-``: returned for standard
    output), then the plot, then the animation, each file written atomically.  The file
    names are checked before any work.  A run that fails or is stopped by Ctrl-C writes the
    rows computed so far (with ``keep_failed`` a failed run's plot and animation of them
    too), says where it stopped, and ends: SimulationError (exit 1), or after Ctrl-C exit
    code :data:`INTERRUPTED`.  ``initial`` items (``theta=0.5``) set initial values;
    ``poincare`` asks for the crossings of a section (:class:`Poincare`); ``frames``,
    ``fps`` and ``projection`` (a 3-D system's view) shape the animation."""
    check_outputs(out, plot, animate)
    check_animation_options(animate, frames, fps, projection)
    try:
        system = apply_settings(load_system(reference), settings, COMMAND_LINE)
        system = apply_initial(system, initial, COMMAND_LINE)
        check_phase(system, phase, plot)
        event = poincare.event(system) if poincare is not None else None
        given = {key: value for key, value in options.items() if value is not None}
        t_end = given.pop("t_end", None)
        end = t_end if t_end is not None else system.simulation.get("t_end", 0.0)
        bar = progress_bar(0.0, float(end), force=progress)
        events = [event] if event is not None else []
        trajectory = simulate(system, t_span=t_end, progress=bar, raise_on_failure=False,
                              events=events, **given)  # fmt: skip
        pictures = Pictures(
            plot,
            animate,
            phase,
            progress,
            keep_failed,
            frames=frames,
            fps=fps,
            projection=projection or "auto",
        )
        if poincare is not None and event is not None:
            section = section_of(trajectory, event, poincare.expression, poincare.direction)
            pictures = dataclasses.replace(pictures, section=section, section_axes=poincare.axes)
        return write_simulation(system, trajectory, out, pictures)
    except KeyboardInterrupt:  # before or after the integration: no file half written
        interrupted("Interrupted (Ctrl-C); files not finished were not written.")


@dataclasses.dataclass(frozen=True)
class Poincare:
    """``--poincare EXPR``: the section ``expression`` = 0 crossed in ``direction``, plotted
    in the plane of ``axes`` (None: the section's default)."""

    expression: str
    direction: str = "rising"
    axes: tuple[str, str] | None = None

    @classmethod
    def of(cls, expression: str | None, direction: str, axes: str | None) -> Poincare | None:
        """The request of the command line's flags (None without --poincare);
        SimulationInputError for axes that are not two names or come without it."""
        problems = []
        if axes is not None and expression is None:
            fix = "add --poincare EXPR"
            problems.append(Problem("--poincare-axes", "the axes of a section plot", fix))
        names = tuple(name.strip() for name in (axes or "").split(","))
        if axes is not None and (len(names) != 2 or not all(names)):
            fix = "give two columns, e.g. --poincare-axes y,y_dot"
            problems.append(Problem("--poincare-axes", f"{axes!r} is not two names", fix))
        raise_if_problems(problems, "Cannot simulate", SimulationInputError)
        if expression is None:
            return None
        return cls(expression, direction, (names[0], names[1]) if axes is not None else None)

    def event(self, system: System) -> Crossing:
        """The section's event function; SimulationInputError for axes that are not a
        coordinate or a velocity of ``system``, ExpressionError for an expression that is
        not one of its state."""
        columns = [q.name for q in system.coordinates]
        columns += [name + "_dot" for name in columns]
        unknown = [name for name in self.axes or () if name not in columns]
        if unknown:
            fix = "name coordinates or NAME_dot velocities: " + ", ".join(columns)
            message = f"{', '.join(unknown)}: not a column of the section"
            problems = [Problem("--poincare-axes", message, fix)]
            raise_if_problems(problems, "Cannot simulate", SimulationInputError)
        return section_event(system, self.expression, direction=self.direction, field="--poincare")


def check_phase(system: System, phase: str | None, plot: str | None) -> None:
    """Refuse, before simulating, a --phase that is not a coordinate or comes without --plot."""
    if phase is None:
        return
    names = [q.name for q in system.coordinates]
    problems = []
    if phase not in names:
        fix = "name one of " + ", ".join(names)
        problems.append(Problem("--phase", f"{phase!r} is not a coordinate", fix))
    if plot is None:
        problems.append(Problem("--phase", "the phase portrait is part of --plot", "add --plot"))
    raise_if_problems(problems, "Cannot simulate", SimulationInputError)


#: The exit code of a command stopped by Ctrl-C: 128 + SIGINT, as shells report it.
INTERRUPTED = 130


def interrupted(message: str) -> NoReturn:
    """End the command stopped by Ctrl-C: the message on standard error, exit code
    :data:`INTERRUPTED` (the errors' codes are 1 and 2; an interruption is neither)."""
    sys.stderr.write(f"lagrangian: {message}\n")
    raise SystemExit(INTERRUPTED)


#: The output formats of --plot and --animate.
PLOT_SUFFIXES = (".png", ".pdf", ".svg")
ANIMATION_SUFFIXES = (".gif", ".html", ".mp4")


def check_outputs(out: str, plot: str | None, animate: str | None) -> None:
    """Refuse, before simulating, an output file that cannot be written where it is asked
    (a folder, a missing folder: :mod:`lagrangian.cli.outputs`) or of a format that cannot
    be written: OutputError, every problem at once."""
    problems = file_problems({"--out": out}, "run.csv")
    problems += file_problems({"--plot": plot}, "run.png")
    problems += file_problems({"--animate": animate}, "run.gif")
    if plot is not None and Path(plot).suffix not in PLOT_SUFFIXES:
        problems.append(
            Problem(
                "--plot",
                f"{plot!r} is not a .png, .pdf or .svg file",
                "name it FILE.png, FILE.pdf or FILE.svg",
            )
        )
    suffix = Path(animate).suffix if animate is not None else None
    if suffix is not None and suffix not in ANIMATION_SUFFIXES:
        problems.append(
            Problem(
                "--animate",
                f"{animate!r}: no animation format {suffix or '(none)'}",
                "name it FILE.gif, FILE.html or FILE.mp4",
            )
        )
    if suffix == ".mp4" and not _ffmpeg_available():
        problems.append(
            Problem(
                "--animate",
                "an .mp4 animation needs ffmpeg, which is not installed",
                "install ffmpeg, or name it FILE.gif or FILE.html",
            )
        )
    if problems:
        raise OutputError("Cannot write the output:", problems)


def _ffmpeg_available() -> bool:
    from lagrangian.render.frames_writer import ffmpeg_path

    return ffmpeg_path() is not None


def check_animation_options(
    animate: str | None, frames: int | None, fps: float | None, projection: str | None = None
) -> None:
    """Refuse, before simulating, --frames and --fps that are not counts and rates, or that
    come (with --projection) without --animate: SimulationInputError, every problem at
    once."""
    problems = []
    if frames is not None and frames < 1:
        problems.append(
            Problem("--frames", f"{frames} frames", "give 1 or more, e.g. --frames 100")
        )
    if fps is not None and not (math.isfinite(fps) and fps > 0):
        problems.append(
            Problem("--fps", f"{fps:g} frames per second", "give a positive rate, e.g. --fps 25")
        )
    if projection is not None and projection not in PROJECTIONS:
        problems.append(
            Problem("--projection", repr(projection), "choose one of " + ", ".join(PROJECTIONS))
        )
    alone = {
        "--frames": (frames, "only an animation has frames"),
        "--fps": (fps, "only an animation plays"),
        "--projection": (projection, "only the animation draws a view of the system"),
    }
    for flag, (value, what) in alone.items():
        if value is not None and animate is None:
            problems.append(Problem(flag, what, "add --animate FILE.gif"))
    raise_if_problems(problems, "Cannot simulate", SimulationInputError)


@dataclasses.dataclass(frozen=True)
class Pictures:
    """What ``simulate`` draws after the CSV: the ``plot`` file (its phase portrait of
    ``phase``), the ``animate`` file (``frames`` of it played at ``fps``, a 3-D system seen
    in ``projection``; a progress bar on
    a terminal, or always with ``progress``), and whether a failed run gets them too
    (``keep_failed``); the points of a Poincaré ``section``, written beside the CSV and
    plotted in the plane of ``section_axes`` beside the plot."""

    plot: str | None = None
    animate: str | None = None
    phase: str | None = None
    progress: bool = False
    keep_failed: bool = False
    section: PoincareSection | None = None
    section_axes: tuple[str, str] | None = None
    frames: int | None = None
    fps: float | None = None
    projection: str = "auto"


def write_simulation(
    system: System, trajectory: Trajectory, out: str, pictures: Pictures = Pictures()
) -> str:
    """Write the CSV, then the plot and the animation of a run that reached its end; the
    CSV alone of one that did not (its pictures too with ``keep_failed``), and raise saying
    where it stopped."""
    if out == "-":
        buffer = io.StringIO()
        trajectory.to_csv(buffer)
        csv_text, where = buffer.getvalue(), "standard output"
    elif as_json(out):
        write_run_json(trajectory, out)
        csv_text, where = "", out
    else:
        trajectory.to_csv(out)
        csv_text, where = "", out
    if not trajectory.success:
        if sys.stdout is not None:  # the rows so far, before the error is reported
            sys.stdout.write(csv_text)
        said = trajectory.worded_message(COMMAND_LINE)  # --max-steps, not max_steps=
        stopped = f"{said} {_rows_written(trajectory)} written to {where}."
        if trajectory.status == "interrupted":
            interrupted(stopped)
        raise SimulationError(" ".join([stopped, *_failed_pictures(system, trajectory, pictures)]))
    messages = [f"{len(trajectory.t)} samples written to {where}; {trajectory.drift_summary()}"]
    messages += impacts_written(trajectory, out)
    messages += section_written(pictures.section, out)
    messages += draw_pictures(system, trajectory, pictures)
    if out != "-":
        return "\n".join(messages)
    print("\n".join(messages), file=sys.stderr)  # beside the rows, not among them
    return terminal_preview(csv_text) if _terminal(sys.stdout) else csv_text


#: Rows shown at each end of a CSV printed on a terminal (a pipe gets every row).
PREVIEW_ROWS = 5


def _terminal(stream: object) -> bool:
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())


def terminal_preview(csv_text: str) -> str:
    """The header, the first and the last rows of a CSV, and how to keep them all: what a
    terminal can show of 1000 rows.

    >>> print(terminal_preview("t,x\\n" + "".join(f"{k},{k}\\n" for k in range(20))))
    t,x
    0,0
    1,1
    2,2
    3,3
    4,4
    ... 10 more rows: --out FILE writes them all, or pipe the output
    15,15
    16,16
    17,17
    18,18
    19,19
    """
    lines = csv_text.splitlines()
    header, rows = lines[:1], lines[1:]
    if len(rows) <= 2 * PREVIEW_ROWS + 1:
        return csv_text
    hidden = len(rows) - 2 * PREVIEW_ROWS
    note = f"... {hidden} more rows: --out FILE writes them all, or pipe the output"
    return "\n".join([*header, *rows[:PREVIEW_ROWS], note, *rows[-PREVIEW_ROWS:]])


def impacts_written(trajectory: Trajectory, out: str) -> list[str]:
    """The impacts of the run in a table beside the CSV (``NAME.impacts.csv``), and what they
    were in one line; nothing without impacts."""
    if not trajectory.impacts:
        return []
    summary = impacts_summary(trajectory.impacts)
    if out == "-" or written_in_place(out):  # no table beside a device, in /dev
        return [summary]
    if as_json(out):
        return [f"{summary}; each in the summary's impacts in {out}"]
    table = beside(out, "impacts", ".csv")
    write_impacts_csv(trajectory.impacts, table)
    return [f"{summary}; each written to {table}"]


def section_written(section: PoincareSection | None, out: str) -> list[str]:
    """The points of the Poincaré section in a table beside the CSV (``NAME.poincare.csv``),
    and how many there were; nothing without a section."""
    if section is None:
        return []
    if out == "-" or written_in_place(out):  # no table beside a device, in /dev
        return [f"{section.summary()} (--out FILE writes them beside the run)"]
    table = beside(out, "poincare", ".csv")
    section.to_csv(table)
    return [f"{section.summary()} written to {table}"]


def beside(path: str, kind: str, suffix: str) -> str:
    """A file beside ``path`` holding one ``kind`` of its results: ``run.csv`` ->
    ``run.impacts.csv`` (``suffix`` when the path has none, or is a JSON run's: the table
    is a CSV)."""
    named = Path(path)
    own = "" if as_json(path) else named.suffix
    return str(named.with_name(f"{named.stem}.{kind}{own or suffix}"))


def as_json(out: str) -> bool:
    """Whether ``--out`` asks for the run as JSON (FILE.json) rather than CSV."""
    return out != "-" and Path(out).suffix.lower() == ".json"


def write_run_json(trajectory: Trajectory, out: str) -> None:
    """The run's columns and summary as one JSON document (:func:`run_document`), written
    atomically as the CSV is."""
    text = json.dumps(run_document(trajectory, COMMAND_LINE), allow_nan=False)
    with written_atomically(out) as temporary:
        temporary.write_text(text + "\n", encoding="utf-8")


def _failed_pictures(system: System, trajectory: Trajectory, pictures: Pictures) -> list[str]:
    """The pictures of a failed run's rows with --keep-failed, else how to get them."""
    if pictures.plot is None and pictures.animate is None:
        return []
    if not pictures.keep_failed:
        return ["No pictures of a run that did not reach its end: add --keep-failed for them."]
    if len(trajectory.t) < 2:
        return ["Too few rows to draw."]
    return [
        f"{message[0].upper()}{message[1:]}."
        for message in draw_pictures(system, trajectory, pictures)
    ]


def draw_pictures(system: System, trajectory: Trajectory, pictures: Pictures) -> list[str]:
    """Write the plot and the animation of ``pictures``, each atomically; what was written."""
    messages = []
    if pictures.plot:
        with written_atomically(pictures.plot) as temporary:
            save_plots(trajectory, temporary, pictures.phase, system)
        messages.append(f"plot written to {pictures.plot}")
    if pictures.plot and pictures.section is not None:
        picture = beside(pictures.plot, "poincare", ".png")
        with written_atomically(picture) as temporary:
            save_section_plot(pictures.section, temporary, pictures.section_axes, system)
        messages.append(f"Poincaré section plot written to {picture}")
    if pictures.animate:
        with written_atomically(pictures.animate) as temporary:
            write_animation(
                system,
                trajectory,
                temporary,
                frames=pictures.frames,
                fps=pictures.fps,
                projection=pictures.projection,
                progress=frame_progress(pictures.progress),
            )
        messages.append(f"animation written to {pictures.animate}")
    return messages


def frame_progress(force: bool = False) -> Callable[[int, int], None] | None:
    """A progress bar of the frames of an animation being written, on standard error: only
    on a terminal unless ``force`` (None then)."""
    if progress_bar(0.0, 1.0, force=force) is None:
        return None
    bars: list[Callable[[float], None] | None] = []

    def update(done: int, total: int) -> None:
        if not bars:  # the total is known once writing starts
            bars.append(progress_bar(0.0, float(total), force=True, label="frame "))
        bar = bars[0]
        if bar is not None:
            bar(float(done))

    return update


def _rows_written(trajectory: Trajectory) -> str:
    if not len(trajectory.t):
        return "No rows"
    return f"{len(trajectory.t)} rows, up to t = {trajectory.t[-1]:.6g},"
