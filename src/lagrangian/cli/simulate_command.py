"""``lagrangian simulate``: the output files checked before any work, the integration with a
progress bar, then the data (CSV) first and the pictures after, each file written atomically;
a run that fails or is stopped by Ctrl-C keeps the rows it computed."""

from __future__ import annotations

import dataclasses
import io
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from lagrangian.cli.commands import load_system
from lagrangian.cli.outputs import file_problems
from lagrangian.cli.wording import COMMAND_LINE
from lagrangian.documents import apply_initial, apply_settings
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
from lagrangian.simulation import Trajectory, simulate
from lagrangian.simulation.files import written_atomically, written_in_place
from lagrangian.simulation.impact_table import impacts_summary, write_impacts_csv
from lagrangian.simulation.progress_bar import progress_bar


def run_simulate(
    reference: str,
    *,
    options: dict[str, Any],
    out: str,
    plot: str | None,
    settings: Sequence[str],
    animate: str | None = None,
    progress: bool = False,
    phase: str | None = None,
    initial: Sequence[str] = (),
    keep_failed: bool = False,
) -> str:
    """Simulate; the CSV of docs/architecture.md goes to ``out`` (``-``: returned for standard
    output), then the plot, then the animation, each file written atomically.  The file
    names are checked before any work.  A run that fails or is stopped by Ctrl-C writes the
    rows computed so far (with ``keep_failed`` a failed run's plot and animation of them
    too), says where it stopped, and ends: SimulationError (exit 1), or after Ctrl-C exit
    code :data:`INTERRUPTED`.  ``initial`` items (``theta=0.5``) set initial values."""
    check_outputs(out, plot, animate)
    try:
        system = apply_settings(load_system(reference), settings, COMMAND_LINE)
        system = apply_initial(system, initial, COMMAND_LINE)
        check_phase(system, phase, plot)
        given = {key: value for key, value in options.items() if value is not None}
        t_end = given.pop("t_end", None)
        end = t_end if t_end is not None else system.simulation.get("t_end", 0.0)
        bar = progress_bar(0.0, float(end), force=progress)
        trajectory = simulate(system, t_span=t_end, progress=bar, raise_on_failure=False, **given)
        pictures = Pictures(plot, animate, phase, progress, keep_failed)
        return write_simulation(system, trajectory, out, pictures)
    except KeyboardInterrupt:  # before or after the integration: no file half written
        interrupted("Interrupted (Ctrl-C); files not finished were not written.")


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
    from matplotlib.animation import FFMpegWriter

    return bool(FFMpegWriter.isAvailable())


@dataclasses.dataclass(frozen=True)
class Pictures:
    """What ``simulate`` draws after the CSV: the ``plot`` file (its phase portrait of
    ``phase``), the ``animate`` file (a progress bar on a terminal, or always with
    ``progress``), and whether a failed run gets them too (``keep_failed``)."""

    plot: str | None = None
    animate: str | None = None
    phase: str | None = None
    progress: bool = False
    keep_failed: bool = False


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
    else:
        trajectory.to_csv(out)
        csv_text, where = "", out
    if not trajectory.success:
        if sys.stdout is not None:  # the rows so far, before the error is reported
            sys.stdout.write(csv_text)
        stopped = f"{trajectory.message} {_rows_written(trajectory)} written to {where}."
        if trajectory.status == "interrupted":
            interrupted(stopped)
        raise SimulationError(" ".join([stopped, *_failed_pictures(system, trajectory, pictures)]))
    messages = [f"{len(trajectory.t)} samples written to {out}; {trajectory.drift_summary()}"]
    messages += impacts_written(trajectory, out)
    messages += draw_pictures(system, trajectory, pictures)
    return csv_text if out == "-" else "\n".join(messages)


def impacts_written(trajectory: Trajectory, out: str) -> list[str]:
    """The impacts of the run in a table beside the CSV (``NAME.impacts.csv``), and what they
    were in one line; nothing without impacts."""
    if not trajectory.impacts:
        return []
    summary = impacts_summary(trajectory.impacts)
    if out == "-" or written_in_place(out):  # no table beside a device, in /dev
        return [summary]
    table = impacts_path(out)
    write_impacts_csv(trajectory.impacts, table)
    return [f"{summary}; each written to {table}"]


def impacts_path(out: str) -> str:
    """Where the table of impacts goes: ``run.csv`` -> ``run.impacts.csv``."""
    path = Path(out)
    return str(path.with_name(f"{path.stem}.impacts{path.suffix or '.csv'}"))


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
    if pictures.animate:
        with written_atomically(pictures.animate) as temporary:
            write_animation(
                system, trajectory, temporary, progress=frame_progress(pictures.progress)
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
