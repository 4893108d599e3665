"""First integrals quadratic in the velocities whose coefficients are trigonometric
polynomials in the angles and polynomials in the other coordinates:

    |L|**2 = m**2 r**4 (theta_dot**2 + sin(theta)**2 phi_dot**2)

of a particle in a central potential, in spherical coordinates (Goldstein §3.2), and the
Laplace–Runge–Lenz components of the Kepler problem in polar coordinates (Goldstein §3.9),

    m A_x = (m**2 r**3 theta_dot**2 - m k) cos(theta) + m**2 r**2 r_dot theta_dot sin(theta).

An angle is a coordinate that L and the forces contain only through sin and cos of integer
combinations of the angles; one they do not contain at all is an angle too when its inertia
depends on the coordinates (the azimuth of a sphere, the polar angle of a Kepler problem
whose L has no sine: m r**2), not when it is constant (a cart's position).  The other
coordinates are radial.

The coefficient of the monomial prod v_j**e_j (i powers of radial velocities, a of angular
ones) is sought among the products of

- the monomials of the radial coordinates of degree <= ``degree`` - i + a: an angular
  velocity may carry the r**2 of an angular momentum (m r**2 theta_dot), a radial one the
  constant of a linear momentum (m r_dot), so r**4 multiplies theta_dot**2 in |L|**2 and
  only constants multiply r_dot**2 (the energy's m/2);
- sin(theta)**b cos(theta)**c over the angles, c in (0, 1), sum(b + c) <= ``degree``: a
  basis of the trigonometric polynomials of that order (cos**2 = 1 - sin**2), independent
  without a test.

The search itself (samples of dI/dt on M q_ddot = forcing, its exact null vectors, each
verified to 30 digits) is that of :mod:`~lagrangian.analysis.integrals.quadratic`.

>>> import lagrangian as lg
>>> trigonometric_integrals(lg.examples.planet(), {"m": 1, "mu": 1})[-1]
r**3*theta_dot**2*cos(theta) + r**2*r_dot*theta_dot*sin(theta) - cos(theta)
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute, substitutions
from lagrangian.analysis.integrals.function_basis import FunctionBasis
from lagrangian.analysis.integrals.lie_symmetries import SearchProblem, search_problem
from lagrangian.analysis.integrals.quadratic import Ansatz, integrals_in_basis, velocity_monomials
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import is_zero
from lagrangian.symbolic.symbols import t


@dataclass(frozen=True)
class Angles:
    """The angles of a system: those L and the forces contain (``turning``, through sin and
    cos) and those they do not contain (``cyclic``, the azimuth)."""

    turning: tuple[sp.Symbol, ...] = ()
    cyclic: tuple[sp.Symbol, ...] = ()
    #: cyclic coordinates of constant inertia (a cart's position): no coefficient depends
    #: on them (their momentum and boost are the other stages' findings)
    translations: tuple[sp.Symbol, ...] = ()

    @property
    def all(self) -> tuple[sp.Symbol, ...]:
        """Every angle."""
        return (*self.turning, *self.cyclic)


@dataclass(frozen=True)
class TrigonometricSearch:
    """The search of one system with given parameters, at any degree: its angles and the
    L and forces it reads (with the substitutions made)."""

    problem: SearchProblem
    parameters: Values | None
    angles: Angles

    def ansatz(self, degree: int) -> tuple[FunctionBasis, tuple[Ansatz, ...]]:
        """The functions and the parts of the ansatz of ``degree``."""
        coordinates = self.problem.eom.coordinates
        return trigonometric_ansatz(coordinates, self.angles, degree, reversible(self.problem))

    def unknowns(self, degree: int) -> int:
        """The unknowns of the largest part of the ansatz of ``degree``, counted without
        building it (a 12-link chain's ansatz of degree 4 has millions of functions)."""
        coordinates = self.problem.eom.coordinates
        sizes = ansatz_sizes(coordinates, self.angles, degree, reversible(self.problem))
        return max(sizes, default=0)

    def integrals(
        self, degree: int, novel: Callable[[sp.Expr], bool] | None = None
    ) -> tuple[sp.Expr, ...]:
        """Every first integral in the ansatz of ``degree``, each verified at random states
        to 30 digits; ``novel``, when given, drops a solution before its verification (one
        already known)."""
        basis, ansatze = self.ansatz(degree)
        # the general simplification costs more than the search; the products of sines and
        # cosines of the ansatz read as they are
        problem, parameters = self.problem, self.parameters
        return integrals_in_basis(problem, parameters, basis, ansatze, novel, simplified=False)


def trigonometric_search(
    subject: Subject, parameters: Values | None = None
) -> TrigonometricSearch | None:
    """The search with coefficients trigonometric in the angles, None without angles."""
    problem = search_problem(equations_of(subject), parameters)
    angles = angular_coordinates(problem, parameters)
    return TrigonometricSearch(problem, parameters, angles) if angles.all else None


def trigonometric_integrals(
    subject: Subject, parameters: Values | None = None, degree: int = 2
) -> tuple[sp.Expr, ...]:
    """Every first integral quadratic (at most) in the velocities whose coefficients are in
    the trigonometric ansatz of ``degree`` (module docstring), each verified at random
    states to 30 digits; () when the system has no angles."""
    search = trigonometric_search(subject, parameters)
    return () if search is None else search.integrals(degree)


def angular_coordinates(problem: SearchProblem, parameters: Values | None = None) -> Angles:
    """The coordinates that L and the forces contain only through sin and cos of integer
    combinations of them, and those they do not contain whose inertia depends on the
    coordinates (module docstring)."""
    eom = problem.eom
    q = set(eom.coordinates)
    pieces = [problem.lagrangian, *problem.forces]
    inside = {f for p in pieces for f in p.atoms(sp.sin, sp.cos) if f.args[0].free_symbols & q}
    outside = set()
    for p in pieces:
        outside |= p.xreplace({f: sp.Dummy() for f in inside}).free_symbols & q
    for f in inside:
        argument = f.args[0]
        for s in argument.free_symbols & q:
            if not argument.diff(s).is_integer:
                outside.add(s)  # sin(theta/2) is no trigonometric polynomial of theta
    inner = set().union(*(f.free_symbols for f in inside))
    turning = tuple(s for s in eom.coordinates if s in inner and s not in outside)
    mass = to_sympy(substitute(eom.mass_matrix, substitutions(eom, parameters)))
    present = set().union(*(p.free_symbols for p in pieces))
    # a cyclic coordinate is an azimuth when its inertia grows with the distance from its
    # axis (m r**2 of a polar angle); a translation's (m of a cart) is constant
    absent = [(s, bool(mass[i, i].free_symbols & q)) for i, s in enumerate(eom.coordinates)]
    absent = [(s, turns) for s, turns in absent if s not in present]
    cyclic = tuple(s for s, turns in absent if turns)
    return Angles(turning, cyclic, tuple(s for s, turns in absent if not turns))


def reversible(problem: SearchProblem) -> bool:
    """True when the motions run backwards are motions (L even in the velocities, no
    explicit time, forces free of the velocities): then the even and the odd part of a first
    integral are first integrals each, and are sought apart."""
    eom = problem.eom
    backwards = {v: -v for v in eom.velocities}
    lagrangian = problem.lagrangian
    moving = {eom.time, *eom.velocities}
    return (
        eom.time not in lagrangian.free_symbols
        and not any(f.free_symbols & moving for f in problem.forces)
        and is_zero(sp.expand(lagrangian.xreplace(backwards) - lagrangian))
    )


def trigonometric_ansatz(
    coordinates: Sequence[sp.Symbol], angles: Angles, degree: int, even_and_odd: bool = False
) -> tuple[FunctionBasis, tuple[Ansatz, ...]]:
    """The functions of the ansatz (the constant first) and its parts that dI/dt never mixes:
    one per Fourier mode of the cyclic angles (a translation of a cyclic angle maps an
    integral to an integral, so each mode of one is one), and with ``even_and_odd`` the
    monomials of degree 2 with K_0 apart from those of degree 1 (module docstring)."""
    radial = [s for s in coordinates if s not in (*angles.all, *angles.translations)]
    functions: list[sp.Expr] = [sp.Integer(1)]
    index: dict[sp.Expr, int] = {sp.Integer(1): 0}
    ansatze = []
    for k, group, radial_degrees, no_constant in _layout(coordinates, angles, degree, even_and_odd):
        waves = _waves(angles, k, degree)
        supports = []
        for radial_degree in radial_degrees:
            support = []
            for power in _monomials(radial, radial_degree):
                for wave in waves:
                    f = power * wave
                    i = index.get(f)
                    if i is None:
                        i = index[f] = len(functions)
                        functions.append(f)
                    support.append(i)
            supports.append(support)
        if no_constant:
            supports[-1] = []  # K_0 is even
        supports[-1] = [i for i in supports[-1] if i]  # a constant K_0 is no integral
        ansatz = Ansatz(tuple(group), tuple(tuple(s) for s in supports))
        if ansatz.unknowns:
            ansatze.append(ansatz)
    basis = FunctionBasis((t, *coordinates), tuple(functions), angles.all)
    return basis, tuple(ansatze)


def ansatz_sizes(
    coordinates: Sequence[sp.Symbol], angles: Angles, degree: int, even_and_odd: bool = False
) -> list[int]:
    """The unknowns of each part of :func:`trigonometric_ansatz`, counted from the sizes of
    its bases alone: C(r + d, d) monomials of degree <= d in r radial coordinates, and the
    trigonometric monomials of :func:`_trigonometric_count`."""
    radial = [s for s in coordinates if s not in (*angles.all, *angles.translations)]
    sizes = []
    for k, _, radial_degrees, no_constant in _layout(coordinates, angles, degree, even_and_odd):
        order = sum(map(abs, k))
        waves = (1 if order == 0 else 2) * _trigonometric_count(len(angles.turning), degree - order)
        counts = [math.comb(len(radial) + d, d) * waves if d >= 0 else 0 for d in radial_degrees]
        if no_constant:
            counts[-1] = 0
        elif order == 0 and radial_degrees[-1] >= 0:
            counts[-1] -= 1  # the constant function, dropped from K_0
        if sum(counts):
            sizes.append(sum(counts))
    return sizes


def _layout(
    coordinates: Sequence[sp.Symbol], angles: Angles, degree: int, even_and_odd: bool
) -> Iterator[tuple[tuple[int, ...], list[tuple[int, ...]], list[int], bool]]:
    """Each part of the ansatz: its Fourier mode k of the cyclic angles, its velocity
    monomials, the degree of the radial monomials of each of them (and of K_0, last), and
    whether K_0 is left out (an odd part of a reversible system)."""
    exponents = velocity_monomials(len(coordinates), 2)
    groups = [exponents]
    if even_and_odd:
        groups = [[e for e in exponents if sum(e) == 2], [e for e in exponents if sum(e) == 1]]
    for k in _fourier_modes(angles, degree):
        for group in groups:
            radial_degrees = [
                degree - sum(-e if s in angles.all else e for s, e in zip(coordinates, powers))
                for powers in [*group, (0,) * len(coordinates)]
            ]
            yield k, group, radial_degrees, even_and_odd and sum(group[0]) == 1


def _fourier_modes(angles: Angles, degree: int) -> Iterator[tuple[int, ...]]:
    """The Fourier modes k of the cyclic angles, each up to its sign, sum |k_j| <= ``degree``."""
    for k in itertools.product(range(-degree, degree + 1), repeat=len(angles.cyclic)):
        leading = next((j for j in k if j), 0)
        if leading >= 0 and sum(map(abs, k)) <= degree:  # -k is the same mode
            yield k


def _waves(angles: Angles, k: tuple[int, ...], degree: int) -> list[sp.Expr]:
    """cos(k . phi) and sin(k . phi) (1 for k = 0) times the trigonometric monomials of the
    other angles of order <= ``degree`` - sum |k_j|."""
    phase = sp.Add(*(j * a for j, a in zip(k, angles.cyclic)))
    waves = [sp.Integer(1)] if phase == 0 else [sp.cos(phase), sp.sin(phase)]
    rest = _trigonometric_monomials(angles.turning, degree - sum(map(abs, k)))
    return [w * r for w in waves for r in rest]


def _monomials(variables: Sequence[sp.Symbol], degree: int) -> list[sp.Expr]:
    """The monomials in ``variables`` of degree <= ``degree``, the lowest first."""
    return [
        sp.Mul(*chosen)
        for d in range(degree + 1)
        for chosen in itertools.combinations_with_replacement(variables, d)
    ]


def _trigonometric_monomials(angles: Sequence[sp.Symbol], degree: int) -> list[sp.Expr]:
    """prod sin(a)**b cos(a)**c with c in (0, 1) and sum(b + c) <= ``degree``: a basis of the
    trigonometric polynomials of order <= ``degree`` in ``angles``."""
    if degree < 0:
        return []
    single = [
        [(b + c, sp.sin(a) ** b * sp.cos(a) ** c) for b in range(degree + 1) for c in (0, 1)]
        for a in angles
    ]
    found: list[sp.Expr] = []

    def choose(j: int, left: int, factors: list[sp.Expr]) -> None:
        # every angle's choices in the order of their product, each branch ended once its
        # order is spent (the product has (2 degree + 2)**n choices, nearly all over it)
        if j == len(single):
            found.append(sp.Mul(*factors))
            return
        for order, f in single[j]:
            if order <= left:
                choose(j + 1, left - order, [*factors, f])

    choose(0, degree, [])
    return sorted(found, key=sp.count_ops)


def _trigonometric_count(angles: int, degree: int) -> int:
    """How many :func:`_trigonometric_monomials` of order <= ``degree`` ``angles`` angles
    have: an angle's factor of order 0 is 1, of order o > 0 sin**o or sin**(o-1) cos."""
    if degree < 0:
        return 0
    ways = [1] + [0] * degree  # ways[o]: the products of the angles so far of order o
    for _ in range(angles):
        ways = [ways[o] + 2 * sum(ways[:o]) for o in range(degree + 1)]
    return sum(ways)
