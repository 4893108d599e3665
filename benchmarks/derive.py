"""Benchmark: deriving the equations of motion of an n-link planar pendulum.

What is measured
    The wall time to go from nothing to the matrix form M(q) q_ddot = f(q, q_dot) of an n-link
    planar pendulum: point masses m_i at the ends of massless rods of length l_i, gravity g
    along -y, absolute angles theta_i from the downward vertical, so bob i sits at
    sum_{k<=i} l_k (sin theta_k, -cos theta_k). Three derivations are compared:

    lagrangian  ``lg.derive(lg.examples.n_link_pendulum(n))``, then ``mass_matrix`` and ``forcing``;
    kane        sympy.physics.mechanics ``KanesMethod`` (frames oriented by q_i about N.z, points
                placed with ``-l_i * A_i.y``, ``v2pt_theory``, kinematic equations q_i' - u_i = 0,
                gravity loads), then ``mass_matrix`` and ``forcing`` (the dynamic part, u_i = q_i');
    lagrange    sympy.physics.mechanics ``LagrangesMethod`` on the same particles with their
                potential energies, then ``mass_matrix`` and ``forcing``.

How
    Every run is a fresh process (this file with the hidden ``--worker METHOD N``), so no SymPy
    cache carries over. The worker imports sympy, symengine and the method's package first, then
    times only building the system, deriving and reading M and f. A run whose derivation exceeds
    the cap is killed and reported as "> cap"; a method that hit the cap is not run at larger n
    (its cost only grows with n). Methods alternate run by run (lagrangian, kane, lagrange,
    lagrangian, ...) so machine noise hits them alike; the table shows the median.

    Output size is ``count_ops`` of ``sympy.cse([*M, *f])`` (replacements plus reduced
    expressions), with dynamic symbols turned into plain ones first so a function call q_i(t)
    costs no more than a symbol. It is measured once per method and n, untimed, for lagrangian
    and kane. For n <= 4 the worker also checks, untimed, that M^{-1} f agrees numerically at a
    random state with an independent derivation (lagrangian against Kane, Kane against Lagrange).

Usage
    python benchmarks/derive.py                  # n = 2 4 8 10 12 16 20, 3 repeats, 300 s cap
    python benchmarks/derive.py --quick          # n = 2 4 10, 1 repeat
    python benchmarks/derive.py --n 2 4 10 --repeat 5 --cap 120
    python benchmarks/derive.py --record         # also append the results to benchmarks/RESULTS.md
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import json
import math
import os
import platform
import queue
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

from machine import cpu_model, package_version

HERE = Path(__file__).resolve()
SRC = HERE.parents[1] / "src"
RESULTS = HERE.parent / "RESULTS.md"

METHODS = ("lagrangian", "kane", "lagrange")
#: The chain written three ways (lagrangian), for the scaling measurement (``--chains``).
CHAIN_METHODS = ("particles", "rods", "cartesian")
OURS = ("lagrangian", *CHAIN_METHODS)
CHAIN_N = (25, 50, 100, 200)
KANE_CHAIN_N = (25, 50)  # KanesMethod beside them where it ends within the cap
CHAIN_TARGET_SECONDS = 3.0  # 200 links
CHAIN_TARGET_RATIO = 20.0  # t(200) / t(50); n^2 alone gives 16
LABELS = {
    "lagrangian": "lagrangian",
    "kane": "KanesMethod",
    "lagrange": "LagrangesMethod",
    "particles": "particles",
    "rods": "rigid rods",
    "cartesian": "Cartesian + constraints",
}
DEFAULT_N = (2, 4, 8, 10, 12, 16, 20)
QUICK_N = (2, 4, 10)
STARTUP_SECONDS = 120.0  # allowance for the worker's imports, not part of the cap
CHECK_MAX_N = 4
REFERENCE = {"lagrangian": "kane", "kane": "lagrange"}  # independent derivation to check against
SIZED = ("lagrangian", "kane")
SPEED_TARGETS = (("kane", 10, 10.0), ("kane", 20, 10.0), ("lagrange", 10, 100.0))


# --------------------------------------------------------------------------- the derivations


def derive_lagrangian(n: int):
    """M and f from the package under test."""
    import lagrangian as lg

    eom = lg.derive(lg.examples.n_link_pendulum(n))
    return eom.mass_matrix, eom.forcing


def _mechanics_pendulum(n: int, kane: bool):
    """Frame, coordinates, speeds, particles and gravity loads of the pendulum.

    With ``kane`` the links turn at independent speeds u_i (named ``theta{i}_dot``); otherwise
    at q_i'. Bob i is at P_{i-1} - l_i A_i.y = P_{i-1} + l_i (sin q_i, -cos q_i).
    """
    import sympy as sp
    import sympy.physics.mechanics as me

    q = [me.dynamicsymbols(f"theta{i}") for i in range(1, n + 1)]
    u = [me.dynamicsymbols(f"theta{i}_dot") for i in range(1, n + 1)] if kane else []
    speeds = u if kane else [qi.diff(me.dynamicsymbols._t) for qi in q]
    masses = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    N = me.ReferenceFrame("N")
    origin = me.Point("O")
    origin.set_vel(N, 0)
    particles, loads, previous = [], [], origin
    for i in range(n):
        A = me.ReferenceFrame(f"A{i + 1}")
        A.orient_axis(N, N.z, q[i])
        A.set_ang_vel(N, speeds[i] * N.z)
        P = previous.locatenew(f"P{i + 1}", -lengths[i] * A.y)
        P.v2pt_theory(previous, N, A)
        bob = me.Particle(f"bob{i + 1}", P, masses[i])
        if not kane:
            bob.potential_energy = masses[i] * g * P.pos_from(origin).dot(N.y)
        particles.append(bob)
        loads.append((P, -masses[i] * g * N.y))
        previous = P
    return N, q, u, particles, loads


def derive_kane(n: int):
    """M and f (dynamic part, M u' = f) from sympy.physics.mechanics.KanesMethod."""
    import sympy.physics.mechanics as me

    N, q, u, particles, loads = _mechanics_pendulum(n, kane=True)
    kinematics = [qi.diff(me.dynamicsymbols._t) - ui for qi, ui in zip(q, u, strict=True)]
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kinematics)
    kane.kanes_equations(particles, loads)
    return kane.mass_matrix, kane.forcing


