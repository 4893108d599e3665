"""A reader that closes the pipe early (``lagrangian simulate ... | head``) makes the command
fail in one line, never report success with the data lost."""

import subprocess
import sys

MODEL = """name: V well
coordinates: [x]
parameters: {m: 1, k: 1}
kinetic: m*x_dot**2/2
potential: k*Abs(x)
initial: {x: 1, x_dot: 0}
"""


def test_a_closed_pipe_is_a_failure_with_a_message(tmp_path):
    model = tmp_path / "well.yaml"
    model.write_text(MODEL)
    command = [sys.executable, "-m", "lagrangian.cli.main"]
    args = ["simulate", str(model), "--t-end", "400", "--samples", "100000"]
    process = subprocess.Popen([*command, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert process.stdout is not None and process.stderr is not None
    assert process.stdout.read(10) == b"t,x,x_dot,"
    process.stdout.close()  # the reader goes away, as head does
    error = process.stderr.read().decode()
    process.stderr.close()
    assert process.wait(timeout=120) == 1
    assert "pipe was closed" in error and "--out" in error
    assert "Traceback" not in error and "Exception ignored" not in error


def test_a_reader_that_takes_everything_sees_success(tmp_path):
    model = tmp_path / "well.yaml"
    model.write_text(MODEL)
    command = [sys.executable, "-m", "lagrangian.cli.main", "simulate", str(model)]
    result = subprocess.run(
        [*command, "--t-end", "40", "--samples", "20001"], capture_output=True, timeout=120
    )
    assert result.returncode == 0
    assert len(result.stdout.decode().splitlines()) == 20002  # header and every row
