"""When the Newton iteration of a collocation step keeps its factored Jacobian, and when it
stops: the rules shared by the NumPy step
(:mod:`lagrangian.simulation.variational.collocation_step`) and the compiled one
(:mod:`lagrangian.numerics.fast.collocation`).

The stage equations are solved by simplified Newton iterations (Hairer & Wanner, Solving
Ordinary Differential Equations II, section IV.8): their Jacobian is evaluated and factored
at the first iterate, and the factors are reused by the corrections after it, each of which
then costs one evaluation of the stages and one substitution.  From the guess of
:mod:`lagrangian.numerics.stage_prediction` (the stages of the step before extrapolated, and
corrected), the first correction is a full Newton step, which ends the iteration when it is
below SMALL_CORRECTION (most steps of a smooth motion); the Jacobian changes over it
by the size of that correction, so the corrections after it contract at the rate

    theta_k = |dV_k| / |dV_{k-1}|     (about 1e-7 on a double pendulum at dt = 0.01)

and the error left after the correction dV_k is about theta_k / (1 - theta_k) |dV_k| (HW
IV.8, (8.10)).  The iteration stops, as Newton's method does, at a correction below
SMALL_CORRECTION of the stage positions whose residual was within RESIDUAL_GUARD (within
its square root, :data:`~lagrangian.numerics.stage_prediction.NEWTON_RESIDUAL_GUARD`, for a
correction by the Jacobian at the same iterate, which leaves a residual of the square of
the one before it); after a
reused Jacobian, also with that estimate of the error left below :data:`SETTLED` of them:
a few units of rounding, where the corrections of a converged iteration (its own rounding
noise) are of one or two.  A rate above :data:`REFRESH_RATE` (a poor start, a long
step) has the Jacobian evaluated again at the next iterate: the iteration is then Newton's.

>>> settled(0.0, 1e-9, 1.0), settled(1e-7, 1e-9, 1.0), settled(1e-5, 1e-9, 1.0)
(True, True, False)
"""

from __future__ import annotations

#: The error left after the last correction, relative to the size of the stage positions,
#: below which a reused Jacobian's iteration stops: four units of rounding.
SETTLED = 4 * 2.0**-52
#: A rate of contraction above this has the Jacobian evaluated and factored afresh.
REFRESH_RATE = 1e-3


def settled(rate: float, correction: float, size: float) -> bool:
    """Whether the error left after a correction of size ``correction`` made at the
    contraction ``rate`` (0 for a Jacobian evaluated at the iterate corrected: Newton's
    step) is below SETTLED of ``size`` (0 counts as 1)."""
    if rate == 0.0:
        return True
    return rate < 1.0 and rate / (1.0 - rate) * correction <= SETTLED * (
        size if size != 0.0 else 1.0
    )