def derive_lagrange(n: int):
    """M and f (M q'' = f) from sympy.physics.mechanics.LagrangesMethod."""
    import sympy.physics.mechanics as me

    N, q, _, particles, _ = _mechanics_pendulum(n, kane=False)
    method = me.LagrangesMethod(me.Lagrangian(N, *particles), q, frame=N)
    method.form_lagranges_equations()
    return method.mass_matrix, method.forcing


def rod_chain(n: int):
    """The n-link pendulum written with rigid rods: rod i of mass m_i, length l_i and inertia
    m_i l_i^2 / 12 about its centre, which sits halfway along the rod, turned by theta_i."""
    import sympy as sp

    import lagrangian as lg

    thetas = sp.symbols(f"theta1:{n + 1}")
    masses, lengths = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    x, y = [sp.Integer(0)], [sp.Integer(0)]  # the terms of the joint above the rod
    rods = []
    for i in range(n):
        half = lengths[i] / 2
        centre = (
            sp.Add(*x, half * sp.sin(thetas[i])),
            sp.Add(*y, -half * sp.cos(thetas[i])),
        )
        inertia = masses[i] * lengths[i] ** 2 / 12
        rods.append(lg.RigidBody(f"rod{i + 1}", masses[i], inertia, centre, angle=thetas[i]))
        x.append(lengths[i] * sp.sin(thetas[i]))
        y.append(-lengths[i] * sp.cos(thetas[i]))
    return lg.System(
        coordinates=thetas,
        parameters={s: 1.0 for s in (*masses, *lengths, g)},
        rigid_bodies=rods,
        gravity=(0, -g),
    )


def cartesian_chain(n: int):
    """The n-link pendulum written in the bobs' Cartesian coordinates x_i, y_i, each rod a
    holonomic constraint (x_i - x_(i-1))^2 + (y_i - y_(i-1))^2 - l_i^2 = 0."""
    import sympy as sp

    import lagrangian as lg

    xs, ys = sp.symbols(f"x1:{n + 1}"), sp.symbols(f"y1:{n + 1}")
    masses, lengths = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    particles, constraints = [], []
    for i in range(n):
        previous = (xs[i - 1], ys[i - 1]) if i else (0, 0)
        particles.append(lg.Particle(f"bob{i + 1}", masses[i], (xs[i], ys[i])))
        rod = (xs[i] - previous[0]) ** 2 + (ys[i] - previous[1]) ** 2 - lengths[i] ** 2
        constraints.append(lg.Holonomic(rod, name=f"rod{i + 1}"))
    return lg.System(
        coordinates=[c for pair in zip(xs, ys, strict=True) for c in pair],
        parameters={s: 1.0 for s in (*masses, *lengths, g)},
        particles=particles,
        constraints=constraints,
        gravity=(0, -g),
    )


