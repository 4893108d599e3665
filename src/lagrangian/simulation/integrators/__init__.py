"""Integrators: the protocol every formulation, stepper and integrator shares (``protocol``),
the one Python loop that drives every stepper — SciPy's solvers, RK4, the variational and
collocation steps, a batch's members stepped together — with output, events, budget and
Ctrl-C in one place (``loop``, over a lanes axis: ``lanes``, its rows in ``output``), the
fixed-step RK4, events, the step and wall-time budget, the compiled C loop's adapter
(``compiled``), and the piecewise loop of a motion whose equations change at events
(``piecewise``: switching surfaces, active sets of unilateral constraints).
"""
