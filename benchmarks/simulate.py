"""Benchmark: simulating an n-link pendulum and a batch of double pendulums, against PyDy + SciPy.

What is measured
    (a) The 10-link planar pendulum (point masses 1, rods 1, g = 9.81, every angle 0.5 rad at
        rest, absolute angles) over 10 s with DOP853, rtol = atol = 1e-9, output at every step:
        pydy        sympy.physics.mechanics KanesMethod, ``pydy.codegen.ode_function_generators.
                    generate_ode_function(..., generator="cython")``, scipy.integrate.solve_ivp;
        native C loop
                    ``lagrangian.simulate`` as it is called by default: SciPy's DOP853 step
                    for step in the C loop compiled once per machine by the system C compiler
                    (``numerics/fast/c_loop.c``), calling the right-hand side compiled by
                    SymEngine's LLVM backend through its C function pointer;
        SciPy solvers
                    ``lagrangian.simulate`` with no C compiler found (the default backend's
                    fallback): SciPy's DOP853 on the LLVM-compiled equations.
        "simulate" times the integration alone, everything compiled and warm (best of 5 calls in
        the process); "end to end" times loading the model + derive + compilation + simulate
        in a fresh process, its packages imported before the clock starts, with
        empty caches (a new NUMBA_CACHE_DIR and XDG_CACHE_HOME; PyDy compiles its Cython in a
        new temporary directory). "native C loop, library cached" is the end-to-end time when
        the on-disk cache already holds the C loop's shared library, which is the same for
        every system: the case of every run after the first on a machine. "with imports" adds
        the time of the imports to the end-to-end time. The final states are compared.
    (b) 10^4 double pendulums (masses and rods 1, starts at rest with angles drawn uniformly in
        [-1, 1]^2, seed 0) over 10 s, DOP853, rtol = atol = 1e-9, final state only:
        ``lagrangian.simulate_batch`` with the default backend (member by member in the C loop)
        and the default backend without a C compiler (NumPy, vectorized over the members),
        against a Python loop of solve_ivp over the same compiled NumPy right-hand side, timed
        on the first 200 starts only (its throughput, trajectories per second, does not depend
        on how many).
    (c) Where the end-to-end time of "native C loop, library cached" goes (fresh processes,
        median): loading the library, the derivation, the LLVM compilation, the loop alone,
        and the rest of the first ``lagrangian.simulate`` call (input checks, the functions of
        the energies, the Trajectory).
    (e) Events, constraints and RK4 on the default path, the C loop against SciPy's solvers
        (no C compiler found), warm, best of 5 ``lagrangian.simulate`` calls: the double
        pendulum over 100 s (DOP853, rtol = atol = 1e-9) with two non-terminal events
        (theta = 0, and phi_dot rising through 0), a pendulum in Cartesian coordinates with the
        holonomic constraint x^2 + y^2 = l^2 in the multiplier form over 100 s (the same
        tolerances), and the double pendulum over 10 s by RK4 with dt = 1e-3 (the Python loop
        over RK4's OdeSolver without a compiler); the largest difference of the event times
        and of the final states.  (The numba loops and table (d), their right-hand side
        harness, are gone: the C loop is the one compiled engine of the Runge–Kutta family.)

How
    Every measurement is a fresh process (this file with the hidden ``--worker``); the workers
    import their packages before the clock starts. Measurements alternate between the
    contenders run by run; tables show the median of ``--repeat`` runs.

Usage
    python benchmarks/simulate.py                 # 3 repeats, 10^4 batch
    python benchmarks/simulate.py --quick         # 1 repeat, 10^3 batch
    python benchmarks/simulate.py --record        # also append the results to benchmarks/RESULTS.md
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve()
SRC = HERE.parents[1] / "src"
sys.path.insert(0, str(HERE.parent))
from machine import cpu_model, package_version  # noqa: E402

RESULTS = HERE.parent / "RESULTS.md"
LINKS, T_END, TOL = 10, 10.0, 1e-9
LOOP_SUBSET = 200
#: (what, contender, at least this many times PyDy's speed, or the solve_ivp loop's for batches)
TARGETS = (
    ("simulate", "native C loop, library cached", 8.0),
    ("end to end", "native C loop, library cached", 25.0),
    ("batch", "C loop", 50.0),
)
#: Worker contender -> backend of lagrangian.simulate ("scipy": no C compiler is found).
BACKENDS = {"native": "numpy", "scipy": "numpy"}
#: Batch contender -> backend of lagrangian.simulate_batch ("vectorized": no C compiler).
BATCH_BACKENDS = {"C loop": "numpy", "vectorized": "numpy"}
#: The largest difference of the final state from PyDy's accepted as "the same state".
SAME_STATE = 1e-9


# --------------------------------------------------------------------------- the contenders


def pydy_model(n: int):
    """(derive seconds, rhs(x, t, p)) of the PyDy pendulum, its Cython compiled."""
    import sympy as sp
    import sympy.physics.mechanics as me
    from pydy.codegen.ode_function_generators import generate_ode_function

    q, u = me.dynamicsymbols(f"q1:{n + 1}"), me.dynamicsymbols(f"u1:{n + 1}")
    m, l, g = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}"), sp.Symbol("g")
    N, origin = me.ReferenceFrame("N"), me.Point("O")
    origin.set_vel(N, 0)
    particles, loads, previous = [], [], origin
    for i in range(n):
        A = N.orientnew(f"A{i}", "Axis", [q[i], N.z])
        A.set_ang_vel(N, u[i] * N.z)
        P = previous.locatenew(f"P{i}", -l[i] * A.y)
        P.v2pt_theory(previous, N, A)
        particles.append(me.Particle(f"bob{i}", P, m[i]))
        loads.append((P, -m[i] * g * N.y))
        previous = P
    kinematics = [qi.diff() - ui for qi, ui in zip(q, u)]
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kinematics)
    kane.kanes_equations(particles, loads)
    return generate_ode_function(
        kane.forcing_full,
        q,
        u,
        [*m, *l, g],
        mass_matrix=kane.mass_matrix_full,
        generator="cython",
    )


def pendulum_start(n: int):
    import numpy as np

    return np.array([0.5] * n + [0.0] * n), np.array([1.0] * (2 * n) + [9.81])


def run_pydy(rhs, n: int):
    import numpy as np
    from scipy.integrate import solve_ivp

    x0, p = pendulum_start(n)
    sol = solve_ivp(lambda t, x: rhs(x, t, p), (0, T_END), x0, method="DOP853", rtol=TOL, atol=TOL)
    return np.asarray(sol.y[:, -1])


def run_lagrangian(eom, n: int, contender: str):
    import numpy as np

    import lagrangian as lg

    backend = BACKENDS[contender]
    x0, _ = pendulum_start(n)
    names = [f"theta{i}" for i in range(1, n + 1)]
    initial = dict(zip(names + [f"{s}_dot" for s in names], x0))
    run = lg.simulate(eom, initial, T_END, method="DOP853", rtol=TOL, atol=TOL, backend=backend)
    return np.concatenate([run.q[-1], run.q_dot[-1]])


def batch_starts(k: int):
    import numpy as np

    return np.random.default_rng(0).uniform(-1.0, 1.0, size=(k, 2))


def run_batch(backend: str, k: int):
    """Seconds for k trajectories with lagrangian.simulate_batch, and the final states."""
    import lagrangian as lg

    eom = lg.derive(lg.examples.double_pendulum())
    starts = batch_starts(k)
    if backend == "vectorized":  # the default backend on a machine without a C compiler
        from lagrangian.numerics.fast import c_build

        c_build.find_compiler = lambda: None

    def once(rows):
        initial = {"theta": rows[:, 0], "phi": rows[:, 1], "theta_dot": 0.0, "phi_dot": 0.0}
        return lg.simulate_batch(
            eom,
            initial,
            T_END,
            method="DOP853",
            rtol=TOL,
            atol=TOL,
            samples=2,  # the final states are what is compared: keep only the ends
            backend=BATCH_BACKENDS[backend],
        )

    once(starts[:2])  # compile
    start = time.perf_counter()
    batch = once(starts)
    return time.perf_counter() - start, batch.final_q[:LOOP_SUBSET].tolist()


def crossing(t, q, q_dot):
    return q[0]


def rising(t, q, q_dot):
    return q_dot[1]


rising.direction = 1


def features() -> dict:
    """(e): seconds of the C loop and of SciPy's solvers with events and with a constraint."""
    import numpy as np
    import sympy as sp

    import lagrangian as lg
    from lagrangian.numerics.fast import c_build, c_loop

    x, y = sp.symbols("x y")
    m, g, l = sp.symbols("m g l", positive=True)
    cartesian = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81, l: 1.0},
        gravity=(0, -g),
        constraints=[lg.Holonomic(x**2 + y**2 - l**2)],
        particles=[lg.Particle("bob", m, (x, y))],
    )
    double = lg.derive(lg.examples.double_pendulum())
    start = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
    adaptive = {"method": "DOP853", "rtol": TOL, "atol": TOL}
    cases = {
        "events": (double, start, 100.0, {**adaptive, "events": [crossing, rising]}),
        "constraint": (
            lg.derive(cartesian),
            {"x": np.sin(1.0), "y": -np.cos(1.0), "x_dot": 0.0, "y_dot": 0.0},
            100.0,
            adaptive,
        ),
        "rk4": (double, start, 10.0, {"method": "RK4", "dt": 1e-3}),
    }
    result: dict = {}
    for path in ("native", "scipy"):
        if path == "scipy":
            c_build.find_compiler = lambda: None
            c_build.loop_library.cache_clear()
        assert c_loop.available() == (path == "native")
        for case, (eom, initial, t_end, keywords) in cases.items():
            runs = []
            for _ in range(5):
                clock = time.perf_counter()
                run = lg.simulate(eom, initial, t_end, **keywords)
                runs.append(time.perf_counter() - clock)
            result[f"{case} {path}"] = min(runs)
            result[f"{case} {path} final"] = np.concatenate([run.q[-1], run.q_dot[-1]]).tolist()
            result[f"{case} {path} events"] = [event.t for event in run.events]
    return result