#: Seconds the last chain derivation took to build its System (the rest is deriving).
BUILT: dict[str, float] = {}


def _built(build, n: int):
    start = time.perf_counter()
    system = build(n)
    BUILT["seconds"] = time.perf_counter() - start
    return system


def derive_rods(n: int):
    """M and f of the chain of rigid rods."""
    import lagrangian as lg

    eom = lg.derive(_built(rod_chain, n))
    return eom.mass_matrix, eom.forcing


def derive_cartesian(n: int):
    """M and f of the Cartesian chain, with its multiplier form (constraint Jacobian, the
    acceleration-level gamma) read as well."""
    import lagrangian as lg

    constrained = lg.constrained_equations(_built(cartesian_chain, n))
    constrained.constraint_jacobian, constrained.gamma  # noqa: B018
    return constrained.mass_matrix, constrained.forcing


def derive_particles(n: int):
    """M and f of the built-in chain of particles (lagrangian's own row, its build timed
    apart)."""
    import lagrangian as lg

    eom = lg.derive(_built(lg.examples.n_link_pendulum, n))
    return eom.mass_matrix, eom.forcing


DERIVERS = {
    "lagrangian": derive_lagrangian,
    "kane": derive_kane,
    "lagrange": derive_lagrange,
    "particles": derive_particles,
    "rods": derive_rods,
    "cartesian": derive_cartesian,
}


# --------------------------------------------------------------------------- untimed measures


def plain(matrix):
    """Replace q(t) by the symbol ``q`` and q'(t) by ``q_dot``, as lagrangian names them."""
    import sympy as sp
    from sympy.core.function import AppliedUndef

    matrix = sp.ImmutableMatrix(matrix)
    rule = {d: sp.Symbol(f"{d.expr.func.__name__}_dot") for d in matrix.atoms(sp.Derivative)}
    rule.update({f: sp.Symbol(f.func.__name__) for f in matrix.atoms(AppliedUndef)})
    return matrix.xreplace(rule)


def output_size(M, f) -> int:
    """count_ops of the common-subexpression-eliminated entries of M and f."""
    import sympy as sp

    replacements, reduced = sp.cse([*plain(M), *plain(f)])
    return sum(sp.count_ops(rhs) for _, rhs in replacements) + sum(map(sp.count_ops, reduced))


def accelerations(M, f, values: dict[str, float]):
    """M^{-1} f with every symbol replaced by the number of the same name."""
    import numpy as np

    M, f = plain(M), plain(f)
    symbols = M.free_symbols | f.free_symbols
    unknown = sorted(s.name for s in symbols if s.name not in values)
    if unknown:
        raise ValueError(f"no value for symbols {unknown}")
    rule = {s: values[s.name] for s in symbols}
    numeric_M = np.array(M.xreplace(rule).evalf(), dtype=float)
    numeric_f = np.array(f.xreplace(rule).evalf(), dtype=float).ravel()
    return np.linalg.solve(numeric_M, numeric_f)


def random_state(n: int) -> dict[str, float]:
    """Reproducible random parameters, angles and angular velocities, keyed by name."""
    import numpy as np

    rng = np.random.default_rng(1000 + n)
    values = {"g": 9.81}
    for i in range(1, n + 1):
        values[f"m{i}"], values[f"l{i}"] = rng.uniform(0.5, 2.0, size=2)
        values[f"theta{i}"], values[f"theta{i}_dot"] = rng.uniform(-1.5, 1.5, size=2)
    return {name: float(value) for name, value in values.items()}


def check_against(reference: str, n: int, M, f) -> str:
    """'ok', or how M^{-1} f differs from the ``reference`` derivation at a random state."""
    import numpy as np

    values = random_state(n)
    try:
        ours = accelerations(M, f, values)
        theirs = accelerations(*DERIVERS[reference](n), values)
    except Exception as exc:
        return f"could not compare with {LABELS[reference]}: {type(exc).__name__}: {exc}"
    if np.allclose(ours, theirs, rtol=1e-9, atol=1e-9):
        return "ok"
    return f"differs from {LABELS[reference]}: max |diff| = {np.max(np.abs(ours - theirs)):.3g}"


