"""A Trajectory and a Batch survive pickling (sent between processes: multiprocessing, Dask)
whole and as read-only as they were made, for every kind of system: free, with events,
constrained (multipliers and residuals), with impacts, electrical, and a constrained batch."""

import pickle
from dataclasses import fields

import numpy as np
import pytest

import lagrangian as lg


def _crossing(t, q, q_dot):
    return q[0]


def _same(a, b) -> bool:
    """Equal as values: arrays to the bit (NaN equal to NaN), mappings item by item."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)
    if isinstance(a, dict | tuple | list) or hasattr(a, "items"):
        if hasattr(a, "items"):
            return dict(a).keys() == dict(b).keys() and all(_same(a[k], b[k]) for k in a)
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b


def _read_only(value) -> bool:
    """Every array reachable from the fields is read-only."""
    if isinstance(value, np.ndarray):
        return not value.flags.writeable
    if hasattr(value, "items"):
        return all(_read_only(v) for _, v in value.items())
    return True


RUNS = {
    "double pendulum with an event": lambda: lg.simulate(
        lg.examples.double_pendulum(),
        {"theta": 0.5, "phi": 0.3, "theta_dot": 0.0, "phi_dot": 0.0},
        3.0,
        events=[_crossing],
    ),
    "cylinder rolling on an incline (constrained)": lambda: lg.simulate(
        lg.examples.cylinder_on_incline(), t_span=1.0
    ),
    "rolling disc (3-D, nonholonomic)": lambda: lg.simulate(lg.examples.rolling_disc(), t_span=1.0),
    "bouncing ball (impacts)": lambda: lg.simulate(lg.examples.bouncing_ball(), t_span=3.0),
    "series RLC circuit": lambda: lg.simulate(lg.examples.series_rlc(), t_span=1.0),
}


@pytest.mark.parametrize("case", sorted(RUNS))
def test_a_trajectory_comes_back_from_a_pickle_whole_and_read_only(case):
    run = RUNS[case]()
    back = pickle.loads(pickle.dumps(run))
    assert type(back) is type(run)
    for f in fields(run):
        assert _same(getattr(back, f.name), getattr(run, f.name)), f.name
        assert _read_only(getattr(back, f.name)), f.name
    with pytest.raises(ValueError):
        back.q[0, 0] = 1.0
    assert back.drift() == run.drift()  # what is computed from the fields agrees too


def test_the_bouncing_balls_impacts_survive():
    run = RUNS["bouncing ball (impacts)"]()
    assert run.impacts  # the case holds what the test is about
    back = pickle.loads(pickle.dumps(run))
    assert [dict(i.after) for i in back.impacts] == [dict(i.after) for i in run.impacts]


@pytest.mark.parametrize(
    "model, initial",
    [
        ("double_pendulum", {"theta": [0.1, 0.2], "phi": 0.3, "theta_dot": 0.0, "phi_dot": 0.0}),
        ("cylinder_on_incline", None),
    ],
)
def test_a_batch_comes_back_from_a_pickle_whole_and_read_only(model, initial):
    system = getattr(lg.examples, model)()
    if initial is None:  # two members around the model's own start
        start = dict(system.initial)
        speed = next(k for k in start if str(k).endswith("_dot"))
        initial = {**{str(k): v for k, v in start.items()}, str(speed): [0.0, 0.5]}
    batch = lg.simulate_batch(system, initial, 1.0, project_initial=model != "double_pendulum")
    back = pickle.loads(pickle.dumps(batch))
    for f in fields(batch):
        assert _same(getattr(back, f.name), getattr(batch, f.name)), f.name
        assert _read_only(getattr(back, f.name)), f.name
    if model == "cylinder_on_incline":  # the constrained batch's columns came along
        assert back.multipliers is not None
        assert np.array_equal(back.multipliers, batch.multipliers, equal_nan=True)
