"""Check: a change to the derivation leaves every equation as it was, expression by expression.

What is compared
    For every built-in example and benchmark (``lagrangian.examples``), and for the 3-D
    models written by hand in the benchmarks (the bicycle of :func:`bicycle.hand_bicycle`,
    the rolling disc as a product of rotation matrices, expanded and as quaternions, the
    3-D chains of rods in Euler angles, joint angles and matrix products), the ``srepr`` of
    ``lg.derive``'s mass matrix, forcing, Coriolis vector, gravity, generalized forces and
    time terms, and with constraints ``lg.constrained_equations``' constraint Jacobian and
    gamma.  ``srepr`` is SymPy's exact tree: two derivations agree only when they build the
    same expressions, not merely equal ones.  The model itself is compared too (``system``:
    the srepr of every field of the ``System``, its bodies, orientations, inertias,
    constraints, frames, ...), so a change to how a model is built shows where it starts.

Usage
    python benchmarks/same_equations.py --src OLD/src --out before.json
    python benchmarks/same_equations.py --src src --out after.json
    python benchmarks/same_equations.py --compare before.json after.json
    python benchmarks/same_equations.py --src src --out some.json --only whipple_bicycle

    ``--src`` is the source tree derived with (a checkout's ``src``); each model is derived
    in a fresh process, so no cache of one run feeds the next.  ``--compare`` lists the
    entries that differ and exits 1 when any does (and then also tells whether the
    difference simplifies to zero).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from collections.abc import Mapping
from pathlib import Path

HERE = Path(__file__).resolve().parent
FIELDS = ("mass_matrix", "forcing", "coriolis", "gravity", "generalized_forces", "time_terms")
CONSTRAINED = ("constraint_jacobian", "gamma")
#: The models written by hand in the benchmarks: name -> (module, function, arguments).
HAND = {
    "hand_bicycle": ("bicycle", "hand_bicycle", ()),
    "hand_rolling_disc_product": ("multibody", "hand_rolling_disc", ("product",)),
    "hand_rolling_disc_expanded": ("multibody", "hand_rolling_disc", ("expanded",)),
    "hand_rolling_disc_quaternion": ("multibody", "hand_rolling_disc", ("quaternion",)),
    "euler_chain_3": ("multibody", "euler_chain", (3,)),
    "relative_chain_3": ("multibody", "relative_chain", (3,)),
    "hand_chain_3": ("multibody", "hand_chain", (3,)),
}


def model_names(src: str) -> list[str]:
    """Every built-in example and benchmark, then the hand-written models."""
    found = subprocess.run(
        [
            sys.executable,
            "-c",
            "from lagrangian.examples import CATALOG, BENCHMARKS;"
            "print(' '.join([*CATALOG, *BENCHMARKS]))",
        ],
        env=_environment(src),
        capture_output=True,
        text=True,
        check=True,
    )
    return [*found.stdout.split(), *HAND]


def _environment(src: str) -> dict:
    import os

    return {**os.environ, "PYTHONPATH": str(Path(src).resolve())}


def system_fingerprint(value: object) -> object:
    """Every field of ``value`` (a System, and what it holds) as srepr strings, nested."""
    import dataclasses

    import sympy as sp

    if isinstance(value, (sp.Basic, sp.MatrixBase)):
        return sp.srepr(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [
            type(value).__name__,
            *(
                [f.name, system_fingerprint(getattr(value, f.name))]
                for f in dataclasses.fields(value)
            ),
        ]
    if isinstance(value, Mapping):
        return ["map", *([system_fingerprint(k), system_fingerprint(v)] for k, v in value.items())]
    if isinstance(value, (tuple, list)):
        return [type(value).__name__, *(system_fingerprint(v) for v in value)]
    return repr(value)


def fingerprint(name: str) -> dict:
    """srepr of each derived matrix of model ``name`` (run in the worker process)."""
    import sympy as sp

    import lagrangian as lg
    from lagrangian.examples import get

    if name in HAND:
        sys.path.insert(1, str(HERE))
        module, function, arguments = HAND[name]
        built = getattr(__import__(module), function)(*arguments)
        system = built if isinstance(built, lg.System) else built[0]
    else:
        system = get(name)()
    found = {"system": json.dumps(system_fingerprint(system))}
    start = time.perf_counter()
    equations = lg.derive(system)
    found.update({field: sp.srepr(getattr(equations, field)) for field in FIELDS})
    if system.constraints:
        constrained = lg.constrained_equations(system)
        found.update({field: sp.srepr(getattr(constrained, field)) for field in CONSTRAINED})
    found["seconds"] = time.perf_counter() - start
    return found


def collect(src: str, out: Path, only: list[str] | None = None) -> None:
    results = {}
    for name in only or model_names(src):
        done = subprocess.run(
            [sys.executable, __file__, "--worker", name],
            env=_environment(src),
            capture_output=True,
            text=True,
            check=False,
        )
        lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
        results[name] = json.loads(lines[-1]) if lines else {"error": done.stderr[-500:]}
        print(f"{name}: {results[name].get('seconds', 'error')}", file=sys.stderr)
    out.write_text(json.dumps(results, indent=1))


def compare(before: Path, after: Path) -> int:
    import sympy as sp

    old, new = json.loads(before.read_text()), json.loads(after.read_text())
    differ = 0
    for name in sorted(new):
        a, b = old.get(name, {}), new.get(name, {})
        for field in sorted((set(a) | set(b)) - {"seconds"}):
            if a.get(field) == b.get(field):
                continue
            differ += 1
            zero = "?"
            if field in a and field in b and field not in ("error", "system"):
                difference = sp.sympify(a[field]) - sp.sympify(b[field])
                zero = str(sp.simplify(difference) == sp.zeros(*difference.shape))
            print(f"DIFFER {name}.{field} (difference simplifies to zero: {zero})")
    checked = sum(len(set(v) - {"seconds"}) for v in new.values())
    print(f"{len(new)} models, {checked} matrices and systems compared, {differ} differ")
    return 1 if differ else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--src", help="the source tree to derive with")
    parser.add_argument("--out", type=Path, help="where to write the fingerprints (JSON)")
    parser.add_argument("--compare", nargs=2, type=Path, metavar=("BEFORE", "AFTER"))
    parser.add_argument("--only", nargs="+", metavar="MODEL", help="these models alone")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        print(json.dumps(fingerprint(args.worker)), flush=True)
        return 0
    if args.compare:
        return compare(*args.compare)
    if not (args.src and args.out):
        parser.error("give --src and --out, or --compare BEFORE AFTER")
    collect(args.src, args.out, args.only)
    return 0


if __name__ == "__main__":
    sys.exit(main())
