"""Frames written straight to files: a GIF with Pillow (one palette for the whole animation,
so colours do not flicker and frames quantize fast), an MP4 through ffmpeg's standard input
when ffmpeg is installed, a PNG of one frame.

>>> import numpy as np, tempfile, pathlib
>>> frames = [np.full((8, 8, 3), k * 60, dtype=np.uint8) for k in range(3)]
>>> path = pathlib.Path(tempfile.mkdtemp()) / "a.gif"
>>> write_gif(iter(frames), path, fps=10, colors=["#3c3c3c", "#787878"])
>>> from PIL import Image
>>> with Image.open(path) as picture:
...     picture.n_frames
3
"""

from __future__ import annotations

import itertools
import shutil
import subprocess
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

#: Colours of the shared GIF palette.
COLORS = 255


def ffmpeg_path() -> str | None:
    """The ffmpeg program (matplotlib's setting, else on PATH), None when there is none."""
    import matplotlib

    configured = matplotlib.rcParams.get("animation.ffmpeg_path", "ffmpeg")
    return shutil.which(configured) or shutil.which("ffmpeg")


def write_gif(
    frames: Iterator[np.ndarray], path: Path, fps: float, colors: Sequence[str] = ()
) -> None:
    """RGB frames as a looping GIF at ``fps``, all on one palette: that of the first frame
    and of ``colors`` (hex: what appears later, a trail, an impact's flash)."""
    from PIL import Image

    first = next(frames)
    swatches = [np.full((8, first.shape[1], 3), _rgb(color), dtype=np.uint8) for color in colors]
    source = Image.fromarray(np.concatenate([first, *swatches], axis=0))
    palette = source.quantize(COLORS, method=Image.Quantize.MEDIANCUT)
    pictures = [
        Image.fromarray(frame).quantize(palette=palette, dither=Image.Dither.NONE)
        for frame in itertools.chain([first], frames)
    ]
    pictures[0].save(path, format="GIF", save_all=True, append_images=pictures[1:],
                     duration=round(1000 / fps), loop=0)  # fmt: skip


def _rgb(color: str) -> tuple[int, int, int]:
    value = color.lstrip("#")
    return int(value[0:2], 16), int(value[2:4], 16), int(value[4:6], 16)


def write_mp4(frames: Iterator[np.ndarray], path: Path, fps: float) -> None:
    """RGB frames as an H.264 MP4 through ffmpeg (sizes made even, as yuv420p needs)."""
    program = ffmpeg_path()
    if program is None:
        raise FileNotFoundError("an .mp4 animation needs ffmpeg, which is not installed")
    first = next(frames)
    height, width = first.shape[0] // 2 * 2, first.shape[1] // 2 * 2
    command = [program, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
               "-s", f"{width}x{height}", "-r", f"{fps:g}", "-i", "-", "-pix_fmt", "yuv420p",
               "-vcodec", "libx264", "-f", "mp4", str(path)]  # fmt: skip
    with subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE) as encoder:
        assert encoder.stdin is not None
        for frame in (first, *frames):
            encoder.stdin.write(np.ascontiguousarray(frame[:height, :width]).tobytes())
        encoder.stdin.close()
        error = encoder.stderr.read().decode(errors="replace") if encoder.stderr else ""
        if encoder.wait() != 0:
            raise OSError(f"ffmpeg could not write {path}: {error.strip()}")


def write_png(frame: np.ndarray, path: Path) -> None:
    """One RGB frame as a PNG picture."""
    from PIL import Image

    Image.fromarray(frame).save(path, format="PNG")