# --------------------------------------------------------------------------- the worker


def emit(event: str, **data) -> None:
    """One JSON line to the parent: ready, derived (seconds), done (seconds, ops, check)."""
    print(json.dumps({"event": event, **data}), flush=True)


def import_for(method: str) -> None:
    """Import everything the derivation needs, so the timing excludes import time.

    For lagrangian, also fail (as unavailable) when the API the benchmark calls is missing.
    """
    import sympy.physics.mechanics  # noqa: F401

    with contextlib.suppress(ImportError):
        import symengine  # noqa: F401
    if method in OURS:
        sys.path.insert(0, str(SRC))  # benchmark the checkout, installed or not
        import lagrangian

        lagrangian.derive  # noqa: B018
        lagrangian.examples.n_link_pendulum  # noqa: B018
        # the chains' other ways of writing: their lazily imported parts, imported here
        lagrangian.constrained_equations  # noqa: B018
        lagrangian.RigidBody, lagrangian.Holonomic  # noqa: B018
    warm_up_sympy()


def warm_up_sympy() -> None:
    """Trigger SymPy's lazy first-use imports (its first Add imports sympy.tensor and
    sympy.combinatorics, about 50 ms) the same way for every method, so none pays import
    time inside the timed region."""
    import sympy as sp

    a, b = sp.symbols("warm_a warm_b")
    _ = (a * sp.sin(b) + b * sp.cos(a)) ** 2


def worker(method: str, n: int, measure: bool) -> int:
    """Time one derivation in this (fresh) process; report through ``emit``."""
    try:
        import_for(method)
    except Exception as exc:
        emit("unavailable", error=f"{type(exc).__name__}: {exc}")
        return 0
    emit("ready")
    try:
        start, started_cpu = time.perf_counter(), time.process_time()
        M, f = DERIVERS[method](n)
        seconds = time.perf_counter() - start
        cpu = time.process_time() - started_cpu
    except Exception as exc:
        emit("error", error=f"{type(exc).__name__}: {exc}")
        return 0
    emit("derived", seconds=seconds)
    ops = output_size(M, f) if measure and method in SIZED else None
    check = None
    if measure and n <= CHECK_MAX_N and method in REFERENCE:
        check = check_against(REFERENCE[method], n, M, f)
    emit("done", seconds=seconds, ops=ops, check=check, built=BUILT.get("seconds"), cpu=cpu)
    return 0


# --------------------------------------------------------------------------- the parent


@dataclass
class Run:
    """Outcome of one worker process."""

    status: str  # ok, capped, unavailable, error
    seconds: float = math.inf
    ops: int | None = None
    check: str | None = None
    error: str | None = None
    built: float | None = None  # of ``seconds``, building the System (chain formulations)
    cpu: float | None = None  # CPU seconds of the derivation (this process alone)


def _pump(stream, events: queue.Queue) -> None:
    for line in stream:
        if line.startswith("{"):
            events.put(json.loads(line))
    events.put({"event": "exit"})


def _next_event(events: queue.Queue, timeout: float) -> dict | None:
    try:
        return events.get(timeout=timeout)
    except queue.Empty:
        return None


def _follow(events: queue.Queue, cap: float) -> Run:
    """Turn the worker's events into a Run; the cap counts from 'ready' to 'derived'."""
    event = _next_event(events, STARTUP_SECONDS)
    if event is None or event["event"] == "exit":
        return Run("error", error="worker did not start")
    if event["event"] != "ready":
        return Run(event["event"], error=event.get("error"))
    event = _next_event(events, cap)
    if event is None:
        return Run("capped")
    if event["event"] != "derived":
        return Run("error", error=event.get("error", "worker died while deriving"))
    seconds = event["seconds"]
    event = _next_event(events, cap)  # the untimed size and check get a cap of their own
    if event is None or event["event"] != "done":
        return Run("ok", seconds, error="size/check did not finish")
    return Run(
        "ok", seconds, event["ops"], event["check"], built=event.get("built"), cpu=event.get("cpu")
    )