def run_loop(k: int):
    """Seconds for a Python loop of solve_ivp over the first k starts, and the final states."""
    import numpy as np
    from scipy.integrate import solve_ivp

    import lagrangian as lg
    from lagrangian.numerics.compile import compile_equations

    compiled = compile_equations(lg.derive(lg.examples.double_pendulum()))
    p = np.array([1.0, 1.0, 1.0, 1.0, 9.81])
    finals = []
    start = time.perf_counter()
    for theta, phi in batch_starts(k):
        sol = solve_ivp(
            lambda t, x: compiled.rhs(t, x, p),
            (0, T_END),
            [theta, phi, 0.0, 0.0],
            method="DOP853",
            rtol=TOL,
            atol=TOL,
        )
        finals.append(sol.y[:2, -1].tolist())
    return time.perf_counter() - start, finals


# --------------------------------------------------------------------------- the worker


def worker(kind: str, contender: str, size: int) -> dict:
    """One measurement in this fresh process."""
    imports = time.perf_counter()
    import numpy as np  # noqa: F401
    import scipy.integrate  # noqa: F401

    sys.path.insert(0, str(SRC))
    import lagrangian as lg

    if contender == "pydy":
        import pydy.codegen.ode_function_generators  # noqa: F401
        import sympy.physics.mechanics  # noqa: F401
    else:  # the modules behind the verbs (loaded on first use)
        lg.derive, lg.simulate, lg.examples  # noqa: B018
    if contender == "scipy":  # the default backend on a machine without a C compiler
        from lagrangian.numerics.fast import c_build

        c_build.find_compiler = lambda: None
    imports = time.perf_counter() - imports
    if kind == "startup":
        return native_startup_parts()
    if kind == "features":
        return features()
    if kind == "batch":
        seconds, finals = run_loop(size) if contender == "loop" else run_batch(contender, size)
        return {"seconds": seconds, "count": size, "finals": finals}
    start = time.perf_counter()
    if contender == "pydy":
        rhs = pydy_model(LINKS)
        final = run_pydy(rhs, LINKS)
    else:
        eom = lg.derive(lg.examples.n_link_pendulum(LINKS))
        final = run_lagrangian(eom, LINKS, contender)
    end_to_end = time.perf_counter() - start
    runs = []
    for _ in range(5):
        start = time.perf_counter()
        final = (
            run_pydy(rhs, LINKS) if contender == "pydy" else run_lagrangian(eom, LINKS, contender)
        )
        runs.append(time.perf_counter() - start)
    result = {
        "end_to_end": end_to_end,
        "with_imports": imports + end_to_end,
        "simulate": min(runs),
        "final": final.tolist(),
    }
    if contender == "native":
        result["loop"] = time_loop_alone(eom, LINKS)
    return result


