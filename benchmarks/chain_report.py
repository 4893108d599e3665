"""CPU seconds of ``lagrangian analyze`` and ``lagrangian export`` of the n-link pendulum as a
user runs them: the command line in a fresh process each time (the derivation, the analysis
or the code generation, and the printing), with the size of what it writes.

    PYTHONPATH=src python benchmarks/chain_report.py analyze text 25 50 100
    PYTHONPATH=src python benchmarks/chain_report.py analyze json 100
    PYTHONPATH=src python benchmarks/chain_report.py export c 25 50 100

CPU time (``time.process_time`` of the child, the interpreter's start and imports left out),
the steadier measure on a shared machine; the 1-minute load average is printed beside each
figure.  Compare two versions by pointing PYTHONPATH at each in turn.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile

CHILD = """
import sys, time
from lagrangian.cli.main import main
t0 = time.process_time()
code = main(sys.argv[1:])
t1 = time.process_time()
print(f"{code} {t1 - t0:.2f}", file=sys.stderr)
"""


def measure(command: str, form: str, n: int) -> str:
    """One run in a fresh process: exit code, CPU seconds, characters written, load."""
    with tempfile.TemporaryDirectory() as folder:
        example = f"examples/n_link_pendulum:{n}"
        if command == "analyze":
            args = ["analyze", example, "--format", form]
        else:
            args = ["export", example, "--language", form, "--out", folder]
        target = os.path.join(folder, "report.out")
        with open(target, "w") as out:
            done = subprocess.run(
                [sys.executable, "-c", CHILD, *args],
                stdout=out,
                stderr=subprocess.PIPE,
                text=True,
                check=False,
            )
        written = sum(os.path.getsize(os.path.join(folder, f)) for f in os.listdir(folder))
        with open("/proc/loadavg") as average:
            load = average.read().split()[0]
    code, cpu = done.stderr.strip().splitlines()[-1].split()
    return f"{command} {form} n={n}: exit {code}, CPU {cpu} s, {written:,} characters, load {load}"


def main(argv: list[str]) -> None:
    command, form, sizes = argv[0], argv[1], [int(n) for n in argv[2:]]
    for n in sizes:
        print(measure(command, form, n), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
