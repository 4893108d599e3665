"""The time grid of the compiled variational marches, made node by node, and their output rows.

A march of 10^7 steps keeps no array of 10^7 times: its nodes are made as it reaches them,
the same nodes as :meth:`lagrangian.simulation.variational.march.StepSchedule.grid` (the
reference in NumPy):

    uniform nodes   U_j = min(t0 + j dt, t1) for j < count, U_count = t1   (count < 0: none)
    grid            the sorted union of the U_j and the ``extra`` times, leaving out every
                    time within ``tolerance`` of the time before it in the union

and an output time T goes to the first node at or after T - tolerance (the last node when
none is).  ``schedule`` = (span, extra, wanted, every): span = [t0, dt, t1, tolerance, count],
``wanted`` the output times (sorted), ``every`` whether every node is an output (its row is its
index).  A march keeps its place in ``cursor`` (:data:`CURSOR` names the entries) and the times
of its last nodes in ``clock`` = [t_{k-2}, t_{k-1}, t_k, t_{k+1}, the last time of the
union]; both live in arrays between two chunks of steps.

The output arrays ``out`` = (q, v, residual, multipliers, node, t) have one row per output
time (per node with ``every``).  This module is imported only when numba is installed.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lagrangian.numerics.fast.newton import largest

#: The entries of a march's cursor: next uniform node, next extra time, next wanted output
#: time, next output row, current node k (-1 before the first), rows of node k [start, end),
#: known earlier nodes (0, 1, 2: the history of the midpoint rule's guess), evaluations.
UNIFORM, EXTRA, WANTED, ROW, NODE, FIRST_ROW, END_ROW, KNOWN, EVALUATIONS = range(9)
CURSOR = 9


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def uniform_node(span, j) -> float:
    """U_j (module docstring)."""
    t0, dt, t1, count = span[0], span[1], span[2], int(span[4])
    if j == count:
        return t1
    return min(t0 + dt * j, t1)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def next_union(schedule, cursor) -> float:
    """The next time of the union of the uniform nodes and the extra times (inf after the
    last), each equal time once."""
    span, extra = schedule[0], schedule[1]
    count = int(span[4])
    u = uniform_node(span, cursor[UNIFORM]) if cursor[UNIFORM] <= count else np.inf
    x = extra[cursor[EXTRA]] if cursor[EXTRA] < extra.size else np.inf
    value = min(u, x)
    if u == value and cursor[UNIFORM] <= count:
        cursor[UNIFORM] += 1
    while cursor[EXTRA] < extra.size and extra[cursor[EXTRA]] == value:
        cursor[EXTRA] += 1
    return value


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def next_node(schedule, cursor, clock) -> float:
    """The node after the last one made (the first node at the start); inf after the last."""
    tolerance = schedule[0][3]
    while True:
        value = next_union(schedule, cursor)
        first = cursor[NODE] < 0 and clock[4] != clock[4]  # no union time yet (NaN)
        previous = clock[4]
        clock[4] = value
        if value == np.inf or first or value - previous > tolerance:
            return value


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def wants_output(schedule, cursor, t, last) -> bool:
    """Whether the node at time t (the ``last`` node or not) has an output row."""
    wanted, every = schedule[2], schedule[3]
    if every or last:
        return True
    return cursor[WANTED] < wanted.size and wanted[cursor[WANTED]] - schedule[0][3] <= t


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def record(schedule, cursor, t, last, q, v, h, jacobian, rate, out) -> None:
    """The output rows of node ``cursor[NODE]`` at time t (with every remaining output time
    when it is the ``last`` node): q, v, the node and its time, and the largest residual
    max(|h|, |A v + dh/dt|); the rows' range into cursor[FIRST_ROW:END_ROW]."""
    wanted, every = schedule[2], schedule[3]
    q_out, v_out, residual_out, node_out, t_out = out[0], out[1], out[2], out[4], out[5]
    worst = largest(h)
    for j in range(h.size):
        total = rate[j]
        for i in range(q.size):
            total += jacobian[j, i] * v[i]
        worst = max(worst, abs(total))
    cursor[FIRST_ROW] = cursor[ROW]
    tolerance = schedule[0][3]
    while cursor[ROW] < q_out.shape[0]:
        if not every and not last and wanted[cursor[WANTED]] - tolerance > t:
            break
        row = cursor[ROW]
        for i in range(q.size):
            q_out[row, i] = q[i]
            v_out[row, i] = v[i]
        residual_out[row] = worst
        node_out[row] = cursor[NODE]
        t_out[row] = t
        cursor[ROW] += 1
        cursor[WANTED] += 1
        if every:
            break
    cursor[END_ROW] = cursor[ROW]


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def begin(schedule, cursor, clock, q, v, h, jacobian, rate, out) -> None:
    """Before the first step (cursor[NODE] < 0): make the first two nodes and record the
    first's output rows from the state there."""
    if cursor[NODE] >= 0:
        return
    clock[2] = next_node(schedule, cursor, clock)
    cursor[NODE] = 0
    clock[3] = next_node(schedule, cursor, clock)
    record(schedule, cursor, clock[2], clock[3] == np.inf, q, v, h, jacobian, rate, out)


@njit(cache=False, nogil=True, error_model="numpy", inline="always")
def arrive(schedule, cursor, clock, t2, q, v, h, jacobian, rate, out) -> None:
    """After a step from clock[2] to clock[3]: the next node is t2 (inf: none); record the
    output rows of the node reached from the state there."""
    clock[0], clock[1], clock[2], clock[3] = clock[1], clock[2], clock[3], t2
    cursor[NODE] += 1
    record(schedule, cursor, clock[2], t2 == np.inf, q, v, h, jacobian, rate, out)