def time_loop_alone(eom, n: int) -> float:
    """Best of 5 of the C loop alone (no input checks, no Trajectory)."""
    from lagrangian.numerics.fast.c_loop import integrate
    from lagrangian.numerics.fast.c_loop import native_equations as fast_equations
    from lagrangian.numerics.fast.settings import Settings

    x0, p = pendulum_start(n)
    settings = Settings("DOP853", (0.0, T_END), x0[:0], TOL, TOL)
    runs = []
    for _ in range(5):
        start = time.perf_counter()
        integrate(fast_equations(eom), settings, x0, p)
        runs.append(time.perf_counter() - start)
    return min(runs)


def native_startup_parts() -> dict:
    """Seconds of each part of the end-to-end run of the native C loop with its library
    cached (the modules of lagrangian.simulate imported before)."""
    import lagrangian as lg
    from lagrangian.numerics.fast import c_build, c_loop
    from lagrangian.numerics.fast.settings import Settings

    clock = time.perf_counter()

    def lap() -> float:
        nonlocal clock
        now = time.perf_counter()
        seconds, clock = now - clock, now
        return seconds

    assert c_loop.available()
    parts = {"load the C loop's library (and check its digest)": lap()}
    eom = lg.derive(lg.examples.n_link_pendulum(LINKS))
    parts["load and derive"] = lap()
    fast = c_loop.native_equations(eom)
    parts["LLVM compilation of the right-hand side"] = lap()
    x0, p = pendulum_start(LINKS)
    c_loop.integrate(fast, Settings("DOP853", (0.0, T_END), x0[:0], TOL, TOL), x0, p)
    parts["the loop (first call)"] = lap()
    run_lagrangian(eom, LINKS, "native")
    parts["the rest of the first simulate call (checks, energies, Trajectory)"] = lap()
    assert c_build.loop_library() is not None
    return parts


