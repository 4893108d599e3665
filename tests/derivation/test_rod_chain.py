"""A chain of rigid rods (rod k's centre halfway along it, the rods below hinged at its end):
its entries of M are l_j l_k (m_k/2 + m_(k+1) + ... + m_n) cos(theta_j - theta_k), collected
from the products as the expanded entry would be, checked against KanesMethod and against
collecting the expansion itself."""

from __future__ import annotations

import symengine as se
import sympy as sp
import sympy.physics.mechanics as me

import lagrangian as lg
from lagrangian.derivation import kinetic
from lagrangian.derivation.collect import collect_state
from lagrangian.derivation.terms import euler_lagrange_terms


def rod_chain(n: int) -> lg.System:
    thetas = lg.coordinates(" ".join(f"theta{i + 1}" for i in range(n)))
    thetas = thetas if isinstance(thetas, (list, tuple)) else [thetas]
    masses, lengths = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    x, y = sp.Integer(0), sp.Integer(0)
    rods = []
    for i in range(n):
        half = lengths[i] / 2
        centre = (x + half * sp.sin(thetas[i]), y - half * sp.cos(thetas[i]))
        inertia = masses[i] * lengths[i] ** 2 / 12
        rods.append(lg.RigidBody(f"rod{i + 1}", masses[i], inertia, centre, angle=thetas[i]))
        x, y = x + lengths[i] * sp.sin(thetas[i]), y - lengths[i] * sp.cos(thetas[i])
    return lg.System(
        coordinates=thetas,
        parameters=[*masses, *lengths, g],
        rigid_bodies=rods,
        gravity=(0, -g),
    )


def kane_rod_chain(n: int) -> tuple[sp.Matrix, sp.Matrix, list, list]:
    """M and the forcing of the same chain from KanesMethod (u_k = theta_k')."""
    q = me.dynamicsymbols(f"theta1:{n + 1}")
    u = me.dynamicsymbols(f"theta1:{n + 1}_u")
    masses, lengths = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    frame = me.ReferenceFrame("N")
    joint = me.Point("O")
    joint.set_vel(frame, 0)
    bodies, loads = [], []
    for i in range(n):
        body = me.ReferenceFrame(f"B{i}")
        body.orient_axis(frame, frame.z, q[i])
        body.set_ang_vel(frame, u[i] * frame.z)
        centre = joint.locatenew(f"C{i}", -lengths[i] / 2 * body.y)
        centre.v2pt_theory(joint, frame, body)
        inertia = me.inertia(body, 0, 0, masses[i] * lengths[i] ** 2 / 12)
        bodies.append(me.RigidBody(f"rod{i}", centre, body, masses[i], (inertia, centre)))
        loads.append((centre, -masses[i] * g * frame.y))
        joint = joint.locatenew(f"J{i}", -lengths[i] * body.y)
        joint.v2pt_theory(centre, frame, body)
    kinematics = [qi.diff(me.dynamicsymbols._t) - ui for qi, ui in zip(q, u, strict=True)]
    kane = me.KanesMethod(frame, q_ind=q, u_ind=u, kd_eqs=kinematics)
    kane.kanes_equations(bodies, loads)
    return kane.mass_matrix, kane.forcing, q, u


def test_a_chain_of_four_rods_is_kanes_method() -> None:
    n = 4
    eom = lg.derive(rod_chain(n))
    mass, forcing, q, u = kane_rod_chain(n)
    plain = {**dict(zip(u, eom.velocities, strict=True))}
    plain.update(dict(zip(q, eom.coordinates, strict=True)))
    assert sp.simplify(eom.mass_matrix - mass.xreplace(plain)) == sp.zeros(n, n)
    difference = (eom.forcing - forcing.xreplace(plain)).applyfunc(sp.expand_trig)
    assert sp.simplify(difference) == sp.zeros(n, 1)


def test_the_rods_entries_are_collected_as_their_expansion(monkeypatch) -> None:
    """Each entry collected from its products is the collection of its expansion, the same
    SymEngine expression, for chains of 2 to 12 rods (and the fast way is taken), with what
    the entries share remembered across them (the memo M's collection passes) or not."""
    compared = []
    original = kinetic.collected_entry

    def checked(entry, state, memo=None):
        slow = collect_state(se.expand(entry), state)
        for shared in (kinetic.EntryMemo(), memo):
            fast = kinetic._collected_products(entry, state, shared)
            compared.append(fast is not None)
            if fast is not None:
                assert fast == slow and str(fast) == str(slow)
        return original(entry, state, memo)

    monkeypatch.setattr(kinetic, "collected_entry", checked)
    monkeypatch.setattr(kinetic._ColumnTable, "split", lambda *_: None)  # every entry here
    for n in (2, 5, 12):
        lg.derive(rod_chain(n)).mass_matrix  # noqa: B018
    assert sum(compared) > len(compared) / 2


def test_the_rods_entries_made_from_their_columns_are_the_collection_of_their_expansion(
    monkeypatch,
) -> None:
    """Each entry of M made from its column pairs (r_j cos(a - b) times the collected sum of
    the radii s_i times their holders' masses) is the collection of the expanded entry
    summed from its products, the same SymEngine expression, for chains of 2 to 12 rods;
    every entry with two products is made so: all but the diagonal (the rod's inertia, no
    cosine) and the last rod's column (its centre alone)."""
    made = []
    original = kinetic._ColumnTable.split

    def checked(table, groups, state, memo):
        split = original(table, groups, state, memo)
        if split is not None and len(groups) > 1:
            fast = split[1] * split[0]
            entry = se.Add(
                *[table.weight_sum(holders) * table.products[ids] for holders, ids in groups]
            )
            slow = collect_state(se.expand(entry), state)
            assert fast == slow and str(fast) == str(slow)
            assert se.Mul(*split[2]) == split[0]  # w is the product of its parts
            made.append(fast)
        return split

    monkeypatch.setattr(kinetic._ColumnTable, "split", checked)
    for n in (2, 5, 12):
        lg.derive(rod_chain(n)).mass_matrix  # noqa: B018
    assert len(made) == sum((n - 1) * (n - 2) // 2 for n in (2, 5, 12))


def test_gravity_read_off_the_columns_is_the_gradient_of_the_potential() -> None:
    """G read off M's column table (each column at q_k times the masses that hold it) is,
    once tidied, the same SymEngine expression as the tidied gradient of the expanded
    potential, and the same polynomial, for chains of particles and of rods short and long
    enough for their sums of masses to be kept whole; the table is what gave it."""
    for build in (lg.examples.n_link_pendulum, rod_chain):
        for n in (3, 9, 14):
            terms = euler_lagrange_terms(build(n))
            by_potential = terms.potential_gradient(terms.assembly.potential)
            assert terms.kinetic.point_columns is not None
            # G_1 = g l_1 (... + m_n) sin(theta_1) one product, the gradient's n terms
            assert terms.gravity[0].is_Mul and len(se.expand(by_potential[0]).args) == n
            for by_columns, gradient in zip(terms.gravity, by_potential, strict=True):
                assert terms.tidy(by_columns) == terms.tidy(gradient)
                assert se.expand(by_columns - gradient) == 0