def run_worker(method: str, n: int, cap: float, measure: bool) -> Run:
    """Run one measurement in a fresh process, killing it when it overruns."""
    command = [sys.executable, str(HERE), "--worker", method, str(n)]
    command += ["--measure"] if measure else []
    with tempfile.TemporaryFile("w+") as stderr:
        with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=stderr, text=True) as proc:
            events: queue.Queue = queue.Queue()
            threading.Thread(target=_pump, args=(proc.stdout, events), daemon=True).start()
            try:
                run = _follow(events, cap)
            finally:
                if proc.poll() is None:
                    proc.kill()
                proc.wait()
        if run.status == "error" and run.error and "worker" in run.error:
            stderr.seek(0)
            run.error += ": " + stderr.read().strip()[-400:]
    return run


@dataclass
class Cell:
    """All runs of one method at one n."""

    times: list[float] = field(default_factory=list)
    ops: int | None = None
    status: str = "ok"  # ok, capped, skipped (capped at a smaller n), unavailable, error
    notes: list[str] = field(default_factory=list)
    built: list[float] = field(default_factory=list)  # seconds building the System
    cpu: list[float] = field(default_factory=list)  # CPU seconds of the runs

    @property
    def median(self) -> float | None:
        """Median seconds (inf when over the cap), None when nothing was measured."""
        if self.status == "skipped":
            return math.inf
        return statistics.median(self.times) if self.times else None


def _record_run(cell: Cell, run: Run, method: str, n: int) -> None:
    if run.status in ("unavailable", "error"):
        cell.status = run.status
        cell.notes.append(f"{LABELS[method]} n={n}: {run.status}: {run.error}")
        return
    cell.times.append(run.seconds)
    if run.built is not None:
        cell.built.append(run.built)
    if run.cpu is not None:
        cell.cpu.append(run.cpu)
    if run.status == "capped":
        cell.status = "capped"
    cell.ops = run.ops if run.ops is not None else cell.ops
    if run.error:
        cell.notes.append(f"{LABELS[method]} n={n}: {run.error}")
    if run.check not in (None, "ok"):
        cell.notes.append(f"WARNING {LABELS[method]} n={n}: M^-1 f {run.check}")


def measure(
    ns: list[int], repeat: int, cap: float, methods_at=lambda n: METHODS
) -> dict[tuple[str, int], Cell]:
    """Run every method (``methods_at(n)``) at every n ``repeat`` times, alternating methods
    run by run."""
    cells = {(method, n): Cell() for n in ns for method in methods_at(n)}
    stopped: dict[str, str] = {}  # method -> status it carries to larger n
    for n in ns:
        for r in range(repeat):
            for method in methods_at(n):
                cell = cells[method, n]
                if method in stopped and cell.status == "ok":
                    cell.status = stopped[method]
                if cell.status != "ok":
                    continue
                run = run_worker(method, n, cap, measure=(r == 0))
                _record_run(cell, run, method, n)
                shown = f"{run.seconds:.3g} s" if run.status == "ok" else run.status
                print(f"  n={n:<3} {method:<10} run {r + 1}/{repeat}: {shown}", file=sys.stderr)
        for method in methods_at(n):
            status = cells[method, n].status
            if status != "ok":
                stopped.setdefault(method, "skipped" if status == "capped" else status)
    return cells


# --------------------------------------------------------------------------- the report


def _seconds_text(cell: Cell, cap: float) -> str:
    if cell.status in ("unavailable", "error"):
        return cell.status
    median = cell.median
    if median is None:
        return "-"
    if math.isinf(median):
        return f"> {cap:g}" + (" †" if cell.status == "skipped" else "")
    return f"{median:.3g}"


def speedup(cells, method: str, n: int, cap: float) -> tuple[float, bool] | None:
    """(median time of ``method`` / median of lagrangian, is-lower-bound), or None."""
    ours, theirs = cells["lagrangian", n].median, cells[method, n].median
    if ours is None or theirs is None or math.isinf(ours):
        return None
    if math.isinf(theirs):
        return cap / ours, True
    return theirs / ours, False


def _speedup_text(ratio: tuple[float, bool] | None) -> str:
    if ratio is None:
        return "-"
    value, lower = ratio
    return ("> " if lower else "") + f"{value:.3g}"