def run_worker(kind: str, contender: str, size: int, cache: str | None) -> dict:
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # imports as on any machine: from bytecode
    with tempfile.TemporaryDirectory() as empty:
        # numba's cache and the C loop's library (in XDG_CACHE_HOME/lagrangian)
        env["NUMBA_CACHE_DIR"] = env["XDG_CACHE_HOME"] = cache or empty
        command = [sys.executable, str(HERE), "--worker", kind, contender, str(size)]
        done = subprocess.run(command, capture_output=True, text=True, env=env, timeout=3600)
    for line in done.stdout.splitlines():
        if line.startswith("{"):
            return json.loads(line)
    return {"error": done.stderr.strip()[-600:]}


# --------------------------------------------------------------------------- the parent


def measure(repeat: int, batch_size: int) -> dict:
    """Every measurement ``repeat`` times, alternating contenders."""
    warm_cache = tempfile.mkdtemp(prefix="c-loop-")
    run_worker("pendulum", "native", 0, warm_cache)  # fills the cache with the C loop's library
    plan = [
        ("pendulum", "pydy", 0, None),
        ("pendulum", "native C loop, library cached", 0, warm_cache),
        ("pendulum", "native C loop, empty cache", 0, None),
        ("pendulum", "SciPy solvers", 0, None),
        ("startup", "native", 0, warm_cache),
        ("batch", "C loop", batch_size, warm_cache),
        ("batch", "vectorized", batch_size, None),
        ("batch", "loop", LOOP_SUBSET, None),
        ("features", "native", 0, warm_cache),
    ]
    results: dict = {}
    for r in range(repeat):
        for kind, label, size, cache in plan:
            contender = CONTENDERS.get(label.split(",")[0], label.split(",")[0])
            result = run_worker(kind, contender, size, cache)
            results.setdefault((kind, label), []).append(result)
            print(
                f"  {kind:<8} {label:<20} run {r + 1}/{repeat}: "
                f"{ {k: v for k, v in result.items() if k not in ('final', 'finals')} }",
                file=sys.stderr,
            )
    return results


#: Row labels -> worker contenders.
CONTENDERS = {"native C loop": "native", "SciPy solvers": "scipy"}


