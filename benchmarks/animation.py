"""Benchmark: the README tour's animation, against matplotlib's own animation writer.

What is measured
    The command line (fresh processes, CPU time of the process and its children from
    ``resource.getrusage``, and wall time)::

        lagrangian simulate examples/double_pendulum --t-end 20 --out traj.csv
        ... --animate traj.gif
        ... --animate traj.html

    the animation's own cost being the difference from the run without it; and the size of
    the files.  ``--before DIR`` runs the same commands on an older tree alongside (e.g.
    ``git archive REV src | tar -x -C DIR``), the rounds interleaved.

    The anchor, in one process on the same scene and the same frames: matplotlib's
    ``FuncAnimation`` saved with its ``PillowWriter`` (the whole figure drawn for every frame)
    and ``to_jshtml`` (a PNG per frame), against lagrangian's writer (the still parts drawn
    once, the moving ones per frame, straight to Pillow; the HTML as the scene's numbers and
    a player script).  Ratios are anchor time over lagrangian's.

Usage
    python benchmarks/animation.py                       # 3 rounds
    python benchmarks/animation.py --before /tmp/before/src --rounds 2
    python benchmarks/animation.py --record              # also append to RESULTS.md
"""

from __future__ import annotations

import argparse
import datetime
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve()
SRC = HERE.parents[1] / "src"
RESULTS = HERE.parent / "RESULTS.md"
TOUR = ["simulate", "examples/double_pendulum", "--t-end", "20", "--out", "traj.csv"]
CASES = {"no animation": [], "GIF": ["--animate", "traj.gif"], "HTML": ["--animate", "traj.html"]}


def run_command(src: Path, extra: list[str], folder: Path) -> tuple[float, float, int]:
    """(CPU seconds, wall seconds, bytes of the animation) of one fresh ``lagrangian`` run."""
    env = dict(os.environ, PYTHONPATH=str(src))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "lagrangian", *TOUR, *extra], env=env, cwd=folder,
                   check=True, capture_output=True)  # fmt: skip
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    size = (folder / extra[1]).stat().st_size if extra else 0
    return cpu, wall, size


def measure_commands(trees: dict[str, Path], rounds: int) -> dict[tuple[str, str], tuple]:
    """Median (CPU, wall, size) of every case in every tree, the rounds interleaved."""
    samples: dict[tuple[str, str], list[tuple[float, float, int]]] = {}
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        for _ in range(rounds):
            for tree, src in trees.items():
                for case, extra in CASES.items():
                    samples.setdefault((tree, case), []).append(run_command(src, extra, folder))
    return {key: tuple(statistics.median(v) for v in zip(*runs)) for key, runs in samples.items()}


def measure_anchor(rounds: int) -> dict[str, float]:
    """Seconds (CPU of this process) to write the tour's GIF and HTML with matplotlib's
    FuncAnimation and with lagrangian's writer, same scene, same frames; and the sizes."""
    sys.path.insert(0, str(SRC))
    import matplotlib.animation as mpl_animation

    import lagrangian as lg
    from lagrangian.render.animation import Animation
    from lagrangian.render.scene import scene_of

    system = lg.examples.double_pendulum()
    trajectory = lg.simulate(system, t_span=20.0, samples=1000)
    scene = scene_of(system, trajectory)
    times: dict[str, list[float]] = {}
    sizes: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        for _ in range(rounds):
            for name, write in {
                "lagrangian GIF": lambda: Animation(scene).save(folder / "a.gif"),
                "lagrangian HTML": lambda: Animation(scene).save(folder / "a.html"),
                "matplotlib GIF": lambda: _matplotlib(scene, mpl_animation).save(
                    str(folder / "m.gif"), writer=mpl_animation.PillowWriter(fps=scene.fps)),
                "matplotlib HTML": lambda: (folder / "m.html").write_text(
                    _matplotlib(scene, mpl_animation).to_jshtml(fps=scene.fps)),
            }.items():  # fmt: skip
                start = time.process_time()
                write()
                times.setdefault(name, []).append(time.process_time() - start)
        for name, file in (("lagrangian GIF", "a.gif"), ("lagrangian HTML", "a.html"),
                           ("matplotlib GIF", "m.gif"), ("matplotlib HTML", "m.html")):  # fmt: skip
            sizes[name] = (folder / file).stat().st_size
    return {**{k: statistics.median(v) for k, v in times.items()},
            **{k + " bytes": v for k, v in sizes.items()}, "frames": scene.frames}  # fmt: skip


def _matplotlib(scene, mpl_animation):  # type: ignore[no-untyped-def]
    """matplotlib's FuncAnimation over the same figure, drawing it whole for every frame."""
    from lagrangian.render.scene_draw import SceneFigure

    figure = SceneFigure(scene)
    for _, artists in figure.movers:
        for artist in artists:
            artist.set_animated(False)
    return mpl_animation.FuncAnimation(figure.figure, figure.update, frames=scene.frames,
                                       interval=1000 / scene.fps, blit=False)  # fmt: skip


def report(commands: dict, anchor: dict[str, float], trees: dict[str, Path], rounds: int) -> str:
    lines = [
        f"Median of {rounds} rounds; 1-minute load average {os.getloadavg()[0]:.2f} on "
        f"{os.cpu_count()} cores (a shared machine: wall times vary, CPU times less).",
        "",
        "Command line: `lagrangian " + " ".join(TOUR) + " [--animate traj.gif|traj.html]`",
        "",
        "| tree | case | CPU s | wall s | animation CPU s (minus no animation) | file bytes |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for tree, src in trees.items():
        base = commands[(tree, "no animation")][0]
        for case in CASES:
            cpu, wall, size = commands[(tree, case)]
            extra = f"{cpu - base:.2f}" if case != "no animation" else ""
            lines.append(f"| {tree} (`{src}`) | {case} | {cpu:.2f} | {wall:.2f} | {extra} | "
                         f"{int(size) if size else ''} |")  # fmt: skip
    lines += [
        "",
        f"Anchor, one process, the same scene of {int(anchor['frames'])} frames "
        "(CPU seconds to write the file):",
        "",
        "| format | lagrangian s | matplotlib FuncAnimation s | matplotlib / lagrangian | "
        "lagrangian bytes | matplotlib bytes |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for kind in ("GIF", "HTML"):
        ours, theirs = anchor[f"lagrangian {kind}"], anchor[f"matplotlib {kind}"]
        lines.append(f"| {kind} | {ours:.2f} | {theirs:.2f} | {theirs / ours:.1f} | "
                     f"{int(anchor[f'lagrangian {kind} bytes'])} | "
                     f"{int(anchor[f'matplotlib {kind} bytes'])} |")  # fmt: skip
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--before", type=Path, help="an older tree's src to measure alongside")
    parser.add_argument("--record", action="store_true", help="append the results to RESULTS.md")
    args = parser.parse_args()
    trees = {"before": args.before} if args.before else {}
    trees["after"] = SRC
    commands = measure_commands(trees, args.rounds)
    print(commands, flush=True)  # the long part done: seen before the anchor runs
    anchor = measure_anchor(args.rounds)
    text = report(commands, anchor, trees, args.rounds)
    print(text)
    if args.record:
        stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M+00:00")
        heading = f"\n## The tour's animation (benchmarks/animation.py), {stamp}\n\n"
        command = "Measured by `python benchmarks/animation.py " + " ".join(sys.argv[1:]) + "`.\n\n"
        with RESULTS.open("a", encoding="utf-8") as results:
            results.write(heading + command + text + "\n")


if __name__ == "__main__":
    main()