def table(cells, ns: list[int], cap: float) -> str:
    """The results as a Markdown table."""
    header = (
        "| n | lagrangian s | Kane s | Lagrange s | Kane/lagrangian | Lagrange/lagrangian "
        "| ops lagrangian | ops Kane |"
    )
    lines = [header, "|" + "---:|" * 8]
    for n in ns:
        ops = [cells[m, n].ops for m in SIZED]
        row = [str(n), *(_seconds_text(cells[m, n], cap) for m in METHODS)]
        row += [_speedup_text(speedup(cells, m, n, cap)) for m in ("kane", "lagrange")]
        row += ["-" if o is None else str(o) for o in ops]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def _speed_verdict(cells, method: str, n: int, factor: float, cap: float) -> str:
    target = f"n={n}: lagrangian >= {factor:g}x faster than {LABELS[method]}"
    if ("lagrangian", n) not in cells:
        return f"N/A   {target} (n={n} not run)"
    ratio = speedup(cells, method, n, cap)
    if ratio is None:
        return f"N/A   {target} (lagrangian not measured)"
    value, lower = ratio
    if value >= factor:
        return f"PASS  {target} ({_speedup_text(ratio)}x)"
    if lower:
        return f"N/A   {target} (only known: {_speedup_text(ratio)}x; raise --cap)"
    return f"FAIL  {target} ({_speedup_text(ratio)}x)"


def _size_verdict(cells, ns: list[int]) -> str:
    target = "output no larger than KanesMethod's at every n"
    pairs = {n: (cells["lagrangian", n].ops, cells["kane", n].ops) for n in ns}
    compared = {n: p for n, p in pairs.items() if None not in p}
    if not compared:
        return f"N/A   {target} (no n with both sizes)"
    larger = [n for n, (ours, theirs) in compared.items() if ours > theirs]
    missing = [n for n in ns if n not in compared]
    suffix = f"; not compared at n={missing}" if missing else ""
    if larger:
        return f"FAIL  {target} (larger at n={larger}{suffix})"
    return f"PASS  {target} (compared at n={sorted(compared)}{suffix})"


def verdicts(cells, ns: list[int], cap: float) -> list[str]:
    """One PASS / FAIL / N/A line per target."""
    lines = [_speed_verdict(cells, m, n, factor, cap) for m, n, factor in SPEED_TARGETS]
    return [*lines, _size_verdict(cells, ns)]


def report(cells, ns: list[int], repeat: int, cap: float) -> str:
    """Table, footnotes, notes and verdicts."""
    notes = [note for cell in cells.values() for note in cell.notes]
    parts = [
        f"Median of {repeat} run(s) per cell, seconds; cap {cap:g} s per run.",
        "",
        table(cells, ns, cap),
        "",
    ]
    if any(cell.status == "skipped" for cell in cells.values()):
        parts += ["† not run: the method hit the cap at a smaller n.", ""]
    if notes:
        parts += [*notes, ""]
    parts += ["```", *verdicts(cells, ns, cap), "```"]
    return "\n".join(parts)


# --------------------------------------------------------------------------- chains


def chain_methods(n: int) -> tuple[str, ...]:
    """The chain written three ways, and KanesMethod where it ends in reasonable time."""
    return (*CHAIN_METHODS, "kane") if n in KANE_CHAIN_N else CHAIN_METHODS


def chain_table(cells, ns: list[int], cap: float) -> str:
    """Seconds of each formulation (of which building the System), KanesMethod's beside."""
    header = "| n | " + " | ".join(f"{LABELS[m]} s (build) [CPU]" for m in CHAIN_METHODS)
    lines = [header + " | KanesMethod s | Kane/particles |", "|" + "---:|" * 6]
    for n in ns:
        row = [str(n)]
        for method in CHAIN_METHODS:
            cell = cells[method, n]
            built = f" ({statistics.median(cell.built):.2f})" if cell.built else ""
            row.append(_seconds_text(cell, cap) + built + _cpu_text(cell))
        kane = cells.get(("kane", n))
        row.append(_seconds_text(kane, cap) + _cpu_text(kane) if kane else "not run")
        ratio = None
        if kane and cells["particles", n].median and kane.median:
            ratio = speedup({**cells, ("lagrangian", n): cells["particles", n]}, "kane", n, cap)
        row.append(_speedup_text(ratio))
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def _cpu_text(cell: Cell) -> str:
    return f" [{statistics.median(cell.cpu):.3g}]" if cell.cpu else ""


