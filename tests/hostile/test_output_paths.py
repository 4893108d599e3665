"""Output paths that are not plain files (issue 34, items 0 and 7): a device, a FIFO or a
link is written through, never replaced by a regular file (``--out /dev/null`` run as root
once replaced the system's null device with the CSV); a folder, or a file in a missing
folder, is refused before any work with the option, the path given and the fix.

The devices and FIFOs are made in the test's own folder: the system's ``/dev/null`` is never
touched."""

from __future__ import annotations

import contextlib
import os
import stat
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from lagrangian.simulation.files import written_atomically, written_in_place

MODEL = (
    "coordinates: [x]\nparameters: {m: 1, k: 1}\nkinetic: m*x_dot**2/2\npotential: k*x**2/2\n"
    "initial: {x: 0.5, x_dot: 0}\nsimulate: {t_end: 1}\n"
)


@contextlib.contextmanager
def fifo_read(path: Path) -> Iterator[list[str]]:
    """A FIFO at ``path`` read to its end by a thread; the text read, once the block ends."""
    os.mkfifo(path)
    read: list[str] = []

    def reader() -> None:
        with open(path, encoding="utf-8") as stream:
            read.append(stream.read())

    thread = threading.Thread(target=reader, daemon=True)
    thread.start()
    try:
        yield read
    finally:
        thread.join(timeout=60)
        if thread.is_alive():  # nothing opened the FIFO: release the reader
            with contextlib.suppress(OSError):
                os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
            thread.join(timeout=5)


def null_device(folder: Path) -> Path:
    """A character device like /dev/null (1, 3) made in ``folder``; skip where devices
    cannot be made (not root) or used (a folder on a nodev file system)."""
    node = folder / "null"
    try:
        os.mknod(node, stat.S_IFCHR | 0o666, os.makedev(1, 3))
        with open(node, "w") as stream:
            stream.write("probe")
    except (PermissionError, AttributeError) as error:
        pytest.skip(f"no character device can be made or opened here: {error}")
    return node


def test_a_fifo_is_written_through_and_stays_a_fifo(tmp_path):
    fifo = tmp_path / "out.csv"
    with fifo_read(fifo) as read, written_atomically(fifo) as temporary:
        assert temporary == fifo
        temporary.write_text("t\n0\n")
    assert read == ["t\n0\n"]
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]


def test_simulate_into_a_fifo_keeps_the_fifo(cli, tmp_path):
    (tmp_path / "model.yaml").write_text(MODEL)
    fifo = tmp_path / "out.csv"
    with fifo_read(fifo) as read:  # a thread runs: the command runs in a fresh process
        outcome = cli(["simulate", "model.yaml", "--samples", "11", "--out", str(fifo)])
    assert outcome.code == 0, outcome
    assert read and read[0].startswith("t,x,x_dot,energy") and len(read[0].splitlines()) == 12
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.yaml", "out.csv"]


def test_simulate_onto_a_character_device_keeps_the_device(cli, tmp_path):
    node = null_device(tmp_path)
    (tmp_path / "model.yaml").write_text(MODEL)
    outcome = cli(["simulate", "model.yaml", "--samples", "11", "--out", str(node)])
    assert outcome.code == 0, outcome
    assert stat.S_ISCHR(os.lstat(node).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.yaml", "null"]


def test_the_kernel_folders_and_devices_are_written_in_place(tmp_path):
    # judged by the path alone: nothing under /dev is opened or stat'ed here
    assert written_in_place("/dev/null") and written_in_place("/dev/stdout")
    assert written_in_place("/proc/self/fd/1")
    assert not written_in_place(tmp_path / "new.csv")
    (tmp_path / "old.csv").write_text("old\n")
    assert not written_in_place(tmp_path / "old.csv")


def test_a_link_stays_a_link_and_its_target_is_replaced(tmp_path):
    real = tmp_path / "data"
    real.mkdir()
    (real / "run.csv").write_text("old\n")
    link = tmp_path / "link.csv"
    link.symlink_to(real / "run.csv")
    with written_atomically(link) as temporary:
        assert temporary.parent == real  # beside the target: same file system
        temporary.write_text("new\n")
    assert link.is_symlink() and (real / "run.csv").read_text() == "new\n"
    assert sorted(p.name for p in real.iterdir()) == ["run.csv"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data", "link.csv"]


def test_a_folder_is_refused_by_its_own_name(tmp_path):
    with (
        pytest.raises(IsADirectoryError, match="Is a directory") as caught,
        written_atomically(tmp_path),
    ):
        pass
    assert caught.value.filename == str(tmp_path)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("option", "name", "words"),
    [
        ("--out", "missing/run.csv", ["--out", "'missing/run.csv'", "does not exist", "mkdir -p"]),
        ("--out", ".", ["--out", "'.' is a folder", "such as ./run.csv"]),
        ("--plot", "missing/run.png", ["--plot", "'missing/run.png'", "does not exist"]),
        ("--plot", "folder.png", ["--plot", "'folder.png' is a folder"]),
        ("--animate", "missing/run.gif", ["--animate", "does not exist"]),
        ("--out", "model.yaml/run.csv", ["--out", "'model.yaml' is a file, not a folder"]),
    ],
)
def test_an_output_that_cannot_be_written_there_is_refused_by_option(
    cli, tmp_path, option, name, words
):
    (tmp_path / "model.yaml").write_text(MODEL)
    (tmp_path / "folder.png").mkdir()
    argv = ["simulate", "model.yaml", "--samples", "11", "--out", "run.csv", option, name]
    outcome = cli(argv)
    assert outcome.code == 2 and not outcome.internal, outcome
    for word in words:
        assert word in outcome.err, (word, outcome)
    assert "[Errno" not in outcome.err  # the user's path and the fix, not an errno
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder.png", "model.yaml"]


@pytest.mark.parametrize("out", ["model.yaml", "model.yaml/sub"])
def test_export_into_a_file_is_refused_by_option(cli, tmp_path, out):
    (tmp_path / "model.yaml").write_text(MODEL)
    outcome = cli(["export", "model.yaml", "--out", out])
    assert outcome.code == 2 and not outcome.internal, outcome
    assert "--out" in outcome.err and "is a file, not a folder" in outcome.err