def _median(runs: list[dict], key: str) -> float:
    values = [run[key] for run in runs if key in run]
    return statistics.median(values) if values else float("nan")


def report(results: dict, batch_size: int) -> str:
    import numpy as np

    pendulum = {label: runs for (kind, label), runs in results.items() if kind == "pendulum"}
    reference = np.array(pendulum["pydy"][0]["final"])
    lines = [
        f"(a) {LINKS}-link pendulum, {T_END:g} s, DOP853 rtol = atol = {TOL:g}; median seconds.",
        "",
        "| contender | simulate s | end to end s | with imports s "
        "| max abs difference of final state from PyDy |",
        "|---|---:|---:|---:|---:|",
    ]
    differences = {}
    for label, runs in pendulum.items():
        differences[label] = np.max(np.abs(np.array(runs[0].get("final", reference)) - reference))
        lines.append(
            f"| {label} | {_median(runs, 'simulate'):.4g} | "
            f"{_median(runs, 'end_to_end'):.3g} | {_median(runs, 'with_imports'):.3g} | "
            f"{differences[label]:.2g} |"
        )
    pydy = {key: _median(pendulum["pydy"], key) for key in ("simulate", "end_to_end")}
    lines += ["", "Ratios (PyDy time / lagrangian time):", ""]
    for label, runs in pendulum.items():
        if label != "pydy":
            lines.append(
                f"- {label}: simulate {pydy['simulate'] / _median(runs, 'simulate'):.3g}x, "
                f"end to end {pydy['end_to_end'] / _median(runs, 'end_to_end'):.3g}x"
            )
    lines += _batch_lines(results, batch_size)
    ratios = {
        "simulate": lambda label: pydy["simulate"] / _median(pendulum[label], "simulate"),
        "end to end": lambda label: pydy["end_to_end"] / _median(pendulum[label], "end_to_end"),
        "batch": lambda label: _throughput(results, label) / _throughput(results, "loop"),
    }
    lines += _startup_lines(results, "native")
    lines += [*_feature_lines(results), "", "```"]
    for name, label, factor in TARGETS:
        ratio = ratios[name](label)
        verdict = "PASS" if ratio >= factor else "FAIL"
        lines.append(f"{verdict}  {label}: {name} >= {factor:g}x ({ratio:.3g}x)")
    worst = max(differences[label] for label in pendulum)
    verdict = "PASS" if worst <= SAME_STATE else "FAIL"
    lines.append(f"{verdict}  same final state as PyDy to {SAME_STATE:g} ({worst:.2g})")
    native = _median(pendulum["native C loop, library cached"], "loop")
    lines += ["```", "", NOTES.format(native=native)]
    return "\n".join(lines)


def _throughput(results: dict, label: str) -> float:
    runs = results[("batch", label)]
    return _median(runs, "count") / _median(runs, "seconds")


def _batch_lines(results: dict, batch_size: int) -> list[str]:
    import numpy as np

    batch = {label: runs for (kind, label), runs in results.items() if kind == "batch"}
    loop_finals = np.array(batch["loop"][0]["finals"])
    lines = [
        "",
        f"(b) double pendulums, {T_END:g} s, DOP853 rtol = atol = {TOL:g}: {batch_size} with "
        f"simulate_batch, the solve_ivp loop timed on the first {LOOP_SUBSET}.",
        "",
        "| contender | trajectories/s | x loop | max abs difference from the loop (first 200) |",
        "|---|---:|---:|---:|",
    ]
    for label, runs in batch.items():
        finals = np.array(runs[0]["finals"])[: len(loop_finals)]
        difference = np.max(np.abs(finals - loop_finals))
        lines.append(
            f"| {label} | {_throughput(results, label):.4g} | "
            f"{_throughput(results, label) / _throughput(results, 'loop'):.3g} | "
            f"{difference:.2g} |"
        )
    return lines


