"""Integrators: the protocol every formulation, stepper and integrator shares (``protocol``),
the one Python loop that drives every stepper — SciPy's solvers, RK4, the variational and
collocation steps — with output, events, budget and Ctrl-C in one place (``loop``), the
fixed-step RK4, events, the step and wall-time budget, the compiled C loop's adapter
(``compiled``), and the piecewise loop of a motion whose equations change at events
(``piecewise``: switching surfaces, active sets of unilateral constraints).
"""