def chain_verdicts(cells, ns: list[int]) -> list[str]:
    """200 links within 3 s, and t(200) / t(50) within 20, for each formulation."""
    lines = []
    for method in CHAIN_METHODS:
        label = LABELS[method]
        t50 = cells[method, 50].median if (method, 50) in cells else None
        t200 = cells[method, 200].median if (method, 200) in cells else None
        if t200 is None or math.isinf(t200):
            lines.append(f"N/A   {label}: n=200 not measured")
            continue
        verdict = "PASS" if t200 <= CHAIN_TARGET_SECONDS else "FAIL"
        lines.append(f"{verdict}  {label}: 200 links <= {CHAIN_TARGET_SECONDS:g} s ({t200:.3g} s)")
        if t50 is None or math.isinf(t50):
            continue
        ratio = t200 / t50
        verdict = "PASS" if ratio <= CHAIN_TARGET_RATIO else "FAIL"
        lines.append(f"{verdict}  {label}: t(200)/t(50) <= {CHAIN_TARGET_RATIO:g} ({ratio:.3g})")
        c50, c200 = cells[method, 50].cpu, cells[method, 200].cpu
        if c50 and c200:  # on a loaded machine the CPU time is the steadier measure
            ratio = statistics.median(c200) / statistics.median(c50)
            verdict = "PASS" if ratio <= CHAIN_TARGET_RATIO else "FAIL"
            lines.append(
                f"{verdict}  {label}: CPU t(200)/t(50) <= {CHAIN_TARGET_RATIO:g} ({ratio:.3g})"
            )
    return lines


def chain_report(cells, ns: list[int], repeat: int, cap: float) -> str:
    notes = [note for cell in cells.values() for note in cell.notes]
    parts = [
        f"Median of {repeat} run(s) per cell, wall seconds from nothing to M and the forcing "
        f"(the Cartesian chain: its multiplier form); in round brackets the part spent "
        f"building the System, in square brackets the CPU seconds of the worker; cap {cap:g} s "
        f"per run; 1-minute load {os.getloadavg()[0]:.1f} at the end on {os.cpu_count()} cores.",
        "",
        chain_table(cells, ns, cap),
        "",
        *notes,
        "```",
        *chain_verdicts(cells, ns),
        "```",
    ]
    return "\n".join(parts)


# --------------------------------------------------------------------------- recording

HEADER = """# Benchmark results

Deriving the equations of motion of an n-link planar pendulum with lagrangian,
sympy.physics.mechanics KanesMethod and LagrangesMethod (see the docstring of
`benchmarks/derive.py` for what is timed and how). Each section is appended by

    python benchmarks/derive.py --record
"""


def record(text: str) -> None:
    """Append a dated section with the machine description and ``text`` to RESULTS.md."""
    machine = [
        f"- platform: {platform.platform()}",
        f"- CPU: {cpu_model()}",
        f"- python {platform.python_version()}, sympy {package_version('sympy')}, "
        f"symengine {package_version('symengine')}",
    ]
    now = datetime.datetime.now().astimezone().isoformat(timespec="minutes")
    section = "\n".join([f"## {now}", "", *machine, "", text, ""])
    existing = RESULTS.read_text() if RESULTS.exists() else HEADER
    RESULTS.write_text(existing.rstrip("\n") + "\n\n" + section)


# --------------------------------------------------------------------------- command line


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, nargs="+", help=f"pendulum sizes (default {DEFAULT_N})")
    parser.add_argument("--repeat", type=int, default=3, help="runs per method and n (3)")
    parser.add_argument("--cap", type=float, default=300.0, help="seconds per single run (300)")
    parser.add_argument("--quick", action="store_true", help=f"n = {QUICK_N}, one run each")
    parser.add_argument("--record", action="store_true", help=f"append results to {RESULTS.name}")
    parser.add_argument(
        "--chains",
        action="store_true",
        help=f"large chains written three ways (n = {CHAIN_N}), KanesMethod at n = {KANE_CHAIN_N}",
    )
    parser.add_argument("--worker", nargs=2, metavar=("METHOD", "N"), help=argparse.SUPPRESS)
    parser.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    if args.worker:
        method, n = args.worker
        return worker(method, int(n), args.measure)
    repeat = 1 if args.quick else args.repeat
    if args.chains:
        ns = sorted(set(args.n or CHAIN_N))
        cells = measure(ns, repeat, args.cap, chain_methods)
        text = chain_report(cells, ns, repeat, args.cap)
    else:
        ns = sorted(set(args.n or (QUICK_N if args.quick else DEFAULT_N)))
        cells = measure(ns, repeat, args.cap)
        text = report(cells, ns, repeat, args.cap)
    print(text)
    if args.record:
        record(text)
        print(f"\nappended to {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