def _feature_lines(results: dict) -> list[str]:
    import numpy as np

    runs = results[("features", "native")]
    lines = [
        "",
        "(e) Events and a constraint, 100 s, DOP853 rtol = atol = "
        f"{TOL:g}, and RK4: the C loop against SciPy's solvers (best of 5, median of the "
        "runs).",
        "",
        "| case | C loop s | SciPy solvers s | ratio | largest difference (events, final state) |",
        "|---|---:|---:|---:|---:|",
    ]
    for case, title in (
        ("events", "double pendulum, two events"),
        ("constraint", "Cartesian pendulum, multiplier form"),
        ("rk4", "double pendulum, RK4 dt = 1e-3, 10 s"),
    ):
        native, scipy = _median(runs, f"{case} native"), _median(runs, f"{case} scipy")
        first = runs[0]
        difference = max(
            np.max(
                np.abs(np.subtract(first[f"{case} native final"], first[f"{case} scipy final"]))
            ),
            max(
                (
                    abs(a - b)
                    for a, b in zip(first[f"{case} native events"], first[f"{case} scipy events"])
                ),
                default=0.0,
            ),
        )
        same = len(first[f"{case} native events"]) == len(first[f"{case} scipy events"])
        lines.append(
            f"| {title} | {native:.3g} | {scipy:.3g} | {scipy / native:.3g}x | "
            f"{difference:.2g}{'' if same else ' (event counts differ)'} |"
        )
    return lines


def _startup_lines(results: dict, contender: str) -> list[str]:
    runs = results[("startup", contender)]
    label = {"native": "native C loop, library cached"}
    lines = [
        "",
        f"(c) Where the end-to-end time of {label[contender]} goes (fresh processes, median).",
        "",
        "| part | seconds |",
        "|---|---:|",
    ]
    lines += [f"| {part} | {_median(runs, part):.3g} |" for part in runs[0]]
    return lines


NOTES = """Notes. "simulate" is the whole ``lagrangian.simulate`` call: input checks, the run, and
the Trajectory (energies and conserved quantities of every output row); the C loop alone takes
{native:.3g} s. It compiles each model's right-hand side with SymEngine's LLVM backend (table
(c)) and calls it from the integration loop compiled once per machine by the system C
compiler into a shared library kept in the user's cache folder (the "empty cache" row
compiles it, about a second, once). Loading the C library takes a millisecond; "with
imports" adds every import."""


def c_compiler() -> str:
    """The C compiler the C loop is built with, and the first line of its --version."""
    sys.path.insert(0, str(SRC))
    from lagrangian.numerics.fast.c_build import find_compiler

    compiler = find_compiler()
    if compiler is None:
        return "none found"
    done = subprocess.run([compiler, "--version"], capture_output=True, text=True, timeout=60)
    return f"{compiler} ({(done.stdout.splitlines() or ['unknown'])[0]})"


def record(text: str, note: str) -> None:
    """Append a dated section with the machine, the load and ``text`` to RESULTS.md (earlier
    sections stay: the file is the history of the measurements)."""
    import datetime
    import platform

    machine = [
        f"- platform: {platform.platform()}",
        f"- CPU: {cpu_model()} ({os.cpu_count()} cores)",
        f"- python {platform.python_version()}, "
        + ", ".join(
            f"{name} {package_version(name)}"
            for name in ("numpy", "scipy", "numba", "pydy", "cython")
        ),
        f"- C compiler of the C loop: {c_compiler()}",
        f"- 1-minute load average at the end: {os.getloadavg()[0]:.2f}",
    ]
    now = datetime.datetime.now().astimezone().isoformat(timespec="minutes")
    title = f"## Simulation (benchmarks/simulate.py), {now}" + (f" ({note})" if note else "")
    section = "\n".join([title, "", *machine, "", text])
    existing = RESULTS.read_text()
    RESULTS.write_text(existing.rstrip("\n") + "\n\n" + section + "\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement (3)")
    parser.add_argument("--batch", type=int, default=10_000, help="double pendulums (10^4)")
    parser.add_argument("--quick", action="store_true", help="1 run each, 10^3 double pendulums")
    parser.add_argument("--record", action="store_true", help=f"append results to {RESULTS.name}")
    parser.add_argument("--note", default="", help="a note for the recorded section's title")
    parser.add_argument("--worker", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        kind, contender, size = args.worker
        print(json.dumps(worker(kind, contender, int(size))), flush=True)
        return 0
    repeat, batch_size = (1, 1000) if args.quick else (args.repeat, args.batch)
    text = report(measure(repeat, batch_size), batch_size)
    print(text)
    if args.record:
        record(text, args.note)
        print(f"\nappended to {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
